//! The portable and AVX2 + FMA fills: one row at a time in the source, vectorized over rows by
//! the compiler.
//!
//! # Math
//!
//! For grid point `i` and row `j` of `U` (columns read contiguously),
//!
//! ```text
//!     a_ij = U_j w_a(s_i),   b_ij = U_j w_b(s_i),   c_ij as CMode says,
//! ```
//!
//! each dot product evaluated as `u_0 v_0`, then `+ u_q v_q` for `q = 1, ..., 5` in that order
//! (fused multiply-adds in the FMA kernel, one rounding each). The AVX-512 kernel
//! ([`super::avx512`]) performs the same operations in the same order, so its rows are
//! bit-identical to the AVX2 + FMA ones.

use crate::constraints::Row;

/// How the kernel produces `c` (see the module docs of [`super`], "Cost").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum CMode {
    /// `c = U w_c` (6 multiply-adds).
    Full,
    /// `c = c_force + U_t w_c,t` (3).
    ConstForce,
    /// `c = c_force + U_t[.., 0..2] w_c,t[0..2]` (2): the last torque component is zero.
    ConstForceNoTz,
    /// As [`CMode::ConstForceNoTz`], and the constant force part of `w_c` is `(0, 0, f_z)`
    /// (vertical gravity), so that `c_force = U_z f_z` (one product). The AVX-512 kernel
    /// [`super::FillKernel::Avx512Gz`] recomputes that product at every row instead of loading
    /// `c_force`; every other kernel loads it as for [`CMode::ConstForceNoTz`]. The rows are the
    /// same bit for bit: `c_force` is stored as `U_z f_z + (U_y 0 + U_x 0)`, which is the
    /// rounded product `U_z f_z` (adding a zero is exact).
    VerticalForceNoTz,
}

/// `a * b + c`, fused when the kernel is compiled with FMA (one rounding, faster), plain
/// otherwise (a software fused multiply-add would be slow).
#[inline(always)]
pub(super) fn madd<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// One row: `u` is row `j` of `U`, `cf` its `c_force` entry (unused in [`CMode::Full`]).
/// `C`: 0 full, 1 constant force, 2 constant force and zero last torque component.
#[inline(always)]
pub(super) fn row<const FMA: bool, const C: u8>(u: &[f64; 6], cf: f64, wi: &[[f64; 6]; 3]) -> Row {
    let [wa, wb, wc] = wi;
    let dot = |v: &[f64; 6]| {
        let s = madd::<FMA>(u[1], v[1], u[0] * v[0]);
        let s = madd::<FMA>(u[2], v[2], s);
        let s = madd::<FMA>(u[3], v[3], s);
        let s = madd::<FMA>(u[4], v[4], s);
        madd::<FMA>(u[5], v[5], s)
    };
    let c = match C {
        0 => dot(wc),
        1 => {
            let s = madd::<FMA>(u[3], wc[3], cf);
            let s = madd::<FMA>(u[4], wc[4], s);
            madd::<FMA>(u[5], wc[5], s)
        }
        _ => madd::<FMA>(u[4], wc[4], madd::<FMA>(u[3], wc[3], cf)),
    };
    Row {
        a: dot(wa),
        b: dot(wb),
        c,
    }
}

/// The sweep: for each grid point, for each row `j`.
#[inline(always)]
fn fill_kernel<const FMA: bool, const C: u8>(
    cols: &[Vec<f64>; 6],
    c_force: &[f64],
    w: &[[[f64; 6]; 3]],
    out: &mut [Row],
) {
    let m = cols[0].len();
    if m == 0 {
        return;
    }
    let [c0, c1, c2, c3, c4, c5] = cols;
    let (c0, c1, c2, c3, c4, c5) = (&c0[..m], &c1[..m], &c2[..m], &c3[..m], &c4[..m], &c5[..m]);
    let cf = if C == 0 { &[][..] } else { &c_force[..m] };
    for (wi, rows) in w.iter().zip(out.chunks_exact_mut(m)) {
        for j in 0..m {
            let u = [c0[j], c1[j], c2[j], c3[j], c4[j], c5[j]];
            rows[j] = row::<FMA, C>(&u, if C == 0 { 0.0 } else { cf[j] }, wi);
        }
    }
}

#[inline(always)]
fn dispatch<const FMA: bool>(
    cols: &[Vec<f64>; 6],
    c_force: &[f64],
    mode: CMode,
    w: &[[[f64; 6]; 3]],
    out: &mut [Row],
) {
    match mode {
        CMode::Full => fill_kernel::<FMA, 0>(cols, c_force, w, out),
        CMode::ConstForce => fill_kernel::<FMA, 1>(cols, c_force, w, out),
        CMode::ConstForceNoTz | CMode::VerticalForceNoTz => {
            fill_kernel::<FMA, 2>(cols, c_force, w, out)
        }
    }
}

/// Portable fill (separate multiply and add; any CPU). `out` holds `w.len()` times `m` rows.
pub(super) fn fill_portable(
    cols: &[Vec<f64>; 6],
    c_force: &[f64],
    mode: CMode,
    w: &[[[f64; 6]; 3]],
    out: &mut [Row],
) {
    dispatch::<false>(cols, c_force, mode, w, out)
}

/// AVX2 + FMA fill, same contract as [`fill_portable`].
///
/// # Safety
///
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn fill_avx2(
    cols: &[Vec<f64>; 6],
    c_force: &[f64],
    mode: CMode,
    w: &[[[f64; 6]; 3]],
    out: &mut [Row],
) {
    dispatch::<true>(cols, c_force, mode, w, out)
}
