//! A dense primal simplex for linear programs with four equality rows,
//!
//! ```text
//! maximize c . x   subject to   A x = b,  x >= 0,      A: 4 x n, full row rank,
//! ```
//!
//! the support-function LPs of the direct static-equilibrium polygon ([`super::direct`]). With
//! only four rows the basis inverse `B^-1` is kept explicitly (4 x 4) and the reduced costs
//! `r_j = c_j - y . A_j`, `y = B^-T c_B`, are recomputed from the data at every iteration, so
//! errors do not build up along a warm-started sequence of LPs. Phase 1 starts from the four
//! artificial columns `sign(b_i) e_i`. Entering column: largest reduced cost (Dantzig), switching
//! to Bland's smallest-index rule after a run of degenerate pivots (no cycling); leaving row: the
//! smallest ratio, ties to the smallest column index.
//!
//! Nothing here is trusted: the caller verifies every answer from the data (primal residuals,
//! dual reduced costs), see [`super::direct`].

// Index loops over the 4 x 4 basis read like the linear algebra.
#![allow(clippy::needless_range_loop)]

/// Number of equality rows.
pub(crate) const M: usize = 4;

/// Why a solve stopped without an optimum.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum LpStop {
    /// The objective is unbounded above (the feasible set is unbounded).
    Unbounded,
    /// Phase 1 ended with a positive infeasibility: no `x >= 0` meets `A x = b`.
    Infeasible,
    /// An artificial column stayed basic (the rows are dependent within the pivot tolerance).
    RankDeficient,
    /// The iteration cap was reached (should not happen with Bland's rule; a guard).
    IterationCap,
    /// The basis matrix became singular within the pivot tolerance.
    Singular,
}

/// The LP data and the current basis; reused across solves (no allocation after `reset`).
#[derive(Debug, Clone, Default)]
pub(crate) struct Lp4 {
    /// Columns `A_j`.
    pub a: Vec<[f64; M]>,
    /// Right-hand side.
    pub b: [f64; M],
    /// Basic column of each row (`>= n` for artificial `n + i`).
    pub basis: [usize; M],
    /// `B^-1`, row-major.
    binv: [[f64; M]; M],
    /// Values of the basic variables, `B^-1 b`.
    pub xb: [f64; M],
    /// Dual vector `y = B^-T c_B` of the last solve.
    pub y: [f64; M],
    /// Whether column `j` is basic.
    in_basis: Vec<bool>,
    /// The rows of `A` (structure of arrays, for the reduced-cost loop).
    soa: [Vec<f64>; M],
    /// Reduced costs of the last iteration.
    red: Vec<f64>,
    /// Objective coefficients of the current solve.
    c: Vec<f64>,
    /// Thresholds: reduced cost (optimality) and pivot size.
    opt_tol: f64,
    pivot_tol: f64,
    /// Pivots done since `reset` (all solves).
    pub pivots: usize,
    /// Rank-one updates of `B^-1` since it was last computed from the basis.
    updates: usize,
}

/// Product-form updates between two recomputations of `B^-1` from the basis columns: few
/// enough that rounding does not build up (the caller verifies every answer anyway).
const REFACTOR_EVERY: usize = 8;

impl Lp4 {
    /// Takes new data (`a` filled by the caller) and puts the artificial basis in place.
    pub fn reset(&mut self, n: usize, b: [f64; M], opt_tol: f64, pivot_tol: f64) {
        debug_assert_eq!(self.a.len(), n);
        self.b = b;
        self.opt_tol = opt_tol;
        self.pivot_tol = pivot_tol;
        self.in_basis.clear();
        self.in_basis.resize(n, false);
        self.c.clear();
        self.c.resize(n, 0.0);
        self.red.clear();
        self.red.resize(n, 0.0);
        for (k, row) in self.soa.iter_mut().enumerate() {
            row.clear();
            row.extend(self.a.iter().map(|a| a[k]));
        }
        self.binv = [[0.0; M]; M];
        for i in 0..M {
            self.basis[i] = n + i;
            let s = if b[i] < 0.0 { -1.0 } else { 1.0 };
            self.binv[i][i] = s;
            self.xb[i] = b[i].abs();
        }
        self.pivots = 0;
        self.updates = 0;
    }

