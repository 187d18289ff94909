//! A small dense linear program in inequality form, solved by the simplex method on its
//! vertices (active sets), for the support functions and membership tests of [`super`].
//!
//! ```text
//!     maximize  c . v   subject to   G v <= h   (m unit rows),   lo <= v <= hi   (2 n bound rows)
//! ```
//!
//! A vertex is `n` active rows `A` with `G_A` invertible and `v = G_A^-1 h_A`; its multipliers
//! are `lambda = G_A^-T c` (`c = G_A^T lambda`). The vertex is optimal when it is feasible and
//! `lambda >= 0`.
//!
//! - **Primal simplex** (from a feasible vertex, when only `c` changed): while some
//!   `lambda_r < 0`, leave row `r` along `d = -G_A^-1 e_r` (the objective grows by `-lambda_r`
//!   per unit step) up to the first row that blocks (ratio test).
//! - **Dual simplex** (from `lambda >= 0`, when the rows changed or from the box): while some row
//!   `j` is violated (the most violated first), write `g_j = G_A^T w` and swap `j` in for the
//!   active row `r` with `w_r > 0` of least `lambda_r / w_r`; when no `w_r > 0`, no point
//!   satisfies the rows: the program is infeasible.
//! - **The box's corner** maximizing `c` (upper bounds where `c_i >= 0`, lower ones elsewhere)
//!   is a vertex with `lambda = |c| >= 0`: the dual simplex always has a start.
//!
//! After a run of degenerate steps (no progress), both switch to Bland's rule (smallest
//! index), which cannot cycle; an iteration cap guards the rest. `G_A^-1` is updated by the
//! rank-one formula at each swap: with `B' = B + e_r (g - g_r)^T` and `b_r` column `r` of
//! `B^-1`, `B'^-1 = B^-1 - b_r (g^T B^-1 - e_r^T) / (g^T b_r)`. It is recomputed from the
//! active rows (Gauss-Jordan with partial pivoting) every [`REFACTOR_EVERY`] swaps and at every
//! new start, so rounding does not accumulate along a warm-started sequence.
//!
//! Nothing here is trusted by the caller beyond what it re-checks: a membership is certified by
//! the witness it returns, a projection's rows by the vertices they pass through.

// Index loops over the small dense matrices read like the linear algebra.
#![allow(clippy::needless_range_loop)]

/// Largest number of variables.
pub const MAX_VARS: usize = 2 + 6 * 3 + 1;

/// How a solve ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LpStatus {
    /// The vertex in the workspace is optimal.
    Optimal,
    /// No point satisfies the rows and the box.
    Infeasible,
    /// The iteration cap was reached, or the active rows became singular (should not happen;
    /// a guard).
    Failed,
}

/// The rows (`G`, `h`: `m x n`, unit rows) and the box of a program. `G` is stored by
/// columns, so that `G v` (the feasibility scans, the ratio tests) runs down contiguous
/// columns.
#[derive(Debug, Clone, Default)]
pub struct Program {
    /// Number of variables.
    pub n: usize,
    /// `G` by columns: `g[k * m + j]` is row `j`'s coefficient `k` (`m = h.len()`); every
    /// row of unit norm.
    pub g: Vec<f64>,
    /// `h`.
    pub h: Vec<f64>,
    /// Lower bounds.
    pub lo: Vec<f64>,
    /// Upper bounds.
    pub hi: Vec<f64>,
}

impl Program {
    /// Number of rows (without the bounds).
    #[inline]
    pub fn m(&self) -> usize {
        self.h.len()
    }

    /// Sets `G` from its rows, `rows` row-major (`m x n`, `m = h.len()`).
    pub fn set_rows(&mut self, rows: &[f64]) {
        let (m, n) = (self.m(), self.n);
        debug_assert_eq!(rows.len(), m * n);
        self.g.clear();
        self.g.resize(m * n, 0.0);
        for (j, r) in rows.chunks_exact(n.max(1)).enumerate() {
            for (k, &v) in r.iter().enumerate() {
                self.g[k * m + j] = v;
            }
        }
    }

    /// Row `j`'s coefficient `k` (rows `m + 2 i` and `m + 2 i + 1` are `v_i <= hi_i` and
    /// `-v_i <= -lo_i`).
    #[inline]
    fn coef(&self, j: usize, k: usize) -> f64 {
        let m = self.m();
        if j < m {
            self.g[k * m + j]
        } else {
            let b = j - m;
            if b / 2 != k {
                0.0
            } else if b.is_multiple_of(2) {
                1.0
            } else {
                -1.0
            }
        }
    }

