//! Whether a state `(u, x)` admits extra variables `y` satisfying lifted rows: a witness `y`
//! is tried first (the rows evaluated at it), then a linear program finds the `y` of largest
//! margin, which becomes the next witness.
//!
//! # Math
//!
//! With every row normalized, `r_j = (a_j, b_j, d_j) / |(a_j, b_j, d_j)|`, the state is
//! admissible when some `y` in the box has `a_j u + b_j x + c_j + d_j . y <= 0` for all `j`.
//! The program `maximize t subject to d_j . y + t <= -(a_j u + b_j x + c_j)` (rows normalized
//! again with their `t` column) gives the `y` whose smallest slack `t` is largest: the state is
//! admissible when `t >= -eps`, and that `y`, being central, stays a witness for nearby states
//! (the next grid point, the next check), so most checks cost one evaluation of the rows.
//! A positive answer is always certified by a witness evaluated in the rows themselves.
//!
//! **Cuts.** A state that is not admissible is separated from those that are by the dual of
//! the program. Write its rows `g_j . (y, t) <= h_j(u, x)` with
//! `h_j = -(a_j u + b_j x + c_j) / (|r_j| s_j)` and the box as rows of constant right-hand
//! side. At the optimum the active rows' multipliers `lambda >= 0` give `e_t = G_A^T lambda`,
//! so for any `(u, x)` and any feasible `(y, t)`, `t <= phi(u, x) = lambda . h_A(u, x)` (weak
//! duality), with equality at the state tested: `phi(u_0, x_0) = t* < 0`. An admissible state
//! has a feasible `(y, 0)`, hence `phi >= 0`: the row `-phi(u, x) <= 0`, linear in `(u, x)`,
//! holds at every admissible state and is violated by `-t*` at the tested one. It is the
//! tangent plane of the concave margin function `t*(u, x)` at that state (Kelley's cutting
//! plane): where the state lies on the same piece of `t*` as the boundary of the projection,
//! it is a facet of the projection.

use super::lp::{LpStatus, Program, Simplex, MAX_VARS};
use super::project::LiftedRows;
use crate::constraints::Row;
use crate::error::ToppError;

/// Reusable state of [`Membership::contains`].
#[derive(Debug, Clone, Default)]
pub struct Membership {
    program: Program,
    simplex: Simplex,
    c: Vec<f64>,
    /// The witnesses found last, whatever the polytope (tried after the caller's: neighbouring
    /// grid points along a path share their forces).
    recent: Witnesses,
    /// Lifted row and weight `1 / (|r| s)` of each row of the program.
    map: Vec<(usize, f64)>,
    /// Programs solved (the witnesses failed).
    pub lps: usize,
    /// Checks answered by the witness alone.
    pub witnessed: usize,
}

/// Contact-force witnesses of one lifted polytope: the `y` of the admissible states checked
/// last, the most recently useful first (at most [`MAX_WITNESSES`]). Along a path the same
/// polytope is asked about a few different states (the two ends of a controllable set, the
/// forward pass's state): one witness each.
///
/// Each witness keeps the state it was checked at and its smallest slack there, `sigma`: the
/// rows are unit in `(u, x, y)`, so `|(a, b)| <= 1` and the witness holds at every state within
/// `sigma` of that one without evaluating the rows.
#[derive(Debug, Clone, Default)]
pub struct Witnesses {
    ws: Vec<Witness>,
    /// The row that rejected a witness last (tried first: a witness that fails usually fails
    /// there).
    hint: usize,
    /// The margin program's optimal active set where it last gave a cut: the next state asked
    /// about lies on that cut, usually on the same piece of the margin function, where the same
    /// active set is optimal.
    cut_basis: Vec<usize>,
}

#[derive(Debug, Clone)]
struct Witness {
    y: Vec<f64>,
    at: [f64; 2],
    slack: f64,
}

/// Witnesses kept per polytope. Default 12: the retiming of the box climbing (its first solve
/// and the refinement's) asks each lifted side about 29 states, many of them again; with 4
/// witnesses, 2104 of the 5444 margin programs that found a state admissible were about a state
/// accepted before, and with 12 the programs are 2782 in all (the oracle's time in the first
/// solve, medians of 20 runs in three rounds: 6.7-7.4 -> 6.4-6.7 ms; the hand on the wall's
/// 11.1-11.5 -> 8.2-8.8 ms).
pub const MAX_WITNESSES: usize = 12;

