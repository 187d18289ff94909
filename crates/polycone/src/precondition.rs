//! Preconditioning: a change of coordinates that makes the conversion independent of units and
//! of the reference point.
//!
//! # Math
//!
//! Let `V` (`n x d`, one generator per row) have the thin SVD `V = Y S Q` with `S = diag(s_1 >=
//! ... >= s_r > 0)` (singular values above [`crate::tol::Tolerances::rank`] times `s_1`), `Q`
//! (`r x d`) orthonormal rows. Then
//!
//! - `span(V)` is the row space of `Q` and the **equations** of the cone are an orthonormal basis
//!   `E` of its complement (`E v = 0` for every generator);
//! - the **whitened coordinates** of `x in span(V)` are `y = S^{-1} Q x`, and the whitened
//!   generators are the rows of `W = V Q^T S^{-1} = Y`, which has orthonormal columns.
//!
//! For any invertible linear map `M` of `R^d` (a change of reference point of wrenches, a change
//! of units), `V M^T` has whitened generators `Y O` with `O` orthogonal: the problem the double
//! description solves is the same up to a rotation, so its combinatorics and conditioning do
//! not depend on where the world origin is or on the units. A facet `u_w . y <= 0` in whitened
//! coordinates is `u . x <= 0` with `u = Q^T S^{-1} u_w` (then normalized).
//!
//! Zero generators (norm at most [`crate::tol::Tolerances::zero_generator`] times the largest) are
//! dropped; whitened generators are normalized to unit rows, and positively parallel duplicates
//! (distance at most [`crate::tol::Tolerances::duplicate`]) are merged.
//!
//! # How the SVD is computed (`d <= 8`)
//!
//! Householder QR of the kept rows, `V = H R` (`H` orthogonal, `R` `d x d` upper triangular,
//! zero rows past `n` when `n < d`), then a one-sided Jacobi SVD of `R`: rotations `J` of pairs
//! of columns until `R J = U S` has orthogonal columns; `S` (sorted) are the singular values and
//! the columns of `J` the right singular vectors `Q^T`. Since `V^T V = R^T H^T H R = R^T R`,
//! `V` and `R` have the same singular values and right singular vectors. Same answer up to
//! rounding: Householder QR is backward stable, the computed `R` is the exact factor of
//! `V + E_1` with `|E_1| <= c_1 eps |V|`; each Jacobi rotation is backward stable too, and the
//! stopping rules (`JACOBI_ORTHOGONALITY`, `JACOBI_NOISE` in `tol.rs`) leave
//! off-diagonal cosines and skipped parts of at most `16 eps |V|_F` per column, so `S` and `Q`
//! are an exact SVD of `V + E` with `|E| <= c eps |V|_F`. By Weyl's inequality the singular
//! values differ from the exact ones by at most `|E|`, and by Wedin's theorem the kept row
//! space by at most `|E| / gap`: the same bounds the general SVD (bidiagonalization and QR
//! iteration, used before and still for `d > 8`) satisfies. The rank decision is unchanged
//! (`linalg::numerical_rank` with [`crate::tol::Tolerances::rank`] relative to the
//! largest). The tests check the result against the definition (`|V q_c| = s_c`, `Y = V Q^T
//! S^{-1}` with orthonormal columns, `[Q; E]` orthogonal) and against the general SVD on random,
//! rank-deficient, row-scaled and huge/tiny matrices; where the two disagree it is the
//! general SVD that fails the definition (nalgebra 0.34 was off by `1.5e-3` on a rank-2
//! `19 x 8` matrix, and gave `|Y^T Y - I| = 5e-14` against `1e-15` here on a wrench cone).
//!
//! `whiten_into` reuses the buffers of a `Whitened` and a `WhitenScratch` (those of
//! [`crate::Workspace`]): once they are large enough it allocates nothing.

use nalgebra::DMatrix;

use crate::linalg::{dot, normalize, numerical_rank, qr_jacobi_svd, sorted_svd_general};
use crate::tol::{Tolerances, JACOBI_MAX_SWEEPS, JACOBI_NOISE, JACOBI_ORTHOGONALITY};

/// A span-form problem in whitened coordinates.
#[derive(Clone, Debug, Default)]
pub(crate) struct Whitened {
    /// Dimension of `span(V)`.
    pub r: usize,
    /// Dimension of the input space.
    pub d: usize,
    /// `r x d`, orthonormal rows spanning `span(V)`, row-major.
    pub q: Vec<f64>,
    /// The `r` singular values kept.
    pub sv: Vec<f64>,
    /// `(d - r) x d`, orthonormal rows: the equations.
    pub equations: DMatrix<f64>,
    /// Input indices of the nonzero generators.
    pub kept: Vec<usize>,
    /// Whitened unit generators, `kept.len() x r`, row-major.
    pub w: Vec<f64>,
    /// Indices into `kept` of the generators left after merging duplicates.
    pub distinct: Vec<usize>,
    /// Largest `|E v| / max |v|` over the generators (how far they are from `span(V)`).
    pub equation_residual: f64,
    /// The exact power of two the input was multiplied by before the SVD (so that `sv` are the
    /// singular values of `scale * V`); 1 when no scaling was needed.
    pub scale: f64,
}

impl Whitened {
    /// Whitened generator `i` (index into `kept`).
    #[inline]
    pub fn gen(&self, i: usize) -> &[f64] {
        &self.w[i * self.r..(i + 1) * self.r]
    }

