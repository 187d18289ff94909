//! The exact projection of a lifted polytope onto `(u, x)`, by support functions (the
//! expanding polygon of Bretl and Lall, "Testing static equilibrium for legged robots", IEEE
//! T-RO 2008, here on `(u, x)` instead of the CoM plane).
//!
//! # Math
//!
//! `P = {(u, x) : exists y, a_j u + b_j x + c_j + d_j . y <= 0 for all j}` within a box is a
//! convex polygon. Its support function `h(n) = max {n . (u, x) : (u, x, y) feasible}` is one
//! LP ([`super::lp`]); the maximizer projects to a vertex `v(n)` of `P`. Starting from a few
//! directions (the axes, and the facet normals of the previous grid point's polygon), the
//! vertices found span an inner polygon; for each of its edges `[v_a, v_b]` the support in the
//! edge's outward normal `n` decides: `h(n) <= n . v_a + eps` certifies the edge as a facet of
//! `P` (the outer and inner polygons agree there), otherwise the new vertex `v(n)` splits it.
//! Every certified edge becomes the row `n . (u, x) - h(n) <= 0`; together they are `P` to
//! within `eps` (the facets' support values are exact LP optima, so the rows never cut a
//! feasible point by more than the LP's tolerance).
//!
//! The multipliers of the LP at a facet name the lifted rows that define it
//! ([`Projection::support`]): the caller's joints and contacts behind each row.
//!
//! **Cost.** One LP per vertex and one per facet, each warm-started from the last optimal
//! vertex (a few pivots at most); across grid points the previous facet normals are tried
//! first, so that a polygon that barely moved costs one LP per facet and one per edge check.

use super::lp::{LpStatus, Program, Simplex, MAX_VARS};
use crate::constraints::Row;
use crate::error::ToppError;
use crate::lp2::Box2;

/// Rows `a u + b x + c + d . y <= 0` over `(u, x)` and `k` extra variables `y`, with
/// `|y_i| <= y_bound`, stored with `|(a, b, d)| = 1` (a row and its positive multiple are the
/// same constraint; a row with `a = b = d = 0` is the constant constraint `c <= 0`).
///
/// Stored by columns (`a` of every row, then `b`, `c`, `d_0`, ...): the membership tests
/// evaluate every row at once down contiguous columns.
#[derive(Debug, Clone, Default)]
pub struct LiftedRows {
    k: usize,
    /// Rows stored.
    len: usize,
    /// Rows each column has room for (the columns' stride in `data`).
    cap: usize,
    /// Column `i` (`a, b, c, d_0 .. d_{k-1}`, then the weights: per row `1 / sqrt(|d|^2 + 1)`,
    /// the row's weight in the margin program of [`super::member`], 0 for a constant row) is
    /// `data[i * cap..i * cap + len]` (one block: a side of a sample allocates once).
    data: Vec<f64>,
    /// Bound on every extra variable (in their unit).
    pub y_bound: f64,
}

impl LiftedRows {
    /// No rows, `k` extra variables bounded by `y_bound`.
    ///
    /// ```
    /// let r = stance_topp::lifted::LiftedRows::new(6, 1e3);
    /// assert!(r.is_empty());
    /// ```
    pub fn new(k: usize, y_bound: f64) -> Self {
        Self::with_capacity(k, y_bound, 0)
    }

    /// No rows, room for `rows` of them.
    pub fn with_capacity(k: usize, y_bound: f64, rows: usize) -> Self {
        Self {
            k,
            len: 0,
            cap: rows,
            data: vec![0.0; rows * (4 + k)],
            y_bound,
        }
    }

    /// Removes every row (keeps `k`, the bound and the room).
    pub fn clear(&mut self) {
        self.len = 0;
    }

