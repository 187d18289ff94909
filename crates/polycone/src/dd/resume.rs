//! Resuming a finished double description with more constraint rows.
//!
//! # Math
//!
//! After [`DdCore::run`] on rows `a_1 .. a_m`, the state is the list of extreme rays of
//! `P_m = {x : a_j . x <= 0, j <= m}` with their zero sets `Z(r) ⊆ {1..m}`. That is exactly the
//! invariant the iteration keeps after adding its `m`-th row: nothing in it depends on the rows
//! being all known in advance. So `P_{m+q} = P_m ∩ {x : a_j . x <= 0, m < j <= m + q}` is
//! obtained by the same step ([`DdCore::add_row`]) on the new rows, in order, with indices
//! `m + 1 .. m + q` for their bits. The only change of representation is the width of the zero
//! sets: when `m + q` crosses a multiple of 64 they are re-packed into more words (bits keep
//! their indices, the new words start empty: no ray is tight on a row not yet added).
//!
//! The result is the set of extreme rays a run on all `m + q` rows gives, up to the order of the
//! rays and floating-point rounding (the intermediate cones differ with the insertion order, the
//! final one does not); the caller certifies it like any other result.

use super::bitset;
use super::core::{DdCore, DdFailure};

impl DdCore {
    /// Intersects the current cone with `{x : row . x <= 0}` for each of the `count` new rows
    /// of `a` (`count x k`, row-major, unit rows), numbered after the rows added so far.
    /// `eps_zero` decides `row . x = 0` as in [`DdCore::run`]. On error the state is no longer
    /// a valid double description (rerun from scratch).
    pub(crate) fn add_rows(
        &mut self,
        a: &[f64],
        count: usize,
        eps_zero: f64,
    ) -> Result<(), DdFailure> {
        let k = self.k;
        debug_assert_eq!(a.len(), count * k);
        if count == 0 {
            return Ok(());
        }
        let m0 = self.m;
        self.repack(bitset::words_for(m0 + count));
        self.m = m0 + count;
        if k == 0 || self.n == 0 {
            // No space, or the cone is already {0}: no row can change that.
            return Ok(());
        }
        // The same monomorphized copies as `run`.
        match k {
            3 => self.add_rows_k::<3>(a, m0, count, eps_zero),
            4 => self.add_rows_k::<4>(a, m0, count, eps_zero),
            5 => self.add_rows_k::<5>(a, m0, count, eps_zero),
            6 => self.add_rows_k::<6>(a, m0, count, eps_zero),
            7 => self.add_rows_k::<7>(a, m0, count, eps_zero),
            8 => self.add_rows_k::<8>(a, m0, count, eps_zero),
            _ => self.add_rows_k::<0>(a, m0, count, eps_zero),
        }
    }

    /// [`Self::add_rows`] with `k = K` fixed at compile time (`K = 0`: `self.k`).
    fn add_rows_k<const K: usize>(
        &mut self,
        a: &[f64],
        m0: usize,
        count: usize,
        eps_zero: f64,
    ) -> Result<(), DdFailure> {
        let k = self.k;
        for (t, row) in a.chunks_exact(k).take(count).enumerate() {
            self.add_row::<K>(row, m0 + t, eps_zero)?;
            if self.n == 0 {
                break;
            }
        }
        Ok(())
    }

