//! Exact 2-variable linear programs, the kernel of reachability analysis.
//!
//! # Problem
//!
//! Over the plane of `v = (u, x)` (path acceleration `u = s''`, squared path speed `x = s'^2`):
//!
//! ```text
//!     maximize    c . v            (ties broken by maximizing t . v)
//!     subject to  n_j . v <= d_j   for every line j,
//!                 u_lo <= u <= u_hi,  x_lo <= x <= x_hi      (a bounding box)
//! ```
//!
//! Each reachability stage (Pham and Pham, T-RO 2018) solves two of these: `c = (0, +-1)` for
//! the bounds of a controllable set, `c = +-(2 Delta, 1)` for the bounds of a reachable set.
//!
//! # Algorithm
//!
//! Seidel's incremental algorithm (R. Seidel, "Small-dimensional linear programming and convex
//! hulls made easy", 1991) in two dimensions, written for this crate: start from the optimal
//! vertex of the box; add the lines one by one; when the current optimum violates the new line,
//! the new optimum lies on that line, found by a 1-D LP over the lines added so far (an interval
//! of the line parameter). The answer is exact up to floating-point round-off of the
//! intersections; ties are resolved lexicographically (first `c`, then `t`), so the optimum is
//! unique and the algorithm is correct in any order. Expected `O(m)` work in random order,
//! `O(m^2)` worst case; a warm start puts the lines that were active at the previous grid point
//! first, after which most lines only cost one dot product.
//!
//! No allocation: the caller owns the line buffer and the order buffer.

use crate::tol::Tolerances;

/// A half-plane `nu u + nx x <= d` with `|(nu, nx)| = 1`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Line {
    /// Coefficient of `u`.
    pub nu: f64,
    /// Coefficient of `x`.
    pub nx: f64,
    /// Right-hand side.
    pub d: f64,
}

impl Line {
    /// The half-plane `a u + b x + c <= 0` scaled to a unit normal, or `None` when `(a, b)` is
    /// zero to within `zero_row * max(1, |c|)` (a constant constraint `c <= 0`).
    ///
    /// ```
    /// use stance_topp::lp2::Line;
    /// let l = Line::from_row(3.0, 4.0, -10.0, 1e-12).unwrap();
    /// assert!((l.nu - 0.6).abs() < 1e-15 && (l.nx - 0.8).abs() < 1e-15 && (l.d - 2.0).abs() < 1e-15);
    /// assert!(Line::from_row(0.0, 0.0, -1.0, 1e-12).is_none());
    /// ```
    #[inline]
    pub fn from_row(a: f64, b: f64, c: f64, zero_row: f64) -> Option<Line> {
        let norm = a.hypot(b);
        if norm <= zero_row * c.abs().max(1.0) {
            None
        } else {
            Some(Line {
                nu: a / norm,
                nx: b / norm,
                d: -c / norm,
            })
        }
    }

    /// Signed violation `n . v - d` of the point `(u, x)` (positive: outside).
    ///
    /// ```
    /// use stance_topp::lp2::Line;
    /// let l = Line { nu: 0.0, nx: 1.0, d: 2.0 }; // x <= 2
    /// assert_eq!(l.violation(5.0, 3.0), 1.0);
    /// ```
    #[inline]
    pub fn violation(&self, u: f64, x: f64) -> f64 {
        self.nu * u + self.nx * x - self.d
    }
}

/// Bounding box of a 2-variable LP.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Box2 {
    /// Lower bound on `u`.
    pub u_lo: f64,
    /// Upper bound on `u`.
    pub u_hi: f64,
    /// Lower bound on `x`.
    pub x_lo: f64,
    /// Upper bound on `x`.
    pub x_hi: f64,
}

/// Outcome of [`solve`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Lp2 {
    /// The optimum `(u, x)` and the indices of the (up to two) lines active there; box sides are
    /// `None`.
    Optimal {
        /// Optimal `u`.
        u: f64,
        /// Optimal `x`.
        x: f64,
        /// Lines (indices into the `lines` slice) that define the optimal vertex.
        active: [Option<usize>; 2],
    },
    /// No point satisfies every line and the box.
    Infeasible,
}

/// Statistics of one [`solve`] call (for measuring the effect of warm starts).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Lp2Stats {
    /// Number of 1-D sub-problems solved (lines that moved the optimum).
    pub moves: usize,
    /// Number of line evaluations inside the 1-D sub-problems.
    pub inner_steps: usize,
}