    /// Number of extra variables.
    pub fn extra(&self) -> usize {
        self.k
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Appends `a u + b x + c + d . y <= 0` (`d` of length `k`), normalized.
    pub fn push(&mut self, a: f64, b: f64, c: f64, d: &[f64]) {
        debug_assert_eq!(d.len(), self.k);
        let dd = d.iter().map(|x| x * x).sum::<f64>();
        let norm = (a * a + b * b + dd).sqrt();
        let (s, w) = if norm > 0.0 && norm.is_finite() {
            (1.0 / norm, 1.0 / (dd / (norm * norm) + 1.0).sqrt())
        } else {
            (1.0, 0.0)
        };
        if self.len == self.cap {
            self.grow();
        }
        let (j, cap) = (self.len, self.cap);
        // a, b, c, d (scaled), then the weight: entry j of each column in turn
        let abc = [a, b, c];
        let values = abc.iter().chain(d).map(|v| v * s).chain([w]);
        for (i, v) in values.enumerate() {
            self.data[i * cap + j] = v;
        }
        self.len += 1;
    }

    /// Doubles the room of every column (at least 8 rows).
    fn grow(&mut self) {
        let cap = (2 * self.cap).max(8);
        let mut data = vec![0.0; cap * (4 + self.k)];
        for i in 0..4 + self.k {
            data[i * cap..i * cap + self.len].copy_from_slice(self.column(i));
        }
        (self.data, self.cap) = (data, cap);
    }

    /// Column `i` of the rows: `a` (0), `b` (1), `c` (2), then `d_0 .. d_{k-1}` (and the
    /// margin program's weights at `3 + k`).
    #[inline]
    pub fn column(&self, i: usize) -> &[f64] {
        &self.data[i * self.cap..i * self.cap + self.len]
    }

    /// Every row's weight `1 / sqrt(|d|^2 + 1)` in the margin program (0 for a row with
    /// `a = b = d = 0`, a constant).
    #[inline]
    pub(crate) fn weights(&self) -> &[f64] {
        self.column(3 + self.k)
    }

    /// Row `j`'s `(a, b, c)` (panics when there is no row `j`).
    #[inline]
    pub fn abc(&self, j: usize) -> (f64, f64, f64) {
        (self.column(0)[j], self.column(1)[j], self.column(2)[j])
    }

    /// Row `j`'s coefficient of `y_i` (panics when there is no row `j` or no `y_i`).
    #[inline]
    pub fn d(&self, j: usize, i: usize) -> f64 {
        assert!(i < self.k, "y_{i} of {} extra variables", self.k);
        self.column(3 + i)[j]
    }

    /// Row `j` as `(a, b, c, d)`.
    pub fn row(&self, j: usize) -> (f64, f64, f64, Vec<f64>) {
        let (a, b, c) = self.abc(j);
        (a, b, c, (0..self.k).map(|i| self.d(j, i)).collect())
    }
}

/// The projection of a grid point's lifted rows.
#[derive(Debug, Clone, Default)]
pub struct Projection {
    /// The facets as rows `a u + b x + c <= 0` (unit `(a, b)`); empty when the polygon is the
    /// whole box (no row binds) and `[0 u + 0 x + 1 <= 0]` when it is empty.
    pub rows: Vec<Row>,
    /// For each row, the lifted rows with a positive multiplier at its facet (sorted).
    pub support: Vec<Vec<usize>>,
    /// No `(u, x)` in the box admits a `y`.
    pub empty: bool,
    /// Some facet rests on the bound of the extra variables (the projection may then be
    /// smaller than the unbounded one).
    pub y_bound_active: bool,
    /// LPs solved.
    pub lps: usize,
    /// Simplex pivots.
    pub pivots: usize,
}

/// A direction of the expanding polygon and what its LP found.
#[derive(Debug, Clone)]
struct Dir {
    n: [f64; 2],
    angle: f64,
    v: [f64; 2],
    h: f64,
    active: Vec<usize>,
    lambda: Vec<f64>,
    /// The edge to the next direction's vertex is certified (or empty).
    edge_done: bool,
}

/// Reusable state of [`Projector::project`]: the LP, and the previous polygon's facet normals
/// (the warm start of the next grid point).
#[derive(Debug, Clone, Default)]
pub struct Projector {
    program: Program,
    /// The program's rows, row-major, as they are read.
    rows_g: Vec<f64>,
    simplex: Simplex,
    previous: Vec<[f64; 2]>,
    dirs: Vec<Dir>,
}

/// Largest number of LPs one projection may solve before it gives up (a guard: polygons
/// have tens of vertices).
const MAX_LPS: usize = 400;

impl Projector {
    /// An empty projector.
    pub fn new() -> Self {
        Self::default()
    }

    /// Forgets the warm start (for a new sequence of grid points).
    pub fn reset(&mut self) {
        self.previous.clear();
    }

