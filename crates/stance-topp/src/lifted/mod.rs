//! Constraints with extra variables (contact forces beside `(u, x)`), projected onto `(u, x)`.

pub mod lp;
pub mod project;

pub use project::{LiftedRows, Projection, Projector};
