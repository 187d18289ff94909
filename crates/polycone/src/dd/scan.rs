//! The two bitset scans of the one-word double description step, vectorized.
//!
//! With at most 64 constraint rows every zero set is one `u64`, and the step spends its time in
//! two scans over contiguous arrays of them:
//!
//! - [`Scan::candidates`]: the rays `n` of `R-` whose zero set shares at least `k - 2` rows with
//!   a given ray `p` of `R+` (`popcount(Z(p) & Z(n)) >= k - 2`, the necessary half of the
//!   combinatorial adjacency test);
//! - [`Scan::count_supersets`]: the number of current rays `r` whose zero set contains a given
//!   common zero set `c = Z(p) & Z(n)` (`c & !Z(r) == 0`). `p` and `n` always count; any third
//!   ray blocks the pair (the sufficient half of the test).
//!
//! Both are plain loops written so that the compiler vectorizes them, compiled three times:
//! for AVX-512 with its 64-bit population count (`avx512vpopcntdq`), for AVX2, and portable.
//! The variant is chosen once per run from the CPU's features ([`Scan::detect`]); all three
//! return the same answers (unit tests), so results do not depend on the machine.

/// Which compiled variant of the scans runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum Scan {
    /// No special instructions.
    #[default]
    Portable,
    /// AVX2 and `popcnt` (x86-64).
    Avx2,
    /// AVX-512 F/VL/BW with `vpopcntq` (x86-64).
    Avx512,
}

