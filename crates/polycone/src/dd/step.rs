//! One double description step, written once: the current cone intersected with the half-space
//! `{x : a_j . x <= 0}` of the row `a_j` being added (items 2 and 3 of [`crate::dd`]).
//!
//! # The step
//!
//! 1. **Split.** The slacks `s_i = a_j . x_i` of the current (unit) rays, decided at `eps_zero`:
//!    `R+ = {s_i > eps}`, `R- = {s_i < -eps}`, `R0` the rest. If `R+` is empty the cone does not
//!    change; the rays of `R0` become tight on row `j` (bit `j` of their zero sets) and the step
//!    ends.
//! 2. **Survivors.** The rays of `R-`, then those of `R0` (now tight on `j`), in that order, are
//!    the first rays of the next cone.
//! 3. **New rays.** For every pair `(p, n)` of `R+ x R-` that is adjacent (the combinatorial test
//!    of the module doc: `|Z(p) ∩ Z(n)| >= k - 2`, and no third current ray `r` has
//!    `Z(p) ∩ Z(n) ⊆ Z(r)`), in the order `p` then `n`, the ray `s_p x_n - s_n x_p` on the
//!    hyperplane, normalized, with zero set `(Z(p) ∩ Z(n)) ∪ {j}`. A combination that rounds to
//!    zero or overflows is a [`DdFailure::Cancellation`].
//!
//! # Adjacency strategies
//!
//! Steps 1, 2 and the arithmetic of step 3 are one code path whatever the width of the zero sets
//! (`words` `u64` each). Only the search for adjacent pairs has three strategies, chosen by size,
//! all taking the same decisions in the same order, so that the rays come out the same bit for
//! bit (unit test `one_word_path_matches_multi_word_path`):
//!
//! - **one word** (`m <= 64`, the common case): the zero sets are plain `u64` masks and both
//!   halves of the test are the vectorized scans of `scan.rs`;
//! - **several words, few candidates** (fewer than `4 k` pairs pass the counting half): each
//!   candidate scans the current rays for a blocker;
//! - **several words, many candidates**: the transposed incidence (for each row, the set of rays
//!   tight on it) is built once, and a pair is blocked iff the AND of the ray sets of the rows of
//!   `Z(p) ∩ Z(n)` holds a third ray.
//!
//! The exact engine (`crate::exact`) takes the same decisions with exact signs; it shares the
//! combinatorial test ([`adjacent`]) with the second strategy.

use super::bitset;
use super::core::{dim, DdCore, DdFailure};

/// The rays of the next cone, as the step builds them (`k` coordinates and `words` zero-set
/// words each, contiguous).
#[derive(Clone, Debug, Default)]
pub(super) struct Next {
    pub(super) x: Vec<f64>,
    pub(super) z: Vec<u64>,
}

impl Next {
    /// Step 2 for one ray: copies ray `x` with zero set `z`, tight on row `j` when given.
    #[inline(always)]
    fn keep(&mut self, x: &[f64], z: &[u64], tight_on: Option<usize>) {
        self.x.extend_from_slice(x);
        if let [word] = z {
            // One word (the common case): a push, not a slice copy and a bit set (those cost
            // the benchmark cones of 32 and more generators about 4 %, `cones_ab.py`).
            self.z.push(word | tight_on.map_or(0, |j| 1u64 << j));
            return;
        }
        let start = self.z.len();
        self.z.extend_from_slice(z);
        if let Some(j) = tight_on {
            bitset::set(&mut self.z[start..], j);
        }
    }

    /// Step 3 for one adjacent pair: appends the ray `s_p x_q - s_q x_p` (normalized; `p` in
    /// `R+`, `q` in `R-`) with zero set `common ∪ {j}`.
    #[inline(always)]
    fn combine(
        &mut self,
        slack: &[f64],
        x: &[f64],
        [p, q, k]: [usize; 3],
        common: &[u64],
        j: usize,
    ) -> Result<(), DdFailure> {
        let (sp, sq) = (slack[p], slack[q]);
        let start = self.x.len();
        self.x.resize(start + k, 0.0);
        let (xp, xq) = (&x[p * k..(p + 1) * k], &x[q * k..(q + 1) * k]);
        let out = &mut self.x[start..start + k];
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
        self.keep(&[], common, Some(j));
        Ok(())
    }
}

