//! The double description iteration on a pointed cone `{x in R^k : A x <= 0}`, `A` of full
//! column rank `k` (see the module doc of [`crate::dd`]). All buffers live in [`DdCore`] and are
//! reused across calls: once warm, a conversion of the same size does not allocate.

use super::bitset;
use super::scan::Scan;

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
    next_x: Vec<f64>,
    next_z: Vec<u64>,
    slack: Vec<f64>,
    plus: Vec<u32>,
    minus: Vec<u32>,
    zero: Vec<u32>,
    tmp: Vec<u64>,
    order: Vec<usize>,
    in_basis: Vec<bool>,
    basis: Vec<usize>,
    resid: Vec<f64>,
    aug: Vec<f64>,
    /// Transposed incidence of the current rays: for each row `j`, the bitset (over rays) of
    /// the rays tight on `j`; `m * ray_words` words.
    col: Vec<u64>,
    acc: Vec<u64>,
    zp: Vec<u64>,
    zn: Vec<u64>,
    cand: Vec<(u32, u32)>,
    /// Candidate indices into `minus` for one ray of `plus` (one-word path).
    cand_idx: Vec<u32>,
    /// The compiled variant of the bitset scans this CPU runs.
    scan: Scan,
    /// Number of adjacency candidates examined in the last run (for profiling).
    pub pairs_tested: usize,
    /// Tests only: take the multi-word path even when one word would do, to check the
    /// one-word fast path against it.
    #[cfg(test)]
    force_multi_word: bool,
}

impl DdCore {
    /// Appends to `next_x` the new ray on the hyperplane of the row being added, combining the
    /// adjacent rays `p` (slack > 0) and `q` (slack < 0): `slack_p x_q - slack_q x_p`, normalized.
    /// (An associated function over the three buffers, so that callers may hold other fields.)
    #[inline(always)]
    fn push_combination(
        slack: &[f64],
        x: &[f64],
        next_x: &mut Vec<f64>,
        [p, q, k]: [usize; 3],
    ) -> Result<(), DdFailure> {
        let (sp, sq) = (slack[p], slack[q]);
        let start = next_x.len();
        next_x.resize(start + k, 0.0);
        let (xp, xq) = (&x[p * k..(p + 1) * k], &x[q * k..(q + 1) * k]);
        let out = &mut next_x[start..start + k];
        let mut nn = 0.0;
        for ((o, &a), &b) in out.iter_mut().zip(xq).zip(xp) {
            let v = sp * a - sq * b;
            *o = v;
            nn += v * v;
        }
        if nn.is_nan() || nn <= 0.0 || !nn.is_finite() {
            return Err(DdFailure::Cancellation);
        }
        let inv = 1.0 / nn.sqrt();
        for v in out.iter_mut() {
            *v *= inv;
        }
        Ok(())
    }

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