    /// Projects `rows` onto `(u, x)` within `bbox` (module doc) into `out`. `eps` is the
    /// certification tolerance in the units of `(u, x)`, relative to the polygon's size.
    ///
    /// # Errors
    ///
    /// [`ToppError::InvalidValue`] for more than [`MAX_VARS`]` - 2` extra variables, a
    /// non-finite coefficient, or an LP that failed (iteration cap or a singular basis).
    ///
    /// ```
    /// use stance_topp::lifted::{LiftedRows, Projection, Projector};
    /// use stance_topp::lp2::Box2;
    /// // |u - y| <= 1, |y| <= 2  ->  |u| <= 3
    /// let mut r = LiftedRows::new(1, 10.0);
    /// r.push(1.0, 0.0, -1.0, &[-1.0]);
    /// r.push(-1.0, 0.0, -1.0, &[1.0]);
    /// r.push(0.0, 0.0, -2.0, &[1.0]);
    /// r.push(0.0, 0.0, -2.0, &[-1.0]);
    /// let bbox = Box2 { u_lo: -10.0, u_hi: 10.0, x_lo: 0.0, x_hi: 5.0 };
    /// let mut out = Projection::default();
    /// Projector::new().project(&r, bbox, 1e-9, &mut out).unwrap();
    /// let u_max = out.rows.iter().filter(|r| r.a > 0.5).map(|r| -r.c / r.a).fold(f64::INFINITY, f64::min);
    /// assert!((u_max - 3.0).abs() < 1e-9);
    /// ```
    pub fn project(
        &mut self,
        rows: &LiftedRows,
        bbox: Box2,
        eps: f64,
        out: &mut Projection,
    ) -> Result<(), ToppError> {
        out.rows.clear();
        out.support.clear();
        out.empty = false;
        out.y_bound_active = false;
        out.lps = 0;
        out.pivots = 0;
        let k = rows.extra();
        if 2 + k + 1 > MAX_VARS {
            return Err(ToppError::InvalidValue {
                what: "lifted rows",
                detail: format!(
                    "{k} extra variables; at most {} are supported",
                    MAX_VARS - 2
                ),
            });
        }
        let Some(index) = self.load_program(rows, bbox, out)? else {
            return Ok(());
        };
        let Some(axes) = self.initial_polygon(out)? else {
            return Ok(());
        };
        let size = (bbox.u_hi - bbox.u_lo)
            .abs()
            .max((bbox.x_hi - bbox.x_lo).abs())
            .max(1e-300);
        let facets = self.expand(eps * size, out)?;
        self.write_rows(facets, axes, &index, out);
        Ok(())
    }

    /// The LP's constraints: the lifted rows as unit rows `g . (u, x, y) <= h` (rows with
    /// `a = b = d = 0` are constants, skipped when they hold), and the box on `(u, x)` and
    /// the bound on `y` as variable bounds. Returns the lifted row of each program row;
    /// `None` when a constant row is violated (nothing is feasible: `out` says so, the row as
    /// its support).
    fn load_program(
        &mut self,
        rows: &LiftedRows,
        bbox: Box2,
        out: &mut Projection,
    ) -> Result<Option<Vec<usize>>, ToppError> {
        let k = rows.extra();
        let p = &mut self.program;
        p.n = 2 + k;
        let g = &mut self.rows_g;
        g.clear();
        p.h.clear();
        for j in 0..rows.len() {
            let (a, b, c) = rows.abc(j);
            let d = (0..k).map(|i| rows.d(j, i));
            let norm = (a * a + b * b + d.clone().map(|x| x * x).sum::<f64>()).sqrt();
            if !norm.is_finite() || !c.is_finite() {
                return Err(ToppError::NotFinite {
                    what: "lifted row",
                    point: 0,
                    row: j,
                    value: if c.is_finite() { norm } else { c },
                });
            }
            if norm == 0.0 {
                if c > 0.0 {
                    // a violated constant row: nothing is feasible
                    out.empty = true;
                    out.rows.push(Row {
                        a: 0.0,
                        b: 0.0,
                        c: 1.0,
                    });
                    out.support.push(vec![j]);
                    return Ok(None);
                }
                continue;
            }
            g.push(a / norm);
            g.push(b / norm);
            g.extend(d.map(|x| x / norm));
            p.h.push(-c / norm);
        }
        p.set_rows(g);
        // rows of zero norm were skipped: map program rows back to lifted rows
        let mut index = Vec::with_capacity(p.h.len());
        for j in 0..rows.len() {
            let (a, b, _) = rows.abc(j);
            if a != 0.0 || b != 0.0 || (0..k).any(|i| rows.d(j, i) != 0.0) {
                index.push(j);
            }
        }
        p.lo.clear();
        p.hi.clear();
        p.lo.extend_from_slice(&[bbox.u_lo, bbox.x_lo]);
        p.hi.extend_from_slice(&[bbox.u_hi, bbox.x_hi]);
        p.lo.extend(std::iter::repeat_n(-rows.y_bound, k));
        p.hi.extend(std::iter::repeat_n(rows.y_bound, k));
        Ok(Some(index))
    }

