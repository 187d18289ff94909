//! The AVX-512 fill: eight rows per step, written as three whole 64-byte cache lines.
//!
//! # Math
//!
//! The same products as [`super::kernel`] (`a_ij = U_j w_a(s_i)`, `b_ij = U_j w_b(s_i)`, `c_ij`
//! as [`CMode`] says), one row per vector lane, with the same operations in the same order (a
//! product, then fused multiply-adds for `q = 1, ..., 5`): the rows are bit-identical to the
//! AVX2 + FMA kernel's.
//!
//! # Layout, and why
//!
//! The output is the `(N + 1) m` rows of 24 bytes, grid point after grid point: row `k = i m + j`
//! ("flat" index) at byte `24 k`. Measured on the development machine (see the crate's
//! `bench/peers/topp.md`), the fill is bound by writing these rows into the second-level cache,
//! not by the 14 multiply-adds per row: a pure store of the same 417 KB takes about 6.3 us of
//! the ~10 us fill, and stores that straddle two cache lines cost more. Steps are therefore
//! aligned on the *output*: each step computes the flat rows `k, ..., k + 7` with `24 k`
//! bytes past a 64-byte boundary, i.e. exactly three cache lines, written by three aligned
//! 64-byte stores after six two-source permutes interleave `a`, `b`, `c`.
//!
//! A step may straddle two grid points (when `m` is not a multiple of 8): its lanes take their
//! `w` vectors from one or the other (a masked blend, once per grid point), and its rows of `U`
//! wrap around from `m - 1` to `0`. For that the columns of `U` (and `U_f (m g)`) are stored
//! 64-byte aligned with their first 8 rows repeated after the last ([`WideColumns`]), so that 8
//! consecutive entries from any `j < m` are the rows `j, ..., (j + 7) mod m`. The rows before
//! the first aligned line and after the last whole step (fewer than 8 each) are computed one at
//! a time with the same operations. For `m < 8` every row is computed that way.

use std::arch::x86_64::*;

use super::kernel::{row, CMode};
use crate::constraints::Row;

/// Rows of `U` a step covers (lanes of a 512-bit vector of `f64`).
const LANES: usize = 8;

// The stores write rows as `a, b, c` triples of `f64`: `Row` is `#[repr(C)]` with that layout.
const _: () = assert!(
    std::mem::size_of::<Row>() == 24
        && std::mem::offset_of!(Row, a) == 0
        && std::mem::offset_of!(Row, b) == 8
        && std::mem::offset_of!(Row, c) == 16
);

/// One cache line of `f64`, for 64-byte aligned storage.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
struct Line([f64; LANES]);

/// Columns of `U` and `U_f (m g)`, 64-byte aligned, each of length `m + 8` (rounded up to whole
/// lines) with entry `t` holding row `t mod m` (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct WideColumns {
    /// Columns 0..6 of `U`, then `c_force` (zeros when absent).
    cols: [Vec<Line>; 7],
    m: usize,
}

impl WideColumns {
    /// From the columns of `U` and `c_force` (empty when absent); `None` when `m < 8` (no step
    /// fits in one grid point's rows, every row is computed one at a time).
    pub(super) fn new(cols: &[Vec<f64>; 6], c_force: &[f64]) -> Option<Self> {
        let m = cols[0].len();
        if m < LANES {
            return None;
        }
        let lines = (m + LANES).div_ceil(LANES);
        let wide = |src: &[f64]| -> Vec<Line> {
            let mut v = vec![Line([0.0; LANES]); lines];
            if !src.is_empty() {
                // Rows 0..m, then rows 0..8 again (m >= 8).
                for (t, x) in src[..m].iter().chain(&src[..LANES]).enumerate() {
                    v[t / LANES].0[t % LANES] = *x;
                }
            }
            v
        };
        let cols = std::array::from_fn(|q| if q < 6 { wide(&cols[q]) } else { wide(c_force) });
        Some(Self { cols, m })
    }
}

/// The `w` vectors of one grid point, each component broadcast to all lanes (or blended
/// between two grid points).
#[derive(Clone, Copy)]
struct Splat {
    a: [__m512d; 6],
    b: [__m512d; 6],
    c: [__m512d; 6],
}