    /// Maps a whitened facet normal back: `u = Q^T S^{-1} u_w`, normalized.
    pub fn facet_to_world(&self, u_w: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for ((&u, &s), q) in u_w.iter().zip(&self.sv).zip(self.q.chunks_exact(self.d)) {
            let f = u / s;
            for (o, qv) in out.iter_mut().zip(q) {
                *o += f * qv;
            }
        }
        normalize(out);
    }

    /// [`Self::facet_to_world`] on every row of `fw` (`r` columns) into `out` (`d` columns):
    /// `Q^T S^{-1}` is formed once in `map` (`d x r`), then each facet is one matrix-vector
    /// product (no division per entry).
    pub fn facets_to_world(&self, fw: &[f64], out: &mut [f64], map: &mut Vec<f64>) {
        let (r, d) = (self.r, self.d);
        if r == 0 {
            out.fill(0.0);
            return;
        }
        map.clear();
        map.resize(d * r, 0.0);
        for (c, (q, &s)) in self.q.chunks_exact(d).zip(&self.sv).enumerate() {
            let inv = 1.0 / s;
            for (j, &qv) in q.iter().enumerate() {
                map[j * r + c] = qv * inv;
            }
        }
        match (r == d).then_some(d) {
            Some(3) => map_rows::<3>(map, fw, out),
            Some(4) => map_rows::<4>(map, fw, out),
            Some(5) => map_rows::<5>(map, fw, out),
            Some(6) => map_rows::<6>(map, fw, out),
            Some(7) => map_rows::<7>(map, fw, out),
            Some(8) => map_rows::<8>(map, fw, out),
            _ => {
                for (u_w, u) in fw.chunks_exact(r).zip(out.chunks_exact_mut(d)) {
                    for (o, row) in u.iter_mut().zip(map.chunks_exact(r)) {
                        *o = dot(row, u_w);
                    }
                    normalize(u);
                }
            }
        }
    }

    /// Maps a facet normal `u` to whitened coordinates: `u_w = S Q u`, normalized.
    pub fn facet_from_world(&self, u: &[f64], out: &mut [f64]) {
        for ((o, &s), q) in out
            .iter_mut()
            .zip(&self.sv)
            .zip(self.q.chunks_exact(self.d))
        {
            let qu: f64 = q.iter().zip(u).map(|(a, b)| a * b).sum();
            *o = s * qu;
        }
        normalize(out);
    }

    /// Maps a whitened point back: `x = Q^T S y` (not normalized).
    pub fn point_to_world(&self, y: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for ((&y, &s), q) in y.iter().zip(&self.sv).zip(self.q.chunks_exact(self.d)) {
            let f = y * s;
            for (o, qv) in out.iter_mut().zip(q) {
                *o += f * qv;
            }
        }
    }
}

/// Reusable buffers of [`whiten_into`] (kept across calls: no allocation once they are large
/// enough).
#[derive(Clone, Debug, Default)]
pub(crate) struct WhitenScratch {
    /// The scaled input rows, `n x d`, row-major.
    rows: Vec<f64>,
    /// Their norms.
    norms: Vec<f64>,
    /// The kept rows, column-major, for the QR (overwritten by it).
    a: Vec<f64>,
    /// The `d` singular values, decreasing.
    sv: Vec<f64>,
    /// The matching right singular vectors, `d x d`, row-major.
    vt: Vec<f64>,
    /// The whitened generators in the order of their first coordinates, the position of each
    /// in that order, and which are distinct (for the duplicate test).
    order: Vec<usize>,
    position: Vec<usize>,
    distinct_flag: Vec<bool>,
}

/// `out_i = normalize(map x_i)` for the rows `x_i` of `x`, with `map` square of the fixed size
/// `D` (row-major): loops of fixed length, unrolled.
fn map_rows<const D: usize>(map: &[f64], x: &[f64], out: &mut [f64]) {
    let mut m = [[0.0f64; D]; D];
    for (row, src) in m.iter_mut().zip(map.chunks_exact(D)) {
        row.copy_from_slice(src);
    }
    for (xi, oi) in x.chunks_exact(D).zip(out.chunks_exact_mut(D)) {
        let xi: &[f64; D] = xi.try_into().expect("rows of length D");
        let mut y = [0.0f64; D];
        for (yj, row) in y.iter_mut().zip(&m) {
            *yj = row.iter().zip(xi).map(|(a, b)| a * b).sum();
        }
        let inv = 1.0 / y.iter().map(|v| v * v).sum::<f64>().sqrt();
        for (o, v) in oi.iter_mut().zip(y) {
            *o = if inv.is_finite() { v * inv } else { v };
        }
    }
}

/// Whitens the generators `v` (rows), assumed finite with `v.ncols() >= 1`, into a new
/// [`Whitened`] (see [`whiten_into`], which reuses buffers).
pub(crate) fn whiten(v: &DMatrix<f64>, tol: &Tolerances) -> Whitened {
    let mut out = Whitened::default();
    whiten_into(v, tol, &mut out, &mut WhitenScratch::default());
    out
}

