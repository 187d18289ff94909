//! (crate under construction; see the crate README and issues)
pub mod polytope;