/// # Safety
///
/// AVX-512F (inlined into [`fill_avx512`] only).
#[inline(always)]
unsafe fn splat(w: &[[f64; 6]; 3]) -> Splat {
    Splat {
        a: std::array::from_fn(|q| _mm512_set1_pd(w[0][q])),
        b: std::array::from_fn(|q| _mm512_set1_pd(w[1][q])),
        c: std::array::from_fn(|q| _mm512_set1_pd(w[2][q])),
    }
}

/// Lanes whose bit is set in `mask` from `y`, the others from `x`.
///
/// # Safety
///
/// AVX-512F (inlined into [`fill_avx512`] only).
#[inline(always)]
unsafe fn blend(mask: __mmask8, x: &Splat, y: &Splat) -> Splat {
    Splat {
        a: std::array::from_fn(|q| _mm512_mask_blend_pd(mask, x.a[q], y.a[q])),
        b: std::array::from_fn(|q| _mm512_mask_blend_pd(mask, x.b[q], y.b[q])),
        c: std::array::from_fn(|q| _mm512_mask_blend_pd(mask, x.c[q], y.c[q])),
    }
}

/// Permute indices interleaving `a`, `b` (first table: indices 0-7 and 8-15) and then `c`
/// (second step: 8-15) into the three lines `a0 b0 c0 a1 b1 c1 a2 b2 | c2 a3 b3 c3 a4 b4 c4 a5
/// | b5 c5 a6 b6 c6 a7 b7 c7` (entries written 0 are overwritten by the second step).
///
/// # Safety
///
/// AVX-512F (inlined into [`fill_avx512`] only).
#[inline(always)]
unsafe fn interleave_indices() -> [__m512i; 6] {
    [
        _mm512_setr_epi64(0, 8, 0, 1, 9, 0, 2, 10),
        _mm512_setr_epi64(0, 1, 8, 3, 4, 9, 6, 7),
        _mm512_setr_epi64(0, 3, 11, 0, 4, 12, 0, 5),
        _mm512_setr_epi64(10, 1, 2, 11, 4, 5, 12, 7),
        _mm512_setr_epi64(13, 0, 6, 14, 0, 7, 15, 0),
        _mm512_setr_epi64(0, 13, 2, 3, 14, 5, 6, 15),
    ]
}

/// One step: rows `j, ..., j + 7 (mod m)` of `U` against `w`, written to the three aligned
/// lines at `o`.
///
/// # Safety
///
/// AVX-512F; `cols` point to [`WideColumns`] columns with `j < m`; `o` is 64-byte aligned and
/// valid for 24 writes.
#[inline(always)]
unsafe fn step<const C: u8>(
    cols: &[*const f64; 7],
    j: usize,
    w: &Splat,
    idx: &[__m512i; 6],
    o: *mut f64,
) {
    let u: [__m512d; 6] = std::array::from_fn(|q| _mm512_loadu_pd(cols[q].add(j)));
    let dot = |v: &[__m512d; 6]| {
        let mut s = _mm512_mul_pd(u[0], v[0]);
        for q in 1..6 {
            s = _mm512_fmadd_pd(u[q], v[q], s);
        }
        s
    };
    let a = dot(&w.a);
    let b = dot(&w.b);
    let c = match C {
        0 => dot(&w.c),
        1 => {
            let s = _mm512_fmadd_pd(u[3], w.c[3], _mm512_loadu_pd(cols[6].add(j)));
            let s = _mm512_fmadd_pd(u[4], w.c[4], s);
            _mm512_fmadd_pd(u[5], w.c[5], s)
        }
        _ => {
            let s = _mm512_fmadd_pd(u[3], w.c[3], _mm512_loadu_pd(cols[6].add(j)));
            _mm512_fmadd_pd(u[4], w.c[4], s)
        }
    };
    let line0 = _mm512_permutex2var_pd(_mm512_permutex2var_pd(a, idx[0], b), idx[1], c);
    let line1 = _mm512_permutex2var_pd(_mm512_permutex2var_pd(a, idx[2], b), idx[3], c);
    let line2 = _mm512_permutex2var_pd(_mm512_permutex2var_pd(a, idx[4], b), idx[5], c);
    _mm512_store_pd(o, line0);
    _mm512_store_pd(o.add(LANES), line1);
    _mm512_store_pd(o.add(2 * LANES), line2);
}