    fn n(&self) -> usize {
        self.a.len()
    }

    /// Column `j` of the extended matrix `[A  diag(sign b)]`.
    fn column(&self, j: usize) -> [f64; M] {
        let n = self.n();
        if j < n {
            self.a[j]
        } else {
            let mut e = [0.0; M];
            e[j - n] = if self.b[j - n] < 0.0 { -1.0 } else { 1.0 };
            e
        }
    }

    /// Phase 1: drives the artificials out (maximize `-sum` of artificials), then pivots any
    /// zero-level artificial out of the basis.
    pub fn phase1(&mut self, feas_tol: f64, max_iter: usize) -> Result<(), LpStop> {
        let n = self.n();
        self.c.iter_mut().for_each(|c| *c = 0.0);
        self.iterate(-1.0, max_iter)?;
        let infeas: f64 = (0..M)
            .filter(|&i| self.basis[i] >= n)
            .map(|i| self.xb[i])
            .sum();
        if infeas > feas_tol {
            return Err(LpStop::Infeasible);
        }
        // Artificials at level zero: pivot in the structural column with the largest entry.
        for r in 0..M {
            if self.basis[r] < n {
                continue;
            }
            let mut best = (usize::MAX, self.pivot_tol);
            for j in 0..n {
                if self.in_basis[j] {
                    continue;
                }
                let d = self.binv_row_dot(r, &self.a[j]).abs();
                if d > best.1 {
                    best = (j, d);
                }
            }
            if best.0 == usize::MAX {
                return Err(LpStop::RankDeficient);
            }
            self.pivot(r, best.0)?;
        }
        Ok(())
    }

    /// Phase 2 from the current (feasible, artificial-free) basis, objective `c_j = cost(j)`.
    pub fn maximize(&mut self, cost: impl Fn(usize) -> f64, max_iter: usize) -> Result<(), LpStop> {
        for (j, c) in self.c.iter_mut().enumerate() {
            *c = cost(j);
        }
        self.iterate(0.0, max_iter)
    }

    fn binv_row_dot(&self, r: usize, v: &[f64; M]) -> f64 {
        let row = &self.binv[r];
        row[0] * v[0] + row[1] * v[1] + row[2] * v[2] + row[3] * v[3]
    }

    /// Dual vector `y = B^-T c_B` (`art_cost` for artificial columns).
    fn duals(&mut self, art_cost: f64) {
        let n = self.n();
        let mut y = [0.0; M];
        for i in 0..M {
            let j = self.basis[i];
            let cb = if j < n { self.c[j] } else { art_cost };
            if cb == 0.0 {
                continue;
            }
            for k in 0..M {
                y[k] += cb * self.binv[i][k];
            }
        }
        self.y = y;
    }

    /// Primal simplex iterations with objective `self.c` on the structural columns and
    /// `art_cost` on the artificial ones (which never enter).
    fn iterate(&mut self, art_cost: f64, max_iter: usize) -> Result<(), LpStop> {
        let n = self.n();
        let mut degenerate_run = 0usize;
        for _ in 0..max_iter {
            self.duals(art_cost);
            let y = self.y;
            // Reduced costs r_j = c_j - y . A_j, a straight loop over the columns (SoA).
            {
                let [a0, a1, a2, a3] = &self.soa;
                let (c, r) = (&self.c[..n], &mut self.red[..n]);
                let (a0, a1, a2, a3) = (&a0[..n], &a1[..n], &a2[..n], &a3[..n]);
                for j in 0..n {
                    r[j] = c[j] - (y[0] * a0[j] + y[1] * a1[j] + y[2] * a2[j] + y[3] * a3[j]);
                }
            }
            let bland = degenerate_run >= 2;
            let mut enter = usize::MAX;
            let mut best = self.opt_tol;
            for j in 0..n {
                let r = self.red[j];
                if r > best && !self.in_basis[j] {
                    enter = j;
                    if bland {
                        break;
                    }
                    best = r;
                }
            }
            if enter == usize::MAX {
                return Ok(());
            }
            // Ratio test on d = B^-1 A_enter.
            let col = self.a[enter];
            let mut leave = usize::MAX;
            let mut ratio = f64::INFINITY;
            for i in 0..M {
                let d = self.binv_row_dot(i, &col);
                if d > self.pivot_tol {
                    let t = self.xb[i].max(0.0) / d;
                    let better = t < ratio
                        || (t == ratio && leave != usize::MAX && self.basis[i] < self.basis[leave]);
                    if better {
                        ratio = t;
                        leave = i;
                    }
                }
            }
            if leave == usize::MAX {
                return Err(LpStop::Unbounded);
            }
            degenerate_run = if ratio == 0.0 { degenerate_run + 1 } else { 0 };
            self.pivot(leave, enter)?;
        }
        Err(LpStop::IterationCap)
    }

