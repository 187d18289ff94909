//! The double description of [`super::DdCore`] for small inputs, with the dimension fixed at
//! compile time: at most 64 rows (one-word zero sets) and a few dozen rays.
//!
//! The certificate runs one such conversion per facet that has neither closed form (the ridges
//! of a facet are the facets of the cone of its tight generators, in its hyperplane: typically
//! 7 to 9 rows in 5-D for the paper's wrench cones), so its fixed costs matter more than its
//! asymptotics. It takes exactly the decisions of [`super::DdCore::run`], with the same
//! floating-point operations in the same order, so the rays agree bit for bit (unit test); it
//! only drops the generality: the basis is solved in fixed-size arrays and the rays live in
//! flat buffers indexed with a compile-time stride.

use super::core::DdFailure;

/// Largest number of rows handled here (zero sets are one `u64`).
pub(crate) const MAX_ROWS: usize = 64;

/// Reusable buffers of [`SmallDd::run`].
#[derive(Clone, Debug, Default)]
pub(crate) struct SmallDd {
    /// Current rays (`n x k`, unit) and their zero sets.
    pub x: Vec<f64>,
    pub z: Vec<u64>,
    next_x: Vec<f64>,
    next_z: Vec<u64>,
    slack: Vec<f64>,
    plus: Vec<u32>,
    minus: Vec<u32>,
    zero: Vec<u32>,
    resid: Vec<f64>,
}

impl SmallDd {
    /// Number of current rays.
    #[inline]
    pub fn n(&self) -> usize {
        self.z.len()
    }

    /// The extreme rays of `{x : A x <= 0}` (`a`: `m x k` row-major, unit rows), as
    /// [`super::DdCore::run`] computes them. `None` when the input is outside this routine's
    /// range (`m > 64`, `k` not in `3..=8`, or more than `max_rays` rays at some step): run
    /// [`super::DdCore`] instead.
    pub fn run(
        &mut self,
        a: &[f64],
        m: usize,
        k: usize,
        eps_zero: f64,
        eps_rank: f64,
        max_rays: usize,
    ) -> Option<Result<(), DdFailure>> {
        if m > MAX_ROWS || m < k {
            return None;
        }
        match k {
            3 => self.run_k::<3>(a, m, eps_zero, eps_rank, max_rays),
            4 => self.run_k::<4>(a, m, eps_zero, eps_rank, max_rays),
            5 => self.run_k::<5>(a, m, eps_zero, eps_rank, max_rays),
            6 => self.run_k::<6>(a, m, eps_zero, eps_rank, max_rays),
            7 => self.run_k::<7>(a, m, eps_zero, eps_rank, max_rays),
            8 => self.run_k::<8>(a, m, eps_zero, eps_rank, max_rays),
            _ => None,
        }
    }

    fn run_k<const K: usize>(
        &mut self,
        a: &[f64],
        m: usize,
        eps_zero: f64,
        eps_rank: f64,
        max_rays: usize,
    ) -> Option<Result<(), DdFailure>> {
        debug_assert_eq!(a.len(), m * K);
        self.x.clear();
        self.z.clear();
        // Basis: greedy pivoted Gram-Schmidt (the first row clear of the span, else the
        // largest residual), as `DdCore`.
        let clear = crate::tol::BASIS_CLEAR * crate::tol::BASIS_CLEAR;
        self.resid.clear();
        self.resid.extend_from_slice(a);
        let mut used = 0u64;
        let mut basis = [0usize; 8];
        let mut q = [0.0f64; K];
        for slot in basis.iter_mut().take(K) {
            let mut best = usize::MAX;
            let mut best_norm = -1.0;
            for (i, r) in self.resid.chunks_exact(K).enumerate() {
                if used >> i & 1 == 1 {
                    continue;
                }
                let nn: f64 = r.iter().map(|v| v * v).sum();
                if nn >= clear {
                    best_norm = nn;
                    best = i;
                    break;
                }
                if nn > best_norm * (1.0 + crate::tol::BASIS_TIE) {
                    best_norm = nn;
                    best = i;
                }
            }
            if best == usize::MAX || best_norm.sqrt() <= eps_rank {
                return Some(Err(DdFailure::RankDeficient));
            }
            let inv = 1.0 / best_norm.sqrt();
            used |= 1 << best;
            *slot = best;
            for (qv, &rv) in q.iter_mut().zip(&self.resid[best * K..(best + 1) * K]) {
                *qv = rv * inv;
            }
            for (i, r) in self.resid.chunks_exact_mut(K).enumerate() {
                if used >> i & 1 == 1 {
                    continue;
                }
                let d: f64 = r.iter().zip(q.iter()).map(|(x, y)| x * y).sum();
                for (x, y) in r.iter_mut().zip(q.iter()) {
                    *x -= d * y;
                }
            }
        }
        // Initial rays: the columns of -A_K^{-1}, by Gauss-Jordan with partial pivoting on
        // [A_K | I], as `DdCore`.
        let mut aug = [[0.0f64; 16]; K];
        for (r, row) in aug.iter_mut().enumerate() {
            row[..K].copy_from_slice(&a[basis[r] * K..(basis[r] + 1) * K]);
            row[K + r] = 1.0;
        }
        let w = 2 * K;
        for c in 0..K {
            let mut p = c;
            for r in c + 1..K {
                if aug[r][c].abs() > aug[p][c].abs() {
                    p = r;
                }
            }
            if aug[p][c] == 0.0 {
                return Some(Err(DdFailure::RankDeficient));
            }
            aug.swap(p, c);
            let inv = 1.0 / aug[c][c];
            for v in &mut aug[c][c..w] {
                *v *= inv;
            }
            let pivot = aug[c];
            for (r, row) in aug.iter_mut().enumerate() {
                if r == c {
                    continue;
                }
                let f = row[c];
                if f != 0.0 {
                    for (x, y) in row[c..w].iter_mut().zip(&pivot[c..w]) {
                        *x -= f * y;
                    }
                }
            }
        }
        let basis_mask = basis[..K].iter().fold(0u64, |s, &b| s | 1 << b);
        for i in 0..K {
            let start = self.x.len();
            let mut nn = 0.0;
            for row in aug.iter() {
                let v = -row[K + i];
                self.x.push(v);
                nn += v * v;
            }
            let inv = 1.0 / nn.sqrt();
            for v in &mut self.x[start..] {
                *v *= inv;
            }
            self.z.push(basis_mask & !(1 << basis[i]));
        }
        // The other rows in input order.
        let need = K.saturating_sub(2) as u32;
        for j in 0..m {
            if used >> j & 1 == 1 {
                continue;
            }
            let row: &[f64; K] = a[j * K..(j + 1) * K].try_into().expect("row of length K");
            match self.add_row::<K>(row, j, eps_zero, need, max_rays) {
                Some(Ok(())) => {}
                other => return other,
            }
            if self.z.is_empty() {
                break;
            }
        }
        Some(Ok(()))
    }