/// Whitens the generators `v` (rows), assumed finite with `v.ncols() >= 1`, into `out`,
/// reusing the buffers of `out` and `scratch`: once they are large enough, nothing is
/// allocated for `d <= 8` (the general SVD of larger `d`, or when the fast one does not
/// converge, allocates).
pub(crate) fn whiten_into(
    v: &DMatrix<f64>,
    tol: &Tolerances,
    out: &mut Whitened,
    scratch: &mut WhitenScratch,
) {
    // Fixed-length inner loops for the common dimensions (see `crate::dd` for the same idea).
    match v.ncols() {
        1 => whiten_core::<1>(v, tol, out, scratch),
        2 => whiten_core::<2>(v, tol, out, scratch),
        3 => whiten_core::<3>(v, tol, out, scratch),
        4 => whiten_core::<4>(v, tol, out, scratch),
        5 => whiten_core::<5>(v, tol, out, scratch),
        6 => whiten_core::<6>(v, tol, out, scratch),
        7 => whiten_core::<7>(v, tol, out, scratch),
        8 => whiten_core::<8>(v, tol, out, scratch),
        _ => whiten_core::<0>(v, tol, out, scratch),
    }
}

/// [`whiten_into`] with `d = D` fixed at compile time (`D = 0`: dynamic, general SVD).
fn whiten_core<const D: usize>(
    v: &DMatrix<f64>,
    tol: &Tolerances,
    out: &mut Whitened,
    scratch: &mut WhitenScratch,
) {
    let n = v.nrows();
    let d = if D == 0 { v.ncols() } else { D };
    // Scale by a power of two (exact, and the cone does not change) so that the largest entry
    // is about 1: norms of rows with entries near 1e300 or 1e-300 neither overflow nor vanish.
    let amax = v.as_slice().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let (f1, f2) = if amax > 0.0 && !(0.5..=1.0).contains(&amax) {
        let e = amax.log2().floor() as i32;
        // Two steps: 2^-e alone may not be representable for subnormal inputs.
        let (e1, e2) = (e / 2, e - e / 2);
        (2f64.powi(-e1), 2f64.powi(-e2))
    } else {
        (1.0, 1.0)
    };
    let WhitenScratch {
        rows,
        norms,
        a,
        sv: sv_all,
        vt,
        order,
        position,
        distinct_flag,
    } = scratch;
    rows.clear();
    rows.resize(n * d, 0.0);
    if n > 0 {
        for (j, col) in v.as_slice().chunks_exact(n).enumerate() {
            for (row, &x) in rows.chunks_exact_mut(d).zip(col) {
                row[j] = x * f1 * f2;
            }
        }
    }
    norms.clear();
    norms.extend(rows.chunks_exact(d).map(|row| dot(row, row).sqrt()));
    let maxn = norms.iter().copied().fold(0.0, f64::max);
    out.d = d;
    // (May overflow to infinity for subnormal inputs; users of `scale` check.)
    out.scale = f1 * f2;
    out.kept.clear();
    out.kept
        .extend((0..n).filter(|&i| norms[i] > 0.0 && norms[i] > tol.zero_generator * maxn));
    out.q.clear();
    out.sv.clear();
    out.w.clear();
    out.distinct.clear();
    out.equation_residual = 0.0;
    let nk = out.kept.len();
    let mut eq = std::mem::take(&mut out.equations).data.into();
    if nk == 0 {
        out.r = 0;
        set_rows(&mut eq, d, d, |e, j| if e == j { 1.0 } else { 0.0 });
        out.equations = DMatrix::from_vec(d, d, eq);
        return;
    }
    // The kept rows, column-major, and their sorted SVD.
    a.clear();
    a.resize(nk * d, 0.0);
    for (t, &i) in out.kept.iter().enumerate() {
        for (j, &x) in rows[i * d..(i + 1) * d].iter().enumerate() {
            a[j * nk + t] = x;
        }
    }
    sv_all.clear();
    sv_all.resize(d, 0.0);
    vt.clear();
    vt.resize(d * d, 0.0);
    let (o, m) = ([JACOBI_ORTHOGONALITY, JACOBI_NOISE], JACOBI_MAX_SWEEPS);
    if D == 0 || qr_jacobi_svd::<D>(a, nk, o, m, sv_all, vt).is_none() {
        let vk = DMatrix::from_fn(nk, d, |t, j| rows[out.kept[t] * d + j]);
        let (s, m) = sorted_svd_general(&vk);
        sv_all.copy_from_slice(&s);
        for (row, dst) in vt.chunks_exact_mut(d).enumerate() {
            for (j, x) in dst.iter_mut().enumerate() {
                *x = m[(row, j)];
            }
        }
    }
    let r = numerical_rank(sv_all, tol.rank);
    out.r = r;
    out.q.extend_from_slice(&vt[..r * d]);
    out.sv.extend_from_slice(&sv_all[..r]);
    set_rows(&mut eq, d - r, d, |e, j| vt[(r + e) * d + j]);
    out.equations = DMatrix::from_vec(d - r, d, eq);
    // Whitened unit generators (`S^-1 Q` first, in the scratch `a` the QR is done with), and
    // how far the generators are from span(V).
    a.clear();
    for (q, &s) in out.q.chunks_exact(d).zip(&out.sv) {
        a.extend(q.iter().map(|x| x / s));
    }
    out.w.resize(nk * r, 0.0);
    let mut equation_residual: f64 = 0.0;
    for (&i, wt) in out.kept.iter().zip(out.w.chunks_exact_mut(r.max(1))) {
        let row = &rows[i * d..(i + 1) * d];
        for (o, qs) in wt.iter_mut().zip(a.chunks_exact(d)) {
            *o = dot(qs, row);
        }
        normalize(wt);
        for ev in vt[r * d..].chunks_exact(d) {
            equation_residual = equation_residual.max(dot(ev, row).abs());
        }
    }
    // (Divided once: rounded division is monotone, so this is the largest quotient.)
    let equation_residual = equation_residual / maxn;
    out.equation_residual = equation_residual;
    if nk < SORTED_DUPLICATE_TEST_FROM {
        let w = &out.w;
        'outer: for t in 0..nk {
            let gt = &w[t * r..(t + 1) * r];
            for &s in &out.distinct {
                if is_duplicate(gt, &w[s * r..(s + 1) * r], tol.duplicate) {
                    continue 'outer;
                }
            }
            out.distinct.push(t);
        }
    } else {
        mark_distinct(
            &out.w,
            nk,
            r,
            tol.duplicate,
            &mut out.distinct,
            [order, position],
            distinct_flag,
        );
    }
}