    /// `out = G v` over the rows (not the bounds), each entry summed in the order of the
    /// variables.
    #[inline]
    fn times(&self, v: &[f64], out: &mut Vec<f64>) {
        let m = self.m();
        out.clear();
        out.resize(m, 0.0);
        if m == 0 {
            return;
        }
        for (col, &vk) in self.g.chunks_exact(m).zip(&v[..self.n]) {
            for (o, &g) in out.iter_mut().zip(col) {
                *o += g * vk;
            }
        }
    }

    /// Right-hand side of row `j`.
    #[inline]
    fn rhs(&self, j: usize) -> f64 {
        let m = self.m();
        if j < m {
            self.h[j]
        } else {
            let b = j - m;
            if b.is_multiple_of(2) {
                self.hi[b / 2]
            } else {
                -self.lo[b / 2]
            }
        }
    }
}

/// The simplex's state: an active set and what follows from it.
#[derive(Debug, Clone, Default)]
pub struct Simplex {
    /// Active rows (indices into the rows then the bounds).
    pub active: Vec<usize>,
    /// `G_A^-1`, row-major `n x n`.
    binv: Vec<f64>,
    /// The vertex.
    pub v: Vec<f64>,
    /// Multipliers of the active rows.
    pub lambda: Vec<f64>,
    /// Scratch.
    tmp: Vec<f64>,
    gj: Vec<f64>,
    w: Vec<f64>,
    d: Vec<f64>,
    row: Vec<f64>,
    /// `G v` and `G d` (rows only).
    gv: Vec<f64>,
    gd: Vec<f64>,
    mark: Vec<bool>,
    /// Swaps since the last refactorization.
    updates: usize,
    /// Bland's rule from the first step (a retry after a failure: it cannot cycle).
    pub bland: bool,
    /// Pivots since creation.
    pub pivots: usize,
}

/// Relative feasibility tolerance: a row is violated when `g . v - h > FEAS max(1, |v|)`.
const FEAS: f64 = 1e-9;
/// Optimality tolerance on the multipliers, relative to `|c|`.
const OPT: f64 = 1e-11;
/// Smallest pivot element.
const PIVOT: f64 = 1e-9;
/// Degenerate steps before Bland's rule.
const DEGENERATE_RUN: usize = 8;
/// Iteration cap per solve, per variable and row.
const MAX_ITER_FACTOR: usize = 8;
/// Rank-one updates between two recomputations of `G_A^-1` from the active rows.
pub const REFACTOR_EVERY: usize = 16;

impl Simplex {
    /// Recomputes `G_A^-1`, the vertex and (for `c`) the multipliers. `false` when `G_A` is
    /// singular.
    fn refactor(&mut self, p: &Program, c: &[f64]) -> bool {
        let (n, m) = (p.n, p.m());
        // [G_A | I] -> [I | G_A^-1] by Gauss-Jordan with partial pivoting (row operations: the
        // right half ends as G_A^-1 whatever the row swaps)
        let w = 2 * n;
        self.tmp.clear();
        self.tmp.resize(n * w, 0.0);
        for (i, (&j, t)) in self
            .active
            .iter()
            .zip(self.tmp.chunks_exact_mut(w))
            .enumerate()
        {
            if j < m {
                for (k, tk) in t[..n].iter_mut().enumerate() {
                    *tk = p.g[k * m + j];
                }
            } else if (j - m) / 2 < n {
                let b = j - m;
                t[b / 2] = if b.is_multiple_of(2) { 1.0 } else { -1.0 };
            }
            // (else a warm start's index beyond this program's rows: a zero row, singular)
            t[n + i] = 1.0;
        }
        let mut pivot_row = [0.0; 2 * MAX_VARS];
        for col in 0..n {
            let (mut best, mut piv) = (0.0, col);
            for r in col..n {
                let a = self.tmp[r * w + col].abs();
                if a > best {
                    best = a;
                    piv = r;
                }
            }
            if best <= 1e-14 {
                return false;
            }
            if piv != col {
                let (top, bottom) = self.tmp.split_at_mut(piv * w);
                top[col * w..(col + 1) * w].swap_with_slice(&mut bottom[..w]);
            }
            let pr = &mut self.tmp[col * w..(col + 1) * w];
            let d = 1.0 / pr[col];
            for v in &mut pr[col..] {
                *v *= d;
            }
            let pr_saved = &mut pivot_row[..w];
            pr_saved.copy_from_slice(pr);
            for (r, row) in self.tmp.chunks_exact_mut(w).enumerate() {
                if r != col {
                    let f = row[col];
                    if f != 0.0 {
                        for (v, &q) in row[col..].iter_mut().zip(&pr_saved[col..]) {
                            *v -= f * q;
                        }
                    }
                }
            }
        }
        self.binv.clear();
        self.binv.resize(n * n, 0.0);
        for r in 0..n {
            self.binv[r * n..(r + 1) * n].copy_from_slice(&self.tmp[r * w + n..r * w + 2 * n]);
        }
        self.updates = 0;
        self.vertex(p);
        self.multipliers(n, c);
        true
    }