    /// Column `enter` replaces the basic column of row `r`; `B^-1` is recomputed from the
    /// basis columns (4 x 4 Gauss-Jordan with partial pivoting) and `x_B = B^-1 b`.
    /// Column `enter` replaces the basic column of row `r`. `B^-1` and `x_B` get the rank-one
    /// (product-form) update with `d = B^-1 A_enter`; every [`REFACTOR_EVERY`] updates they are
    /// recomputed from the basis columns.
    fn pivot(&mut self, r: usize, enter: usize) -> Result<(), LpStop> {
        let n = self.n();
        let col = self.a[enter];
        let d: [f64; M] = std::array::from_fn(|i| self.binv_row_dot(i, &col));
        if d[r].abs() <= self.pivot_tol {
            return Err(LpStop::Singular);
        }
        let old = self.basis[r];
        if old < n {
            self.in_basis[old] = false;
        }
        self.basis[r] = enter;
        self.in_basis[enter] = true;
        self.pivots += 1;
        self.updates += 1;
        if self.updates >= REFACTOR_EVERY {
            return self.refactor();
        }
        let inv = 1.0 / d[r];
        let row_r: [f64; M] = std::array::from_fn(|k| self.binv[r][k] * inv);
        let x_r = self.xb[r] * inv;
        for i in 0..M {
            if i == r {
                continue;
            }
            let f = d[i];
            if f != 0.0 {
                for k in 0..M {
                    self.binv[i][k] -= f * row_r[k];
                }
                self.xb[i] -= f * x_r;
            }
        }
        self.binv[r] = row_r;
        self.xb[r] = x_r;
        Ok(())
    }

    fn refactor(&mut self) -> Result<(), LpStop> {
        self.updates = 0;
        // [B | I] -> [I | B^-1], B's columns are the basic columns.
        let mut m = [[0.0; 2 * M]; M];
        for i in 0..M {
            let col = self.column(self.basis[i]);
            for k in 0..M {
                m[k][i] = col[k];
            }
            m[i][M + i] = 1.0;
        }
        for p in 0..M {
            let mut piv = p;
            for k in p + 1..M {
                if m[k][p].abs() > m[piv][p].abs() {
                    piv = k;
                }
            }
            if m[piv][p].abs() <= self.pivot_tol {
                return Err(LpStop::Singular);
            }
            m.swap(p, piv);
            let inv = 1.0 / m[p][p];
            for v in m[p].iter_mut() {
                *v *= inv;
            }
            for k in 0..M {
                if k != p {
                    let f = m[k][p];
                    if f != 0.0 {
                        for c in 0..2 * M {
                            m[k][c] -= f * m[p][c];
                        }
                    }
                }
            }
        }
        for i in 0..M {
            self.binv[i].copy_from_slice(&m[i][M..]);
        }
        for i in 0..M {
            self.xb[i] = self.binv_row_dot(i, &self.b);
        }
        Ok(())
    }