/// From this many kept generators on, the duplicate test sorts them by first coordinate
/// ([`mark_distinct`]); below, comparing each with every earlier distinct one is faster
/// (measured: whitening 10-15 % faster compared one by one at 16 and 32 generators, 20 %
/// faster sorted at 64). Same decisions either way.
const SORTED_DUPLICATE_TEST_FROM: usize = 48;

/// Whether the whitened generators `gt` and `gs` are within `duplicate` (Euclidean): within
/// it in every coordinate first (most pairs fail that in one of the first coordinates;
/// symmetric stances tie in the first), then the distance.
#[inline]
fn is_duplicate(gt: &[f64], gs: &[f64], duplicate: f64) -> bool {
    !gt.iter().zip(gs).any(|(a, b)| (a - b).abs() > duplicate)
        && gt
            .iter()
            .zip(gs)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            <= duplicate * duplicate
}

/// The generators (indices into the `nk` whitened rows `w`, dimension `r`) left after dropping
/// each one within `duplicate` (Euclidean) of an earlier one left, in increasing order: the
/// first of each group of positively parallel generators.
///
/// The same decisions as comparing each row with every earlier distinct one, found faster: a
/// duplicate is within `duplicate` in the first coordinate, so only the neighbours of a row in
/// the order of first coordinates are compared.
fn mark_distinct(
    w: &[f64],
    nk: usize,
    r: usize,
    duplicate: f64,
    distinct: &mut Vec<usize>,
    [order, position]: [&mut Vec<usize>; 2],
    is_distinct: &mut Vec<bool>,
) {
    distinct.clear();
    if r == 0 {
        // Every row is the empty vector: all duplicates of the first.
        distinct.extend((0..nk).take(1));
        return;
    }
    order.clear();
    order.extend(0..nk);
    order.sort_unstable_by(|&x, &y| w[x * r].total_cmp(&w[y * r]));
    position.clear();
    position.resize(nk, 0);
    for (k, &t) in order.iter().enumerate() {
        position[t] = k;
    }
    is_distinct.clear();
    is_distinct.resize(nk, false);
    let near = |gt: &[f64], s: usize| is_duplicate(gt, &w[s * r..(s + 1) * r], duplicate);
    for t in 0..nk {
        let gt = &w[t * r..(t + 1) * r];
        let k = position[t];
        // Only rows already marked distinct (so earlier than `t`) count.
        let below = order[..k]
            .iter()
            .rev()
            .take_while(|&&s| gt[0] - w[s * r] <= duplicate)
            .any(|&s| is_distinct[s] && near(gt, s));
        let above = || {
            order[k + 1..]
                .iter()
                .take_while(|&&s| w[s * r] - gt[0] <= duplicate)
                .any(|&s| is_distinct[s] && near(gt, s))
        };
        if !below && !above() {
            is_distinct[t] = true;
            distinct.push(t);
        }
    }
}

/// Fills `buf` with the `rows x cols` column-major matrix whose entry `(e, j)` is `f(e, j)`.
fn set_rows(buf: &mut Vec<f64>, rows: usize, cols: usize, f: impl Fn(usize, usize) -> f64) {
    buf.clear();
    buf.resize(rows * cols, 0.0);
    for j in 0..cols {
        for e in 0..rows {
            buf[j * rows + e] = f(e, j);
        }
    }
}

#[cfg(test)]
mod alloc_count {
    //! A counting global allocator for this crate's unit tests (per thread, so that tests running
    //! in parallel do not see each other's allocations).

    use std::alloc::{GlobalAlloc, Layout, System};
    use std::cell::Cell;

    use super::*;

    thread_local! {
        static COUNT: Cell<usize> = const { Cell::new(0) };
    }

    fn bump() {
        let _ = COUNT.try_with(|c| c.set(c.get() + 1));
    }

    struct Counting;