    /// `v = G_A^-1 h_A`.
    fn vertex(&mut self, p: &Program) {
        let n = p.n;
        self.row.clear();
        self.row.extend(self.active.iter().map(|&j| p.rhs(j)));
        self.v.clear();
        self.v.resize(n, 0.0);
        for r in 0..n {
            let b = &self.binv[r * n..(r + 1) * n];
            let mut s = 0.0;
            for k in 0..n {
                s += b[k] * self.row[k];
            }
            self.v[r] = s;
        }
    }

    /// `lambda = G_A^-T c`.
    fn multipliers(&mut self, n: usize, c: &[f64]) {
        self.lambda.clear();
        self.lambda.resize(n, 0.0);
        for k in 0..n {
            if c[k] != 0.0 {
                let b = &self.binv[k * n..(k + 1) * n];
                for i in 0..n {
                    self.lambda[i] += b[i] * c[k];
                }
            }
        }
    }

    /// Puts row `j` in place of active row `r` (rank-one update of `G_A^-1`, or a
    /// recomputation every [`REFACTOR_EVERY`] swaps); `false` when the new `G_A` is singular.
    fn swap(&mut self, p: &Program, c: &[f64], r: usize, j: usize) -> bool {
        let n = p.n;
        self.active[r] = j;
        self.pivots += 1;
        if self.updates + 1 >= REFACTOR_EVERY {
            return self.refactor(p, c);
        }
        // row = g^T B^-1, den = g^T b_r
        self.gj.clear();
        self.gj.extend((0..n).map(|k| p.coef(j, k)));
        self.row.clear();
        self.row.resize(n, 0.0);
        for k in 0..n {
            let g = self.gj[k];
            if g != 0.0 {
                let b = &self.binv[k * n..(k + 1) * n];
                for i in 0..n {
                    self.row[i] += g * b[i];
                }
            }
        }
        let den = self.row[r];
        if den.abs() <= 1e-12 {
            return self.refactor(p, c);
        }
        self.row[r] -= 1.0;
        for k in 0..n {
            let f = self.binv[k * n + r] / den;
            if f != 0.0 {
                for i in 0..n {
                    self.binv[k * n + i] -= f * self.row[i];
                }
            }
        }
        self.updates += 1;
        self.vertex(p);
        self.multipliers(n, c);
        true
    }

    /// The box corner maximizing `c` as the active set.
    pub fn box_corner(&mut self, p: &Program, c: &[f64]) {
        let m = p.m();
        self.active.clear();
        self.active.extend((0..p.n).map(|i| {
            if c[i] >= 0.0 {
                m + 2 * i
            } else {
                m + 2 * i + 1
            }
        }));
    }

    /// The most violated row, or with `bland` the violated row of smallest index (the rows,
    /// then the bounds, in the order of their indices).
    fn most_violated(&mut self, p: &Program, bland: bool) -> Option<usize> {
        let n = p.n;
        let scale = self.v[..n].iter().fold(1.0f64, |a, x| a.max(x.abs()));
        let lim = FEAS * scale;
        let mut best = (lim, None);
        p.times(&self.v, &mut self.gv);
        for (j, (&s, &h)) in self.gv.iter().zip(&p.h).enumerate() {
            let viol = s - h;
            if viol > best.0 {
                if bland {
                    return Some(j);
                }
                best = (viol, Some(j));
            }
        }
        let m = p.m();
        for (i, (&vi, (&lo, &hi))) in self.v[..n].iter().zip(p.lo.iter().zip(&p.hi)).enumerate() {
            for (j, viol) in [(m + 2 * i, vi - hi), (m + 2 * i + 1, -vi - (-lo))] {
                if viol > best.0 {
                    if bland {
                        return Some(j);
                    }
                    best = (viol, Some(j));
                }
            }
        }
        best.1
    }