    /// The first vertices of the inner polygon, into `self.dirs`: the supports in the
    /// directions of the axes and of the previous polygon's facet normals. Returns the four
    /// axis directions (their supporting lines become rows too); `None` when the LP is
    /// infeasible (the projection is empty: `out` says so, and the warm start is forgotten).
    fn initial_polygon(&mut self, out: &mut Projection) -> Result<Option<Vec<Dir>>, ToppError> {
        let mut initial: Vec<[f64; 2]> = vec![[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]];
        initial.extend(self.previous.iter().copied());
        self.dirs.clear();
        let mut axes: Vec<Dir> = Vec::with_capacity(4);
        for (q, nrm) in initial.into_iter().enumerate() {
            match self.support(nrm, out)? {
                Some(d) => {
                    if q < 4 {
                        axes.push(d.clone());
                    }
                    self.insert(d);
                }
                None => {
                    out.empty = true;
                    out.rows.push(Row {
                        a: 0.0,
                        b: 0.0,
                        c: 1.0,
                    });
                    out.support.push(Vec::new());
                    self.previous.clear();
                    return Ok(None);
                }
            }
        }
        Ok(Some(axes))
    }

    /// The expansion of the module doc: every edge `[v_a, v_b]` of the inner polygon (from each
    /// direction's vertex to the next one's, cyclically) is certified, `h(n) <= n . v_a + tol`
    /// in its outward normal `n` (a facet, returned), or split by the new vertex `v(n)`,
    /// sweeping until every edge is done. Edges shorter than `tol` are done as they are.
    fn expand(&mut self, tol: f64, out: &mut Projection) -> Result<Vec<Dir>, ToppError> {
        let mut facets: Vec<Dir> = Vec::new();
        while let Some(i) = self.dirs.iter().position(|d| !d.edge_done) {
            if out.lps > MAX_LPS {
                return Err(ToppError::InvalidValue {
                    what: "lifted rows",
                    detail: format!(
                        "the projection onto (u, x) did not converge in {MAX_LPS} LPs; \
                         report this input"
                    ),
                });
            }
            let j = (i + 1) % self.dirs.len();
            let (va, vb) = (self.dirs[i].v, self.dirs[j].v);
            let e = [vb[0] - va[0], vb[1] - va[1]];
            let len = e[0].hypot(e[1]);
            if len <= tol || self.dirs.len() == 1 {
                self.dirs[i].edge_done = true;
                continue;
            }
            let nrm = [e[1] / len, -e[0] / len];
            let on_edge = nrm[0] * va[0] + nrm[1] * va[1];
            let Some(d) = self.support(nrm, out)? else {
                return Err(ToppError::InvalidValue {
                    what: "lifted rows",
                    detail: "an LP became infeasible during the projection; report this input"
                        .into(),
                });
            };
            if d.h <= on_edge + tol {
                self.dirs[i].edge_done = true;
                facets.push(d);
            } else if self.insert(d).is_none() {
                // the direction was already there (an angle tie): the edge stays as found
                self.dirs[i].edge_done = true;
            }
        }
        Ok(facets)
    }

    /// The rows `n . (u, x) - h(n) <= 0` of the facets, and the supporting lines of the axes
    /// (they bound a polygon that is a segment or a point, and cost nothing otherwise), each
    /// with its support: the lifted rows (through `index`) with a positive multiplier at the
    /// LP's optimum; a positive multiplier on a bound of `y` sets
    /// [`Projection::y_bound_active`]. The facet normals are the next warm start.
    fn write_rows(
        &mut self,
        facets: Vec<Dir>,
        axes: Vec<Dir>,
        index: &[usize],
        out: &mut Projection,
    ) {
        let previous: Vec<[f64; 2]> = facets.iter().map(|d| d.n).collect();
        for d in facets.into_iter().chain(axes) {
            out.rows.push(Row {
                a: d.n[0],
                b: d.n[1],
                c: -d.h,
            });
            let mut sup: Vec<usize> = d
                .active
                .iter()
                .zip(&d.lambda)
                .filter(|(&a, &l)| a < index.len() && l > 1e-12)
                .map(|(&a, _)| index[a])
                .collect();
            if d.active
                .iter()
                .zip(&d.lambda)
                .any(|(&a, &l)| a >= index.len() + 4 && l > 1e-12)
            {
                out.y_bound_active = true;
            }
            sup.sort_unstable();
            out.support.push(sup);
        }
        self.previous = previous;
    }

