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
//! - [`retime::retime`] holds one stance for the whole motion: split a multi-stance motion at
//!   the contact switches and chain the segments through their end speeds yourself.
//! - The CoM path is a polyline or a clamped cubic spline through waypoints (rest to rest: the
//!   spline's end tangents are zero); other paths go through [`stance_topp`] directly.
//! - Without `angular_momentum` samples the model is a point mass (`L' = 0`); with them, `l1`
//!   and `l2` are interpolated linearly between samples, so between samples the retiming is
//!   only as good as that interpolation (sample at least at the grid's resolution where they
//!   vary fast, e.g. from [`stance_robot::path_terms_along`]).
//! - The stance's GIWC must be full-dimensional for retiming (a lower-dimensional GIWC, e.g.
//!   point contacts only, is reported as an error naming the equations).
//! - The whole-body pipeline of the paper (IK along the path, `l1`, `l2` from the robot model,
//!   the MuJoCo check) is not wired into [`retime`] yet.

pub use polycone;
pub use stance_contact;
pub use stance_robot;
pub use stance_topp;

pub mod error;
pub mod motion;
pub mod retime;
pub mod tol;

pub use error::StanceError;