    /// One double description step: intersects the current cone with `{x : row . x <= 0}`.
    pub(super) fn add_row<const K: usize>(
        &mut self,
        row: &[f64],
        j: usize,
        eps_zero: f64,
    ) -> Result<(), DdFailure> {
        #[cfg(test)]
        let one_word = self.words == 1 && !self.force_multi_word;
        #[cfg(not(test))]
        let one_word = self.words == 1;
        if one_word {
            return self.add_row_one_word::<K>(row, j, eps_zero);
        }
        let (k, words) = (dim::<K>(self.k), self.words);
        self.slack.clear();
        self.plus.clear();
        self.minus.clear();
        self.zero.clear();
        for i in 0..self.n {
            let x = &self.x[i * k..(i + 1) * k];
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
                let i = i as usize;
                bitset::set(&mut self.z[i * words..(i + 1) * words], j);
            }
            return Ok(());
        }
        self.next_x.clear();
        self.next_z.clear();
        let mut next_n = 0;
        // Keep R- and R0 (the latter now tight on row j).
        for (&i, is_zero) in self
            .minus
            .iter()
            .map(|i| (i, false))
            .chain(self.zero.iter().map(|i| (i, true)))
        {
            let i = i as usize;
            self.next_x.extend_from_slice(&self.x[i * k..(i + 1) * k]);
            let start = self.next_z.len();
            self.next_z
                .extend_from_slice(&self.z[i * words..(i + 1) * words]);
            if is_zero {
                bitset::set(&mut self.next_z[start..start + words], j);
            }
            next_n += 1;
        }
        // Candidate pairs: |Z(p) ∩ Z(n)| >= k - 2.
        let need = k.saturating_sub(2) as u32;
        self.zp.clear();
        for &p in &self.plus {
            let p = p as usize;
            self.zp
                .extend_from_slice(&self.z[p * words..(p + 1) * words]);
        }
        self.zn.clear();
        for &q in &self.minus {
            let q = q as usize;
            self.zn
                .extend_from_slice(&self.z[q * words..(q + 1) * words]);
        }
        self.cand.clear();
        candidate_pairs(&self.zp, &self.zn, words, need, &mut self.cand);
        // Few candidates: scanning the rays for a blocker is cheaper than building the
        // transposed incidence (measured on 6-D wrench cones).
        let scan = self.cand.len() < 4 * k;
        if scan {
            self.tmp.clear();
            self.tmp.resize(words, 0);
            for ci in 0..self.cand.len() {
                let (pi, ni) = self.cand[ci];
                let p = self.plus[pi as usize] as usize;
                let q = self.minus[ni as usize] as usize;
                for t in 0..words {
                    self.tmp[t] = self.z[p * words + t] & self.z[q * words + t];
                }
                self.pairs_tested += 1;
                let tmp = &self.tmp;
                let blocked = (0..self.n).any(|r| {
                    r != p
                        && r != q
                        && tmp
                            .iter()
                            .zip(&self.z[r * words..(r + 1) * words])
                            .all(|(a, b)| a & !b == 0)
                });
                if blocked {
                    continue;
                }
                Self::push_combination(&self.slack, &self.x, &mut self.next_x, [p, q, k])?;
                let zs = self.next_z.len();
                self.next_z.extend_from_slice(&self.tmp);
                bitset::set(&mut self.next_z[zs..zs + words], j);
                next_n += 1;
            }
        } else if !self.cand.is_empty() {
            // Transposed incidence, for the combinatorial adjacency test: a third ray tight on
            // every row of Z(p) ∩ Z(n) is in the AND of those rows' ray sets.
            let rw = bitset::words_for(self.n);
            self.col.clear();
            self.col.resize(self.m * rw, 0);
            for i in 0..self.n {
                for (wi, &w0) in self.z[i * words..(i + 1) * words].iter().enumerate() {
                    let mut w = w0;
                    while w != 0 {
                        let b = w.trailing_zeros() as usize;
                        w &= w - 1;
                        let jj = wi * 64 + b;
                        self.col[jj * rw + i / 64] |= 1u64 << (i % 64);
                    }
                }
            }
            self.acc.clear();
            self.acc.resize(rw, 0);
            self.tmp.clear();
            self.tmp.resize(words, 0);
            for ci in 0..self.cand.len() {
                let (pi, ni) = self.cand[ci];
                let p = self.plus[pi as usize] as usize;
                let q = self.minus[ni as usize] as usize;
                for t in 0..words {
                    self.tmp[t] = self.z[p * words + t] & self.z[q * words + t];
                }
                self.pairs_tested += 1;
                self.acc.fill(u64::MAX);
                for (wi, &w0) in self.tmp.iter().enumerate() {
                    let mut w = w0;
                    while w != 0 {
                        let b = w.trailing_zeros() as usize;
                        w &= w - 1;
                        let jj = wi * 64 + b;
                        for (a, c) in self.acc.iter_mut().zip(&self.col[jj * rw..(jj + 1) * rw]) {
                            *a &= c;
                        }
                    }
                }
                self.acc[p / 64] &= !(1u64 << (p % 64));
                self.acc[q / 64] &= !(1u64 << (q % 64));
                // Only rays 0..n exist: clear the bits past them.
                if !self.n.is_multiple_of(64) {
                    self.acc[rw - 1] &= (1u64 << (self.n % 64)) - 1;
                }
                if self.acc.iter().any(|&w| w != 0) {
                    continue;
                }
                Self::push_combination(&self.slack, &self.x, &mut self.next_x, [p, q, k])?;
                let zs = self.next_z.len();
                self.next_z.extend_from_slice(&self.tmp);
                bitset::set(&mut self.next_z[zs..zs + words], j);
                next_n += 1;
            }
        }
        std::mem::swap(&mut self.x, &mut self.next_x);
        std::mem::swap(&mut self.z, &mut self.next_z);
        self.n = next_n;
        Ok(())
    }

    /// [`Self::add_row`] when every zero set fits one word (`m <= 64`, the common case): the
    /// same steps on plain `u64` masks, without per-pair slices.
    fn add_row_one_word<const K: usize>(
        &mut self,
        row: &[f64],
        j: usize,
        eps_zero: f64,
    ) -> Result<(), DdFailure> {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("popcnt") {
                // SAFETY: the CPU supports `popcnt`, checked just above.
                return unsafe { self.add_row_one_word_popcnt::<K>(row, j, eps_zero) };
            }
        }
        self.add_row_one_word_body::<K>(row, j, eps_zero)
    }

    /// [`Self::add_row_one_word_body`] compiled with the `popcnt` instruction.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "popcnt")]
    unsafe fn add_row_one_word_popcnt<const K: usize>(
        &mut self,
        row: &[f64],
        j: usize,
        eps_zero: f64,
    ) -> Result<(), DdFailure> {
        self.add_row_one_word_body::<K>(row, j, eps_zero)
    }

    #[inline(always)]
    fn add_row_one_word_body<const K: usize>(
        &mut self,
        row: &[f64],
        j: usize,
        eps_zero: f64,
    ) -> Result<(), DdFailure> {
        let k = dim::<K>(self.k);
        let bit = 1u64 << j;
        self.slack.clear();
        self.plus.clear();
        self.minus.clear();
        self.zero.clear();
        for (i, x) in self.x.chunks_exact(k).take(self.n).enumerate() {
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
            return Ok(());
        }
        self.next_x.clear();
        self.next_z.clear();
        // Keep R- and R0 (the latter now tight on row j).
        for &i in &self.minus {
            let i = i as usize;
            self.next_x.extend_from_slice(&self.x[i * k..(i + 1) * k]);
            self.next_z.push(self.z[i]);
        }
        for &i in &self.zero {
            let i = i as usize;
            self.next_x.extend_from_slice(&self.x[i * k..(i + 1) * k]);
            self.next_z.push(self.z[i] | bit);
        }
        // Candidate pairs: |Z(p) ∩ Z(n)| >= k - 2 (a vectorized scan of the zero sets of R-,
        // gathered contiguously), then no third ray r with Z(p) ∩ Z(n) ⊆ Z(r) (a vectorized
        // count of the current zero sets containing Z(p) ∩ Z(n): p and n always do).
        let need = k.saturating_sub(2) as u32;
        let n = self.n;
        let scan = self.scan;
        self.zn.clear();
        self.zn
            .extend(self.minus.iter().map(|&q| self.z[q as usize]));
        for &p in &self.plus {
            let p = p as usize;
            let zp = self.z[p];
            self.cand_idx.clear();
            scan.candidates(zp, &self.zn, need, &mut self.cand_idx);
            for &qi in &self.cand_idx {
                let common = zp & self.zn[qi as usize];
                self.pairs_tested += 1;
                if scan.count_supersets(common, &self.z[..n]) > 2 {
                    continue;
                }
                let q = self.minus[qi as usize] as usize;
                Self::push_combination(&self.slack, &self.x, &mut self.next_x, [p, q, k])?;
                self.next_z.push(common | bit);
            }
        }
        self.n = self.next_z.len();
        std::mem::swap(&mut self.x, &mut self.next_x);
        std::mem::swap(&mut self.z, &mut self.next_z);
        Ok(())
    }
}

