//! Exact 2-variable linear programs, the kernel of reachability analysis.
//!
//! # Problem
//!
//! Over the plane of `v = (u, x)` (path acceleration `u = s''`, squared path speed `x = s'^2`):
//!
//! ```text
//!     maximize    c . v            (ties broken by maximizing t . v)
//!     subject to  a_j u + b_j x + c_j <= 0   for every line j,
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
//! first, after which most lines cost one multiply-add test.
//!
//! Rows are used as given (not normalized), and every test is **invariant to a positive scaling
//! of a row** (which does not change its half-plane): a row is violated when its value exceeds
//! `tol.feasibility * |(a, b)| * max(1, |(u, x)|)` (a distance of `tol.feasibility` in the
//! `(u, x)` plane, relative to the size of the point), tested on squares so that no square
//! root or division is spent on the lines that do not move the optimum. A row with
//! `|(a, b)| <= tol.zero_row * |c|` is the constant constraint `c <= 0`. No allocation.

use crate::constraints::Row;
use crate::tol::Tolerances;

/// The rows of one reachability stage: up to two leading rows (the next controllable set), the
/// rows of grid point `i` (and the cuts a separation oracle added to it), and with
/// interpolation the rows of grid point `i + 1` (and its cuts) evaluated at the next state: row
/// `(a, b, c)` of `next` stands for `(a + 2 Delta b, b, c)`, i.e. it is evaluated at
/// `(u, x + 2 Delta u)`. Global row indices run over `head[..n_head]`, then `here`,
/// `here_cuts`, `next`, `next_cuts`.
#[derive(Debug, Clone, Copy)]
pub struct StageLines<'a> {
    /// Leading rows (the first `n_head` are used).
    pub head: [Row; 2],
    /// Number of leading rows used.
    pub n_head: usize,
    /// Rows of grid point `i`.
    pub here: &'a [Row],
    /// Cuts of grid point `i` ([`crate::solver::Separation`]).
    pub here_cuts: &'a [Row],
    /// Rows of grid point `i + 1` (interpolation; empty for collocation).
    pub next: &'a [Row],
    /// Cuts of grid point `i + 1` (interpolation).
    pub next_cuts: &'a [Row],
    /// `2 Delta_i`.
    pub two_delta: f64,
}

impl<'a> StageLines<'a> {
    /// A plain set of rows (no leading rows, no interpolation rows).
    ///
    /// ```
    /// use stance_topp::lp2::StageLines;
    /// use stance_topp::Row;
    /// let rows = [Row { a: 1.0, b: 0.0, c: -1.0 }];
    /// assert_eq!(StageLines::from_rows(&rows).len(), 1);
    /// ```
    pub fn from_rows(rows: &'a [Row]) -> Self {
        Self {
            head: [Row::default(); 2],
            n_head: 0,
            here: rows,
            here_cuts: &[],
            next: &[],
            next_cuts: &[],
            two_delta: 0.0,
        }
    }

    /// Number of rows.
    ///
    /// ```
    /// use stance_topp::lp2::StageLines;
    /// assert_eq!(StageLines::from_rows(&[]).len(), 0);
    /// ```
    pub fn len(&self) -> usize {
        self.n_head
            + self.here.len()
            + self.here_cuts.len()
            + self.next.len()
            + self.next_cuts.len()
    }

    /// Whether there are no rows.
    ///
    /// ```
    /// use stance_topp::lp2::StageLines;
    /// assert!(StageLines::from_rows(&[]).is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Row `j < len()` as a row in `(u, x)` (interpolation rows transformed).
    ///
    /// ```
    /// use stance_topp::lp2::StageLines;
    /// use stance_topp::Row;
    /// let next = [Row { a: 1.0, b: 2.0, c: 3.0 }];
    /// let l = StageLines { next: &next, two_delta: 0.5, ..StageLines::from_rows(&[]) };
    /// assert_eq!(l.get(0), Row { a: 2.0, b: 2.0, c: 3.0 });
    /// ```
    #[inline]
    pub fn get(&self, j: usize) -> Row {
        if j < self.n_head {
            return self.head[j];
        }
        let j = j - self.n_head;
        if j < self.here.len() {
            return self.here[j];
        }
        let j = j - self.here.len();
        if j < self.here_cuts.len() {
            return self.here_cuts[j];
        }
        let j = j - self.here_cuts.len();
        let r = if j < self.next.len() {
            self.next[j]
        } else {
            self.next_cuts[j - self.next.len()]
        };
        Row {
            a: r.a + self.two_delta * r.b,
            b: r.b,
            c: r.c,
        }
    }

