//! A dense active-set solver for the IK's quadratic program, with its own optimality
//! certificate.
//!
//! # Math
//!
//! ```text
//! minimize    1/2 x^T P x + c^T x
//! subject to  A x = b                  (m rows, the contact equations)
//!             lo <= x <= hi            (per coordinate; infinite bounds allowed)
//! ```
//!
//! with `P` symmetric positive definite (the IK's regularization makes it so). For a working set
//! `W` of coordinates held at one of their bounds and the free rest `F`, the equality-constrained
//! minimizer solves the KKT system
//!
//! ```text
//! P_FF x_F + A_F^T lambda = r := -(c_F + P_FW x_W),     A_F x_F = b' := b - A_W x_W
//! ```
//!
//! by the range-space method: `P_FF = L L^T` (Cholesky), `Y = L^-1 A_F^T`, `z = L^-1 r`, then
//! `(Y^T Y) lambda = Y^T z - b'` (a second Cholesky, m x m) and `x_F = L^-T (z - Y lambda)`.
//! The working set is updated as in a primal-dual active-set method for bound constraints
//! (Hintermueller, Ito and Kunisch, SIAM J. Optim. 2003): every free coordinate that leaves its
//! box joins `W` at the bound it crossed; when none does, the held coordinate whose multiplier
//! `g_i = (P x + c + A^T lambda)_i` has the wrong sign (`g_i < 0` at a lower bound, `> 0` at an
//! upper bound) by the largest amount is released. The working set of the previous call is the
//! starting guess (consecutive IK steps share their active joint bounds), so a step usually
//! takes one KKT solve.
//!
//! **Certificate.** The answer is called optimal only when the KKT conditions of the full
//! problem are verified on it: bounds within `primal_tol`, `|A x - b|_inf` within `primal_tol`,
//! and every multiplier of a held bound of the right sign within `dual_tol` (the stationarity
//! of the free coordinates holds by construction of the solve). For a convex QP these
//! conditions are sufficient for optimality. Anything else (an iteration cap, a singular
//! `Y^T Y` from redundant contact rows, an infeasible problem) is reported, and the caller
//! falls back to the interior-point solver, which also decides infeasibility.
//!
//! **General inequality rows** `G x <= h` (a few rows: the IK's clearances) are handled by an
//! outer active set around this solver ([`DenseQpWorkspace::solve_with_rows`]): the held rows
//! join the equations (`A` stacked with `G_held`), the most violated free row joins, and a held
//! row whose multiplier `lambda_j` is negative leaves (with `P x + c + A^T lambda = 0`, a row
//! `g x <= h` needs `lambda_j >= 0`). The answer is certified as above, plus every row within
//! `primal_tol` and every held row's multiplier non-negative within `dual_tol`.
//!
//! The solver allocates only when the dimensions change; its cost is dominated by the Cholesky
//! factorization of `P_FF` (`n^3 / 6` multiply-adds) and the `m` triangular solves of `Y`.

use nalgebra::{DMatrix, DVector};

/// Where a coordinate is in the working set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Held {
    Free,
    Lower,
    Upper,
}

/// Options of [`DenseQpWorkspace::solve`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DenseQpOptions {
    /// Largest number of KKT solves before giving up (default
    /// [`crate::tol::IK_DENSE_MAX_ITERATIONS`]).
    pub max_iterations: usize,
    /// Bound and equality tolerance, relative to `max(1, |bound|)` and `max(1, |b|_inf)`
    /// (default [`crate::tol::IK_DENSE_PRIMAL_TOL`]).
    pub primal_tol: f64,
    /// Multiplier sign tolerance, relative to the scale of the gradient (default
    /// [`crate::tol::IK_DENSE_DUAL_TOL`]).
    pub dual_tol: f64,
}

impl Default for DenseQpOptions {
    fn default() -> Self {
        Self {
            max_iterations: crate::tol::IK_DENSE_MAX_ITERATIONS,
            primal_tol: crate::tol::IK_DENSE_PRIMAL_TOL,
            dual_tol: crate::tol::IK_DENSE_DUAL_TOL,
        }
    }
}