/// The flat sweep (module docs). `wide` is `None` only when `m < 8`.
///
/// # Safety
///
/// AVX-512F and FMA; `out.len() == w.len() * m`; `c_force` has `m` entries unless `C == 0`;
/// `wide` built from the same columns and `c_force`.
#[inline(always)]
unsafe fn sweep<const C: u8>(
    cols: &[Vec<f64>; 6],
    c_force: &[f64],
    wide: Option<&WideColumns>,
    w: &[[[f64; 6]; 3]],
    out: &mut [Row],
) {
    let m = cols[0].len();
    let total = out.len();
    let one = |k: usize| {
        let j = k % m;
        let u = std::array::from_fn(|q| cols[q][j]);
        row::<true, C>(&u, if C == 0 { 0.0 } else { c_force[j] }, &w[k / m])
    };
    let Some(wide) = wide.filter(|x| x.m == m) else {
        for (k, r) in out.iter_mut().enumerate() {
            *r = one(k);
        }
        return;
    };
    // First flat row on a 64-byte boundary (`Row` is 24 bytes with 8-byte alignment, so one of
    // the first 8 rows is).
    let base = out.as_ptr() as usize;
    let head = (0..LANES)
        .find(|&k| (base + k * std::mem::size_of::<Row>()).is_multiple_of(64))
        .unwrap_or(0)
        .min(total);
    for (k, r) in out[..head].iter_mut().enumerate() {
        *r = one(k);
    }
    let cols_ptr: [*const f64; 7] = std::array::from_fn(|q| wide.cols[q].as_ptr().cast::<f64>());
    let idx = interleave_indices();
    let o = out.as_mut_ptr().cast::<f64>();
    let (mut k, mut i, mut j) = (head, head / m, head % m);
    let mut wi = splat(&w[i.min(w.len() - 1)]);
    while k + LANES <= total {
        // Whole steps inside grid point i.
        while j + LANES <= m {
            // SAFETY: k + 8 <= total (rows k..k+8 of `out`, 64-byte aligned since k - head is a
            // multiple of 8) and j < m.
            step::<C>(&cols_ptr, j, &wi, &idx, o.add(3 * k));
            j += LANES;
            k += LANES;
            if k + LANES > total {
                break;
            }
        }
        if k + LANES > total {
            break;
        }
        // Rows k.. reach grid point i + 1 (< N + 1 since k + 8 <= total).
        let next = splat(&w[i + 1]);
        if j < m {
            // Lanes m - j.. belong to grid point i + 1; their rows of U wrap to 0, 1, ...
            let mask = (0xffu32 << (m - j)) as __mmask8;
            step::<C>(&cols_ptr, j, &blend(mask, &wi, &next), &idx, o.add(3 * k));
            k += LANES;
            j = j + LANES - m;
        } else {
            j -= m;
        }
        i += 1;
        wi = next;
    }
    for (kk, r) in out.iter_mut().enumerate().skip(k) {
        *r = one(kk);
    }
}

/// AVX-512 fill, same contract as [`super::kernel::fill_portable`] plus `wide` (see
/// [`WideColumns::new`]).
///
/// # Safety
///
/// The CPU must support AVX-512F and FMA; `out.len() == w.len() * m`; `c_force` has `m` entries
/// unless `mode` is [`CMode::Full`]; `wide` built from the same `cols` and `c_force`.
#[target_feature(enable = "avx512f,fma")]
pub(super) unsafe fn fill_avx512(
    cols: &[Vec<f64>; 6],
    c_force: &[f64],
    wide: Option<&WideColumns>,
    mode: CMode,
    w: &[[[f64; 6]; 3]],
    out: &mut [Row],
) {
    match mode {
        CMode::Full => sweep::<0>(cols, c_force, wide, w, out),
        CMode::ConstForce => sweep::<1>(cols, c_force, wide, w, out),
        CMode::ConstForceNoTz => sweep::<2>(cols, c_force, wide, w, out),
    }
}