    /// The five segments `(rows, two_delta, first global index)`.
    #[inline]
    pub(crate) fn segments(&self) -> [(&[Row], f64, usize); 5] {
        let h = self.n_head;
        let a = h + self.here.len();
        let b = a + self.here_cuts.len();
        let c = b + self.next.len();
        [
            (&self.head[..self.n_head], 0.0, 0),
            (self.here, 0.0, h),
            (self.here_cuts, 0.0, a),
            (self.next, self.two_delta, b),
            (self.next_cuts, self.two_delta, c),
        ]
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
        /// Lines (indices into the lines) that define the optimal vertex.
        active: [Option<usize>; 2],
    },
    /// No point satisfies every line and the box.
    Infeasible,
}

/// Statistics of [`solve`] calls (for measuring the effect of warm starts).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Lp2Stats {
    /// Number of 1-D sub-problems solved (lines that moved the optimum).
    pub moves: usize,
    /// Number of line evaluations inside the 1-D sub-problems.
    pub inner_steps: usize,
}

/// `max(1, u^2 + x^2)`: tolerances are relative to the size of the point, since the round-off
/// of a row value grows with it (speeds `x` up to `tol.max_x` occur where the rows leave the
/// speed unbounded).
#[inline(always)]
fn point_scale2(u: f64, x: f64) -> f64 {
    (u * u + x * x).max(1.0)
}

/// First row of `rows[from..]` violated at `(u, x + td u)` by more than
/// `feas * max(1, |(a + td b, b)|) * max(1, |(u, x + td u)|)` (the tight loop of the kernel).
#[inline(always)]
pub(crate) fn first_violated(
    rows: &[Row],
    from: usize,
    td: f64,
    u: f64,
    x: f64,
    feas2: f64,
) -> Option<usize> {
    if from >= rows.len() {
        return None;
    }
    let xe = x + td * u;
    let scale2 = point_scale2(u, xe);
    let precise = |q: usize, r: &Row| -> Option<usize> {
        let v = r.a * u + r.b * xe + r.c;
        if v > 0.0 {
            let a = r.a + td * r.b;
            if v * v > feas2 * scale2 * (a * a + r.b * r.b) {
                return Some(q);
            }
        }
        None
    };
    // Blocks of rows are first screened without branches (any positive value?); most rows are
    // strictly satisfied, so the precise test runs on few blocks.
    let mut q = from;
    while q + SCREEN_BLOCK <= rows.len() {
        let block = &rows[q..q + SCREEN_BLOCK];
        let mut any = false;
        for r in block {
            any |= r.a * u + r.b * xe + r.c > 0.0;
        }
        if any {
            for (p, r) in block.iter().enumerate() {
                if let Some(j) = precise(q + p, r) {
                    return Some(j);
                }
            }
        }
        q += SCREEN_BLOCK;
    }
    rows[q..]
        .iter()
        .enumerate()
        .find_map(|(p, r)| precise(q + p, r))
}

/// Rows screened together by the branch-free test of the kernel's scan.
const SCREEN_BLOCK: usize = 8;