impl Witnesses {
    /// None yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// The most recently useful witness.
    ///
    /// ```
    /// assert!(stance_topp::lifted::Witnesses::new().first().is_none());
    /// ```
    pub fn first(&self) -> Option<&[f64]> {
        self.ws.first().map(|w| w.y.as_slice())
    }

    /// Whether one of them holds at `(u, x)` (it moves to the front), with a lower bound of its
    /// smallest slack there. `own`: these are the polytope's own witnesses (else a workspace's
    /// recent ones, of any polytope: their anchors say nothing here, and those of another size
    /// never hold). `hint`: the row tried first, updated to the row that rejected the last
    /// witness.
    fn find(
        &mut self,
        rows: &LiftedRows,
        u: f64,
        x: f64,
        hint: &mut usize,
        own: bool,
    ) -> Option<f64> {
        if own {
            let dist = |w: &Witness| (u - w.at[0]).hypot(x - w.at[1]);
            if let Some(i) = self.ws.iter().position(|w| dist(w) < w.slack) {
                let bound = self.ws[i].slack - dist(&self.ws[i]);
                self.ws[..=i].rotate_right(1);
                return Some(bound);
            }
        }
        for i in 0..self.ws.len() {
            match scan(rows, u, x, &self.ws[i].y, *hint) {
                Ok(slack) => {
                    let w = &mut self.ws[i];
                    // re-anchored where the slack is larger
                    if own && slack > w.slack {
                        (w.at, w.slack) = ([u, x], slack);
                    }
                    self.ws[..=i].rotate_right(1);
                    return Some(slack);
                }
                Err(j) => *hint = j,
            }
        }
        None
    }

    /// Adds `y`, which holds at `(u, x)` with smallest slack `slack`, in front (the oldest goes
    /// beyond [`MAX_WITNESSES`]).
    fn remember(&mut self, y: &[f64], at: [f64; 2], slack: f64) {
        if self.ws.len() < MAX_WITNESSES {
            self.ws.push(Witness {
                y: y.to_vec(),
                at,
                slack,
            });
        } else {
            let last = self.ws.last_mut().expect("full");
            last.y.clear();
            last.y.extend_from_slice(y);
            (last.at, last.slack) = (at, slack);
        }
        self.ws.rotate_right(1);
    }
}

/// The rows at `(u, x, y)`, row `hint` first: `Ok(smallest slack)` (0 where a row holds only
/// within the tolerance) when every row holds within the tolerance, else `Err(a violated
/// row)`. A `y` of the wrong length violates row 0.
fn scan(rows: &LiftedRows, u: f64, x: f64, y: &[f64], hint: usize) -> Result<f64, usize> {
    if y.len() != rows.extra() {
        return Err(0);
    }
    let scale = y
        .iter()
        .fold(u.abs().max(x.abs()).max(1.0), |a, v| a.max(v.abs()));
    let lim = EPS * scale;
    if hint < rows.len() {
        let (a, b, c) = rows.abc(hint);
        let mut v = a * u + b * x + c;
        for (i, yi) in y.iter().enumerate() {
            v += rows.d(hint, i) * yi;
        }
        if v > lim {
            return Err(hint);
        }
    }
    // the rows in blocks, each evaluated down the columns (the same sums, in the same order,
    // as row by row)
    let mut slack = f64::INFINITY;
    let mut values = [0.0; SCAN_BLOCK];
    let (ca, cb, cc) = (rows.column(0), rows.column(1), rows.column(2));
    for start in (0..rows.len()).step_by(SCAN_BLOCK) {
        let end = (start + SCAN_BLOCK).min(rows.len());
        let vals = &mut values[..end - start];
        for (v, ((a, b), c)) in vals.iter_mut().zip(
            ca[start..end]
                .iter()
                .zip(&cb[start..end])
                .zip(&cc[start..end]),
        ) {
            *v = a * u + b * x + c;
        }
        for (i, &yi) in y.iter().enumerate() {
            for (v, d) in vals.iter_mut().zip(&rows.column(3 + i)[start..end]) {
                *v += d * yi;
            }
        }
        // the largest value, in lanes (NaN never wins: as `f64::min` ignores it)
        let mut lanes = [f64::NEG_INFINITY; 4];
        let mut quads = vals.chunks_exact(4);
        for q in quads.by_ref() {
            for (l, &v) in lanes.iter_mut().zip(q) {
                if v > *l {
                    *l = v;
                }
            }
        }
        for (l, &v) in lanes.iter_mut().zip(quads.remainder()) {
            if v > *l {
                *l = v;
            }
        }
        let largest = lanes
            .into_iter()
            .fold(f64::NEG_INFINITY, |a, v| if v > a { v } else { a });
        let violated = if largest > lim {
            vals.iter().position(|&v| v > lim)
        } else {
            None
        };
        if let Some(j) = violated {
            return Err(start + j);
        }
        slack = slack.min(-largest);
    }
    Ok(slack.max(0.0))
}

