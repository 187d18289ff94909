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
//! ("flat" index) at byte `24 k`. Measured on the development machine (`bench/peers/topp.md`
//! in the repository, example `fill_bounds`), the fill is bound first by writing these rows into
//! the second-level cache: for 172 rows and 101 grid points, storing the same 417 KB and
//! computing nothing takes most of the fill's time, about as long as the 14 multiply-adds per
//! row without stores, and the two overlap only in part; stores that straddle two cache lines
//! cost more. Steps are therefore
//! aligned on the *output*: each step computes the flat rows `k, ..., k + 7` with `24 k`
//! bytes past a 64-byte boundary, i.e. exactly three cache lines, written by three aligned
//! 64-byte stores after six two-source permutes interleave `a`, `b`, `c`.
//!
//! A step may straddle two grid points (when `m` is not a multiple of 8): its lanes take their
//! `w` vectors from one or the other (a masked blend, once per grid point), and its rows of `U`
//! wrap around from `m - 1` to `0`. Within grid point `i`, steps start at rows
//! `j = r_i (mod 8)`, `r_i = (k_0 - i m) mod 8` (`k_0` the first aligned flat row). Loads that
//! straddle two cache lines also cost (measured), so the columns of `U` and `U_f (m g)` are
//! stored once per phase `r = 0, ..., 7`, 64-byte aligned and rotated so that the 8 rows
//! `j, ..., (j + 7) mod m` of any step of phase `r` are one aligned line ([`WideColumns`], 8
//! times the size of `U`). The grid points are swept phase after phase (`r_i` repeats with
//! period `8 / gcd(m mod 8, 8)`) so that one phase of the columns stays in the first-level
//! cache while the output streams through it. The rows before the first aligned line and after
//! the last whole step (fewer than 8 each) are computed one at a time with the same
//! operations. For `m < 8` every row is computed that way.
//!
//! # Loads against multiply-adds ([`CMode::VerticalForceNoTz`])
//!
//! Per step the kernel issues 6 loads of `U`, one of `U_f (m g)`, 14 multiply-adds, 6
//! permutes and 3 stores. Measured on the development machine (`bench/peers/topp.md`), each
//! load per step costs about as much as the multiply-adds and permutes it feeds while the
//! stores stream out (the first-level cache serves the loads and the lines written back to the
//! second level): with vertical gravity, `U_f (m g) = U_z m g_z` is therefore recomputed by one
//! multiply from the `U_z` already loaded instead of loaded (`FillKernel::Avx512Gz`, faster on
//! 137 and 172 rows). The product is the one stored in `U_f (m g)`, so the rows are
//! unchanged bit for bit. Keeping `U` in a layout that needs no permutes (each output line
//! computed directly, 18 multiply-adds and 18 loads per step) was measured slower for the
//! same reason.

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

/// Columns of `U` and `U_f (m g)` ("sources" 0-5 and 6), 64-byte aligned, once per phase
/// `r = 0..8`: in phase `r`, entry `x` holds row `(x + r - 8) mod m`, so that the 8 rows
/// `j, ..., (j + 7) mod m` of a step with `j = r (mod 8)` are the aligned line at `x = j - r + 8`
/// (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct WideColumns {
    /// Phase after phase, source after source, `lines` lines each.
    data: Vec<Line>,
    lines: usize,
    m: usize,
}

/// Sources per phase: the 6 columns of `U`, then `c_force`.
const SOURCES: usize = 7;

/// Grid points are swept phase by phase within chunks of about this many bytes of output
/// (unit: bytes; 256 KiB). Not a numerical threshold (results do not depend on it), a cache
/// size: a chunk's output stays well inside a 2 MB second-level cache, so sweeping it phase by
/// phase costs nothing, while sweeping a whole output larger than the cache phase by phase was
/// measured slower than in order (N = 1000, 4 MB of rows; `bench/peers/topp.md`).
const PHASE_CHUNK_BYTES: usize = 256 * 1024;

impl WideColumns {
    /// From the columns of `U` and `c_force` (empty when absent: zeros); `None` when `m < 8`
    /// (no step fits in one grid point's rows, every row is computed one at a time).
    pub(super) fn new(cols: &[Vec<f64>; 6], c_force: &[f64]) -> Option<Self> {
        let m = cols[0].len();
        if m < LANES {
            return None;
        }
        // Largest entry read: x + 7 with x = j - r + 8 <= m + 7.
        let lines = (m + 2 * LANES - 1).div_ceil(LANES);
        // periodic[q][y] = source q at row y mod m, for every y a phase reads (empty for an
        // absent c_force, whose phases are zeros).
        let periodic: Vec<Vec<f64>> = (0..SOURCES)
            .map(|q| {
                let src: &[f64] = if q < 6 { &cols[q] } else { c_force };
                let mut p = Vec::new();
                while !src.is_empty() && p.len() < m + LANES * lines {
                    p.extend_from_slice(src);
                }
                p
            })
            .collect();
        let mut data = Vec::with_capacity(LANES * SOURCES * lines);
        for r in 0..LANES {
            // Entry 0 of phase r holds row (r - 8) mod m.
            let start = (r + LANES * m - LANES) % m;
            for p in &periodic {
                if p.is_empty() {
                    data.extend(std::iter::repeat_n(Line([0.0; LANES]), lines));
                } else {
                    data.extend(
                        p[start..]
                            .chunks_exact(LANES)
                            .take(lines)
                            .map(|c| Line(std::array::from_fn(|t| c[t]))),
                    );
                }
            }
        }
        Some(Self { data, lines, m })
    }

