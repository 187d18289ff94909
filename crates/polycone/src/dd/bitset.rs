//! Zero sets as bitsets: one bit per constraint, packed in `u64` words.
//!
//! A ray's zero set `Z(r) = {j : a_j . r = 0}` is stored as `words` consecutive `u64` in a flat
//! arena; bit `j % 64` of word `j / 64` is constraint `j`.

/// Number of `u64` words for `n` bits.
#[inline]
pub(crate) fn words_for(n: usize) -> usize {
    n.div_ceil(64).max(1)
}

/// Sets bit `j`.
#[inline]
pub(crate) fn set(z: &mut [u64], j: usize) {
    z[j / 64] |= 1u64 << (j % 64);
}

/// `out = a & b`, returns the popcount of `out`.
#[inline]
pub(crate) fn and_count(a: &[u64], b: &[u64], out: &mut [u64]) -> u32 {
    let mut c = 0;
    for ((o, x), y) in out.iter_mut().zip(a).zip(b) {
        *o = x & y;
        c += o.count_ones();
    }
    c
}

/// Is `a` a subset of `b`?
#[inline]
pub(crate) fn subset(a: &[u64], b: &[u64]) -> bool {
    a.iter().zip(b).all(|(x, y)| x & !y == 0)
}