/// Rows evaluated at once by [`scan`] (a block on the stack).
const SCAN_BLOCK: usize = 16;

/// A row in `(u, x)` valid for every admissible state ([`Membership::separate`]).
#[derive(Debug, Clone, PartialEq)]
pub struct LiftedCut {
    /// `a u + b x + c <= 0`.
    pub row: Row,
    /// The lifted rows it combines, with their weights, largest first.
    pub support: Vec<(usize, f64)>,
}

/// The margin program's outcome.
enum Margin {
    /// Solved: the largest margin `t` (the optimum is in the simplex).
    Solved(f64),
    /// No extra variables: the rows are in `(u, x)` already.
    NoExtra,
    /// Row `j` is `c <= 0` with `c > 0`: nothing is admissible.
    ConstantRow(usize),
}

/// Relative tolerance of a row at a state: `value <= EPS |row| max(1, |(u, x, y)|)`.
const EPS: f64 = 1e-9;

/// Largest margin the program looks for (in the rows' normalized units): far beyond any state.
const MAX_MARGIN: f64 = 1e12;

impl Membership {
    /// An empty workspace.
    pub fn new() -> Self {
        Self::default()
    }

    /// Simplex pivots of the programs solved so far.
    pub fn pivots(&self) -> usize {
        self.simplex.pivots
    }

    /// Whether every row holds at `(u, x, y)` (within the tolerance; the rows are unit).
    pub fn holds_at(rows: &LiftedRows, u: f64, x: f64, y: &[f64]) -> bool {
        scan(rows, u, x, y, 0).is_ok()
    }

    /// Whether `(u, x)` admits a `y` with `|y_i| <= rows.y_bound` (module doc): the
    /// `witnesses` are tried first, then the ones this workspace found last, then the
    /// margin program, whose `y` joins the witnesses when it holds.
    ///
    /// # Errors
    ///
    /// [`ToppError::InvalidValue`] when the program fails (a guard).
    ///
    /// ```
    /// use stance_topp::lifted::{LiftedRows, Membership, Witnesses};
    /// // |u - y| <= 1, |y| <= 2: u in [-3, 3]
    /// let mut r = LiftedRows::new(1, 10.0);
    /// r.push(1.0, 0.0, -1.0, &[-1.0]);
    /// r.push(-1.0, 0.0, -1.0, &[1.0]);
    /// r.push(0.0, 0.0, -2.0, &[1.0]);
    /// r.push(0.0, 0.0, -2.0, &[-1.0]);
    /// let (mut m, mut w) = (Membership::new(), Witnesses::new());
    /// assert!(m.contains(&r, 2.9, 1.0, &mut w).unwrap());
    /// assert!(!m.contains(&r, 3.1, 1.0, &mut w).unwrap());
    /// ```
    pub fn contains(
        &mut self,
        rows: &LiftedRows,
        u: f64,
        x: f64,
        witnesses: &mut Witnesses,
    ) -> Result<bool, ToppError> {
        if self.witnessed(rows, u, x, witnesses) {
            return Ok(true);
        }
        match self.max_margin(rows, u, x, &mut witnesses.cut_basis)? {
            Margin::Solved(_) => Ok(self.keep_witness(rows, u, x, witnesses)),
            Margin::NoExtra | Margin::ConstantRow(_) => Ok(false),
        }
    }

    /// Whether a known witness holds at `(u, x)` (the caller's, then the workspace's recent
    /// ones).
    fn witnessed(&mut self, rows: &LiftedRows, u: f64, x: f64, w: &mut Witnesses) -> bool {
        if rows.extra() == 0 {
            return Self::holds_at(rows, u, x, &[]);
        }
        let mut hint = w.hint;
        let found = w.find(rows, u, x, &mut hint, true);
        w.hint = hint;
        if found.is_some() {
            self.witnessed += 1;
            return true;
        }
        if let Some(slack) = self.recent.find(rows, u, x, &mut w.hint, false) {
            self.witnessed += 1;
            w.remember(&self.recent.ws[0].y, [u, x], slack);
            return true;
        }
        false
    }

