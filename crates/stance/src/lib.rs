//! # stance
//!
//! Multi-contact stability of legged robots, after Caron, Pham and Nakamura, "Leveraging Cone
//! Double Description for Multi-contact Stability of Humanoids with Applications to Statics and
//! Dynamics" (RSS 2015). This crate is the facade: it re-exports the layers below, and writes
//! their answers as JSON reports ([`report`]).
//!
//! - [`polycone`]: polyhedral cones, double description (span form <-> face form), certified.
//! - [`stance_contact`]: contact wrench cones, the GIWC `U_stance`, static and robust static
//!   equilibrium, supporting contact forces.
//! - [`stance_topp`]: time-optimal path parameterization on `a u + b x + c <= 0`.
//! - [`stance_robot`]: robot model from URDF, kinematics and centroidal momentum.
//! - [`motion`] (the `stance-motion` crate): whole-body motions across stances: a humanoid's
//!   path made by the acceleration-level IK, `U_stance` per stance, eq. 14 with the real body's
//!   angular momentum, one chained retiming of all segments, the trajectory and its independent
//!   force check; the paper's stair- and box-climbing experiments on JVRC-1 by name. Its modules
//!   for the other retimings are also re-exported here:
//!   - [`retime`]: the paper's Section V for one stance: a stance and a CoM path become the rows
//!     of eq. (14) through `U_stance` (computed once), solved by reachability analysis, with the
//!     violation of contact stability between grid points measured (and optionally refined
//!     away);
//!   - [`joints`]: fixed-base robots' joint paths retimed under actuator limits.
//!
//! The physics validation in MuJoCo (`stance-sim`) and the offline 3-D page (`stance-view`) are
//! crates of their own, used by the command line.
//!
//! # The pipeline in one call
//!
//! ```
//! use stance::retime::{retime, ComMotionSpec};
//! // Sway the CoM from above the left foot to above the right foot, rest to rest.
//! let spec: ComMotionSpec = serde_json::from_str(r#"{
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
//! Each layer states its own: [`polycone`], [`stance_contact`], [`stance_topp`],
//! [`stance_robot`] and [`motion`] (retiming, whole-body motions, actuator limits,
//! collisions). The simulator (`stance-sim`) and the 3-D page (`stance-view`) are separate crates
//! that only the command line depends on.

pub use polycone;
pub use stance_contact;
pub use stance_robot;
pub use stance_topp;

/// Whole-body motions across stances, and the retimings (the `stance-motion` crate).
pub use stance_motion as motion;
pub use stance_motion::{binding, error, input, joints, limits, retime, tol, StanceError};

pub mod report;