    /// Pointers to the 7 sources of phase `r`.
    fn phase(&self, r: usize) -> [*const f64; SOURCES] {
        let p = &self.data[r * SOURCES * self.lines..(r + 1) * SOURCES * self.lines];
        std::array::from_fn(|q| p[q * self.lines..].as_ptr().cast::<f64>())
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

/// One step: the 8 rows of `U` at entry `x` of a phase of [`WideColumns`] against `w`, written
/// to the three aligned lines at `o`.
///
/// # Safety
///
/// AVX-512F; `src` from [`WideColumns::phase`], `x` a multiple of 8 with `x + 8 <= 8 lines`;
/// `o` 64-byte aligned and valid for 24 writes.
#[inline(always)]
unsafe fn step<const C: u8>(
    src: &[*const f64; SOURCES],
    x: usize,
    w: &Splat,
    idx: &[__m512i; 6],
    o: *mut f64,
) {
    let u: [__m512d; 6] = std::array::from_fn(|q| _mm512_load_pd(src[q].add(x)));
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
            let s = _mm512_fmadd_pd(u[3], w.c[3], _mm512_load_pd(src[6].add(x)));
            let s = _mm512_fmadd_pd(u[4], w.c[4], s);
            _mm512_fmadd_pd(u[5], w.c[5], s)
        }
        2 => {
            let s = _mm512_fmadd_pd(u[3], w.c[3], _mm512_load_pd(src[6].add(x)));
            _mm512_fmadd_pd(u[4], w.c[4], s)
        }
        _ => {
            // c_force = U_z f_z recomputed (w.c[2] = f_z): one multiply instead of a load.
            let s = _mm512_fmadd_pd(u[3], w.c[3], _mm512_mul_pd(u[2], w.c[2]));
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

/// The sweep (module docs). With `wide` `None` (`m < 8`) every row is computed one at a time.
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
    let n = w.len();
    let total = out.len();
    let one = |k: usize| {
        let j = k % m;
        let u = std::array::from_fn(|q| cols[q][j]);
        row::<true, C>(&u, if C == 0 { 0.0 } else { c_force[j] }, &w[k / m])
    };
    // Steps cover the flat rows head..end: head is the first row on a 64-byte boundary (`Row`
    // is 24 bytes with 8-byte alignment, so one of the first 8 rows is), end - head a multiple
    // of 8.
    let base = out.as_ptr() as usize;
    let head = (0..LANES)
        .find(|&k| (base + k * std::mem::size_of::<Row>()).is_multiple_of(64))
        .unwrap_or(0);
    let (head, end) = match wide.filter(|x| x.m == m) {
        Some(_) if total >= head + LANES => (head, head + (total - head) / LANES * LANES),
        _ => (total, total),
    };
    for (k, r) in out[..head].iter_mut().enumerate() {
        *r = one(k);
    }
    for (k, r) in out.iter_mut().enumerate().skip(end) {
        *r = one(k);
    }
    let Some(wide) = wide.filter(|_| end > head) else {
        return;
    };
    let idx = interleave_indices();
    let o = out.as_mut_ptr().cast::<f64>();
    // Grid point i owns the steps starting in its rows; they all start at j = r_i (mod 8) with
    // r_i = (head - i m) mod 8, which repeats with period 8 / gcd(m mod 8, 8). Within a chunk of
    // grid points (a multiple of the period), grid points of one phase are swept together so
    // that one phase of the columns stays in the L1 cache.
    let period = LANES >> (m % LANES).trailing_zeros().min(3);
    let chunk = (PHASE_CHUNK_BYTES / (m * std::mem::size_of::<Row>()) / period).max(1) * period;
    for c0 in (0..n).step_by(chunk) {
        let cn = (c0 + chunk).min(n);
        for i0 in c0..(c0 + period).min(cn) {
            let r = (head + LANES * m - (i0 * m) % LANES) % LANES;
            let src = wide.phase(r);
            for i in (i0..cn).step_by(period) {
                let (first, next_first) = (i * m, (i + 1) * m);
                // First step start >= max(i m, head) congruent to head (mod 8).
                let mut k = first.max(head);
                k += (head + LANES * LANES - k % LANES) % LANES;
                let stop = next_first.min(end);
                let mut x = k - first + LANES - r;
                let wi = splat(&w[i]);
                while k + LANES <= next_first && k < stop {
                    // SAFETY: rows k..k+8 lie in head..end (k < end, end - k a multiple of 8),
                    // 64-byte aligned; x = j - r + 8 with j = k - i m < m.
                    step::<C>(&src, x, &wi, &idx, o.add(3 * k));
                    k += LANES;
                    x += LANES;
                }
                if k < stop {
                    // The step straddles grid points i and i + 1 (< n since k + 8 <= end <= total):
                    // lanes next_first - k.. take w_{i+1}; the phase's entries wrap to row 0.
                    let mask = (0xffu32 << (next_first - k)) as __mmask8;
                    let mixed = blend(mask, &wi, &splat(&w[i + 1]));
                    step::<C>(&src, x, &mixed, &idx, o.add(3 * k));
                }
            }
        }
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
        CMode::VerticalForceNoTz => sweep::<3>(cols, c_force, wide, w, out),
    }
}