/// Solves `max c . v` (ties: `max t . v`) over `lines` and `bbox`, adding first the lines listed
/// in `first` (a warm start; out-of-range indices are ignored) and then the others in index
/// order. `order` is a scratch buffer (resized, never shrunk, so it allocates only when it grows).
///
/// ```
/// use stance_topp::lp2::{solve, Box2, Line, Lp2, Lp2Stats};
/// use stance_topp::Tolerances;
/// // max x subject to x + u <= 2, x - u <= 0 (so x <= 1 at u = 1).
/// let s = std::f64::consts::FRAC_1_SQRT_2;
/// let lines = [Line { nu: s, nx: s, d: 2.0 * s }, Line { nu: -s, nx: s, d: 0.0 }];
/// let bbox = Box2 { u_lo: -10.0, u_hi: 10.0, x_lo: 0.0, x_hi: 10.0 };
/// let mut order = Vec::new();
/// let mut stats = Lp2Stats::default();
/// let r = solve(&lines, bbox, [0.0, 1.0], [1.0, 0.0], &[], &mut order, &Tolerances::default(), &mut stats);
/// match r {
///     Lp2::Optimal { u, x, .. } => assert!((u - 1.0).abs() < 1e-12 && (x - 1.0).abs() < 1e-12),
///     Lp2::Infeasible => panic!(),
/// }
/// ```
#[allow(clippy::too_many_arguments)]
pub fn solve(
    lines: &[Line],
    bbox: Box2,
    c: [f64; 2],
    t: [f64; 2],
    first: &[usize],
    order: &mut Vec<usize>,
    tol: &Tolerances,
    stats: &mut Lp2Stats,
) -> Lp2 {
    let feas = tol.feasibility;
    if bbox.u_lo > bbox.u_hi + feas || bbox.x_lo > bbox.x_hi + feas {
        return Lp2::Infeasible;
    }
    // Lexicographically optimal vertex of the box.
    let pick = |lo: f64, hi: f64, ci: f64, ti: f64| {
        if ci > 0.0 || (ci == 0.0 && ti >= 0.0) {
            hi
        } else {
            lo
        }
    };
    let mut u = pick(bbox.u_lo, bbox.u_hi, c[0], t[0]);
    let mut x = pick(bbox.x_lo, bbox.x_hi, c[1], t[1]);
    let mut active: [Option<usize>; 2] = [None, None];

    // Insertion order: warm-start lines first, then the rest.
    let m = lines.len();
    order.clear();
    for &j in first {
        if j < m && !order.contains(&j) {
            order.push(j);
        }
    }
    let n_first = order.len();
    for j in 0..m {
        if !order[..n_first].contains(&j) {
            order.push(j);
        }
    }

    for k in 0..order.len() {
        let lk = lines[order[k]];
        if lk.violation(u, x) <= feas {
            continue;
        }
        stats.moves += 1;
        // The new optimum lies on line k: p(tau) = p0 + tau * dir.
        let (p0u, p0x) = (lk.nu * lk.d, lk.nx * lk.d);
        let (du, dx) = (-lk.nx, lk.nu);
        let mut lo = f64::NEG_INFINITY;
        let mut hi = f64::INFINITY;
        let mut lo_by: Option<usize> = None;
        let mut hi_by: Option<usize> = None;
        // Box sides as four lines: u <= u_hi, -u <= -u_lo, x <= x_hi, -x <= -x_lo.
        let sides = [
            (1.0, 0.0, bbox.u_hi),
            (-1.0, 0.0, -bbox.u_lo),
            (0.0, 1.0, bbox.x_hi),
            (0.0, -1.0, -bbox.x_lo),
        ];
        for &(nu, nx, d) in &sides {
            let sj = nu * du + nx * dx;
            let rj = d - (nu * p0u + nx * p0x);
            if sj.abs() <= tol.parallel {
                if rj < -feas {
                    return Lp2::Infeasible;
                }
            } else if sj > 0.0 {
                let v = rj / sj;
                if v < hi {
                    hi = v;
                    hi_by = None;
                }
            } else {
                let v = rj / sj;
                if v > lo {
                    lo = v;
                    lo_by = None;
                }
            }
        }
        for &jj in &order[..k] {
            stats.inner_steps += 1;
            let lj = lines[jj];
            let sj = lj.nu * du + lj.nx * dx;
            let rj = lj.d - (lj.nu * p0u + lj.nx * p0x);
            if sj.abs() <= tol.parallel {
                if rj < -feas {
                    return Lp2::Infeasible;
                }
            } else if sj > 0.0 {
                let v = rj / sj;
                if v < hi {
                    hi = v;
                    hi_by = Some(jj);
                }
            } else {
                let v = rj / sj;
                if v > lo {
                    lo = v;
                    lo_by = Some(jj);
                }
            }
        }
        if lo > hi + feas {
            return Lp2::Infeasible;
        }
        let cd = c[0] * du + c[1] * dx;
        let td = t[0] * du + t[1] * dx;
        let up = if cd.abs() > tol.parallel {
            cd > 0.0
        } else {
            td >= 0.0
        };
        let (tau, by) = if lo > hi {
            (0.5 * (lo + hi), if up { hi_by } else { lo_by })
        } else if up {
            (hi, hi_by)
        } else {
            (lo, lo_by)
        };
        u = p0u + tau * du;
        x = p0x + tau * dx;
        active = [Some(order[k]), by];
    }
    Lp2::Optimal { u, x, active }
}