    /// Solves for `c` from the current active set (warm start) or the box corner: the dual
    /// simplex while the vertex is infeasible, then the primal simplex.
    pub fn solve(&mut self, p: &Program, c: &[f64]) -> LpStatus {
        let n = p.n;
        if self.active.len() != n || !self.refactor(p, c) {
            self.box_corner(p, c);
            if !self.refactor(p, c) {
                return LpStatus::Failed;
            }
        }
        let cnorm = c
            .iter()
            .map(|x| x * x)
            .sum::<f64>()
            .sqrt()
            .max(f64::MIN_POSITIVE);
        let max_iter = MAX_ITER_FACTOR * (p.m() + 3 * n) * if self.bland { 8 } else { 1 };
        let run = if self.bland { DEGENERATE_RUN } else { 0 };
        let dual_ok = |s: &Simplex| s.lambda.iter().all(|&l| l >= -OPT * cnorm);
        // a warm start that is neither primal nor dual feasible restarts from the box
        if !dual_ok(self) && self.most_violated(p, false).is_some() {
            self.box_corner(p, c);
            if !self.refactor(p, c) {
                return LpStatus::Failed;
            }
        }
        // dual phase
        let mut degenerate = run;
        let mut iter = 0;
        while let Some(j) = self.most_violated(p, degenerate >= DEGENERATE_RUN) {
            iter += 1;
            if iter > max_iter {
                return LpStatus::Failed;
            }
            // w = G_A^-T g_j
            self.gj.clear();
            self.gj.extend((0..n).map(|k| p.coef(j, k)));
            self.w.clear();
            self.w.resize(n, 0.0);
            for k in 0..n {
                let g = self.gj[k];
                if g != 0.0 {
                    let b = &self.binv[k * n..(k + 1) * n];
                    for i in 0..n {
                        self.w[i] += g * b[i];
                    }
                }
            }
            let mut leave = None;
            let mut best = f64::INFINITY;
            for i in 0..n {
                if self.w[i] > PIVOT {
                    let ratio = self.lambda[i].max(0.0) / self.w[i];
                    let better = match leave {
                        None => true,
                        Some(l) if degenerate >= DEGENERATE_RUN => {
                            ratio < best - 1e-15
                                || (ratio <= best + 1e-15 && self.active[i] < self.active[l])
                        }
                        Some(_) => ratio < best,
                    };
                    if better {
                        best = ratio;
                        leave = Some(i);
                    }
                }
            }
            let Some(r) = leave else {
                return LpStatus::Infeasible;
            };
            degenerate = if best <= 1e-14 { degenerate + 1 } else { run };
            if !self.swap(p, c, r, j) {
                return LpStatus::Failed;
            }
        }
        // primal phase
        degenerate = run;
        loop {
            iter += 1;
            if iter > max_iter {
                return LpStatus::Failed;
            }
            // leaving row: the most negative multiplier (Bland: the smallest row index)
            let mut r = None;
            for i in 0..n {
                if self.lambda[i] < -OPT * cnorm {
                    let better = match r {
                        None => true,
                        Some(q) if degenerate >= DEGENERATE_RUN => self.active[i] < self.active[q],
                        Some(q) => self.lambda[i] < self.lambda[q],
                    };
                    if better {
                        r = Some(i);
                    }
                }
            }
            let Some(r) = r else {
                return LpStatus::Optimal;
            };
            // d = -G_A^-1 e_r
            self.d.clear();
            self.d.extend((0..n).map(|k| -self.binv[k * n + r]));
            self.mark.clear();
            self.mark.resize(p.m() + 2 * n, false);
            for &a in &self.active {
                self.mark[a] = true;
            }
            let mut enter = None;
            let mut best = f64::INFINITY;
            let bland_step = degenerate >= DEGENERATE_RUN;
            let mut consider = |j: usize, gd: f64, gv: f64, rhs: f64| {
                if gd > PIVOT {
                    let t = (rhs - gv).max(0.0) / gd;
                    let better = match enter {
                        None => true,
                        Some(e) if bland_step => t < best - 1e-15 || (t <= best + 1e-15 && j < e),
                        Some(_) => t < best,
                    };
                    if better {
                        best = t;
                        enter = Some(j);
                    }
                }
            };
            p.times(&self.d, &mut self.gd);
            p.times(&self.v, &mut self.gv);
            let (d, v) = (&self.d[..n], &self.v[..n]);
            for (j, ((&gd, &gv), &h)) in self.gd.iter().zip(&self.gv).zip(&p.h).enumerate() {
                if !self.mark[j] {
                    consider(j, gd, gv, h);
                }
            }
            let m = p.m();
            for i in 0..n {
                if !self.mark[m + 2 * i] {
                    consider(m + 2 * i, d[i], v[i], p.hi[i]);
                }
                if !self.mark[m + 2 * i + 1] {
                    consider(m + 2 * i + 1, -d[i], -v[i], -p.lo[i]);
                }
            }
            let Some(j) = enter else {
                // unbounded cannot happen inside the box: a guard
                return LpStatus::Failed;
            };
            degenerate = if best <= 1e-14 { degenerate + 1 } else { run };
            if !self.swap(p, c, r, j) {
                return LpStatus::Failed;
            }
        }
    }