/// Solves `max c . v` (ties: `max t . v`) over `lines` and `bbox`, adding first the lines listed
/// in `first` (a warm start: global indices; out-of-range ones are ignored, at most 8 used) and
/// then all lines in index order.
///
/// ```
/// use stance_topp::lp2::{solve, Box2, Lp2, Lp2Stats, StageLines};
/// use stance_topp::{Row, Tolerances};
/// // max x subject to x + u <= 2, x - u <= 0 (so x <= 1 at u = 1).
/// let rows = [Row { a: 1.0, b: 1.0, c: -2.0 }, Row { a: -1.0, b: 1.0, c: 0.0 }];
/// let bbox = Box2 { u_lo: -10.0, u_hi: 10.0, x_lo: 0.0, x_hi: 10.0 };
/// let mut stats = Lp2Stats::default();
/// let lines = StageLines::from_rows(&rows);
/// let r = solve(&lines, bbox, [0.0, 1.0], [1.0, 0.0], &[], &Tolerances::default(), &mut stats);
/// match r {
///     Lp2::Optimal { u, x, .. } => assert!((u - 1.0).abs() < 1e-12 && (x - 1.0).abs() < 1e-12),
///     Lp2::Infeasible => panic!(),
/// }
/// ```
pub fn solve(
    lines: &StageLines<'_>,
    bbox: Box2,
    c: [f64; 2],
    t: [f64; 2],
    first: &[usize],
    tol: &Tolerances,
    stats: &mut Lp2Stats,
) -> Lp2 {
    let feas = tol.feasibility;
    let feas2 = feas * feas;
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
    let mut v = Vertex {
        u: pick(bbox.u_lo, bbox.u_hi, c[0], t[0]),
        x: pick(bbox.x_lo, bbox.x_hi, c[1], t[1]),
        active: [None, None],
    };
    let m = lines.len();
    let mut warm = [0usize; 8];
    let mut nf = 0;
    for &j in first {
        if j < m && nf < warm.len() && !warm[..nf].contains(&j) {
            warm[nf] = j;
            nf += 1;
        }
    }
    let warm = &warm[..nf];
    let ctx = Ctx {
        lines,
        bbox,
        c,
        t,
        tol,
    };
    // Warm lines first.
    for (q, &j) in warm.iter().enumerate() {
        let r = lines.get(j);
        let val = r.a * v.u + r.b * v.x + r.c;
        if val > 0.0 && val * val > feas2 * point_scale2(v.u, v.x) * (r.a * r.a + r.b * r.b) {
            stats.moves += 1;
            if !ctx.move_onto(j, &warm[..q], None, &mut v, stats) {
                return Lp2::Infeasible;
            }
        }
    }
    // Then every line, segment by segment (warm lines are re-checked harmlessly: the optimum
    // satisfies them).
    for (seg, &(rows, td, base)) in lines.segments().iter().enumerate() {
        let mut from = 0;
        while let Some(q) = first_violated(rows, from, td, v.u, v.x, feas2) {
            stats.moves += 1;
            if !ctx.move_onto(base + q, warm, Some((seg, q)), &mut v, stats) {
                return Lp2::Infeasible;
            }
            from = q + 1;
        }
    }
    Lp2::Optimal {
        u: v.u,
        x: v.x,
        active: v.active,
    }
}

/// Two LPs over the same lines and box (for example `max x` and `min x`), solved in one pass
/// over the rows: each row is read once and tested against both current optima. Same answers
/// as two calls of [`solve`] with the same warm starts (up to round-off); since the feasible
/// region is shared, one infeasibility makes both infeasible.
///
/// ```
/// use stance_topp::lp2::{solve_pair, Box2, Lp2, Lp2Stats, StageLines};
/// use stance_topp::{Row, Tolerances};
/// // 1 <= x + u <= 2, x - u <= 0: x in [0, 1] (x = 0 at u = 1).
/// let rows = [
///     Row { a: 1.0, b: 1.0, c: -2.0 },
///     Row { a: -1.0, b: -1.0, c: 1.0 },
///     Row { a: -1.0, b: 1.0, c: 0.0 },
/// ];
/// let bbox = Box2 { u_lo: -10.0, u_hi: 10.0, x_lo: 0.0, x_hi: 10.0 };
/// let objs = [([0.0, 1.0], [1.0, 0.0]), ([0.0, -1.0], [-1.0, 0.0])];
/// let [hi, lo] = solve_pair(&StageLines::from_rows(&rows), bbox, objs, [&[], &[]],
///     &Tolerances::default(), &mut Lp2Stats::default());
/// let (Lp2::Optimal { x: x_hi, .. }, Lp2::Optimal { x: x_lo, .. }) = (hi, lo) else { panic!() };
/// assert!((x_hi - 1.0).abs() < 1e-12 && x_lo.abs() < 1e-12);
/// ```
pub fn solve_pair(
    lines: &StageLines<'_>,
    bbox: Box2,
    objs: [([f64; 2], [f64; 2]); 2],
    first: [&[usize]; 2],
    tol: &Tolerances,
    stats: &mut Lp2Stats,
) -> [Lp2; 2] {
    let feas = tol.feasibility;
    let feas2 = feas * feas;
    if bbox.u_lo > bbox.u_hi + feas || bbox.x_lo > bbox.x_hi + feas {
        return [Lp2::Infeasible; 2];
    }
    let pick = |lo: f64, hi: f64, ci: f64, ti: f64| {
        if ci > 0.0 || (ci == 0.0 && ti >= 0.0) {
            hi
        } else {
            lo
        }
    };
    let m = lines.len();
    let mut warm = [[0usize; 8]; 2];
    let mut nf = [0usize; 2];
    let mut v: [Vertex; 2] = std::array::from_fn(|p| {
        let (c, t) = objs[p];
        Vertex {
            u: pick(bbox.u_lo, bbox.u_hi, c[0], t[0]),
            x: pick(bbox.x_lo, bbox.x_hi, c[1], t[1]),
            active: [None, None],
        }
    });
    for p in 0..2 {
        for &j in first[p] {
            if j < m && nf[p] < 8 && !warm[p][..nf[p]].contains(&j) {
                warm[p][nf[p]] = j;
                nf[p] += 1;
            }
        }
    }
    let ctx: [Ctx; 2] = std::array::from_fn(|p| Ctx {
        lines,
        bbox,
        c: objs[p].0,
        t: objs[p].1,
        tol,
    });
    for p in 0..2 {
        let warm_p = &warm[p][..nf[p]];
        for (q, &j) in warm_p.iter().enumerate() {
            let r = lines.get(j);
            let val = r.a * v[p].u + r.b * v[p].x + r.c;
            if val > 0.0
                && val * val > feas2 * point_scale2(v[p].u, v[p].x) * (r.a * r.a + r.b * r.b)
            {
                stats.moves += 1;
                if !ctx[p].move_onto(j, &warm_p[..q], None, &mut v[p], stats) {
                    return [Lp2::Infeasible; 2];
                }
            }
        }
    }
    for (seg, &(rows, td, base)) in lines.segments().iter().enumerate() {
        let mut from = 0;
        while let Some(q) = first_violated2(rows, from, td, &v, feas2) {
            for p in 0..2 {
                if first_violated(&rows[..q + 1], q, td, v[p].u, v[p].x, feas2).is_some() {
                    stats.moves += 1;
                    let warm_p = &warm[p][..nf[p]];
                    if !ctx[p].move_onto(base + q, warm_p, Some((seg, q)), &mut v[p], stats) {
                        return [Lp2::Infeasible; 2];
                    }
                }
            }
            from = q + 1;
        }
    }
    v.map(|v| Lp2::Optimal {
        u: v.u,
        x: v.x,
        active: v.active,
    })
}

