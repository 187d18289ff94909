//! Constraints with extra variables (contact forces beside `(u, x)`), projected onto `(u, x)`.

pub mod lp;
pub mod member;
pub mod project;

pub use member::{LiftedCut, Membership, Witnesses};
pub use project::{LiftedRows, Projection, Projector};