    /// The LP in direction `nrm`: `Some` vertex and support, `None` when infeasible.
    fn support(&mut self, nrm: [f64; 2], out: &mut Projection) -> Result<Option<Dir>, ToppError> {
        let n = self.program.n;
        let mut c = vec![0.0; n];
        c[0] = nrm[0];
        c[1] = nrm[1];
        let before = self.simplex.pivots;
        let status = self.simplex.solve_or_retry(&self.program, &c);
        out.lps += 1;
        out.pivots += self.simplex.pivots - before;
        match status {
            LpStatus::Optimal => {
                let v = [self.simplex.v[0], self.simplex.v[1]];
                Ok(Some(Dir {
                    n: nrm,
                    angle: nrm[1].atan2(nrm[0]),
                    v,
                    h: nrm[0] * v[0] + nrm[1] * v[1],
                    active: self.simplex.active.clone(),
                    lambda: self.simplex.lambda.clone(),
                    edge_done: false,
                }))
            }
            LpStatus::Infeasible => Ok(None),
            LpStatus::Failed => Err(ToppError::InvalidValue {
                what: "lifted rows",
                detail: "the LP of the projection onto (u, x) failed (singular or cycling); \
                         report this input"
                    .into(),
            }),
        }
    }

    /// Inserts a direction in angular order and returns its position; `None` when one with
    /// (nearly) the same angle is there already. The edge that ended at its predecessor's
    /// next vertex is open again.
    fn insert(&mut self, d: Dir) -> Option<usize> {
        let pos = self.dirs.partition_point(|x| x.angle < d.angle);
        let near = |x: &Dir| (x.angle - d.angle).abs() < 1e-12;
        if self.dirs.get(pos).is_some_and(near)
            || pos > 0 && self.dirs.get(pos - 1).is_some_and(near)
        {
            return None;
        }
        self.dirs.insert(pos, d);
        let before = (pos + self.dirs.len() - 1) % self.dirs.len();
        self.dirs[before].edge_done = false;
        Some(pos)
    }
}

#[cfg(test)]
mod tests {
    use super::LiftedRows;

    /// The columns hold what was pushed, normalized, whatever the room given at the start (the
    /// columns grow by copies) and after a clear.
    #[test]
    fn rows_by_columns_keep_what_was_pushed() {
        let row = |j: usize| {
            let f = j as f64;
            (f - 3.0, 0.5 * f, -1.0 - f, [f.sin(), 2.0, -f])
        };
        for room in [0, 1, 7, 40] {
            let mut r = LiftedRows::with_capacity(3, 9.0, room);
            for pass in 0..2 {
                r.clear();
                for j in 0..19 {
                    let (a, b, c, d) = row(j);
                    r.push(a, b, c, &d);
                }
                assert_eq!(r.len(), 19, "room {room}, pass {pass}");
                for j in 0..19 {
                    let (a, b, c, d) = row(j);
                    let s = (a * a + b * b + d.iter().map(|x| x * x).sum::<f64>()).sqrt();
                    let (ga, gb, gc, gd) = r.row(j);
                    let near = |got: f64, want: f64| (got - want / s).abs() <= 1e-15 * want.abs();
                    assert!(near(ga, a) && near(gb, b) && near(gc, c), "row {j}");
                    assert_eq!(r.column(2)[j], gc);
                    for i in 0..3 {
                        assert!(near(gd[i], d[i]), "row {j}");
                        assert_eq!(r.column(3 + i)[j], gd[i]);
                        assert_eq!(r.d(j, i), gd[i]);
                    }
                    // the weight 1 / sqrt(|d|^2 + 1) of the unit row
                    let dd = d.iter().map(|x| x * x).sum::<f64>() / (s * s);
                    let w = r.weights()[j];
                    assert!((w - 1.0 / (dd + 1.0).sqrt()).abs() <= 1e-15, "row {j}: {w}");
                }
                assert_eq!(r.weights().len(), 19);
            }
        }
    }
}