    #[inline(always)]
    fn add_row<const K: usize>(
        &mut self,
        row: &[f64; K],
        j: usize,
        eps_zero: f64,
        need: u32,
        max_rays: usize,
    ) -> Option<Result<(), DdFailure>> {
        let bit = 1u64 << j;
        self.slack.clear();
        self.plus.clear();
        self.minus.clear();
        self.zero.clear();
        for (i, x) in self.x.chunks_exact(K).enumerate() {
            let s: f64 = row.iter().zip(x).map(|(u, v)| u * v).sum();
            self.slack.push(s);
            if s > eps_zero {
                self.plus.push(i as u32);
            } else if s < -eps_zero {
                self.minus.push(i as u32);
            } else {
                self.zero.push(i as u32);
            }
        }
        if self.plus.is_empty() {
            for &i in &self.zero {
                self.z[i as usize] |= bit;
            }
            return Some(Ok(()));
        }
        self.next_x.clear();
        self.next_z.clear();
        for &i in &self.minus {
            let i = i as usize;
            self.next_x.extend_from_slice(&self.x[i * K..(i + 1) * K]);
            self.next_z.push(self.z[i]);
        }
        for &i in &self.zero {
            let i = i as usize;
            self.next_x.extend_from_slice(&self.x[i * K..(i + 1) * K]);
            self.next_z.push(self.z[i] | bit);
        }
        let z = &self.z;
        for &p in &self.plus {
            let p = p as usize;
            let zp = z[p];
            for &q in &self.minus {
                let q = q as usize;
                let common = zp & z[q];
                if common.count_ones() < need {
                    continue;
                }
                if z.iter().filter(|&&zr| common & !zr == 0).count() > 2 {
                    continue;
                }
                if self.next_z.len() >= max_rays {
                    return None;
                }
                let (sp, sq) = (self.slack[p], self.slack[q]);
                let (xp, xq) = (&self.x[p * K..(p + 1) * K], &self.x[q * K..(q + 1) * K]);
                let mut out = [0.0f64; K];
                let mut nn = 0.0;
                for ((o, &a), &b) in out.iter_mut().zip(xq).zip(xp) {
                    let v = sp * a - sq * b;
                    *o = v;
                    nn += v * v;
                }
                if nn.is_nan() || nn <= 0.0 || !nn.is_finite() {
                    return Some(Err(DdFailure::Cancellation));
                }
                let inv = 1.0 / nn.sqrt();
                for v in out.iter_mut() {
                    *v *= inv;
                }
                self.next_x.extend_from_slice(&out);
                self.next_z.push(common | bit);
            }
        }
        std::mem::swap(&mut self.x, &mut self.next_x);
        std::mem::swap(&mut self.z, &mut self.next_z);
        Some(Ok(()))
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{unit_rows, Lcg};
    use super::super::DdCore;
    use super::*;

    /// Bit for bit the rays and zero sets of `DdCore::run`, on generic and degenerate inputs
    /// of the sizes the certificate sends here (and a few larger ones).
    #[test]
    fn small_matches_dd_core_bit_for_bit() {
        let mut rng = Lcg(0x2545f4914f6cdd1d);
        let mut compared = 0;
        let mut small = SmallDd::default();
        let mut core = DdCore::default();
        for case in 0..600 {
            let k = 3 + case % 6;
            let m = k + (case * 7) % 12;
            let degenerate = case % 3 == 0;
            let a = unit_rows(&mut rng, m, k, degenerate);
            let rc = core.run(&a, m, k, 1e-9, 1e-10);
            let Some(rs) = small.run(&a, m, k, 1e-9, 1e-10, 4096) else {
                panic!("case {case}: out of range");
            };
            assert_eq!(rc, rs, "case {case}");
            if rc.is_err() {
                continue;
            }
            assert_eq!(core.n, small.n(), "case {case}");
            for i in 0..core.n {
                assert_eq!(core.z[i], small.z[i], "case {case} ray {i}");
                let xs = &small.x[i * k..(i + 1) * k];
                assert!(
                    core.ray(i)
                        .iter()
                        .zip(xs)
                        .all(|(p, q)| p.to_bits() == q.to_bits()),
                    "case {case} ray {i}"
                );
            }
            compared += 1;
        }
        assert!(compared > 400, "{compared}");
        // Out of range: too many rows, or too many rays for the cap.
        assert!(small
            .run(&vec![1.0; 65 * 3], 65, 3, 1e-9, 1e-10, 64)
            .is_none());
    }
}