    /// Whether the margin program's `y` holds at `(u, x)`; if so it joins the witnesses.
    fn keep_witness(&mut self, rows: &LiftedRows, u: f64, x: f64, w: &mut Witnesses) -> bool {
        let y = &self.simplex.v[..rows.extra()];
        match scan(rows, u, x, y, 0) {
            Ok(slack) => {
                w.remember(y, [u, x], slack);
                self.recent.remember(y, [u, x], slack);
                true
            }
            Err(_) => false,
        }
    }

    /// [`Membership::contains`] that, when `(u, x)` is not admissible, returns a row in `(u, x)`
    /// that every admissible state satisfies and `(u, x)` violates (module doc: the dual of the
    /// margin program), with the lifted rows behind it by weight, largest first. `None` when
    /// `(u, x)` is admissible: a witness holds, or the largest margin is at least
    /// `-EPS max(1, |u|, |x|)`.
    ///
    /// # Errors
    ///
    /// As [`Membership::contains`].
    ///
    /// ```
    /// use stance_topp::lifted::{LiftedRows, Membership};
    /// // |u - y| <= 1, |y| <= 2: u in [-3, 3]; at u = 4 the cut is u <= 3 (up to a factor)
    /// let mut r = LiftedRows::new(1, 10.0);
    /// r.push(1.0, 0.0, -1.0, &[-1.0]);
    /// r.push(-1.0, 0.0, -1.0, &[1.0]);
    /// r.push(0.0, 0.0, -2.0, &[1.0]);
    /// r.push(0.0, 0.0, -2.0, &[-1.0]);
    /// let (mut m, mut w) = (Membership::new(), stance_topp::lifted::Witnesses::new());
    /// assert!(m.separate(&r, 2.9, 1.0, &mut w).unwrap().is_none());
    /// let cut = m.separate(&r, 4.0, 1.0, &mut w).unwrap().unwrap();
    /// let (a, b, c) = (cut.row.a, cut.row.b, cut.row.c);
    /// assert!(a > 0.0 && b.abs() < 1e-12 && (c / a + 3.0).abs() < 1e-12);
    /// assert_eq!(cut.support[0].0, 0); // u - y <= 1 first
    /// ```
    pub fn separate(
        &mut self,
        rows: &LiftedRows,
        u: f64,
        x: f64,
        witnesses: &mut Witnesses,
    ) -> Result<Option<LiftedCut>, ToppError> {
        if self.witnessed(rows, u, x, witnesses) {
            return Ok(None);
        }
        let scale = u.abs().max(x.abs()).max(1.0);
        match self.max_margin(rows, u, x, &mut witnesses.cut_basis)? {
            Margin::NoExtra => {
                // the most violated row is the cut
                let mut best = (EPS * scale, None);
                for j in 0..rows.len() {
                    let (a, b, c) = rows.abc(j);
                    let v = a * u + b * x + c;
                    if v > best.0 {
                        best = (v, Some(j));
                    }
                }
                Ok(best.1.map(|j| {
                    let (a, b, c) = rows.abc(j);
                    LiftedCut {
                        row: Row { a, b, c },
                        support: vec![(j, 1.0)],
                    }
                }))
            }
            Margin::ConstantRow(j) => Ok(Some(LiftedCut {
                row: Row {
                    a: 0.0,
                    b: 0.0,
                    c: rows.abc(j).2,
                },
                support: vec![(j, 1.0)],
            })),
            Margin::Solved(t) => {
                if self.keep_witness(rows, u, x, witnesses) || t >= -EPS * scale {
                    return Ok(None);
                }
                witnesses.cut_basis.clone_from(&self.simplex.active);
                Ok(Some(self.dual_cut(rows)))
            }
        }
    }

