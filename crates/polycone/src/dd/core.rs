//! The double description iteration on a pointed cone `{x in R^k : A x <= 0}`, `A` of full
//! column rank `k` (see the module doc of [`crate::dd`]). All buffers live in [`DdCore`] and are
//! reused across calls: once warm, a conversion of the same size does not allocate.

use super::bitset;
use super::scan::Scan;
use super::step::Next;

/// Dimensions up to this use stack buffers for small per-call vectors.
const MAX_STACK_K: usize = 16;

/// Why the iteration stopped without an answer.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum DdFailure {
    /// The rows do not contain `k` linearly independent ones at the rank tolerance.
    RankDeficient,
    /// Two rays that should be distinct combined into a (numerically) zero ray.
    Cancellation,
}

/// Reusable state of one double description run.
#[derive(Clone, Debug, Default)]
pub(crate) struct DdCore {
    /// Dimension of the space.
    pub k: usize,
    /// Number of constraint rows.
    pub m: usize,
    /// Words per zero set.
    pub words: usize,
    /// Current rays, `n * k`, each a unit vector.
    pub x: Vec<f64>,
    /// Zero sets of the current rays, `n * words`.
    pub z: Vec<u64>,
    /// Number of current rays.
    pub n: usize,
    /// The rays of the next cone, during a step.
    pub(super) next: Next,
    pub(super) slack: Vec<f64>,
    pub(super) plus: Vec<u32>,
    pub(super) minus: Vec<u32>,
    pub(super) zero: Vec<u32>,
    pub(super) tmp: Vec<u64>,
    order: Vec<usize>,
    in_basis: Vec<bool>,
    basis: Vec<usize>,
    resid: Vec<f64>,
    aug: Vec<f64>,
    /// Transposed incidence of the current rays: for each row `j`, the bitset (over rays) of
    /// the rays tight on `j`; `m * ray_words` words.
    pub(super) col: Vec<u64>,
    pub(super) acc: Vec<u64>,
    pub(super) zp: Vec<u64>,
    pub(super) zn: Vec<u64>,
    pub(super) cand: Vec<(u32, u32)>,
    /// Candidate indices into `minus` for one ray of `plus` (one-word path).
    pub(super) cand_idx: Vec<u32>,
    /// The compiled variant of the bitset scans this CPU runs.
    pub(super) scan: Scan,
    /// Number of adjacency candidates examined in the last run (for profiling).
    pub pairs_tested: usize,
    /// Tests only: take the multi-word path even when one word would do, to check the
    /// one-word fast path against it.
    #[cfg(test)]
    pub(super) force_multi_word: bool,
}

impl DdCore {
    /// Ray `i` as a slice.
    #[inline]
    pub fn ray(&self, i: usize) -> &[f64] {
        &self.x[i * self.k..(i + 1) * self.k]
    }

    /// Computes the extreme rays of `{x : A x <= 0}`; `a` is `m x k` row-major with unit rows
    /// and full column rank. `eps_zero` decides `a . x = 0` (unit vectors), `eps_rank` the
    /// initial basis.
    pub fn run(
        &mut self,
        a: &[f64],
        m: usize,
        k: usize,
        eps_zero: f64,
        eps_rank: f64,
    ) -> Result<(), DdFailure> {
        debug_assert_eq!(a.len(), m * k);
        self.k = k;
        self.m = m;
        self.words = bitset::words_for(m);
        self.n = 0;
        self.x.clear();
        self.z.clear();
        self.pairs_tested = 0;
        self.scan = Scan::detect();
        if k == 0 {
            return Ok(());
        }
        // Monomorphized copies for the common dimensions (3 to 8; the wrench cones of the paper
        // are 6-D, their facets 5-D): fixed-length inner loops unroll; others take the generic
        // path (`K = 0`).
        match k {
            3 => self.run_k::<3>(a, m, eps_zero, eps_rank),
            4 => self.run_k::<4>(a, m, eps_zero, eps_rank),
            5 => self.run_k::<5>(a, m, eps_zero, eps_rank),
            6 => self.run_k::<6>(a, m, eps_zero, eps_rank),
            7 => self.run_k::<7>(a, m, eps_zero, eps_rank),
            8 => self.run_k::<8>(a, m, eps_zero, eps_rank),
            _ => self.run_k::<0>(a, m, eps_zero, eps_rank),
        }
    }