/// First row of `rows[from..]` violated at either vertex (see [`first_violated`]).
#[inline(always)]
fn first_violated2(
    rows: &[Row],
    from: usize,
    td: f64,
    v: &[Vertex; 2],
    feas2: f64,
) -> Option<usize> {
    if from >= rows.len() {
        return None;
    }
    let (u0, x0) = (v[0].u, v[0].x + td * v[0].u);
    let (u1, x1) = (v[1].u, v[1].x + td * v[1].u);
    let (s0, s1) = (point_scale2(u0, x0), point_scale2(u1, x1));
    let precise = |r: &Row| -> bool {
        let a = r.a + td * r.b;
        let nn = a * a + r.b * r.b;
        let v0 = r.a * u0 + r.b * x0 + r.c;
        let v1 = r.a * u1 + r.b * x1 + r.c;
        (v0 > 0.0 && v0 * v0 > feas2 * s0 * nn) || (v1 > 0.0 && v1 * v1 > feas2 * s1 * nn)
    };
    let mut q = from;
    while q + SCREEN_BLOCK <= rows.len() {
        let block = &rows[q..q + SCREEN_BLOCK];
        let mut any = false;
        for r in block {
            let v0 = r.a * u0 + r.b * x0 + r.c;
            let v1 = r.a * u1 + r.b * x1 + r.c;
            any |= (v0 > 0.0) | (v1 > 0.0);
        }
        if any {
            for (p, r) in block.iter().enumerate() {
                if precise(r) {
                    return Some(q + p);
                }
            }
        }
        q += SCREEN_BLOCK;
    }
    rows[q..].iter().position(precise).map(|p| q + p)
}

struct Vertex {
    u: f64,
    x: f64,
    active: [Option<usize>; 2],
}

struct Ctx<'a, 'b> {
    lines: &'a StageLines<'b>,
    bbox: Box2,
    c: [f64; 2],
    t: [f64; 2],
    tol: &'a Tolerances,
}

/// Running interval `[lo, hi]` of the line parameter, each end kept as a fraction
/// `num / den` with `den > 0` (compared by cross-multiplication: no division per row), with the
/// rows that set its ends.
struct Interval {
    lo: (f64, f64),
    hi: (f64, f64),
    lo_by: Option<usize>,
    hi_by: Option<usize>,
}