    // SAFETY: every call is forwarded to the system allocator unchanged.
    unsafe impl GlobalAlloc for Counting {
        unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
            bump();
            unsafe { System.alloc(layout) }
        }
        unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
            bump();
            unsafe { System.alloc_zeroed(layout) }
        }
        unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
            bump();
            unsafe { System.realloc(ptr, layout, new_size) }
        }
        unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
            unsafe { System.dealloc(ptr, layout) }
        }
    }

    #[global_allocator]
    static GLOBAL: Counting = Counting;

    /// Allocations (including reallocations) made by this thread while running `f`.
    pub(crate) fn allocations_in<F: FnOnce()>(f: F) -> usize {
        let before = COUNT.with(Cell::get);
        f();
        COUNT.with(Cell::get) - before
    }

    pub(super) fn golden_for_tests(case: &str) -> DMatrix<f64> {
        let path = format!(
            "{}/../../testdata/cones/{case}.json",
            env!("CARGO_MANIFEST_DIR")
        );
        let text = std::fs::read_to_string(path).unwrap();
        let j: serde_json::Value = serde_json::from_str(&text).unwrap();
        let rows: Vec<Vec<f64>> =
            serde_json::from_value(j["generators"]["float64"].clone()).unwrap();
        DMatrix::from_fn(rows.len(), 6, |i, k| rows[i][k])
    }

    /// A warm `whiten_into` allocates nothing (full rank, rank-deficient with equations,
    /// scaled, and the zero cone). Prints the allocations of a warm `span_to_face` (39 before
    /// this whitening, 10 with it, on the single support).
    #[test]
    fn warm_whitening_does_not_allocate() {
        let tol = Tolerances::default();
        let single = golden_for_tests("single_support_flat");
        let mut flat = single.clone();
        flat.column_mut(2).fill(0.0);
        let inputs = [
            single.clone(),
            golden_for_tests("double_support_flat"),
            flat,
            &single * 1e200,
            DMatrix::zeros(3, 6),
        ];
        let (mut out, mut scratch) = (Whitened::default(), WhitenScratch::default());
        for v in &inputs {
            whiten_into(v, &tol, &mut out, &mut scratch);
        }
        for v in &inputs {
            let n = allocations_in(|| whiten_into(v, &tol, &mut out, &mut scratch));
            assert_eq!(n, 0, "{} x {} input", v.nrows(), v.ncols());
        }
        let opts = crate::DdOptions::default();
        let mut ws = crate::Workspace::new();
        for _ in 0..3 {
            ws.span_to_face(&single, &opts).unwrap();
        }
        let n = allocations_in(|| {
            std::hint::black_box(ws.span_to_face(&single, &opts).unwrap());
        });
        eprintln!("warm span_to_face, single support: {n} allocations");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// [`qr_jacobi_svd`] for `d <= 8`: the number of sweeps (`None`: not handled or not
    /// converged).
    fn small_svd(
        a: &mut [f64],
        n: usize,
        d: usize,
        sv: &mut [f64],
        vt: &mut [f64],
    ) -> Option<usize> {
        let (o, m) = ([JACOBI_ORTHOGONALITY, JACOBI_NOISE], JACOBI_MAX_SWEEPS);
        match d {
            1 => qr_jacobi_svd::<1>(a, n, o, m, sv, vt),
            2 => qr_jacobi_svd::<2>(a, n, o, m, sv, vt),
            3 => qr_jacobi_svd::<3>(a, n, o, m, sv, vt),
            4 => qr_jacobi_svd::<4>(a, n, o, m, sv, vt),
            5 => qr_jacobi_svd::<5>(a, n, o, m, sv, vt),
            6 => qr_jacobi_svd::<6>(a, n, o, m, sv, vt),
            7 => qr_jacobi_svd::<7>(a, n, o, m, sv, vt),
            8 => qr_jacobi_svd::<8>(a, n, o, m, sv, vt),
            _ => None,
        }
    }

    /// The whitening as it was computed before the QR + Jacobi path: nalgebra's SVD of the
    /// kept rows (the same scaling, norms and rank rule), for comparison.
    fn reference(v: &DMatrix<f64>, tol: &Tolerances) -> (Vec<usize>, Vec<f64>, DMatrix<f64>) {
        let amax = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let mut vs = v.clone();
        if amax > 0.0 && !(0.5..=1.0).contains(&amax) {
            let e = amax.log2().floor() as i32;
            vs = vs * 2f64.powi(-(e / 2)) * 2f64.powi(-(e - e / 2));
        }
        let norms: Vec<f64> = (0..vs.nrows()).map(|i| vs.row(i).norm()).collect();
        let maxn = norms.iter().copied().fold(0.0, f64::max);
        let kept: Vec<usize> = (0..vs.nrows())
            .filter(|&i| norms[i] > 0.0 && norms[i] > tol.zero_generator * maxn)
            .collect();
        if kept.is_empty() {
            return (kept, Vec::new(), DMatrix::zeros(0, v.ncols()));
        }
        let vk = DMatrix::from_fn(kept.len(), v.ncols(), |t, j| vs[(kept[t], j)]);
        let (sv, vt) = sorted_svd_general(&vk);
        (kept, sv, vt)
    }

    /// Largest entry of `|a - b|`.
    fn max_diff(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
        (a - b).abs().max()
    }

    /// Checks the fast whitening of `v` against [`reference`] and against the definition.
    fn check_against_reference(v: &DMatrix<f64>) -> Result<(), TestCaseError> {
        let tol = Tolerances::default();
        let d = v.ncols();
        let wh = whiten(v, &tol);
        let (kept, sv_ref, vt_ref) = reference(v, &tol);
        prop_assert_eq!(&wh.kept, &kept);
        if kept.is_empty() {
            prop_assert_eq!(wh.r, 0);
            prop_assert_eq!(max_diff(&wh.equations, &DMatrix::identity(d, d)), 0.0);
            return Ok(());
        }
        // The fast path handled it (no fallback), in few sweeps.
        let mut a = vec![0.0; kept.len() * d];
        for (t, &i) in kept.iter().enumerate() {
            for j in 0..d {
                a[j * kept.len() + t] = v[(i, j)] * wh.scale;
            }
        }
        let (mut sv, mut vt) = (vec![0.0; d], vec![0.0; d * d]);
        let sweeps = small_svd(&mut a, kept.len(), d, &mut sv, &mut vt);
        prop_assert!(sweeps.is_some_and(|s| s <= 12), "sweeps {:?}", sweeps);
        // Singular values: those of `V + E`, `|E| <= c eps |V|` (Weyl: they move by |E|).
        // Where the general SVD disagrees, it is the one that is wrong: its `|V q_c|` is not its
        // `s_c`, while ours is (nalgebra 0.34 is off by 1.5e-3 on a rank-2 19 x 8 matrix, and
        // LAPACK agrees with this one).
        let smax = sv_ref[0].max(sv[0]);
        // `|E| <= c eps |V|_F`, with the `16 eps` per column of the skipped rotations.
        let vk = DMatrix::from_fn(kept.len(), d, |t, j| v[(kept[t], j)] * wh.scale);
        let bound = 64.0 * f64::EPSILON * vk.norm();
        let defect = |s: &[f64], vt: &dyn Fn(usize, usize) -> f64| -> f64 {
            (0..d)
                .map(|c| {
                    let q = nalgebra::DVector::from_fn(d, |j, _| vt(c, j));
                    ((&vk * q).norm() - s[c]).abs()
                })
                .fold(0.0, f64::max)
        };
        let ours = defect(&sv, &|c, j| vt[c * d + j]);
        prop_assert!(ours <= bound, "|V q_c| - s_c: {ours:e}");
        if sv.iter().zip(&sv_ref).any(|(a, b)| (a - b).abs() > bound) {
            let theirs = defect(&sv_ref, &|c, j| vt_ref[(c, j)]);
            prop_assert!(theirs > bound, "{sv:?} vs {sv_ref:?}");
            return Ok(());
        }
        // The rank, unless a singular value is within rounding of the threshold.
        let r_ref = numerical_rank(&sv_ref, tol.rank);
        let near = sv_ref
            .iter()
            .any(|&s| (s - tol.rank * smax).abs() <= 2.0 * bound);
        if near {
            return Ok(());
        }
        prop_assert_eq!(wh.r, r_ref);
        let r = wh.r;
        // [Q; E] is orthogonal.
        let mut all = DMatrix::zeros(d, d);
        for c in 0..r {
            for j in 0..d {
                all[(c, j)] = wh.q[c * d + j];
            }
        }
        all.rows_mut(r, d - r).copy_from(&wh.equations);
        prop_assert!(max_diff(&(&all * all.transpose()), &DMatrix::identity(d, d)) <= 1e-14);
        // span(V): the projector on the rows of Q, up to rounding over the gap (Wedin).
        let gap = sv_ref[r - 1] - sv_ref.get(r).copied().unwrap_or(0.0);
        let q_new = all.rows(0, r).into_owned();
        let q_ref = vt_ref.rows(0, r).into_owned();
        let p_diff = max_diff(&(q_new.transpose() * &q_new), &(q_ref.transpose() * &q_ref));
        prop_assert!(
            p_diff <= 1e-14 * smax / gap,
            "projector {p_diff:e}, gap {gap:e}"
        );
        // The whitened generators before normalization, `Y = V Q^T S^-1`, have orthonormal
        // columns: rounding in `Q` along `s_1` shows up multiplied by `s_1 / s_r`. (Checked
        // here rather than against the general SVD, which is the less accurate of the two:
        // on a row scaled by 1e4 it gave cosines of 4e-9 between whitened rows that are
        // orthogonal, where this whitening gives 5e-13.)
        let cond = smax / sv_ref[r - 1];
        let mut y = DMatrix::zeros(kept.len(), r);
        for (t, &i) in kept.iter().enumerate() {
            for c in 0..r {
                y[(t, c)] = (0..d)
                    .map(|j| wh.q[c * d + j] * v[(i, j)] * wh.scale)
                    .sum::<f64>()
                    / wh.sv[c];
            }
            // `w` is `y` normalized (each component within `d eps |v| / s_r`, relative to
            // `|y| >= |v| / s_1`).
            let yn = y.row(t).norm();
            for c in 0..r {
                let err = (wh.w[t * r + c] - y[(t, c)] / yn).abs();
                prop_assert!(err <= 4.0 * d as f64 * f64::EPSILON * cond, "w: {err:e}");
            }
        }
        let orth = max_diff(&(y.transpose() * &y), &DMatrix::identity(r, r));
        prop_assert!(
            orth <= 64.0 * f64::EPSILON * cond,
            "Y^T Y - I: {orth:e}, cond {cond:e}"
        );
        prop_assert!(wh.equation_residual <= 1e-14 + tol.rank * 2.0);
        // Positively parallel rows (the copies the test makes, and rows of a rank-1 matrix
        // with the same sign) are merged, the others kept: unit input rows at most 1e-9 apart
        // (rounding makes ~1e-16; random rows are much farther apart). Their whitened rows
        // agree up to rounding times `cond` (the same bound as above), so this is only
        // expected when that is below `tol.duplicate`.
        // (And only when the directions dropped by the rank decision are rounding: otherwise
        // rows that differ only along them are rightly merged.)
        let dropped = sv_ref.get(r).copied().unwrap_or(0.0);
        if 64.0 * f64::EPSILON * cond > tol.duplicate || dropped > bound {
            return Ok(());
        }
        let unit = |i: usize| (v.row(i) * wh.scale).normalize();
        let mut distinct_ref: Vec<usize> = Vec::new();
        for t in 0..kept.len() {
            if !distinct_ref
                .iter()
                .any(|&s| (unit(kept[t]) - unit(kept[s])).norm() <= 1e-9)
            {
                distinct_ref.push(t);
            }
        }
        prop_assert_eq!(&wh.distinct, &distinct_ref);
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(1000))]
        /// Random `n x d` matrices (`n < d` included) of rank `k`, rows scaled by up to
        /// `10^+-6`, some rows positive multiples of others, the whole scaled by `10^e` with
        /// `e` up to +-300: the fast whitening agrees with the general SVD.
        #[test]
        fn fast_whitening_matches_the_general_svd(
            d in 1usize..=8,
            n in 0usize..20,
            k in 1usize..=8,
            left in proptest::collection::vec(-1.0f64..1.0, 20 * 8),
            right in proptest::collection::vec(-1.0f64..1.0, 8 * 8),
            row_exp in proptest::collection::vec(-6i32..=6, 20),
            scale_rows in any::<bool>(),
            copies in 0usize..4,
            global_exp in -300i32..=300,
        ) {
            let k = k.min(d);
            let l = DMatrix::from_fn(n, k, |i, j| left[i * 8 + j]);
            let rt = DMatrix::from_fn(k, d, |i, j| right[i * 8 + j]);
            let mut v = l * rt;
            if scale_rows {
                for i in 0..n {
                    v.row_mut(i).scale_mut(10f64.powi(row_exp[i]));
                }
            }
            for c in 0..copies.min(n / 2) {
                let row = v.row(n - 1 - c) * 3.0;
                v.row_mut(c).copy_from(&row);
            }
            let v = v * 10f64.powi(global_exp);
            check_against_reference(&v)?;
        }
    }

    /// The duplicate test, brute force: each row against every earlier distinct one.
    fn distinct_brute_force(w: &[f64], nk: usize, r: usize, duplicate: f64) -> Vec<usize> {
        let mut out: Vec<usize> = Vec::new();
        for t in 0..nk {
            let gt = &w[t * r..(t + 1) * r];
            let dup = out.iter().any(|&s| {
                let gs = &w[s * r..(s + 1) * r];
                gt.iter()
                    .zip(gs)
                    .map(|(a, b)| (a - b) * (a - b))
                    .sum::<f64>()
                    <= duplicate * duplicate
            });
            if !dup {
                out.push(t);
            }
        }
        out
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        /// `mark_distinct` decides like the brute force, on rows with tied coordinates and
        /// copies moved by 0.3 to 3 times the threshold (both sides of it), in any direction.
        #[test]
        fn mark_distinct_matches_the_brute_force(
            r in 0usize..5,
            grid in proptest::collection::vec(-2i32..=2, 24 * 4),
            jitter in proptest::collection::vec(-3.0f64..3.0, 24 * 4),
            copy_of in proptest::collection::vec(0usize..24, 24),
            nk in 0usize..24,
        ) {
            let dup = 1e-12;
            let mut w = vec![0.0; nk * r];
            for t in 0..nk {
                for c in 0..r {
                    w[t * r + c] = grid[t * 4 + c] as f64 * 0.5;
                }
                // Some rows: a copy of an earlier one, moved by jitter * dup per coordinate.
                if copy_of[t] < t && t % 2 == 0 {
                    for c in 0..r {
                        w[t * r + c] = w[copy_of[t] * r + c] + jitter[t * 4 + c] * dup / 2.0;
                    }
                }
            }
            let (mut distinct, mut order, mut position, mut flag) =
                (Vec::new(), Vec::new(), Vec::new(), Vec::new());
            mark_distinct(&w, nk, r, dup, &mut distinct, [&mut order, &mut position], &mut flag);
            prop_assert_eq!(distinct, distinct_brute_force(&w, nk, r, dup));
        }
    }

    /// The golden stances, and a flat one (rank 5), agree with the general SVD too.
    #[test]
    fn golden_stances_match_the_general_svd() {
        for case in [
            "single_support_flat",
            "double_support_flat",
            "double_support_stairs",
            "tilted_foot_hand_ledge",
            "opposing_walls_frictionless",
        ] {
            let v = super::alloc_count::golden_for_tests(case);
            check_against_reference(&v).unwrap();
            let mut flat = v.clone();
            flat.column_mut(5).fill(0.0);
            check_against_reference(&flat).unwrap();
        }
    }
}

