//! The double description iteration on a pointed cone `{x in R^k : A x <= 0}`, `A` of full
//! column rank `k` (see the module doc of [`crate::dd`]). All buffers live in [`DdCore`] and are
//! reused across calls: once warm, a conversion of the same size does not allocate.

use super::bitset;

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
    /// Number of adjacency candidates examined in the last run (for profiling).
    pub pairs_tested: usize,
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
        if k == 0 {
            return Ok(());
        }
        self.choose_basis(a, m, k, eps_rank)?;
        self.initial_rays(a, k)?;
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
            if let Err(e) = self.add_row(&a[j * k..(j + 1) * k], j, eps_zero) {
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

    /// Greedy pivoted Gram-Schmidt: picks `k` rows of largest residual norm.
    fn choose_basis(
        &mut self,
        a: &[f64],
        m: usize,
        k: usize,
        eps_rank: f64,
    ) -> Result<(), DdFailure> {
        self.resid.clear();
        self.resid.extend_from_slice(a);
        self.in_basis.clear();
        self.in_basis.resize(m, false);
        self.basis.clear();
        for _ in 0..k {
            let mut best = usize::MAX;
            let mut best_norm = -1.0;
            for i in 0..m {
                if self.in_basis[i] {
                    continue;
                }
                let r = &self.resid[i * k..(i + 1) * k];
                let nn: f64 = r.iter().map(|v| v * v).sum();
                if nn > best_norm {
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
            let (q_start, q_end) = (best * k, (best + 1) * k);
            for t in q_start..q_end {
                self.resid[t] *= inv;
            }
            for i in 0..m {
                if self.in_basis[i] {
                    continue;
                }
                let mut d = 0.0;
                for t in 0..k {
                    d += self.resid[i * k + t] * self.resid[q_start + t];
                }
                for t in 0..k {
                    self.resid[i * k + t] -= d * self.resid[q_start + t];
                }
            }
        }
        Ok(())
    }

    /// Rays of the simplicial cone `{x : A_K x <= 0}`: the columns of `-A_K^{-1}`.
    fn initial_rays(&mut self, a: &[f64], k: usize) -> Result<(), DdFailure> {
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
            for t in 0..w {
                self.aug[c * w + t] *= inv;
            }
            for r in 0..k {
                if r == c {
                    continue;
                }
                let f = self.aug[r * w + c];
                if f != 0.0 {
                    for t in 0..w {
                        self.aug[r * w + t] -= f * self.aug[c * w + t];
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
    fn add_row(&mut self, row: &[f64], j: usize, eps_zero: f64) -> Result<(), DdFailure> {
        let (k, words) = (self.k, self.words);
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
                let (sp, sq) = (self.slack[p], self.slack[q]);
                let start = self.next_x.len();
                let mut nn = 0.0;
                for t in 0..k {
                    let v = sp * self.x[q * k + t] - sq * self.x[p * k + t];
                    self.next_x.push(v);
                    nn += v * v;
                }
                if nn.is_nan() || nn <= 0.0 || !nn.is_finite() {
                    return Err(DdFailure::Cancellation);
                }
                let inv = 1.0 / nn.sqrt();
                for v in &mut self.next_x[start..start + k] {
                    *v *= inv;
                }
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
                if self.n % 64 != 0 {
                    self.acc[rw - 1] &= (1u64 << (self.n % 64)) - 1;
                }
                if self.acc.iter().any(|&w| w != 0) {
                    continue;
                }
                let (sp, sq) = (self.slack[p], self.slack[q]);
                let start = self.next_x.len();
                let mut nn = 0.0;
                for t in 0..k {
                    let v = sp * self.x[q * k + t] - sq * self.x[p * k + t];
                    self.next_x.push(v);
                    nn += v * v;
                }
                if nn.is_nan() || nn <= 0.0 || !nn.is_finite() {
                    return Err(DdFailure::Cancellation);
                }
                let inv = 1.0 / nn.sqrt();
                for v in &mut self.next_x[start..start + k] {
                    *v *= inv;
                }
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
