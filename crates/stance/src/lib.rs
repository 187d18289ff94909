//! # stance
//!
//! Multi-contact stability of legged robots, after Caron, Pham and Nakamura, "Leveraging Cone
//! Double Description for Multi-contact Stability of Humanoids with Applications to Statics and
//! Dynamics" (RSS 2015). This crate is the facade: it re-exports the layers below and holds the
//! glue between them.
//!
//! - [`polycone`]: polyhedral cones, double description (span form <-> face form), certified.
//! - [`stance_contact`]: contact wrench cones, the GIWC `U_stance`, static and robust static
//!   equilibrium, supporting contact forces.
//! - [`stance_topp`]: time-optimal path parameterization on `a u + b x + c <= 0`.
//! - [`stance_robot`]: robot model from URDF, kinematics and centroidal momentum.
//! - [`retime`]: the glue of the paper's Section V: a stance and a CoM path become the rows of
//!   eq. (14) through `U_stance` (computed once), solved by reachability analysis, with the
//!   violation of contact stability between grid points measured (and optionally refined away).
//! - [`motion`]: whole-body motions across stances: a humanoid's path made by the
//!   acceleration-level IK, `U_stance` per stance, eq. 14 with the real body's angular momentum,
//!   one chained retiming of all segments, the trajectory and its independent force check; the
//!   paper's stair- and box-climbing experiments on JVRC-1 by name.
//! - [`sim`]: the physics validation: a retimed motion executed in MuJoCo (PD control with
//!   inverse-dynamics feedforward) and measured (slip, contact losses, falls).
//!
//! # The pipeline in one call
//!
//! ```
//! use stance::retime::{retime, MotionSpec};
//! // Sway the CoM from above the left foot to above the right foot, rest to rest.
//! let spec: MotionSpec = serde_json::from_str(r#"{
//!     "scene": "double-support",
//!     "path": {"waypoints": [[0.0, 0.08, 0.8], [0.03, 0.0, 0.78], [0.0, -0.08, 0.8]]},
//!     "max_violation_fraction": 0.01}"#).unwrap();
//! let r = retime(&spec).unwrap();
//! assert_eq!(r.status, "optimal");
//! assert!(r.giwc_certified);
//! assert!(r.between.unwrap().fraction_of_weight <= 0.01);
//! ```
//!
//! # Limitations
//!
//! - [`retime::retime`] holds one stance for a point-mass CoM path; motions across stances with
//!   the whole body are [`motion`]'s.
//! - The CoM path is a polyline or a clamped cubic spline through waypoints (rest to rest: the
//!   spline's end tangents are zero); other paths go through [`stance_topp`] directly.
//! - Without `angular_momentum` samples the model is a point mass (`L' = 0`); with them, `l1`
//!   and `l2` are interpolated linearly between samples, so between samples the retiming is
//!   only as good as that interpolation (sample at least at the grid's resolution where they
//!   vary fast, e.g. from [`stance_robot::path_terms_along`]).
//! - The stance's GIWC must be full-dimensional for retiming (a lower-dimensional GIWC, e.g.
//!   point contacts only, is reported as an error naming the equations).
//! - [`motion`]: the CoM reference passes through its via-points with its corners rounded
//!   over `2 com_blend` path units (it leaves the straight lines between them near each
//!   corner); free links move along straight lines with minimum-jerk timing and stop at every
//!   via-point. The IK is integrated with `q_ss` constant per step: the retiming enforces the
//!   rows on both sides of every grid point and refines the grid at IK samples where they fail,
//!   so the rows hold at every IK sample, but between IK samples only as the independent force
//!   check measures (no sample of the built-in motions fails it at 1 ms; the
//!   gallery's slope fails it at 15 samples of 2,329, by 1.8e-5 of the weight). The
//!   greedy profile is time-optimal as the grid is refined, not exactly on the grid (measured:
//!   0.23 % longer than a one-shot LP's on `small-sway`). Path speeds are unbounded where the
//!   whole body is at rest in path terms (the start, via-points where nothing else moves):
//!   there the profile may reach the solver's box (`s'^2 = 1e8`), which costs no time. Planar
//!   convex environment surfaces only.
//! - Collisions ([`motion::collision`]): the robot is its capsules and contact boxes (not its
//!   meshes), the environment its surfaces' solids; no self-collision. The IK keeps the
//!   clearance of the links it can move freely, linearised per step (a body may overshoot its
//!   clearance, not the surface, by a fraction of a millimetre); a landing link's path is a hard
//!   task that it cannot bend, so a landing through a solid is reported by the check, not
//!   avoided (write a swing that clears it, or leave the landing to the footholds planner).
//! - Actuator limits ([`limits`], [`motion`], [`joints`]): symmetric limits only, the torque's
//!   from the URDF's `effort` (a joint without one has none), no friction or motor model. In a
//!   motion the torques are enforced at the grid points and, after the refinement, at the IK
//!   samples (the lifted rows by membership); between IK samples the checks at the output
//!   samples measure them (at most `1 + 3e-15` on the built-in and gallery motions at 1 ms).
//!   The contact forces are those of the planning pyramids (planning friction and area), as
//!   the GIWC's: a simulator with more friction or area has more room. `U_stance` + rows +
//!   TOPP with the limits takes 4 to 10 times as long as without (24 ms for the box climbing,
//!   `bench/peers/limits.md`), over the 10 ms the issue asked for on the stairs and the box.
//!   [`joints`] retimes fixed-base robots only (the root fixed to the world); its grid is
//!   refined until no limit is exceeded between grid points by more than
//!   `max_violation_fraction` (default 1e-3).
//! - [`sim`]: MuJoCo runs in Python (the project virtualenv's `mujoco` from PyPI): the
//!   simulator is not linked into the crate. The model's collision geometry is primitive
//!   (contact boxes, link capsules of one radius), JVRC-1's Collada meshes are not used; the
//!   controller tracks joints only (no balance feedback), so the verdict is about the plan
//!   played open loop, as in the paper; its gains (kp 10 000, kv 200) are the project's choice.

pub use polycone;
pub use stance_contact;
pub use stance_robot;
pub use stance_topp;

pub mod binding;
pub mod error;
pub mod input;
pub mod joints;
pub mod limits;
pub mod motion;
mod name_or;
pub mod report;
pub mod retime;
pub mod sim;
mod strict;
pub mod tol;
pub mod view;

pub use error::StanceError;