/// Outcome of the dense solver.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DenseQpStatus {
    /// The KKT conditions were verified on the answer.
    Optimal,
    /// The iteration cap was reached (cycling working sets, or an infeasible problem).
    NotConverged,
    /// `P_FF` or `Y^T Y` is numerically singular (redundant contact rows, or too many held
    /// coordinates for the equations).
    Singular,
}

/// What a solve did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DenseQpReport {
    /// Outcome.
    pub status: DenseQpStatus,
    /// KKT solves.
    pub iterations: usize,
    /// Coordinates held at a bound in the answer.
    pub active: usize,
    /// `|A x - b|_inf`.
    pub equality_residual: f64,
    /// Largest bound violation.
    pub bound_violation: f64,
    /// Largest wrong-signed multiplier of a held bound.
    pub dual_violation: f64,
}

impl DenseQpReport {
    /// Before any solve: not converged, every measure infinite.
    fn unsolved() -> Self {
        Self {
            status: DenseQpStatus::NotConverged,
            iterations: 0,
            active: 0,
            equality_residual: f64::INFINITY,
            bound_violation: f64::INFINITY,
            dual_violation: f64::INFINITY,
        }
    }
}

/// The solver's reusable state: buffers and the working set of the last call (the warm start).
#[derive(Debug, Clone, Default)]
pub struct DenseQpWorkspace {
    n: usize,
    m: usize,
    held: Vec<Held>,
    free: Vec<usize>,
    /// Cholesky factor of `P_FF` (column-major, `nf x nf`, lower triangle).
    l: Vec<f64>,
    /// `Y = L^-1 A_F^T`, column `k` at `k * nf`.
    y: Vec<f64>,
    /// `Y^T Y` and its factor (`m x m`).
    s: Vec<f64>,
    z: Vec<f64>,
    r: Vec<f64>,
    /// The answer.
    x: Vec<f64>,
    /// Multipliers of the equations.
    lambda: Vec<f64>,
    /// Which general inequality rows are held as equations ([`Self::solve_with_rows`]).
    row_active: Vec<bool>,
    /// The equations with the held rows below them, and their right-hand side.
    a_rows: DMatrix<f64>,
    b_rows: DVector<f64>,
    /// Consecutive diagonal blocks of `P` ([`Self::set_blocks`]; empty: dense).
    block_sizes: Vec<usize>,
    /// Per coordinate `i`, the columns `[start, end)` of its block: `P[i][j] = 0` outside.
    block: Vec<(usize, usize)>,
    /// Per free coordinate (in the order of `free`), the free ones of its block `[start, end)`.
    free_block: Vec<(usize, usize)>,
    /// `1 / L[j][j]` (multiplications instead of divisions in the triangular solves).
    l_inv: Vec<f64>,
}

impl DenseQpWorkspace {
    /// An empty workspace (sized on first use).
    ///
    /// ```
    /// let ws = stance_robot::ik::DenseQpWorkspace::new();
    /// assert!(ws.solution().is_empty());
    /// ```
    pub fn new() -> Self {
        Self::default()
    }

    /// The answer of the last solve.
    ///
    /// ```
    /// # use stance_robot::ik::DenseQpWorkspace;
    /// assert_eq!(DenseQpWorkspace::new().solution().len(), 0);
    /// ```
    pub fn solution(&self) -> &[f64] {
        &self.x
    }

    /// Forgets the working set (the next solve starts with every coordinate free).
    ///
    /// ```
    /// let mut ws = stance_robot::ik::DenseQpWorkspace::new();
    /// ws.reset();
    /// ```
    pub fn reset(&mut self) {
        self.held.iter_mut().for_each(|h| *h = Held::Free);
        self.row_active.iter_mut().for_each(|r| *r = false);
    }