#[cfg(test)]
mod timing {
    use super::*;
    use std::time::Instant;

    /// The whitening before this module used QR and Jacobi (nalgebra's SVD of the kept rows,
    /// fresh buffers each call), kept to time both in one run.
    fn whiten_nalgebra(v: &DMatrix<f64>, tol: &Tolerances) -> Whitened {
        // Scale by a power of two (exact, and the cone does not change) so that the largest entry
        // is about 1: norms of rows with entries near 1e300 or 1e-300 neither overflow nor vanish.
        let amax = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if amax > 0.0 && !(0.5..=1.0).contains(&amax) {
            let e = amax.log2().floor() as i32;
            // Two steps: 2^-e alone may not be representable for subnormal inputs.
            let (e1, e2) = (e / 2, e - e / 2);
            let scaled = v * 2f64.powi(-e1) * 2f64.powi(-e2);
            let mut wh = whiten_nalgebra_scaled(&scaled, tol);
            // (May overflow to infinity for subnormal inputs; users of `scale` check.)
            wh.scale = 2f64.powi(-e1) * 2f64.powi(-e2);
            return wh;
        }
        whiten_nalgebra_scaled(v, tol)
    }
    fn whiten_nalgebra_scaled(v: &DMatrix<f64>, tol: &Tolerances) -> Whitened {
        let (n, d) = v.shape();
        let norms: Vec<f64> = (0..n).map(|i| v.row(i).norm()).collect();
        let maxn = norms.iter().copied().fold(0.0, f64::max);
        let kept: Vec<usize> = (0..n)
            .filter(|&i| norms[i] > 0.0 && norms[i] > tol.zero_generator * maxn)
            .collect();
        if kept.is_empty() {
            return Whitened {
                r: 0,
                d,
                q: Vec::new(),
                sv: Vec::new(),
                equations: DMatrix::identity(d, d),
                kept,
                w: Vec::new(),
                distinct: Vec::new(),
                equation_residual: 0.0,
                scale: 1.0,
            };
        }
        let mut vk = DMatrix::zeros(kept.len(), d);
        for (r, &i) in kept.iter().enumerate() {
            vk.row_mut(r).copy_from(&v.row(i));
        }
        let (sv_all, vt) = sorted_svd_general(&vk);
        let r = numerical_rank(&sv_all, tol.rank);
        let mut q = Vec::with_capacity(r * d);
        for c in 0..r {
            q.extend(vt.row(c).iter());
        }
        let equations = vt.rows(r, d - r).into_owned();
        let sv = sv_all[..r].to_vec();
        let mut w = vec![0.0; kept.len() * r];
        let mut equation_residual: f64 = 0.0;
        let mut row = vec![0.0; d];
        for (t, &i) in kept.iter().enumerate() {
            for (x, y) in row.iter_mut().zip(v.row(i).iter()) {
                *x = *y;
            }
            let wt = &mut w[t * r..(t + 1) * r];
            for ((o, qc), &s) in wt.iter_mut().zip(q.chunks_exact(d)).zip(&sv) {
                *o = qc.iter().zip(&row).map(|(a, b)| a * b).sum::<f64>() / s;
            }
            normalize(wt);
            for e in 0..d - r {
                let ev = equations.row(e);
                let dot: f64 = ev.iter().zip(&row).map(|(a, b)| a * b).sum();
                equation_residual = equation_residual.max(dot.abs() / maxn);
            }
        }
        let mut distinct: Vec<usize> = Vec::with_capacity(kept.len());
        'outer: for t in 0..kept.len() {
            let gt = &w[t * r..(t + 1) * r];
            for &s in &distinct {
                let gs = &w[s * r..(s + 1) * r];
                // Most pairs differ in the first coordinate already.
                if (gt[0] - gs[0]).abs() > tol.duplicate {
                    continue;
                }
                let d2: f64 = gt.iter().zip(gs).map(|(a, b)| (a - b) * (a - b)).sum();
                if d2 <= tol.duplicate * tol.duplicate {
                    continue 'outer;
                }
            }
            distinct.push(t);
        }
        Whitened {
            r,
            d,
            q,
            sv,
            equations,
            kept,
            w,
            distinct,
            equation_residual,
            scale: 1.0,
        }
    }

    fn median_us<F: FnMut()>(mut f: F) -> f64 {
        let mut t: Vec<f64> = (0..5000)
            .map(|_| {
                let s = Instant::now();
                f();
                s.elapsed().as_secs_f64() * 1e6
            })
            .collect();
        t.sort_by(f64::total_cmp);
        t[t.len() / 2]
    }

    /// Whitening time, before (nalgebra SVD, allocating) and now (warm buffers), on the golden
    /// stances, in one run:
    /// `cargo test --release -p polycone --lib whitening_time -- --ignored --nocapture`.
    #[test]
    #[ignore]
    fn whitening_time() {
        let tol = Tolerances::default();
        for case in [
            "single_support_flat",
            "surface_cwc_foot",
            "double_support_flat",
            "double_support_stairs",
            "tilted_foot_hand_ledge",
            "opposing_walls_frictionless",
            "opposing_walls_friction",
        ] {
            let v = super::alloc_count::golden_for_tests(case);
            let (mut out, mut scratch) = (Whitened::default(), WhitenScratch::default());
            let mut before = f64::INFINITY;
            let mut after = f64::INFINITY;
            // Alternating rounds, the best median of each.
            for _ in 0..3 {
                before = before.min(median_us(|| {
                    std::hint::black_box(whiten_nalgebra(std::hint::black_box(&v), &tol));
                }));
                after = after.min(median_us(|| {
                    whiten_into(std::hint::black_box(&v), &tol, &mut out, &mut scratch);
                    std::hint::black_box(&out);
                }));
            }
            let old = whiten_nalgebra(&v, &tol);
            assert_eq!(
                (old.r, &old.kept, &old.distinct),
                (out.r, &out.kept, &out.distinct)
            );
            eprintln!(
                "{case:30} {:3} generators: before {before:5.2} us, now {after:5.2} us, x{:.2}",
                v.nrows(),
                before / after
            );
        }
    }
}