    /// [`Self::run`] with the dimension `k = K` fixed at compile time (`K = 0`: `self.k`).
    fn run_k<const K: usize>(
        &mut self,
        a: &[f64],
        m: usize,
        eps_zero: f64,
        eps_rank: f64,
    ) -> Result<(), DdFailure> {
        let k = dim::<K>(self.k);
        self.choose_basis::<K>(a, m, eps_rank)?;
        self.initial_rays::<K>(a)?;
        // Insertion order: the rows not in the basis, in input order.
        self.order.clear();
        for j in 0..m {
            if !self.in_basis[j] {
                self.order.push(j);
            }
        }
        let order = std::mem::take(&mut self.order);
        let mut result = Ok(());
        for &j in &order {
            if let Err(e) = self.add_row::<K>(&a[j * k..(j + 1) * k], j, eps_zero) {
                result = Err(e);
                break;
            }
            if self.n == 0 {
                // The cone is {0}: no row can change that.
                break;
            }
        }
        self.order = order;
        result
    }

    /// Greedy pivoted Gram-Schmidt: picks `k` rows, each the first in input order whose
    /// residual off those taken is at least [`crate::tol::BASIS_CLEAR`] (unit rows), or, when
    /// none is, the one of largest residual (a later row replaces the best so far only if it
    /// beats it by [`crate::tol::BASIS_TIE`]).
    fn choose_basis<const K: usize>(
        &mut self,
        a: &[f64],
        m: usize,
        eps_rank: f64,
    ) -> Result<(), DdFailure> {
        let k = dim::<K>(self.k);
        self.resid.clear();
        self.resid.extend_from_slice(a);
        self.in_basis.clear();
        self.in_basis.resize(m, false);
        self.basis.clear();
        let mut q = [0.0f64; MAX_STACK_K];
        let mut q_heap = Vec::new();
        let q: &mut [f64] = if k <= MAX_STACK_K {
            &mut q[..k]
        } else {
            q_heap.resize(k, 0.0);
            &mut q_heap
        };
        let clear = crate::tol::BASIS_CLEAR * crate::tol::BASIS_CLEAR;
        for _ in 0..k {
            let mut best = usize::MAX;
            let mut best_norm = -1.0;
            for (i, (r, &used)) in self.resid.chunks_exact(k).zip(&self.in_basis).enumerate() {
                if used {
                    continue;
                }
                let nn: f64 = r.iter().map(|v| v * v).sum();
                // The first row in input order clear of the span of those taken (unit rows:
                // residual at least `BASIS_CLEAR`) starts the basis; otherwise the largest
                // residual, ties within rounding to the first row (the unit rows of a whitened
                // input all have norm 1 to the last bit, so the choice must not depend on it).
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
                return Err(DdFailure::RankDeficient);
            }
            let inv = 1.0 / best_norm.sqrt();
            self.in_basis[best] = true;
            self.basis.push(best);
            // q = resid_best / |resid_best|; orthogonalize the others against it.
            for (qv, &rv) in q.iter_mut().zip(&self.resid[best * k..(best + 1) * k]) {
                *qv = rv * inv;
            }
            for (r, &used) in self.resid.chunks_exact_mut(k).zip(&self.in_basis) {
                if used {
                    continue;
                }
                let d: f64 = r.iter().zip(q.iter()).map(|(x, y)| x * y).sum();
                for (x, y) in r.iter_mut().zip(q.iter()) {
                    *x -= d * y;
                }
            }
        }
        Ok(())
    }

