//! # stance-topp
//!
//! Time-optimal path parameterization (TOPP) on canonical linear constraints, by reachability
//! analysis. The crate knows nothing about contacts: the contact-stability rows come from the
//! GIWC through [`factored`] (or any other source of `a`, `b`, `c`).
//!
//! ## The problem (Caron, Pham, Nakamura, RSS 2015, eq. 13-14)
//!
//! A path `s -> q(s)`, `s in [s_0, s_N]`, is retimed as `s(t)`. With `u = s''` and `x = s'^2`,
//! every constraint that is linear in the generalized acceleration becomes, at each point,
//!
//! ```text
//!     a(s) u + b(s) x + c(s) <= 0                                    (13)
//! ```
//!
//! For contact stability of a humanoid with CoM path `p(s)`, GIWC face matrix `U` (rows with
//! `U w_GI <= 0`), mass `m`, gravity `g` and angular-momentum terms `l1`, `l2`:
//!
//! ```text
//!     a(s) = -U (m p_s , m p x p_s  + l1)
//!     b(s) = -U (m p_ss, m p x p_ss + l2)
//!     c(s) =  U (m g   , m p x g)                                     (14)
//! ```
//!
//! ## Reachability analysis (H. Pham and Q.-C. Pham, IEEE T-RO 2018)
//!
//! On a grid `s_0 < ... < s_N` with `u` constant per interval, `x_{i+1} = x_i + 2 Delta_i u_i`.
//! The backward pass computes the controllable sets `K_i = [lo_i, hi_i]` of `x` (the states
//! from which the end interval can still be reached), each from two exact 2-variable LPs
//! ([`lp2`]); the greedy forward pass then takes the largest admissible `u_i` at every step,
//! which maximizes every `x_i` at once and so minimizes the duration
//! `sum 2 Delta_i / (sqrt(x_i) + sqrt(x_{i+1}))` ([`profile`]). Where rest is infeasible
//! (`lo_i > 0`), the pass simply keeps a minimum speed; numerical-integration TOPP fails there.
//!
//! ## How it is checked
//!
//! - The LP kernel against brute-force vertex enumeration (`tests/lp2_brute.rs`, proptest).
//! - Controllable sets against an independent one-shot LP solved by clarabel (max / min `x_i`
//!   over all admissible sequences to the end), to 1e-6, on random instances; durations against
//!   the LP's profile (see Limitations for the measured gaps); infeasibility reported with the
//!   right grid index (`tests/random.rs`).
//! - The shared GIWC instances against toppra 0.6.10: same durations to within toppra's
//!   conservatism (ours shorter by 2e-8 to 8e-7, never longer), every enforced row satisfied to
//!   1e-9 at every grid point (`tests/shared_instances.rs`).
//! - The factored eq. 14 rows against the shared rows to 1e-12 (`tests/factored_between.rs`).
//!
//! The warm start (the rows that were active at the previous stage are added first) leaves the
//! answer unchanged and cuts the solve time severalfold on the shared instances (the optimum
//! found from those rows rarely moves when the others are added); see `bench/peers/topp.md` for
//! the measured figures, and against toppra (faster than its Python package on the shared
//! instances at N = 100 and 1000).
//!
//! ## Between grid points
//!
//! Neither discretization enforces the continuous constraint between grid points; [`between`]
//! evaluates it on a finer grid after solving, reports the largest violation, and refines the
//! grid until it is below a bound.
//!
//! ## Use
//!
//! ```
//! use stance_topp::{solve, CanonicalConstraints, Discretization, Row, SolveOptions, Status};
//! // |u| <= 1 on s in [0, 1], rest to rest: bang-bang, duration 2.
//! let rows = vec![Row { a: 1.0, b: 0.0, c: -1.0 }, Row { a: -1.0, b: 0.0, c: -1.0 }];
//! let s: Vec<f64> = (0..=50).map(|i| i as f64 / 50.0).collect();
//! let offsets: Vec<usize> = (0..=51).map(|i| 2 * i).collect();
//! let k = CanonicalConstraints::new(s, offsets, rows.repeat(51)).unwrap();
//! let sol = solve(&k, &SolveOptions::new(Discretization::Collocation)).unwrap();
//! assert_eq!(sol.status, Status::Optimal);
//! assert!((sol.duration().unwrap() - 2.0).abs() < 1e-9);
//! ```
//!
//! # Limitations
//!
//! - Only canonical *linear* constraints (no second-order cones, no quadratic constraints such
//!   as exact friction cones); linearize them first.
//! - The controls are piecewise constant on the given grid; the continuous constraint holds at
//!   the grid points only (up to `tol.feasibility`), and between them only as far as
//!   [`between`] measured or refined it.
//! - Collocation does not constrain the acceleration applied on arrival at `s_N`
//!   ([`Profile::residuals`] reports it apart), nor, at a grid point where every row has
//!   `a = 0` (a path tangent vanishing there), the acceleration leaving it: the profile can then
//!   bounce (accelerate, brake to rest at the next point). Between grid points collocation was
//!   measured to violate the GIWC by up to 69 % of `m |g|` on `mc_minvel` at N = 100 (0 % with
//!   interpolation); use interpolation, or [`between::refine_until`].
//! - When the rows leave `u` or `x` unbounded, the LPs are bounded by the box `tol.max_u`,
//!   `tol.max_x` and [`Solution::hit_box`] says so. The box, like the tolerances, is in the
//!   unit of time the solver decides in ([`tol`]): the rows' own when it is far from 1.
//! - With a separation oracle the problem is solved in the caller's unit of time (its cuts are
//!   in that unit): contact-stability rows of a humanoid are near unit time; a problem far from
//!   it decides at the tolerances' absolute level (`tol.state` on `x` below 1).
//! - The LP kernel inserts lines in a fixed (warm-start, then index) order, not a random one:
//!   worst case `O(m^2)` per LP on adversarial row orders (not observed on GIWC rows).
//! - Producing `a, b, c` from `U` ([`factored::FactoredRows::fill`]) for 101 grid points runs
//!   the AVX-512 kernel `avx512-gz` where the CPU has AVX-512F (chosen at run time); it meets
//!   the issue's time target for the shared instances' 137 and 172 rows on a quiet machine,
//!   the latter with a small margin (above it when the other core is busy; `bench/peers/topp.md`
//!   has the target, the figures and the commands). Its edge over the previous AVX-512 kernel
//!   (recomputing `U_z m g_z` instead of loading it) needs vertical gravity; for other gravity
//!   vectors it runs as that kernel. Elsewhere the AVX2 + FMA kernel or the portable one runs
//!   (slower: 4 rows per vector with AVX2, the baseline target's vectors otherwise). The fill
//!   is bound by writing its 24-byte rows into the second-level cache (most of its time) plus
//!   the part of its 14 multiply-adds per row that does not overlap with them; beyond that
//!   cache (N = 1000) all kernels are bound by memory. The AVX-512 kernel keeps 8 rotated
//!   copies of `U` (8x its size) built once per factored form.
//! - Row coefficients (and the products of the factored form) are limited to
//!   [`tol::MAX_ABS_COEFFICIENT`] (1e100) and the LP box to [`tol::MAX_BOX`]: the kernel squares
//!   them. Every row test is relative within the row (`tol.zero_row`, `tol.feasibility`), so a
//!   row multiplied by a positive factor gives the same answer: a row of round-off, all of
//!   whose coefficients are noise, is then a real constraint; drop such rows before solving.
//! - The greedy forward pass is time-optimal for the continuous problem as the grid is refined,
//!   not exactly for the discretized one: when rows couple `u` and `x` (`b != 0`), a lower `x_i`
//!   can allow a larger `u_i`. Measured against a one-shot LP (clarabel, maximizing
//!   `sum x_i`): durations agree to 2e-6 on the shared GIWC instances; on smooth random rows
//!   the worst gap shrinks about as `Delta^2` (2.1e-3 at N = 50, 1.7e-4 at N = 100, 6.7e-6 at
//!   N = 400, 50 instances each); on rows that jump randomly between grid points the greedy
//!   profile was up to 8.6 % slower (collocation; 4.6 % with interpolation) in a 200-instance
//!   sweep (`tests/random.rs`, ignored test `sweep_greedy_vs_lp_on_rough_rows`). The
//!   controllable sets themselves match the LP to 1e-6.
//! - The returned [`Solution`] allocates its vectors; the LP kernel and the passes do not.
//! - Separation ([`Workspace::solve_separated`]): the profile is that of the exact sets only if
//!   the oracle's cuts are valid (the solver cannot tell) and its acceptance is honest; each
//!   LP takes at most [`tol::MAX_CUTS_PER_LP`] cuts. The cuts found are kept per grid point in
//!   [`Solution::cuts`]; [`end_speed_range`] takes no oracle. Accepting every LP optimum
//!   certifies the controllable sets' ends; the sets are then exact by convexity, which needs
//!   the oracle's constraints to be convex (the lifted rows are).
//! - [`lifted`]: at most 20 extra variables in a membership test and 18 in a projection
//!   ([`lifted::lp::MAX_VARS`]; a stance of five contacts with torque limits is beyond it, an
//!   error that says so), each bounded by `y_bound` (a cut or facet resting on that bound is valid but looser than the
//!   physics); the small dense simplex refactors `n^3` per solve, so a program costs a few
//!   microseconds at 13 variables and 100 rows. Kelley's cuts are tangent planes of the margin
//!   function, not always facets of the projection: a state far outside may take a few cuts
//!   (at most 8 on the random polytopes of `tests/lifted.rs`).
//! - [`limits`]: symmetric limits only (`|v| <= V`, `|a| <= A`, `|tau| <= T`); the velocity
//!   limit is a bound on `x` at each grid point (with the larger `|q_s|` of an IK step's ends
//!   where the caller gives them), so between grid points it holds only as [`between`] refines.

pub mod between;
pub mod constraints;
pub mod error;
pub mod facets;
pub mod factored;
pub mod lifted;
pub mod limits;
pub mod lp2;
pub mod path;
pub mod profile;
pub mod solver;
pub mod tol;

pub use constraints::{ldexp, CanonicalConstraints, Row};
pub use error::ToppError;
pub use profile::{Profile, Residuals, Sample};
pub use solver::{
    end_speed_range, solve, BackwardPiece, Cut, Cuts, Discretization, Separation, Solution,
    SolutionReport, SolveOptions, SolveStats, Status, Workspace,
};
pub use tol::Tolerances;
