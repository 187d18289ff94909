//! The double description method (Motzkin et al. 1953; Fukuda and Prodon 1996) on a pointed cone.
//!
//! # Problem
//!
//! Given `m` constraint rows `a_j` in `R^k` (unit vectors) whose matrix `A` has full column rank
//! `k`, compute the extreme rays of the pointed cone `P = {x : A x <= 0}`.
//!
//! # Method
//!
//! 1. Pick `k` linearly independent rows `A_K` (greedy pivoting). The cone `{x : A_K x <= 0}` is
//!    simplicial; its extreme rays are the columns of `-A_K^{-1}`, ray `i` being tight on every
//!    row of `K` except the `i`-th.
//! 2. Add the other rows one at a time. For a new row `a`, split the current rays into
//!    `R+ = {r : a . r > 0}` (violating), `R- = {a . r < 0}` and `R0 = {a . r = 0}`. The new
//!    extreme rays are `R- ∪ R0` plus, for every **adjacent** pair `(p, n) in R+ x R-`, the ray
//!    `(a . p) n - (a . n) p` on the hyperplane `a . x = 0`.
//! 3. Adjacency, combinatorial test (Fukuda and Prodon, Proposition 7): `p` and `n` are adjacent
//!    iff `|Z(p) ∩ Z(n)| >= k - 2` (necessary: the 2-face they span is cut out by rank `k - 2`)
//!    and no third ray `q` has `Z(p) ∩ Z(n) ⊆ Z(q)`. `Z(r)` is the zero set of `r` among the rows
//!    added so far, a bitset.
//!
//! 4. Continuing (`resume.rs`): the state after the last row (rays and zero sets) is all the
//!    iteration needs, so more rows can be added later by the same step 2 (the zero sets are
//!    re-packed into more words when the row count crosses a multiple of 64). This is how
//!    [`crate::Continuation`] adds generators to a converted cone.
//!
//! Steps 2 and 3 are written once (`step.rs`), for every width of zero set and every
//! dimension (monomorphized for `k = 3..8`); the run (`core.rs`) does step 1 and calls it per
//! row, as do the continuation (`resume.rs`) and the certificate's per-facet conversions. The
//! exact engine (`crate::exact`) takes the same decisions in integers and shares the
//! combinatorial test.
//!
//! Signs are decided with the tolerance [`crate::tol::Tolerances::incidence`] on slacks of unit
//! vectors (the tolerance contract of the crate docs).

pub(crate) mod bitset;
mod core;
mod resume;
mod scan;
mod step;
#[cfg(test)]
mod testing;

pub(crate) use self::core::{DdCore, DdFailure};
pub(crate) use self::scan::Scan;
pub(crate) use self::step::{adjacent, candidate_pairs};