impl Interval {
    /// Adds `s tau <= r` (`s != 0`) from row `by`.
    #[inline(always)]
    fn clip(&mut self, s: f64, r: f64, by: Option<usize>) {
        if s > 0.0 {
            if r * self.hi.1 < self.hi.0 * s {
                self.hi = (r, s);
                self.hi_by = by;
            }
        } else if (-r) * self.lo.1 > self.lo.0 * (-s) {
            self.lo = (-r, -s);
            self.lo_by = by;
        }
    }
}

impl Ctx<'_, '_> {
    /// Moves the optimum onto line `jk`, the best point of that line satisfying the box, the
    /// lines `warm_before` and, when `upto = Some((segment, q))`, every line of the segments
    /// before `segment` and of `segment` before position `q`. Returns `false` if infeasible.
    fn move_onto(
        &self,
        jk: usize,
        warm_before: &[usize],
        upto: Option<(usize, usize)>,
        v: &mut Vertex,
        stats: &mut Lp2Stats,
    ) -> bool {
        let tol = self.tol;
        let par2 = tol.parallel * tol.parallel;
        let lk = self.lines.get(jk);
        let nn = lk.a * lk.a + lk.b * lk.b;
        if nn <= tol.zero_row * tol.zero_row * lk.c * lk.c {
            // A violated constant row: c > 0.
            return false;
        }
        // Points of line k: p(tau) = p0 + tau * dir, with p0 = -c n / |n|^2 and dir = (-b, a)
        // (|dir| = |n|: tau is not a distance; tolerances are scaled accordingly).
        let w = -lk.c / nn;
        let (p0u, p0x) = (lk.a * w, lk.b * w);
        let (du, dx) = (-lk.b, lk.a);
        // Slack relative to the size of the points involved (the current optimum).
        let feas = tol.feasibility * point_scale2(v.u, v.x).sqrt();
        let feas2 = feas * feas;
        let mut iv = Interval {
            lo: (f64::NEG_INFINITY, 1.0),
            hi: (f64::INFINITY, 1.0),
            lo_by: None,
            hi_by: None,
        };
        // Box sides as unit rows: u <= u_hi, -u <= -u_lo, x <= x_hi, -x <= -x_lo.
        let b = self.bbox;
        for (sj, rj) in [
            (du, b.u_hi - p0u),
            (-du, p0u - b.u_lo),
            (dx, b.x_hi - p0x),
            (-dx, p0x - b.x_lo),
        ] {
            if sj * sj <= par2 * nn {
                if rj < -feas {
                    return false;
                }
            } else {
                iv.clip(sj, rj, None);
            }
        }
        // One row (a, b, c) at (u, x + td u), global index j.
        let clip = |r: &Row, td: f64, j: usize, iv: &mut Interval| -> bool {
            let a = r.a + td * r.b;
            let sj = a * du + r.b * dx;
            let rj = -r.c - (a * p0u + r.b * p0x);
            let nj = a * a + r.b * r.b;
            if sj * sj <= par2 * nj * nn {
                return !(rj < 0.0 && rj * rj > feas2 * nj);
            }
            iv.clip(sj, rj, Some(j));
            true
        };
        for &j in warm_before {
            stats.inner_steps += 1;
            if !clip(&self.lines.get(j), 0.0, j, &mut iv) {
                return false;
            }
        }
        if let Some((seg, q)) = upto {
            for (s, &(rows, td, base)) in self.lines.segments().iter().enumerate().take(seg + 1) {
                let end = if s == seg { q } else { rows.len() };
                for (p, r) in rows[..end].iter().enumerate() {
                    stats.inner_steps += 1;
                    if !clip(r, td, base + p, &mut iv) {
                        return false;
                    }
                }
            }
        }
        let lo = iv.lo.0 / iv.lo.1;
        let hi = iv.hi.0 / iv.hi.1;
        if lo > hi && (lo - hi) * (lo - hi) * nn > feas2 {
            return false;
        }
        let cd = self.c[0] * du + self.c[1] * dx;
        let td = self.t[0] * du + self.t[1] * dx;
        let up = if cd * cd > par2 * nn {
            cd > 0.0
        } else {
            td >= 0.0
        };
        let (tau, by) = if lo > hi {
            (0.5 * (lo + hi), if up { iv.hi_by } else { iv.lo_by })
        } else if up {
            (hi, iv.hi_by)
        } else {
            (lo, iv.lo_by)
        };
        v.u = p0u + tau * du;
        v.x = p0x + tau * dx;
        v.active = [Some(jk), by];
        true
    }
}