/// The dimension: `K` when fixed at compile time, else `k`.
#[inline(always)]
fn dim<const K: usize>(k: usize) -> usize {
    if K == 0 {
        k
    } else {
        debug_assert_eq!(k, K);
        K
    }
}

/// Pairs `(i, j)` of `plus` and `minus` zero sets (`words` words each, contiguous) sharing at
/// least `need` bits, appended to `out`. Uses the `popcnt` instruction when the CPU has it.
fn candidate_pairs(zp: &[u64], zn: &[u64], words: usize, need: u32, out: &mut Vec<(u32, u32)>) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("popcnt") {
            // SAFETY: the CPU supports `popcnt`, checked just above.
            unsafe { candidate_pairs_popcnt(zp, zn, words, need, out) };
            return;
        }
    }
    candidate_pairs_portable(zp, zn, words, need, out);
}

#[inline(always)]
fn candidate_pairs_portable(
    zp: &[u64],
    zn: &[u64],
    words: usize,
    need: u32,
    out: &mut Vec<(u32, u32)>,
) {
    if words == 1 {
        for (i, &a) in zp.iter().enumerate() {
            for (j, &b) in zn.iter().enumerate() {
                if (a & b).count_ones() >= need {
                    out.push((i as u32, j as u32));
                }
            }
        }
        return;
    }
    for (i, a) in zp.chunks_exact(words).enumerate() {
        for (j, b) in zn.chunks_exact(words).enumerate() {
            let c: u32 = a.iter().zip(b).map(|(x, y)| (x & y).count_ones()).sum();
            if c >= need {
                out.push((i as u32, j as u32));
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "popcnt")]
unsafe fn candidate_pairs_popcnt(
    zp: &[u64],
    zn: &[u64],
    words: usize,
    need: u32,
    out: &mut Vec<(u32, u32)>,
) {
    candidate_pairs_portable(zp, zn, words, need, out)
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
