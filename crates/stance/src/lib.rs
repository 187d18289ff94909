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

pub use polycone;
pub use stance_contact;
pub use stance_robot;
pub use stance_topp;

pub mod error;
pub mod retime;
pub mod tol;

pub use error::StanceError;