    /// Widens the zero sets of the current rays to `words` words each (no-op when they are
    /// already that wide). Allocates only when the width changes.
    fn repack(&mut self, words: usize) {
        let old = self.words;
        if words <= old {
            return;
        }
        let n = self.n;
        let mut z = vec![0u64; n * words];
        for (dst, src) in z.chunks_exact_mut(words).zip(self.z.chunks_exact(old)) {
            dst[..old].copy_from_slice(src);
        }
        self.z = z;
        self.words = words;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use super::super::testing::{unit_rows as rows, Lcg};

    /// The rays of `dd` with their zero sets as sorted row lists, sorted by ray.
    fn rays(dd: &DdCore) -> Vec<(Vec<f64>, Vec<usize>)> {
        let mut out: Vec<(Vec<f64>, Vec<usize>)> = (0..dd.n)
            .map(|i| {
                let z = &dd.z[i * dd.words..(i + 1) * dd.words];
                let zs = (0..dd.m)
                    .filter(|&j| z[j / 64] >> (j % 64) & 1 == 1)
                    .collect();
                (dd.ray(i).to_vec(), zs)
            })
            .collect();
        out.sort_by(|a, b| {
            a.0.iter()
                .zip(&b.0)
                .map(|(x, y)| x.total_cmp(y))
                .find(|o| o.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        out
    }

    /// A run on the first `m0` rows resumed with the others gives the rays and zero sets of a
    /// run on all rows, in dimensions 3 to 9, on generic and degenerate rows, with the row
    /// count crossing the one-word / multi-word boundary (64 rows) or not, in one or several
    /// resumptions.
    #[test]
    fn resumed_run_matches_full_run() {
        let mut rng = Lcg(11);
        let mut compared = 0;
        let mut crossed = 0;
        for case in 0..240 {
            let k = 3 + case % 7;
            let m0 = k + 2 + (case * 5) % 60;
            let m = m0 + 1 + (case * 11) % 50;
            let a = rows(&mut rng, m, k, case % 4 == 0);
            let mut full = DdCore::default();
            if full.run(&a, m, k, 1e-9, 1e-10).is_err() {
                continue;
            }
            let mut part = DdCore::default();
            if part.run(&a[..m0 * k], m0, k, 1e-9, 1e-10).is_err() {
                // The first rows alone are rank deficient: not a resumable state.
                continue;
            }
            // Resume in one or two steps.
            let split = if case % 2 == 0 { m } else { (m0 + m) / 2 };
            part.add_rows(&a[m0 * k..split * k], split - m0, 1e-9)
                .unwrap();
            part.add_rows(&a[split * k..], m - split, 1e-9).unwrap();
            assert_eq!(part.m, m);
            assert_eq!(part.words, bitset::words_for(m), "case {case}");
            let (rf, rp) = (rays(&full), rays(&part));
            assert_eq!(rf.len(), rp.len(), "case {case}: ray count");
            for ((xf, zf), (xp, zp)) in rf.iter().zip(&rp) {
                let dist = xf
                    .iter()
                    .zip(xp)
                    .map(|(p, q)| (p - q).abs())
                    .fold(0.0, f64::max);
                assert!(dist < 1e-9, "case {case}: ray distance {dist:e}");
                assert_eq!(zf, zp, "case {case}: zero set");
            }
            compared += 1;
            if bitset::words_for(m0) < bitset::words_for(m) {
                crossed += 1;
            }
        }
        assert!(compared > 150, "{compared}");
        assert!(crossed > 20, "{crossed}");
    }

    /// Adding no row, or rows to the cone `{0}`, keeps the state; widening keeps the bits.
    #[test]
    fn empty_additions_and_repacking() {
        let mut dd = DdCore::default();
        // The orthant x <= 0 in R^3: rays -e_i.
        let a = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        dd.run(&a, 3, 3, 1e-9, 1e-10).unwrap();
        let before = rays(&dd);
        dd.add_rows(&[], 0, 1e-9).unwrap();
        assert_eq!(rays(&dd), before);
        // 70 copies of a redundant row (x + y + z <= 0 up to scaling): 2 words, same rays,
        // every ray tight on none of them.
        let s = 1.0 / 3f64.sqrt();
        let more: Vec<f64> = (0..70).flat_map(|_| [s, s, s]).collect();
        dd.add_rows(&more, 70, 1e-9).unwrap();
        assert_eq!(dd.words, 2);
        assert_eq!(dd.m, 73);
        let after = rays(&dd);
        assert_eq!(after.len(), 3);
        for ((x0, z0), (x1, z1)) in before.iter().zip(&after) {
            assert_eq!(x0, x1);
            assert_eq!(z0, z1);
        }
        // The opposite row -(x + y + z) <= 0 with x, y, z <= 0 leaves {0}.
        dd.add_rows(&[-s, -s, -s], 1, 1e-9).unwrap();
        assert_eq!(dd.n, 0);
        dd.add_rows(&[1.0, 0.0, 0.0], 1, 1e-9).unwrap();
        assert_eq!((dd.n, dd.m), (0, 75));
    }
}
