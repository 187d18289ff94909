//! Reachability analysis (H. Pham and Q.-C. Pham, "A new approach to time-optimal path
//! parameterization based on reachability analysis", IEEE T-RO 2018), written from the paper.
//!
//! # Math
//!
//! Grid `s_0 < ... < s_N`, `Delta_i = s_{i+1} - s_i`, state `x_i = s'(s_i)^2`, control
//! `u_i = s''` constant on `[s_i, s_{i+1}]`, so `x_{i+1} = x_i + 2 Delta_i u_i`. Stage `i`
//! admits the pairs `(u_i, x_i)` of its feasible set `Omega_i` (the rows of grid point `i`;
//! with interpolation also the rows of `i + 1` at `x_i + 2 Delta_i u_i`; bounds; `x >= 0`).
//!
//! - Backward pass: `K_N = [lo_end^2, hi_end^2] ∩ {x : exists u, (u, x) in Omega_N}` and
//!   `K_i = {x : exists u, (u, x) in Omega_i, x + 2 Delta_i u in K_{i+1}}`, an interval whose two
//!   ends are 2-variable LPs (`min x`, `max x`), solved exactly by [`crate::lp2`].
//! - Forward pass (greedy): from `x_0 = sd_start^2 in K_0`, take the largest `u_i` with
//!   `(u_i, x_i) in Omega_i` and `x_i + 2 Delta_i u_i in K_{i+1}`. Each step is a 1-D LP. The
//!   result is the pointwise-largest admissible `x` at every grid point, hence time-optimal for the
//!   discretized problem.
//!
//! Empty sets are reported as [`Status`] values with the grid index. The backward pass can also
//! run piece by piece, last piece first, as the pieces' rows become available (module
//! `pieces`, [`BackwardPiece`]), with the whole solve's answer.

mod options;
mod pieces;
mod reachability;
mod report;
pub mod separation;

pub use options::{Discretization, Solution, SolveOptions, SolveStats, Status};
pub use pieces::BackwardPiece;
pub use reachability::{end_speed_range, solve, Workspace};
pub use report::SolutionReport;
pub use separation::{Cut, Cuts, Separation};