    /// Declares `P` block diagonal, with these consecutive block sizes (empty: dense, the
    /// default): the factorization and the products with `P` then skip the zeros outside the
    /// blocks. A promise the solver does not check: entries outside the blocks are ignored.
    /// Sizes that do not add up to the problem's size are ignored too.
    ///
    /// ```
    /// use nalgebra::{DMatrix, DVector};
    /// use stance_robot::ik::{DenseQpOptions, DenseQpStatus, DenseQpWorkspace};
    /// // two 1 x 1 blocks: minimize |x - (1, 2)|^2 subject to x0 + x1 = 1
    /// let p = DMatrix::identity(2, 2) * 2.0;
    /// let c = DVector::from_vec(vec![-2.0, -4.0]);
    /// let a = DMatrix::from_row_slice(1, 2, &[1.0, 1.0]);
    /// let b = DVector::from_vec(vec![1.0]);
    /// let mut ws = DenseQpWorkspace::new();
    /// ws.set_blocks(&[1, 1]);
    /// let rep = ws.solve(&p, &c, &a, &b, &[f64::NEG_INFINITY; 2], &[f64::INFINITY; 2],
    ///     &DenseQpOptions::default());
    /// assert_eq!(rep.status, DenseQpStatus::Optimal);
    /// assert!((ws.solution()[0] - 0.0).abs() < 1e-12 && (ws.solution()[1] - 1.0).abs() < 1e-12);
    /// ```
    pub fn set_blocks(&mut self, sizes: &[usize]) {
        if self.block_sizes != sizes {
            self.block_sizes.clear();
            self.block_sizes.extend_from_slice(sizes);
            self.block.clear();
        }
    }

    /// The block ranges of `n` coordinates ([`Self::set_blocks`]), laid out once per size.
    fn layout_blocks(&mut self, n: usize) {
        if self.block.len() == n {
            return;
        }
        self.block.clear();
        if self.block_sizes.iter().sum::<usize>() == n {
            let mut start = 0;
            for &k in &self.block_sizes {
                self.block
                    .extend(std::iter::repeat_n((start, start + k), k));
                start += k;
            }
        } else {
            self.block.resize(n, (0, n));
        }
    }

    fn resize(&mut self, n: usize, m: usize) {
        if self.n != n || self.m != m || self.held.len() != n {
            self.n = n;
            self.m = m;
            self.held = vec![Held::Free; n];
            self.free = Vec::with_capacity(n);
            self.l = vec![0.0; n * n];
            self.y = vec![0.0; n * m.max(1)];
            self.s = vec![0.0; m * m];
            self.z = vec![0.0; n];
            self.r = vec![0.0; n];
            self.x = vec![0.0; n];
            self.lambda = vec![0.0; m];
        }
    }