    /// Rays of the simplicial cone `{x : A_K x <= 0}`: the columns of `-A_K^{-1}`.
    fn initial_rays<const K: usize>(&mut self, a: &[f64]) -> Result<(), DdFailure> {
        let k = dim::<K>(self.k);
        let w = 2 * k;
        self.aug.clear();
        self.aug.resize(k * w, 0.0);
        for (r, &row) in self.basis.iter().enumerate() {
            self.aug[r * w..r * w + k].copy_from_slice(&a[row * k..(row + 1) * k]);
            self.aug[r * w + k + r] = 1.0;
        }
        // Gauss-Jordan with partial pivoting.
        for c in 0..k {
            let mut p = c;
            for r in c + 1..k {
                if self.aug[r * w + c].abs() > self.aug[p * w + c].abs() {
                    p = r;
                }
            }
            if self.aug[p * w + c] == 0.0 {
                return Err(DdFailure::RankDeficient);
            }
            if p != c {
                for t in 0..w {
                    self.aug.swap(p * w + t, c * w + t);
                }
            }
            let inv = 1.0 / self.aug[c * w + c];
            let (above, rest) = self.aug.split_at_mut(c * w);
            let (pivot, below) = rest.split_at_mut(w);
            // Columns before `c` are already zero in the pivot row: start at `c`.
            for v in &mut pivot[c..] {
                *v *= inv;
            }
            for row in above.chunks_exact_mut(w).chain(below.chunks_exact_mut(w)) {
                let f = row[c];
                if f != 0.0 {
                    for (x, y) in row[c..].iter_mut().zip(&pivot[c..]) {
                        *x -= f * y;
                    }
                }
            }
        }
        // Column i of the inverse is ray i (negated), tight on every basis row but the i-th.
        self.n = k;
        self.x.resize(k * k, 0.0);
        self.z.clear();
        self.z.resize(k * self.words, 0);
        for i in 0..k {
            let mut nn = 0.0;
            for r in 0..k {
                let v = -self.aug[r * w + k + i];
                self.x[i * k + r] = v;
                nn += v * v;
            }
            let inv = 1.0 / nn.sqrt();
            for r in 0..k {
                self.x[i * k + r] *= inv;
            }
            for (t, &row) in self.basis.iter().enumerate() {
                if t != i {
                    bitset::set(&mut self.z[i * self.words..(i + 1) * self.words], row);
                }
            }
        }
        Ok(())
    }
}

/// The dimension: `K` when fixed at compile time, else `k`.
#[inline(always)]
pub(super) fn dim<const K: usize>(k: usize) -> usize {
    if K == 0 {
        k
    } else {
        debug_assert_eq!(k, K);
        K
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use super::super::testing::{unit_rows as rows, Lcg};

    /// The one-word fast path (plain `u64` masks, candidates and blockers by the vectorized
    /// scans of `dd/scan.rs`) against the multi-word path (slices, candidate list,
    /// transposed incidence or scan): the same rays, bit for bit, in the same order, and the
    /// same zero sets, on generic and degenerate inputs in dimensions 2 to 9.
    #[test]
    fn one_word_path_matches_multi_word_path() {
        let mut rng = Lcg(7);
        let mut compared = 0;
        for case in 0..400 {
            let k = 2 + case % 8;
            let m = k + 1 + (case * 7) % 40;
            let a = rows(&mut rng, m, k, case % 3 == 0);
            let mut fast = DdCore::default();
            let mut slow = DdCore {
                force_multi_word: true,
                ..DdCore::default()
            };
            let rf = fast.run(&a, m, k, 1e-9, 1e-10);
            let rs = slow.run(&a, m, k, 1e-9, 1e-10);
            assert_eq!(rf, rs, "case {case}");
            if rf.is_err() {
                continue;
            }
            assert_eq!(fast.n, slow.n, "case {case}");
            assert_eq!(fast.pairs_tested, slow.pairs_tested, "case {case}");
            for i in 0..fast.n {
                let (xf, xs) = (fast.ray(i), slow.ray(i));
                assert!(
                    xf.iter().zip(xs).all(|(p, q)| p.to_bits() == q.to_bits()),
                    "case {case} ray {i}"
                );
                assert_eq!(fast.z[i], slow.z[i], "case {case} ray {i}");
            }
            compared += 1;
        }
        // Most inputs have full column rank: the comparison is not vacuous.
        assert!(compared > 300, "{compared}");
    }
}
