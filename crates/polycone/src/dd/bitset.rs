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