    /// Solves the QP of the module doc; the answer is in [`Self::solution`]. Dimensions must
    /// agree (`P` n x n, `c` n, `A` m x n, `b` m, `lo`, `hi` n; the caller checks them).
    ///
    /// ```
    /// use nalgebra::{DMatrix, DVector};
    /// use stance_robot::ik::{DenseQpOptions, DenseQpStatus, DenseQpWorkspace};
    /// // minimize |x - (1, 2)|^2 subject to x0 + x1 = 1, x1 <= 0.25
    /// let p = DMatrix::identity(2, 2) * 2.0;
    /// let c = DVector::from_vec(vec![-2.0, -4.0]);
    /// let a = DMatrix::from_row_slice(1, 2, &[1.0, 1.0]);
    /// let b = DVector::from_vec(vec![1.0]);
    /// let mut ws = DenseQpWorkspace::new();
    /// let rep = ws.solve(&p, &c, &a, &b, &[f64::NEG_INFINITY; 2], &[f64::INFINITY, 0.25],
    ///     &DenseQpOptions::default());
    /// assert_eq!(rep.status, DenseQpStatus::Optimal);
    /// let x = ws.solution();
    /// assert!((x[0] - 0.75).abs() < 1e-12 && (x[1] - 0.25).abs() < 1e-12);
    /// ```
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        p: &DMatrix<f64>,
        c: &DVector<f64>,
        a: &DMatrix<f64>,
        b: &DVector<f64>,
        lo: &[f64],
        hi: &[f64],
        opts: &DenseQpOptions,
    ) -> DenseQpReport {
        let (n, m) = (p.nrows(), a.nrows());
        self.resize(n, m);
        self.layout_blocks(n);
        // A warm-start bound that no longer exists is dropped.
        for i in 0..n {
            match self.held[i] {
                Held::Lower if !lo[i].is_finite() => self.held[i] = Held::Free,
                Held::Upper if !hi[i].is_finite() => self.held[i] = Held::Free,
                _ => {}
            }
        }
        let bscale = b.amax().max(1.0);
        let mut report = DenseQpReport::unsolved();
        // the coordinates the last iteration held at once, the most violated first
        let mut joined: Vec<(usize, f64)> = Vec::new();
        for it in 1..=opts.max_iterations {
            report.iterations = it;
            self.place_held(lo, hi);
            if !self.kkt(p, c, a, b) {
                if joined.len() > 1 {
                    // Holding them all at once left too few free coordinates for the
                    // equations: hold only the most violated one.
                    for &(i, _) in &joined[1..] {
                        self.held[i] = Held::Free;
                    }
                    joined.truncate(1);
                    continue;
                }
                report.status = DenseQpStatus::Singular;
                return report;
            }
            // Free coordinates that left their box join the working set.
            joined.clear();
            for &i in &self.free {
                let tol = opts.primal_tol;
                let below = lo[i] - self.x[i];
                let above = self.x[i] - hi[i];
                if lo[i].is_finite() && below > tol * lo[i].abs().max(1.0) {
                    self.held[i] = Held::Lower;
                    joined.push((i, below / lo[i].abs().max(1.0)));
                } else if hi[i].is_finite() && above > tol * hi[i].abs().max(1.0) {
                    self.held[i] = Held::Upper;
                    joined.push((i, above / hi[i].abs().max(1.0)));
                }
            }
            if !joined.is_empty() {
                joined.sort_by(|x, y| y.1.total_cmp(&x.1));
                continue;
            }
            // Multipliers of the held coordinates: release the worst wrong-signed one.
            let any_held = self.held.iter().any(|h| *h != Held::Free);
            let gscale = if any_held {
                (p.amax() * self.x.iter().fold(0.0f64, |s, v| s.max(v.abs())))
                    .max(c.amax())
                    .max(1.0)
            } else {
                1.0
            };
            let mut worst: Option<(usize, f64)> = None;
            let mut active = 0;
            for i in 0..n {
                if self.held[i] == Held::Free {
                    continue;
                }
                active += 1;
                let g = self.gradient(p, c, a, i);
                let wrong = if self.held[i] == Held::Lower { -g } else { g };
                if wrong > opts.dual_tol * gscale && worst.is_none_or(|(_, w)| wrong > w) {
                    worst = Some((i, wrong));
                }
            }
            if let Some((i, _)) = worst {
                self.held[i] = Held::Free;
                continue;
            }
            report.active = active;
            report.dual_violation = 0.0;
            report.bound_violation = (0..n).fold(0.0f64, |v, i| {
                v.max(lo[i] - self.x[i]).max(self.x[i] - hi[i])
            });
            // A x column by column (A is column-major), into the scratch `r`
            let ax = &mut self.r[..m];
            ax.iter_mut().for_each(|v| *v = 0.0);
            for (i, xi) in self.x.iter().enumerate() {
                for (v, aki) in ax.iter_mut().zip(a.column(i).iter()) {
                    *v += aki * xi;
                }
            }
            report.equality_residual = ax
                .iter()
                .zip(b.iter())
                .fold(0.0f64, |v, (ax, b)| v.max((ax - b).abs()));
            let bound_ok = (0..n).all(|i| {
                self.x[i] >= lo[i] - opts.primal_tol * lo[i].abs().max(1.0)
                    && self.x[i] <= hi[i] + opts.primal_tol * hi[i].abs().max(1.0)
            });
            let ax_scale = a.amax() * self.x.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            let eq_ok = report.equality_residual <= opts.primal_tol * bscale.max(ax_scale);
            report.status = if bound_ok && eq_ok && report.bound_violation.is_finite() {
                DenseQpStatus::Optimal
            } else {
                DenseQpStatus::NotConverged
            };
            return report;
        }
        report
    }

    /// Solves the QP with general inequality rows `G x <= h` too (module doc); the answer is in
    /// [`Self::solution`]. Without rows it is [`Self::solve`].
    ///
    /// ```
    /// use nalgebra::{DMatrix, DVector};
    /// use stance_robot::ik::{DenseQpOptions, DenseQpStatus, DenseQpWorkspace};
    /// // minimize |x - (1, 2)|^2 subject to x0 + x1 <= 1
    /// let p = DMatrix::identity(2, 2) * 2.0;
    /// let c = DVector::from_vec(vec![-2.0, -4.0]);
    /// let g = DMatrix::from_row_slice(1, 2, &[1.0, 1.0]);
    /// let h = DVector::from_vec(vec![1.0]);
    /// let (a, b) = (DMatrix::zeros(0, 2), DVector::zeros(0));
    /// let mut ws = DenseQpWorkspace::new();
    /// let rep = ws.solve_with_rows(&p, &c, &a, &b, &g, &h, &[f64::NEG_INFINITY; 2],
    ///     &[f64::INFINITY; 2], &DenseQpOptions::default());
    /// assert_eq!(rep.status, DenseQpStatus::Optimal);
    /// let x = ws.solution();
    /// assert!((x[0] - 0.0).abs() < 1e-12 && (x[1] - 1.0).abs() < 1e-12);
    /// ```
    #[allow(clippy::too_many_arguments)]
    pub fn solve_with_rows(
        &mut self,
        p: &DMatrix<f64>,
        c: &DVector<f64>,
        a: &DMatrix<f64>,
        b: &DVector<f64>,
        g: &DMatrix<f64>,
        h: &DVector<f64>,
        lo: &[f64],
        hi: &[f64],
        opts: &DenseQpOptions,
    ) -> DenseQpReport {
        let (k, m, n) = (g.nrows(), a.nrows(), p.nrows());
        if k == 0 {
            return self.solve(p, c, a, b, lo, hi, opts);
        }
        if self.row_active.len() != k {
            self.row_active = vec![false; k];
        }
        let mut report = DenseQpReport::unsolved();
        let mut iterations = 0;
        for _ in 0..opts.max_iterations {
            let held: Vec<usize> = (0..k).filter(|&j| self.row_active[j]).collect();
            let rows = m + held.len();
            let (mut a_rows, mut b_rows) = (
                std::mem::take(&mut self.a_rows),
                std::mem::take(&mut self.b_rows),
            );
            if a_rows.shape() != (rows, n) {
                a_rows = DMatrix::zeros(rows, n);
                b_rows = DVector::zeros(rows);
            }
            a_rows.rows_mut(0, m).copy_from(a);
            b_rows.rows_mut(0, m).copy_from(b);
            for (r, &j) in held.iter().enumerate() {
                a_rows.row_mut(m + r).copy_from(&g.row(j));
                b_rows[m + r] = h[j];
            }
            report = self.solve(p, c, &a_rows, &b_rows, lo, hi, opts);
            self.a_rows = a_rows;
            self.b_rows = b_rows;
            iterations += report.iterations;
            report.iterations = iterations;
            if report.status != DenseQpStatus::Optimal {
                return report;
            }
            // a held row pulling the wrong way leaves
            let gscale = (p.amax() * self.x.iter().fold(0.0f64, |s, v| s.max(v.abs())))
                .max(c.amax())
                .max(1.0);
            let worst_held = held
                .iter()
                .enumerate()
                .map(|(r, &j)| (j, -self.lambda[m + r]))
                .filter(|&(_, wrong)| wrong > opts.dual_tol * gscale)
                .max_by(|x, y| x.1.total_cmp(&y.1));
            if let Some((j, _)) = worst_held {
                self.row_active[j] = false;
                continue;
            }
            // the most violated free row joins
            let worst_free = (0..k)
                .filter(|&j| !self.row_active[j])
                .map(|j| {
                    let gx: f64 = g.row(j).iter().zip(&self.x).map(|(u, v)| u * v).sum();
                    (j, gx - h[j], opts.primal_tol * h[j].abs().max(1.0))
                })
                .filter(|&(_, excess, tol)| excess > tol)
                .max_by(|x, y| x.1.total_cmp(&y.1));
            if let Some((j, _, _)) = worst_free {
                self.row_active[j] = true;
                continue;
            }
            return report;
        }
        report.status = DenseQpStatus::NotConverged;
        report
    }

    /// `(P x + c + A^T lambda)_i`.
    fn gradient(&self, p: &DMatrix<f64>, c: &DVector<f64>, a: &DMatrix<f64>, i: usize) -> f64 {
        let mut g = c[i];
        let (start, end) = self.block[i];
        for j in start..end {
            g += p[(i, j)] * self.x[j];
        }
        for k in 0..self.m {
            g += a[(k, i)] * self.lambda[k];
        }
        g
    }

    /// Solves the KKT system of the current working set into `x` and `lambda`; `false` when a
    /// factorization meets a non-positive pivot.
    fn kkt(
        &mut self,
        p: &DMatrix<f64>,
        c: &DVector<f64>,
        a: &DMatrix<f64>,
        b: &DVector<f64>,
    ) -> bool {
        let (n, m) = (self.n, self.m);
        self.free.clear();
        self.free
            .extend((0..n).filter(|&i| self.held[i] == Held::Free));
        let nf = self.free.len();
        // each free coordinate's block among the free ones (the free list is increasing)
        self.free_block.clear();
        for &i in &self.free {
            let (start, end) = self.block[i];
            self.free_block.push((
                self.free.partition_point(|&j| j < start),
                self.free.partition_point(|&j| j < end),
            ));
        }
        // r = -(c_F + P_FW x_W); b' = b - A_W x_W
        for (fi, &i) in self.free.iter().enumerate() {
            let mut v = -c[i];
            let (start, end) = self.block[i];
            for j in start..end {
                if self.held[j] != Held::Free {
                    v -= p[(i, j)] * self.x[j];
                }
            }
            self.r[fi] = v;
        }
        // P_FF into l (its blocks), then Cholesky in place (lower, column-major).
        for (cj, &j) in self.free.iter().enumerate() {
            let end = self.free_block[cj].1;
            for (ci, &i) in self.free.iter().enumerate().take(end).skip(cj) {
                self.l[cj * nf + ci] = p[(i, j)];
            }
        }
        if !cholesky_blocks(&mut self.l, nf, Some(&self.free_block), 0.0) {
            return false;
        }
        self.l_inv.clear();
        self.l_inv.extend((0..nf).map(|j| 1.0 / self.l[j * nf + j]));
        // z = L^-1 r
        self.z[..nf].copy_from_slice(&self.r[..nf]);
        forward_blocks(&self.l, &self.l_inv, &self.free_block, &mut self.z[..nf]);
        if m > 0 {
            // Y = L^-1 A_F^T, and Y^T Y, Y^T z - b'
            for k in 0..m {
                let col = &mut self.y[k * nf..(k + 1) * nf];
                for (fi, &i) in self.free.iter().enumerate() {
                    col[fi] = a[(k, i)];
                }
                forward_blocks(&self.l, &self.l_inv, &self.free_block, col);
            }
            let mut diag_max = 0.0f64;
            for k in 0..m {
                for l in k..m {
                    let yk = &self.y[k * nf..(k + 1) * nf];
                    let yl = &self.y[l * nf..(l + 1) * nf];
                    let d: f64 = yk.iter().zip(yl).map(|(u, v)| u * v).sum();
                    self.s[k * m + l] = d;
                    if k == l {
                        diag_max = diag_max.max(d);
                    }
                }
                let yk = &self.y[k * nf..(k + 1) * nf];
                let mut rhs: f64 = yk.iter().zip(&self.z[..nf]).map(|(u, v)| u * v).sum();
                rhs -= b[k];
                for j in 0..n {
                    if self.held[j] != Held::Free {
                        rhs += a[(k, j)] * self.x[j];
                    }
                }
                self.lambda[k] = rhs;
            }
            // Y^T Y is filled in its lower triangle (s[k * m + l], l >= k, column k).
            if !cholesky_blocks(&mut self.s, m, None, diag_max * crate::tol::IK_DENSE_PIVOT) {
                return false;
            }
            forward_solve(&self.s, m, &mut self.lambda);
            backward_solve(&self.s, m, &mut self.lambda);
            // z <- z - Y lambda
            for k in 0..m {
                let lk = self.lambda[k];
                let yk = &self.y[k * nf..(k + 1) * nf];
                for (zi, yi) in self.z[..nf].iter_mut().zip(yk) {
                    *zi -= yi * lk;
                }
            }
        }
        backward_blocks(&self.l, &self.l_inv, &self.free_block, &mut self.z[..nf]);
        for (fi, &i) in self.free.iter().enumerate() {
            self.x[i] = self.z[fi];
        }
        true
    }

    /// Puts every held coordinate on its bound.
    fn place_held(&mut self, lo: &[f64], hi: &[f64]) {
        for i in 0..self.n {
            match self.held[i] {
                Held::Lower => self.x[i] = lo[i],
                Held::Upper => self.x[i] = hi[i],
                Held::Free => {}
            }
        }
    }
}