    /// The cut of the margin program's optimum (module doc): with the multipliers `lambda >= 0`
    /// of its active rows, `sum_rows lambda (a u + b x + c) / (|r| s) - sum_bounds lambda rhs
    /// <= 0` (negative multipliers, within the simplex's tolerance, are dropped and their
    /// effect bounded by the box).
    fn dual_cut(&self, rows: &LiftedRows) -> LiftedCut {
        let p = &self.program;
        let m = p.m();
        let mut row = Row {
            a: 0.0,
            b: 0.0,
            c: 0.0,
        };
        let mut dropped = 0.0;
        let mut support = Vec::new();
        for (&j, &l) in self.simplex.active.iter().zip(&self.simplex.lambda) {
            if l <= 0.0 {
                dropped -= l;
                continue;
            }
            if j < m {
                let (r, w) = self.map[j];
                let (a, b, c) = rows.abc(r);
                let f = l * w;
                row.a += f * a;
                row.b += f * b;
                row.c += f * c;
                support.push((r, f));
            } else {
                let b = j - m;
                let rhs = if b.is_multiple_of(2) {
                    p.hi[b / 2]
                } else {
                    -p.lo[b / 2]
                };
                row.c -= l * rhs;
            }
        }
        // |g . v| <= |v| <= sqrt(k) y_bound at t = 0 for a dropped (unit) row
        row.c -= dropped * (rows.extra() as f64).sqrt() * rows.y_bound;
        support.sort_by(|a, b| b.1.total_cmp(&a.1));
        LiftedCut { row, support }
    }

    /// Solves the margin program at `(u, x)` (module doc) from `start` when given (taken: the
    /// active set where these rows last gave a cut), else from the last program's optimal
    /// active set (the neighbouring grid point's, usually: the same rows in the same order,
    /// moved a little); the optimum stays in the simplex.
    fn max_margin(
        &mut self,
        rows: &LiftedRows,
        u: f64,
        x: f64,
        start: &mut Vec<usize>,
    ) -> Result<Margin, ToppError> {
        let k = rows.extra();
        if k == 0 {
            return Ok(Margin::NoExtra);
        }
        if k + 1 > MAX_VARS {
            return Err(ToppError::InvalidValue {
                what: "lifted rows",
                detail: format!(
                    "{k} extra variables; at most {} are supported",
                    MAX_VARS - 1
                ),
            });
        }
        // maximize t over (y, t): (d_j . y + t) / s_j <= -(a_j u + b_j x + c_j) / s_j
        let p = &mut self.program;
        p.n = k + 1;
        self.map.clear();
        for (j, &w) in rows.weights().iter().enumerate() {
            // (the rows are unit in (a, b, d): the weight is 1 / s_j)
            if w == 0.0 {
                if rows.abc(j).2 > 0.0 {
                    return Ok(Margin::ConstantRow(j));
                }
                continue;
            }
            self.map.push((j, w));
        }
        // G by columns: d_j w_j, then w_j (the t column); h_j = -(a_j u + b_j x + c_j) w_j
        let m = self.map.len();
        p.g.clear();
        p.h.clear();
        if m == rows.len() {
            // (no constant row: the columns as they are stored)
            let w = rows.weights();
            for i in 0..k {
                p.g.extend(rows.column(3 + i).iter().zip(w).map(|(v, w)| v * w));
            }
            p.g.extend_from_slice(w);
            let (ca, cb, cc) = (rows.column(0), rows.column(1), rows.column(2));
            p.h.extend(
                ca.iter()
                    .zip(cb)
                    .zip(cc)
                    .zip(w)
                    .map(|(((a, b), c), w)| -(a * u + b * x + c) * w),
            );
        } else {
            p.g.resize(m * (k + 1), 0.0);
            for (i, &(j, w)) in self.map.iter().enumerate() {
                let (a, b, c) = rows.abc(j);
                for kk in 0..k {
                    p.g[kk * m + i] = rows.d(j, kk) * w;
                }
                p.g[k * m + i] = w;
                p.h.push(-(a * u + b * x + c) * w);
            }
        }
        p.lo.clear();
        p.hi.clear();
        p.lo.extend(std::iter::repeat_n(-rows.y_bound, k));
        p.hi.extend(std::iter::repeat_n(rows.y_bound, k));
        p.lo.push(-MAX_MARGIN);
        p.hi.push(MAX_MARGIN);
        self.c.clear();
        self.c.resize(k + 1, 0.0);
        self.c[k] = 1.0;
        self.lps += 1;
        if start.len() == k + 1 {
            std::mem::swap(&mut self.simplex.active, start);
        }
        start.clear();
        match self.simplex.solve_or_retry(&self.program, &self.c) {
            LpStatus::Optimal => Ok(Margin::Solved(self.simplex.v[k])),
            // (t >= -MAX_MARGIN is always feasible: a guard)
            LpStatus::Infeasible | LpStatus::Failed => Err(ToppError::InvalidValue {
                what: "lifted rows",
                detail: "the membership program failed (singular or cycling); report this \
                         input"
                    .into(),
            }),
        }
    }
}