impl Scan {
    /// The fastest variant this CPU runs.
    pub(crate) fn detect() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("avx512vl")
                && std::arch::is_x86_feature_detected!("avx512bw")
                && std::arch::is_x86_feature_detected!("avx512vpopcntdq")
                && std::arch::is_x86_feature_detected!("popcnt")
            {
                return Scan::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("popcnt")
            {
                return Scan::Avx2;
            }
        }
        Scan::Portable
    }

    /// Appends to `out` the indices `i` with `popcount(a & zn[i]) >= need`, in increasing order.
    #[inline]
    pub(crate) fn candidates(self, a: u64, zn: &[u64], need: u32, out: &mut Vec<u32>) {
        match self {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `Avx512` is only chosen by `detect` when the CPU has these features.
            Scan::Avx512 => unsafe { candidates_avx512(a, zn, need, out) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `Avx2` is only chosen by `detect` when the CPU has these features.
            Scan::Avx2 => unsafe { candidates_avx2(a, zn, need, out) },
            _ => candidates_body(a, zn, need, out),
        }
    }

    /// The number of `zr` in `z` with `c & !zr == 0`.
    #[inline]
    pub(crate) fn count_supersets(self, c: u64, z: &[u64]) -> usize {
        match self {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: as in `candidates`.
            Scan::Avx512 => unsafe { count_supersets_avx512(c, z) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: as in `candidates`.
            Scan::Avx2 => unsafe { count_supersets_avx2(c, z) },
            _ => count_supersets_body(c, z),
        }
    }
}

/// Lanes per block of [`candidates_body`]: one byte of flags.
const BLOCK: usize = 8;

#[inline(always)]
fn candidates_body(a: u64, zn: &[u64], need: u32, out: &mut Vec<u32>) {
    let mut chunks = zn.chunks_exact(BLOCK);
    let mut base = 0u32;
    for c in &mut chunks {
        // Branch-free flags for a block (vectorizes), then the rare hits one by one.
        let mut flags = 0u32;
        for (l, &b) in c.iter().enumerate() {
            flags |= (((a & b).count_ones() >= need) as u32) << l;
        }
        while flags != 0 {
            out.push(base + flags.trailing_zeros());
            flags &= flags - 1;
        }
        base += BLOCK as u32;
    }
    for (l, &b) in chunks.remainder().iter().enumerate() {
        if (a & b).count_ones() >= need {
            out.push(base + l as u32);
        }
    }
}

#[inline(always)]
fn count_supersets_body(c: u64, z: &[u64]) -> usize {
    z.iter().map(|&zr| (c & !zr == 0) as usize).sum()
}

/// [`candidates_body`] with explicit AVX-512 instructions: eight zero sets per step (`vpandq`,
/// `vpopcntq`, one unsigned compare into a mask register), the indices of the hits written
/// with one compressing store (no branch on the data: hits are irregular, and mispredicted
/// branches cost more than the scan itself).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512vpopcntdq,popcnt")]
unsafe fn candidates_avx512(a: u64, zn: &[u64], need: u32, out: &mut Vec<u32>) {
    use std::arch::x86_64::{
        _mm256_add_epi32, _mm256_mask_compressstoreu_epi32, _mm256_set1_epi32, _mm256_setr_epi32,
        _mm512_and_si512, _mm512_cmpge_epu64_mask, _mm512_loadu_si512, _mm512_popcnt_epi64,
        _mm512_set1_epi64,
    };
    let va = _mm512_set1_epi64(a as i64);
    let vneed = _mm512_set1_epi64(need as i64);
    let mut idx = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    let step = _mm256_set1_epi32(BLOCK as i32);
    // Room for every index, so that the compressing stores stay in bounds.
    out.reserve(zn.len());
    let mut len = out.len();
    let mut chunks = zn.chunks_exact(BLOCK);
    for c in &mut chunks {
        // SAFETY: `c` holds BLOCK = 8 u64, 64 bytes; unaligned loads are allowed.
        let v = unsafe { _mm512_loadu_si512(c.as_ptr().cast()) };
        let cnt = _mm512_popcnt_epi64(_mm512_and_si512(va, v));
        let flags = _mm512_cmpge_epu64_mask(cnt, vneed);
        // SAFETY: at most `zn.len()` indices are ever written past the initial length, and
        // `reserve` made room for them; the store writes `popcount(flags)` u32 at `len`.
        unsafe {
            _mm256_mask_compressstoreu_epi32(out.as_mut_ptr().add(len).cast(), flags, idx);
        }
        len += flags.count_ones() as usize;
        idx = _mm256_add_epi32(idx, step);
    }
    // SAFETY: the first `len` entries were written (the old ones, then the stored indices),
    // and `len <= capacity`.
    unsafe { out.set_len(len) };
    let base = (zn.len() - chunks.remainder().len()) as u32;
    for (l, &b) in chunks.remainder().iter().enumerate() {
        if (a & b).count_ones() >= need {
            out.push(base + l as u32);
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,popcnt")]
unsafe fn candidates_avx2(a: u64, zn: &[u64], need: u32, out: &mut Vec<u32>) {
    candidates_body(a, zn, need, out)
}

/// [`count_supersets_body`] with explicit AVX-512 instructions: `vptestnmq` of `c & !z` gives
/// the eight lanes' answers as a mask, counted with `popcnt`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512vpopcntdq,popcnt")]
unsafe fn count_supersets_avx512(c: u64, z: &[u64]) -> usize {
    use std::arch::x86_64::{
        _mm512_andnot_si512, _mm512_loadu_si512, _mm512_set1_epi64, _mm512_testn_epi64_mask,
    };
    let vc = _mm512_set1_epi64(c as i64);
    let mut chunks = z.chunks_exact(BLOCK);
    let mut count = 0usize;
    for ch in &mut chunks {
        // SAFETY: `ch` holds BLOCK = 8 u64, 64 bytes; unaligned loads are allowed.
        let v = unsafe { _mm512_loadu_si512(ch.as_ptr().cast()) };
        // andnot(v, c) = !v & c: zero exactly when c ⊆ v.
        let m = _mm512_testn_epi64_mask(_mm512_andnot_si512(v, vc), _mm512_andnot_si512(v, vc));
        count += m.count_ones() as usize;
    }
    count + count_supersets_body(c, chunks.remainder())
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,popcnt")]
unsafe fn count_supersets_avx2(c: u64, z: &[u64]) -> usize {
    count_supersets_body(c, z)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every variant this machine runs agrees with a naive loop, on lengths around the block
    /// size and on dense and sparse bit patterns.
    #[test]
    fn variants_agree_with_naive_loops() {
        let mut s = 0x9e3779b97f4a7c15u64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        let mut variants = vec![Scan::Portable];
        let best = Scan::detect();
        if best != Scan::Portable {
            variants.push(best);
        }
        #[cfg(target_arch = "x86_64")]
        if best == Scan::Avx512 {
            variants.push(Scan::Avx2);
        }
        let mut hits = 0;
        for case in 0..300 {
            let len = case % 37;
            let sparse = case % 3 == 0;
            let z: Vec<u64> = (0..len)
                .map(|_| {
                    if sparse {
                        next() & next() & next()
                    } else {
                        next()
                    }
                })
                .collect();
            let a = next() | next();
            let need = (case % 40) as u32;
            let naive: Vec<u32> = (0..len as u32)
                .filter(|&i| (a & z[i as usize]).count_ones() >= need)
                .collect();
            let c = if case % 2 == 0 {
                a & next() & next()
            } else {
                0
            };
            let naive_sup = z.iter().filter(|&&zr| c & !zr == 0).count();
            hits += naive.len();
            for &v in &variants {
                let mut got = Vec::new();
                v.candidates(a, &z, need, &mut got);
                assert_eq!(got, naive, "{v:?} case {case}");
                assert_eq!(v.count_supersets(c, &z), naive_sup, "{v:?} case {case}");
            }
        }
        assert!(hits > 100, "{hits}");
    }
}