/// In-place Cholesky of the `n x n` lower triangle of a block-diagonal `a` (column-major):
/// `a = L L^T`, with `blocks[j] = (start, end)` the rows and columns of `j`'s block (`None`:
/// one dense block); `L` keeps the blocks, and nothing outside them is read or written.
/// `false` on a pivot (squared) at most `min_pivot`.
fn cholesky_blocks(
    a: &mut [f64],
    n: usize,
    blocks: Option<&[(usize, usize)]>,
    min_pivot: f64,
) -> bool {
    for j in 0..n {
        let (start, end) = blocks.map_or((0, n), |b| b[j]);
        // a[j][j] -= sum_k<j L[j][k]^2
        let mut d = a[j * n + j];
        for k in start..j {
            let l = a[k * n + j];
            d -= l * l;
        }
        if d.is_nan() || d <= min_pivot || !d.is_finite() {
            return false;
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        // column j below the diagonal: L[i][j] = (a[i][j] - sum_k<j L[i][k] L[j][k]) / d
        for k in start..j {
            let ljk = a[k * n + j];
            if ljk == 0.0 {
                continue;
            }
            let (head, tail) = a.split_at_mut(j * n);
            let colk = &head[k * n..(k + 1) * n];
            let colj = &mut tail[..n];
            for i in j + 1..end {
                colj[i] -= colk[i] * ljk;
            }
        }
        let inv = 1.0 / d;
        for v in &mut a[j * n + j + 1..j * n + end] {
            *v *= inv;
        }
    }
    true
}

/// [`forward_solve`] for a block-diagonal `L` ([`cholesky_blocks`]), `inv` its inverse
/// diagonal.
fn forward_blocks(l: &[f64], inv: &[f64], blocks: &[(usize, usize)], v: &mut [f64]) {
    let n = inv.len();
    for j in 0..n {
        let x = v[j] * inv[j];
        v[j] = x;
        let end = blocks[j].1;
        if x != 0.0 {
            let col = &l[j * n + j + 1..j * n + end];
            for (vi, li) in v[j + 1..end].iter_mut().zip(col) {
                *vi -= li * x;
            }
        }
    }
}

/// [`backward_solve`] for a block-diagonal `L` ([`cholesky_blocks`]), `inv` its inverse
/// diagonal.
fn backward_blocks(l: &[f64], inv: &[f64], blocks: &[(usize, usize)], v: &mut [f64]) {
    let n = inv.len();
    for j in (0..n).rev() {
        let end = blocks[j].1;
        let col = &l[j * n + j + 1..j * n + end];
        let s: f64 = col.iter().zip(&v[j + 1..end]).map(|(li, vi)| li * vi).sum();
        v[j] = (v[j] - s) * inv[j];
    }
}

/// Solves `L y = v` in place (`L` lower, column-major, `n x n`).
fn forward_solve(l: &[f64], n: usize, v: &mut [f64]) {
    for j in 0..n {
        let x = v[j] / l[j * n + j];
        v[j] = x;
        if x != 0.0 {
            let col = &l[j * n + j + 1..(j + 1) * n];
            for (vi, li) in v[j + 1..n].iter_mut().zip(col) {
                *vi -= li * x;
            }
        }
    }
}

/// Solves `L^T y = v` in place.
fn backward_solve(l: &[f64], n: usize, v: &mut [f64]) {
    for j in (0..n).rev() {
        let col = &l[j * n + j + 1..(j + 1) * n];
        let s: f64 = col.iter().zip(&v[j + 1..n]).map(|(li, vi)| li * vi).sum();
        v[j] = (v[j] - s) / l[j * n + j];
    }
}
