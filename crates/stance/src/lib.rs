//! # stance
//!
//! Multi-contact stability of legged robots, after Caron, Pham and Nakamura, "Leveraging Cone
//! Double Description for Multi-contact Stability of Humanoids with Applications to Statics and
//! Dynamics" (RSS 2015). This crate is the facade: it re-exports the layers below and holds the
//! glue between them.
//!
//! - [`polycone`]: polyhedral cones, double description (span form <-> face form).
//! - [`stance_contact`]: contact wrench cones, the GIWC, static equilibrium.
//! - [`stance_topp`]: time-optimal path parameterization.
//! - [`stance_robot`]: robot model, kinematics and centroidal momentum.
//!
//! The glue: [`retime`] turns a stance and a CoM path into the rows of paper eq. 13-14 and
//! retimes the path (the `stance retime` command).
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

pub use polycone;
pub use stance_contact;
pub use stance_robot;
pub use stance_topp;

pub mod error;
pub mod retime;
pub mod tol;

pub use error::StanceError;