impl DdCore {
    /// The step: intersects the current cone with `{x : row . x <= 0}`, `row` being row `j`.
    pub(super) fn add_row<const K: usize>(
        &mut self,
        row: &[f64],
        j: usize,
        eps_zero: f64,
    ) -> Result<(), DdFailure> {
        let k = dim::<K>(self.k);
        let words = self.words;
        // 1. Split.
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
                let i = i as usize;
                bitset::set(&mut self.z[i * words..(i + 1) * words], j);
            }
            return Ok(());
        }
        // 2. Survivors.
        self.next.x.clear();
        self.next.z.clear();
        for (&i, tight_on) in
            (self.minus.iter().map(|i| (i, None))).chain(self.zero.iter().map(|i| (i, Some(j))))
        {
            let i = i as usize;
            let (x, z) = (
                &self.x[i * k..(i + 1) * k],
                &self.z[i * words..(i + 1) * words],
            );
            self.next.keep(x, z, tight_on);
        }
        // 3. New rays, by the strategy for this width.
        #[cfg(test)]
        let one_word = words == 1 && !self.force_multi_word;
        #[cfg(not(test))]
        let one_word = words == 1;
        if one_word {
            self.new_rays_one_word::<K>(j)?;
        } else {
            self.new_rays_multi_word::<K>(j)?;
        }
        std::mem::swap(&mut self.x, &mut self.next.x);
        std::mem::swap(&mut self.z, &mut self.next.z);
        self.n = self.z.len() / words;
        Ok(())
    }

    /// Step 3 with one-word zero sets: the candidates of each `p` by a vectorized scan of the
    /// zero sets of `R-` gathered contiguously, then the blockers by a vectorized count of the
    /// current zero sets containing `Z(p) ∩ Z(n)` (`p` and `n` always do).
    fn new_rays_one_word<const K: usize>(&mut self, j: usize) -> Result<(), DdFailure> {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("popcnt") {
                // SAFETY: the CPU supports `popcnt`, checked just above.
                return unsafe { self.new_rays_one_word_popcnt::<K>(j) };
            }
        }
        self.new_rays_one_word_body::<K>(j)
    }

    /// [`Self::new_rays_one_word_body`] compiled with the `popcnt` instruction.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "popcnt")]
    unsafe fn new_rays_one_word_popcnt<const K: usize>(
        &mut self,
        j: usize,
    ) -> Result<(), DdFailure> {
        self.new_rays_one_word_body::<K>(j)
    }

    #[inline(always)]
    fn new_rays_one_word_body<const K: usize>(&mut self, j: usize) -> Result<(), DdFailure> {
        let k = dim::<K>(self.k);
        let need = k.saturating_sub(2) as u32;
        let (n, scan) = (self.n, self.scan);
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
                self.next
                    .combine(&self.slack, &self.x, [p, q, k], &[common], j)?;
            }
        }
        Ok(())
    }

    /// Step 3 with zero sets of several words: the candidate pairs by counting, then the
    /// blockers by a scan of the rays (few candidates: cheaper than building the transposed
    /// incidence, measured on 6-D wrench cones) or through the transposed incidence.
    fn new_rays_multi_word<const K: usize>(&mut self, j: usize) -> Result<(), DdFailure> {
        let (k, words) = (dim::<K>(self.k), self.words);
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
        if self.cand.is_empty() {
            return Ok(());
        }
        self.tmp.clear();
        self.tmp.resize(words, 0);
        let by_scan = self.cand.len() < 4 * k;
        if !by_scan {
            self.transpose_incidence();
        }
        for ci in 0..self.cand.len() {
            let (pi, ni) = self.cand[ci];
            let p = self.plus[pi as usize] as usize;
            let q = self.minus[ni as usize] as usize;
            for t in 0..words {
                self.tmp[t] = self.z[p * words + t] & self.z[q * words + t];
            }
            self.pairs_tested += 1;
            let blocked = if by_scan {
                !adjacent(&self.tmp, &self.z, words, self.n, [p, q])
            } else {
                self.blocked_by_incidence([p, q])
            };
            if !blocked {
                self.next
                    .combine(&self.slack, &self.x, [p, q, k], &self.tmp, j)?;
            }
        }
        Ok(())
    }

    /// Builds `col`: for each row, the bitset (over the current rays) of the rays tight on it.
    fn transpose_incidence(&mut self) {
        let (words, rw) = (self.words, bitset::words_for(self.n));
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
    }

    /// Whether a ray other than `p` and `q` is tight on every row of `tmp` (= `Z(p) ∩ Z(q)`):
    /// the AND of those rows' ray sets in `col`, less `p` and `q`, is not empty.
    fn blocked_by_incidence(&mut self, [p, q]: [usize; 2]) -> bool {
        let rw = bitset::words_for(self.n);
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
        self.acc.iter().any(|&w| w != 0)
    }
}

/// The sufficient half of the combinatorial adjacency test: no ray of the `n` zero sets `z`
/// (`words` words each) other than `p` and `q` contains `common = Z(p) ∩ Z(q)`.
#[inline]
pub(crate) fn adjacent(
    common: &[u64],
    z: &[u64],
    words: usize,
    n: usize,
    [p, q]: [usize; 2],
) -> bool {
    !(0..n).any(|r| {
        r != p
            && r != q
            && common
                .iter()
                .zip(&z[r * words..(r + 1) * words])
                .all(|(a, b)| a & !b == 0)
    })
}

/// Pairs `(i, j)` of `plus` and `minus` zero sets (`words` words each, contiguous) sharing at
/// least `need` bits, appended to `out`: the necessary half of the adjacency test. Uses the
/// `popcnt` instruction when the CPU has it.
pub(crate) fn candidate_pairs(
    zp: &[u64],
    zn: &[u64],
    words: usize,
    need: u32,
    out: &mut Vec<(u32, u32)>,
) {
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
