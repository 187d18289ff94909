//! Constraints with extra variables (contact forces beside `(u, x)`), projected onto `(u, x)`.

pub mod lp;
pub mod member;
pub mod project;

pub use member::Membership;
pub use project::{LiftedRows, Projection, Projector};