    /// Restores a basis saved from an earlier solve (structural columns only).
    #[cfg(test)]
    pub fn set_basis(&mut self, basis: [usize; M]) -> Result<(), LpStop> {
        if basis == self.basis {
            return Ok(());
        }
        for j in self.basis {
            if j < self.n() {
                self.in_basis[j] = false;
            }
        }
        self.basis = basis;
        for j in basis {
            if j < self.n() {
                self.in_basis[j] = true;
            }
        }
        self.refactor()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force over all bases: the best basic feasible solution.
    fn brute(a: &[[f64; M]], b: [f64; M], c: &[f64]) -> Option<f64> {
        let n = a.len();
        let mut best: Option<f64> = None;
        for i0 in 0..n {
            for i1 in i0 + 1..n {
                for i2 in i1 + 1..n {
                    for i3 in i2 + 1..n {
                        let mut lp = Lp4 {
                            a: a.to_vec(),
                            ..Default::default()
                        };
                        lp.reset(n, b, 1e-12, 1e-12);
                        if lp.set_basis([i0, i1, i2, i3]).is_err() {
                            continue;
                        }
                        if lp.xb.iter().any(|&v| v < -1e-12) {
                            continue;
                        }
                        let v: f64 = (0..M).map(|k| c[lp.basis[k]] * lp.xb[k]).sum();
                        best = Some(best.map_or(v, |x: f64| x.max(v)));
                    }
                }
            }
        }
        best
    }

    fn lcg(s: &mut u64) -> f64 {
        *s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*s >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
    }

    #[test]
    fn optimum_matches_brute_force_on_random_bounded_lps() {
        let mut s = 7u64;
        let mut solved = 0;
        for _ in 0..300 {
            let n = 6 + (lcg(&mut s).abs() * 6.0) as usize;
            // Row 0 all positive: the feasible set is bounded.
            let a: Vec<[f64; M]> = (0..n)
                .map(|_| {
                    [
                        0.5 + lcg(&mut s).abs(),
                        lcg(&mut s),
                        lcg(&mut s),
                        lcg(&mut s),
                    ]
                })
                .collect();
            // b from a random positive combination: feasible.
            let mut b = [0.0; M];
            for col in &a {
                let w = lcg(&mut s).abs();
                for k in 0..M {
                    b[k] += w * col[k];
                }
            }
            let c: Vec<f64> = (0..n).map(|_| lcg(&mut s)).collect();
            let mut lp = Lp4 {
                a: a.clone(),
                ..Default::default()
            };
            lp.reset(n, b, 1e-12, 1e-12);
            lp.phase1(1e-9, 1000).unwrap();
            lp.maximize(|j| c[j], 1000).unwrap();
            let got: f64 = (0..M).map(|k| c[lp.basis[k]] * lp.xb[k]).sum();
            let want = brute(&a, b, &c).unwrap();
            assert!(
                (got - want).abs() <= 1e-9 * (1.0 + want.abs()),
                "{got} vs {want}"
            );
            solved += 1;
        }
        assert_eq!(solved, 300);
    }

    #[test]
    fn infeasible_and_unbounded_are_reported() {
        // x >= 0 with first row all positive cannot reach b_0 < 0.
        let a = vec![
            [1.0, 0.0, 0.0, 0.0],
            [1.0, 1.0, 0.0, 0.0],
            [1.0, 0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0, 1.0],
        ];
        let mut lp = Lp4 {
            a,
            ..Default::default()
        };
        lp.reset(4, [-1.0, 0.0, 0.0, 0.0], 1e-12, 1e-12);
        assert_eq!(lp.phase1(1e-9, 100), Err(LpStop::Infeasible));
        // Column 4 = -(column 0 + column 1): d = (1, 1, 0, 0, 1) >= 0 has A d = 0, so the
        // objective x_4 grows without bound.
        let mut lp = Lp4 {
            a: vec![
                [1.0, 0.0, 0.0, 0.0],
                [0.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
                [-1.0, -1.0, 0.0, 0.0],
            ],
            ..Default::default()
        };
        lp.reset(5, [1.0, 1.0, 1.0, 1.0], 1e-12, 1e-12);
        lp.phase1(1e-9, 100).unwrap();
        assert_eq!(
            lp.maximize(|j| if j == 4 { 1.0 } else { 0.0 }, 100),
            Err(LpStop::Unbounded)
        );
    }

    #[test]
    fn dependent_rows_are_reported() {
        // Row 3 = row 0: rank 3.
        let a = vec![
            [1.0, 0.0, 0.0, 1.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [1.0, 1.0, 1.0, 1.0],
        ];
        let mut lp = Lp4 {
            a,
            ..Default::default()
        };
        lp.reset(4, [1.0, 1.0, 1.0, 1.0], 1e-12, 1e-12);
        assert_eq!(lp.phase1(1e-9, 100), Err(LpStop::RankDeficient));
    }
}
