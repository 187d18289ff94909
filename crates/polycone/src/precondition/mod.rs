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
//! **Row scaling first.** The conversions and the certificate scale every input row (generator,
//! facet or equation) by a power of two so that its largest entry is in `[0.5, 1)`
//! (`scale_rows_pow2`, exact) before calling the whitening: a cone does not change when one
//! row is multiplied by a positive number, and after this no decision (rank, zero generators,
//! duplicates, the certificate's tolerances) can depend on such a factor. So `[[1e-11, 0, 0],
//! [0, 1, 0], [0, 0, 1]]` is the orthant, as `[[1, 0, 0], [0, 1, 0], [0, 0, 1]]` is.
//!
//! Zero generators (rows of zeros after that scaling; the relative test against
//! [`crate::tol::Tolerances::zero_generator`] times the largest norm below can only drop a
//! row of zeros then) are dropped; whitened generators are normalized to unit rows, and
//! positively parallel duplicates (distance at most [`crate::tol::Tolerances::duplicate`]) are
//! merged.
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

/// The power of two `2^-e` that brings the largest `|entry|` of `row` into `[0.5, 1)`; 1 for a
/// zero row. Multiplying by it is exact (no rounding unless the row has entries more than
/// `2^1074` times smaller than its largest, which become subnormal as they were).
#[inline]
pub(crate) fn row_scale(row: impl Iterator<Item = f64>) -> (f64, f64) {
    let amax = row.fold(0.0f64, |m, x| m.max(x.abs()));
    if amax == 0.0 || (0.5..1.0).contains(&amax) {
        return (1.0, 1.0);
    }
    // `amax 2^-e` in [0.5, 1); `log2` may round across a power of two: corrected once.
    let factors = |e: i32| (2f64.powi(-(e / 2)), 2f64.powi(-(e - e / 2)));
    let mut e = amax.log2().floor() as i32 + 1;
    let (f1, f2) = factors(e);
    let scaled = amax * f1 * f2;
    if scaled >= 1.0 {
        e += 1;
    } else if scaled < 0.5 {
        e -= 1;
    }
    factors(e)
}

/// Multiplies every row of `m` by the power of two of [`row_scale`], in place: **the
/// normalization that makes every decision independent of a positive scaling of any single
/// row** (a generator, a facet, an equation). A cone does not change when one of its
/// generators or facet rows is multiplied by a positive number, so nothing downstream may
/// depend on the rows' norms: after this, every nonzero row has its largest entry in
/// `[0.5, 1)`, whatever it was (from `1e-300` to `1e300`). Exact (powers of two), and a row
/// keeps its direction bit for bit.
pub(crate) fn scale_rows_pow2(m: &mut DMatrix<f64>) {
    let (n, d) = m.shape();
    for i in 0..n {
        let (f1, f2) = row_scale((0..d).map(|j| m[(i, j)]));
        if f1 != 1.0 || f2 != 1.0 {
            for j in 0..d {
                m[(i, j)] = m[(i, j)] * f1 * f2;
            }
        }
    }
}

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
    /// `Some(s_{r+1} / s_1)` when the largest singular value taken as zero is above the rounding
    /// level [`crate::tol::RANK_NOISE`]: the rank was decided by the tolerance alone.
    pub rank_undecided: Option<f64>,
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
    out.rank_undecided = None;
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
    out.rank_undecided = (r < d && r > 0 && sv_all[r] > crate::tol::RANK_NOISE * sv_all[0])
        .then(|| sv_all[r] / sv_all[0]);
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
/// ([`mark_distinct`]); below, comparing each with every earlier distinct one is faster (the
/// sort costs more than the comparisons it saves; measured in `bench/peers/cones.md`). Same
/// decisions either way.
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
mod alloc_count;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod timing;