    /// [`Simplex::solve`], and on a failure once more from scratch with Bland's rule from the
    /// first step (the state is then fresh, warm starts lost).
    pub fn solve_or_retry(&mut self, p: &Program, c: &[f64]) -> LpStatus {
        match self.solve(p, c) {
            LpStatus::Failed => {
                *self = Simplex {
                    bland: true,
                    pivots: self.pivots,
                    ..Default::default()
                };
                let status = self.solve(p, c);
                self.bland = false;
                status
            }
            status => status,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Random programs against brute-force vertex enumeration in 2 and 3 variables, solved
    /// in sequence (warm starts across different programs and objectives).
    #[test]
    fn matches_vertex_enumeration() {
        let mut seed = 12345u64;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % 1_000_000) as f64 / 500_000.0 - 1.0
        };
        let mut s = Simplex::default();
        for case in 0..400 {
            let n = 2 + case % 2;
            let m = 3 + case % 7;
            let mut p = Program {
                n,
                g: Vec::new(),
                h: (0..m).map(|_| rnd() + 0.3).collect(),
                lo: vec![-2.0; n],
                hi: vec![2.0; n],
            };
            let mut g = Vec::new();
            for _ in 0..m {
                let r: Vec<f64> = (0..n).map(|_| rnd()).collect();
                let norm = r.iter().map(|x| x * x).sum::<f64>().sqrt();
                g.extend(r.iter().map(|x| x / norm));
            }
            p.set_rows(&g);
            if case % 5 == 0 {
                p.h[0] = -5.0; // often infeasible
            }
            let c: Vec<f64> = (0..n).map(|_| rnd()).collect();
            if case % 3 == 0 {
                s = Simplex::default();
            }
            let status = s.solve(&p, &c);
            // brute force: every n-subset of rows and bounds
            let rows = m + 2 * n;
            let mut best: Option<f64> = None;
            let mut idx: Vec<usize> = (0..n).collect();
            fn next(idx: &mut [usize], rows: usize) -> bool {
                let n = idx.len();
                for i in (0..n).rev() {
                    if idx[i] < rows - (n - i) {
                        idx[i] += 1;
                        for k in i + 1..n {
                            idx[k] = idx[k - 1] + 1;
                        }
                        return true;
                    }
                }
                false
            }
            loop {
                let mut t = Simplex {
                    active: idx.clone(),
                    ..Default::default()
                };
                if t.refactor(&p, &c) && t.most_violated(&p, false).is_none() {
                    let val: f64 = c.iter().zip(&t.v).map(|(a, b)| a * b).sum();
                    best = Some(best.map_or(val, |b: f64| b.max(val)));
                }
                if !next(&mut idx, rows) {
                    break;
                }
            }
            match (status, best) {
                (LpStatus::Optimal, Some(b)) => {
                    let val: f64 = c.iter().zip(&s.v).map(|(a, b)| a * b).sum();
                    assert!((val - b).abs() < 1e-9, "case {case}: {val} vs {b}");
                }
                (LpStatus::Infeasible, None) => {}
                other => panic!("case {case}: {other:?}"),
            }
        }
    }
}
