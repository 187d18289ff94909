//! Small dense linear-algebra helpers on row-major slices and `DMatrix` (rank, bases).

use nalgebra::DMatrix;

/// Full SVD of an `n x d` matrix, sorted: returns the `min(n, d)`... padded to `d` singular
/// values in decreasing order and the `d x d` orthogonal matrix whose rows are the matching
/// right singular vectors (a basis of `R^d`: the row space first, its complement after).
///
/// For `1 <= d <= 8` (finite entries) by [`qr_jacobi_svd`] on the matrix scaled by an exact
/// power of two, falling back to [`sorted_svd_general`]: nalgebra's SVD with singular vectors
/// can return wrong singular values (off by `1.5e-3` on a rank-2 `19 x 8` matrix in the tests
/// of `crate::precondition`; nalgebra issue 1172 has more).
pub(crate) fn sorted_svd(m: &DMatrix<f64>) -> (Vec<f64>, DMatrix<f64>) {
    let (n, d) = m.shape();
    let amax = m.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if (1..=8).contains(&d) && amax.is_finite() {
        // Exact power-of-two scaling so that the largest entry is about 1 (two steps: the
        // single factor may not be representable for subnormal inputs).
        let e = if amax > 0.0 {
            amax.log2().floor() as i32
        } else {
            0
        };
        let (f1, f2) = (2f64.powi(-(e / 2)), 2f64.powi(-(e - e / 2)));
        let mut a: Vec<f64> = m.as_slice().iter().map(|x| x * f1 * f2).collect();
        let mut sv = vec![0.0; d];
        let mut vt = vec![0.0; d * d];
        let o = [crate::tol::JACOBI_ORTHOGONALITY, crate::tol::JACOBI_NOISE];
        let sweeps = crate::tol::JACOBI_MAX_SWEEPS;
        let done = match d {
            1 => qr_jacobi_svd::<1>(&mut a, n, o, sweeps, &mut sv, &mut vt),
            2 => qr_jacobi_svd::<2>(&mut a, n, o, sweeps, &mut sv, &mut vt),
            3 => qr_jacobi_svd::<3>(&mut a, n, o, sweeps, &mut sv, &mut vt),
            4 => qr_jacobi_svd::<4>(&mut a, n, o, sweeps, &mut sv, &mut vt),
            5 => qr_jacobi_svd::<5>(&mut a, n, o, sweeps, &mut sv, &mut vt),
            6 => qr_jacobi_svd::<6>(&mut a, n, o, sweeps, &mut sv, &mut vt),
            7 => qr_jacobi_svd::<7>(&mut a, n, o, sweeps, &mut sv, &mut vt),
            _ => qr_jacobi_svd::<8>(&mut a, n, o, sweeps, &mut sv, &mut vt),
        };
        if done.is_some() {
            // Undo the scaling (exact unless it overflows, for subnormal inputs).
            for x in &mut sv {
                *x = *x / f1 / f2;
            }
            return (sv, DMatrix::from_row_slice(d, d, &vt));
        }
    }
    sorted_svd_general(m)
}

/// [`sorted_svd`] by nalgebra's SVD (bidiagonalization and QR iteration), for any `d`.
pub(crate) fn sorted_svd_general(m: &DMatrix<f64>) -> (Vec<f64>, DMatrix<f64>) {
    let (n, d) = m.shape();
    let padded = if n >= d {
        m.clone()
    } else {
        let mut p = DMatrix::zeros(d, d);
        p.view_mut((0, 0), (n, d)).copy_from(m);
        p
    };
    let svd = padded.svd(false, true);
    let v_t = svd.v_t.expect("v_t was requested");
    let s = svd.singular_values;
    let mut idx: Vec<usize> = (0..s.len()).collect();
    idx.sort_by(|&a, &b| s[b].total_cmp(&s[a]));
    let mut sv = Vec::with_capacity(d);
    let mut vt = DMatrix::zeros(d, d);
    for (r, &i) in idx.iter().enumerate() {
        sv.push(s[i]);
        vt.row_mut(r).copy_from(&v_t.row(i));
    }
    (sv, vt)
}

/// Columns of the Householder QR whose largest entry is below this are rescaled by
/// [`QR_RESCALE`] (an exact power of two) before their norm is squared: `2^-400`.
const QR_RESCALE_BELOW: f64 = f64::from_bits((1023 - 400) << 52);

/// The exact rescaling of [`QR_RESCALE_BELOW`]: `2^500` (a column entry at least
/// [`crate::tol::QR_NEGLIGIBLE`] `= 2^-900` becomes at least `2^-400`, at most `2^100`).
const QR_RESCALE: f64 = f64::from_bits((1023 + 500) << 52);

/// Beyond this `|zeta|` a Jacobi rotation uses `t = 1 / (2 zeta)`: that is what
/// `1 / (|zeta| + sqrt(1 + zeta^2))` rounds to once `zeta^2 > 2^53`, and `zeta^2` would
/// overflow past `1.3e154`. Value `2^32`.
const JACOBI_ZETA_LARGE: f64 = 4_294_967_296.0;

/// Sorted SVD of a small `n x D` matrix by Householder QR, then a one-sided Jacobi SVD of the
/// `D x D` triangular factor.
///
/// `a` holds the matrix column-major (column `k` at `a[k n..(k + 1) n]`) and is overwritten.
/// On success, `sv` gets the `D` singular values in decreasing order (zeros past `min(n, D)`)
/// and `vt` (`D x D`, row-major) the matching right singular vectors as rows: an orthogonal
/// matrix, the row space first, like [`sorted_svd`]. Returns the number of sweeps, the last
/// one without rotation (`None`, outputs unspecified, when Jacobi did not converge within
/// `max_sweeps` sweeps).
///
/// Math: `A = H R` with `H` orthogonal (a product of reflectors), so `A^T A = R^T R` and `A`
/// and `R` have the same singular values and right singular vectors. Jacobi rotates pairs of
/// columns of `B = R` until they are orthogonal, `B J = U S` (`|b_p . b_q| <= orth |b_p| |b_q|`
/// for every pair, up to `D orth` on the last sweep, and no rotation that would move a
/// column by `noise |R|_F` or less), accumulating `J` (orthogonal up to rounding): the column norms are the
/// singular values and the columns of `J` the right singular vectors.
pub(crate) fn qr_jacobi_svd<const D: usize>(
    a: &mut [f64],
    n: usize,
    [orth, noise]: [f64; 2],
    max_sweeps: usize,
    sv: &mut [f64],
    vt: &mut [f64],
) -> Option<usize> {
    let r = householder_r::<D>(a, n);
    // Columns of R, and the accumulated rotations (columns), as fixed-size rows.
    let mut b = [[0.0; D]; D];
    for (i, row) in r.iter().enumerate() {
        for (k, &x) in row.iter().enumerate() {
            b[k][i] = x;
        }
    }
    let mut j = [[0.0; D]; D];
    for (k, col) in j.iter_mut().enumerate() {
        col[k] = 1.0;
    }
    // Rotations that would move a column by at most `noise |R|_F` are not done: on a
    // rank-deficient input the columns left at rounding level (Householder QR leaves about
    // `sqrt(n) D eps |A|` there) would otherwise be rotated for many sweeps against each other
    // and against the rounding each rotation leaves; skipping them is a backward error of
    // `noise |R|_F` per column.
    let frob2: f64 = b.iter().map(|c| dot_n(c, c)).sum();
    let noise2 = noise * noise * frob2;
    // Pairs with a cosine above `orth` are rotated; a sweep counts as progress only with a
    // cosine above `D orth` (the rounding of a computed cosine of `D`-vectors), so that the
    // last sweeps polish to `orth` and the loop still ends.
    let progress = D as f64 * orth;
    let mut sweeps = None;
    for sweep in 1..=max_sweeps {
        let mut rotated = false;
        // Squared column norms, fresh each sweep and updated by the rotations (Hestenes):
        // `|b_p'|^2 = alpha - t gamma`, `|b_q'|^2 = beta + t gamma`, recomputed when the update
        // cancels (the new value below half the old one).
        let mut nrm2 = [0.0; D];
        for (x, col) in nrm2.iter_mut().zip(&b) {
            *x = dot_n(col, col);
        }
        for p in 0..D {
            for q in p + 1..D {
                let (alpha, beta) = (nrm2[p], nrm2[q]);
                let gamma = dot_n(&b[p], &b[q]);
                // A column whose squared norm underflows (below 1.5e-154 on an input whose
                // largest entry is about 1) counts as zero. A rotation moves the shorter
                // column by about `|gamma| / |longer|`: below the noise, it is not done.
                if alpha == 0.0 || beta == 0.0 || gamma * gamma <= noise2 * alpha.max(beta) {
                    continue;
                }
                let scale = alpha.sqrt() * beta.sqrt();
                if gamma.abs() <= orth * scale {
                    continue;
                }
                rotated |= gamma.abs() > progress * scale;
                // The rotation that diagonalizes [[alpha, gamma], [gamma, beta]], by its
                // smaller angle.
                let zeta = (beta - alpha) / (2.0 * gamma);
                let t = if zeta.abs() > JACOBI_ZETA_LARGE {
                    0.5 / zeta
                } else {
                    zeta.signum() / (zeta.abs() + (1.0 + zeta * zeta).sqrt())
                };
                let c = 1.0 / (1.0 + t * t).sqrt();
                let s = c * t;
                rotate(&mut b, p, q, c, s);
                rotate(&mut j, p, q, c, s);
                nrm2[p] = alpha - t * gamma;
                if nrm2[p] < 0.5 * alpha {
                    nrm2[p] = dot_n(&b[p], &b[p]);
                }
                nrm2[q] = beta + t * gamma;
                if nrm2[q] < 0.5 * beta {
                    nrm2[q] = dot_n(&b[q], &b[q]);
                }
            }
        }
        if !rotated {
            sweeps = Some(sweep);
            break;
        }
    }
    sweeps?;
    let mut norms = [0.0; D];
    for (s, col) in norms.iter_mut().zip(&b) {
        *s = dot_n(col, col).sqrt();
    }
    // Decreasing order (insertion sort, stable).
    let mut idx = [0usize; D];
    for (k, x) in idx.iter_mut().enumerate() {
        *x = k;
    }
    for k in 1..D {
        let mut m = k;
        while m > 0 && norms[idx[m]] > norms[idx[m - 1]] {
            idx.swap(m, m - 1);
            m -= 1;
        }
    }
    for (row, &k) in idx.iter().enumerate() {
        sv[row] = norms[k];
        vt[row * D..(row + 1) * D].copy_from_slice(&j[k]);
    }
    sweeps
}

/// Dot product of two fixed-length arrays.
#[inline(always)]
fn dot_n<const D: usize>(a: &[f64; D], b: &[f64; D]) -> f64 {
    let mut s = 0.0;
    for k in 0..D {
        s += a[k] * b[k];
    }
    s
}

/// `(m_p, m_q) <- (c m_p - s m_q, s m_p + c m_q)` on rows `p < q` of `m`.
#[inline(always)]
fn rotate<const D: usize>(m: &mut [[f64; D]; D], p: usize, q: usize, c: f64, s: f64) {
    let (x, y) = (m[p], m[q]);
    for k in 0..D {
        m[p][k] = c * x[k] - s * y[k];
        m[q][k] = s * x[k] + c * y[k];
    }
}

/// The triangular factor `R` (`D x D`, row-major, rows `min(n, D)..D` zero) of the Householder
/// QR `A = H R` of the `n x D` column-major matrix `a` (overwritten by the reflectors' work).
///
/// Each step reflects `x` (column `j`, rows `j..n`) onto `alpha e_1`, `alpha = -sign(x_0) |x|`
/// (no cancellation in `v = x - alpha e_1`), with `H_j = I - v v^T / beta`,
/// `beta = v . v / 2 = |x| (|x| + |x_0|)`. A column whose largest entry is below
/// [`crate::tol::QR_NEGLIGIBLE`] is not reflected (`H_j = I`, its entries below the diagonal
/// dropped: a backward error below `2^-900`); one below `QR_RESCALE_BELOW` is first scaled
/// by an exact power of two (the reflector does not change), so that `|x|^2` neither
/// underflows nor overflows.
fn householder_r<const D: usize>(a: &mut [f64], n: usize) -> [[f64; D]; D] {
    let mut r = [[0.0; D]; D];
    for jc in 0..n.min(D) {
        let (head, tail) = a.split_at_mut((jc + 1) * n);
        let x = &mut head[jc * n + jc..];
        let xmax = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if xmax < crate::tol::QR_NEGLIGIBLE {
            r[jc][jc] = x[0];
            for k in jc + 1..D {
                r[jc][k] = tail[(k - jc - 1) * n + jc];
            }
            continue;
        }
        let f = if xmax < QR_RESCALE_BELOW {
            for v in x.iter_mut() {
                *v *= QR_RESCALE;
            }
            QR_RESCALE
        } else {
            1.0
        };
        let norm = dot(x, x).sqrt();
        let x0 = x[0];
        let alpha = if x0 >= 0.0 { -norm } else { norm };
        x[0] = x0 - alpha;
        let beta = norm * (norm + x0.abs());
        r[jc][jc] = alpha / f;
        for k in jc + 1..D {
            let col = &mut tail[(k - jc - 1) * n + jc..(k - jc) * n];
            let c = dot(x, col) / beta;
            for (y, v) in col.iter_mut().zip(x.iter()) {
                *y -= c * v;
            }
            r[jc][k] = col[0];
        }
    }
    r
}

/// Number of singular values above `rel * s_max` (0 when all are zero).
pub(crate) fn numerical_rank(sv: &[f64], rel: f64) -> usize {
    let smax = sv.first().copied().unwrap_or(0.0);
    if smax <= 0.0 {
        return 0;
    }
    sv.iter().filter(|&&s| s > rel * smax).count()
}

/// Rank of a set of vectors of length `k` (given by an iterator of slices), capped at `target`
/// (the count stops there), by modified Gram-Schmidt with pivoting on the largest residual;
/// residual norms at most `eps` (absolute, the vectors being unit) count as zero. `buf` is
/// reused scratch.
pub(crate) fn rank_of<'a>(
    vectors: impl Iterator<Item = &'a [f64]>,
    k: usize,
    target: usize,
    eps: f64,
    buf: &mut Vec<f64>,
) -> usize {
    buf.clear();
    let mut n = 0;
    for v in vectors {
        buf.extend_from_slice(v);
        n += 1;
    }
    // Fixed-length inner loops for the common dimensions (see `crate::dd` for the same idea).
    match k {
        3 => rank_in_place::<3>(buf, n, 3, target, eps),
        4 => rank_in_place::<4>(buf, n, 4, target, eps),
        5 => rank_in_place::<5>(buf, n, 5, target, eps),
        6 => rank_in_place::<6>(buf, n, 6, target, eps),
        7 => rank_in_place::<7>(buf, n, 7, target, eps),
        _ => rank_in_place::<0>(buf, n, k, target, eps),
    }
}

/// The pivoted Gram-Schmidt of [`rank_of`] on `n` vectors stored in `buf`; `K` is `k` when
/// fixed at compile time (`K = 0`: dynamic).
fn rank_in_place<const K: usize>(
    buf: &mut [f64],
    n: usize,
    k: usize,
    target: usize,
    eps: f64,
) -> usize {
    let k = if K == 0 { k } else { K };
    let mut rank = 0;
    while rank < k.min(target) {
        let mut best = usize::MAX;
        let mut best_nn = eps * eps;
        for (i, v) in buf[rank * k..n * k].chunks_exact(k).enumerate() {
            let i = i + rank;
            let nn: f64 = v.iter().map(|x| x * x).sum();
            if nn > best_nn {
                best_nn = nn;
                best = i;
            }
        }
        if best == usize::MAX {
            break;
        }
        // Move the pivot to position `rank`.
        if best != rank {
            for t in 0..k {
                buf.swap(best * k + t, rank * k + t);
            }
        }
        let q = rank;
        rank += 1;
        let inv = 1.0 / best_nn.sqrt();
        let (head, rest) = buf[..n * k].split_at_mut(rank * k);
        let qv = &mut head[q * k..];
        for x in qv.iter_mut() {
            *x *= inv;
        }
        for v in rest.chunks_exact_mut(k) {
            let d: f64 = v.iter().zip(qv.iter()).map(|(a, b)| a * b).sum();
            for (a, b) in v.iter_mut().zip(qv.iter()) {
                *a -= d * b;
            }
        }
    }
    rank
}

/// Orthonormalizes the rows of `m` (modified Gram-Schmidt, twice), dropping rows whose residual
/// is at most `eps` times their original norm.
pub(crate) fn orthonormal_rows(m: &DMatrix<f64>, eps: f64) -> DMatrix<f64> {
    let d = m.ncols();
    let mut out: Vec<nalgebra::RowDVector<f64>> = Vec::new();
    for r in 0..m.nrows() {
        let mut v = m.row(r).into_owned();
        let n0 = v.norm();
        if n0 == 0.0 {
            continue;
        }
        for _ in 0..2 {
            for q in &out {
                let c = v.dot(q);
                v -= q * c;
            }
        }
        let n1 = v.norm();
        if n1 > eps * n0 {
            out.push(v / n1);
        }
    }
    let mut res = DMatrix::zeros(out.len(), d);
    for (i, q) in out.iter().enumerate() {
        res.row_mut(i).copy_from(q);
    }
    res
}

/// Dot product of two slices.
#[inline]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Normalizes `v` in place; returns its former norm.
#[inline]
pub(crate) fn normalize(v: &mut [f64]) -> f64 {
    let n = dot(v, v).sqrt();
    if n > 0.0 {
        let inv = 1.0 / n;
        for x in v.iter_mut() {
            *x *= inv;
        }
    }
    n
}

/// `|det|` of the `K x K` matrix `m` by Gaussian elimination with partial pivoting (0 when a
/// pivot vanishes).
pub(crate) fn abs_det<const K: usize>(mut m: [[f64; K]; K]) -> f64 {
    let mut det = 1.0;
    for c in 0..K {
        let mut p = c;
        for r in c + 1..K {
            if m[r][c].abs() > m[p][c].abs() {
                p = r;
            }
        }
        let piv = m[p][c];
        if piv == 0.0 {
            return 0.0;
        }
        m.swap(p, c);
        det *= piv.abs();
        let inv = 1.0 / piv;
        for r in c + 1..K {
            let f = m[r][c] * inv;
            for q in c..K {
                m[r][q] -= f * m[c][q];
            }
        }
    }
    det
}

/// Whether `n` unit vectors of `R^k` (`flat`, row-major) have rank `k` in the sense of
/// [`rank_of`] with threshold `eps`, with a fixed-size determinant first (dimensions 2 to 8):
/// `k` unit vectors with `|det| > eps` have every Gram-Schmidt residual above `eps` (their
/// product is `|det|`, each at most 1); with more vectors, the first `k` having
/// `|det| > k eps` leave a residual above `eps` for every `(k - 1)`-dimensional subspace
/// (expanding the determinant along its normal), so the pivoted count reaches `k` too.
/// Otherwise [`rank_of`] decides.
pub(crate) fn spans(flat: &[f64], n: usize, k: usize, eps: f64, buf: &mut Vec<f64>) -> bool {
    if n < k {
        return false;
    }
    let bound = if n == k { eps } else { k as f64 * eps };
    let det = match k {
        2 => Some(abs_det(first_rows::<2>(flat))),
        3 => Some(abs_det(first_rows::<3>(flat))),
        4 => Some(abs_det(first_rows::<4>(flat))),
        5 => Some(abs_det(first_rows::<5>(flat))),
        6 => Some(abs_det(first_rows::<6>(flat))),
        7 => Some(abs_det(first_rows::<7>(flat))),
        8 => Some(abs_det(first_rows::<8>(flat))),
        _ => None,
    };
    if det.is_some_and(|d| d > bound) {
        return true;
    }
    if n > k && greedy_det(flat, n, k, buf) > k as f64 * eps {
        return true;
    }
    rank_of((0..n).map(|i| &flat[i * k..(i + 1) * k]), k, k, eps, buf) == k
}

/// `|det|` of `k` of the `n` unit rows of `flat`, picked in order by Gram-Schmidt: a row joins
/// when its residual is at least a tenth (0 when fewer than `k` do, or `k > 16`). The product of the
/// residuals is the determinant of the rows picked, so [`spans`] can use it like the first
/// `k` rows' (the rows of a facet matrix often start with dependent ones).
fn greedy_det(flat: &[f64], n: usize, k: usize, q: &mut Vec<f64>) -> f64 {
    if k > 16 {
        return 0.0;
    }
    q.clear();
    let mut det = 1.0;
    let mut picked = 0;
    let mut r_buf = [0.0f64; 16];
    let r = &mut r_buf[..k];
    for row in flat.chunks_exact(k).take(n) {
        r.copy_from_slice(row);
        for b in q.chunks_exact(k) {
            let c = dot(b, r);
            for (x, y) in r.iter_mut().zip(b) {
                *x -= c * y;
            }
        }
        let res = dot(r, r).sqrt();
        if res >= 0.1 {
            det *= res;
            q.extend(r.iter().map(|x| x / res));
            picked += 1;
            if picked == k {
                return det;
            }
        }
    }
    0.0
}

/// The first `K` rows of `flat` as a fixed-size matrix.
fn first_rows<const K: usize>(flat: &[f64]) -> [[f64; K]; K] {
    let mut m = [[0.0; K]; K];
    for (r, row) in m.iter_mut().enumerate() {
        row.copy_from_slice(&flat[r * K..(r + 1) * K]);
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// `sorted_svd` on matrices where nalgebra's SVD with singular vectors returns wrong
    /// singular values (nalgebra issue 1172): the squares of the singular values sum to the
    /// squared Frobenius norm, and `|M q_c| = s_c` for each right singular vector.
    #[test]
    fn sorted_svd_is_an_svd_where_nalgebra_fails() {
        let cases = [
            DMatrix::from_row_slice(3, 3, &[1.0, 2.0, 2.0, 2.0, -1.0, -1.0, 2.0, 1.0, -1.0]),
            DMatrix::from_element(3, 5, 1.0),
            DMatrix::from_element(8, 6, 1.0),
        ];
        for m in &cases {
            let (sv, vt) = sorted_svd(m);
            let frob2: f64 = m.iter().map(|x| x * x).sum();
            let sum2: f64 = sv.iter().map(|s| s * s).sum();
            assert!((sum2 - frob2).abs() <= 1e-13 * frob2, "{sum2} vs {frob2}");
            for (c, &s) in sv.iter().enumerate() {
                let q = vt.row(c).transpose();
                assert!(((m * q).norm() - s).abs() <= 1e-13 * frob2.sqrt());
            }
            assert!(sv.windows(2).all(|p| p[0] >= p[1]));
            let o = &vt * vt.transpose() - DMatrix::<f64>::identity(m.ncols(), m.ncols());
            assert!(o.amax() <= 1e-14);
        }
        // The all-ones n x d matrix is rank one with singular value sqrt(n d).
        let (sv, _) = sorted_svd(&cases[1]);
        assert!((sv[0] - 15f64.sqrt()).abs() <= 1e-14 && sv[1] <= 1e-14);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        /// The fast paths of `spans` never claim a rank the pivoted count denies: random unit
        /// rows, some of them copies or near-combinations of others (dependent first rows, a
        /// thin direction of size `10^-e`).
        #[test]
        fn spans_agrees_with_the_pivoted_rank(
            k in 2usize..=8,
            extra in 0usize..6,
            raw in proptest::collection::vec(-1.0f64..1.0, 14 * 8),
            thin in 0u32..14,
            copies in 0usize..4,
        ) {
            let n = k + extra;
            let mut rows: Vec<f64> = raw[..n * k].to_vec();
            // Squash the last coordinate of every row to 10^-thin (a nearly flat set).
            for r in rows.chunks_exact_mut(k) {
                r[k - 1] *= 10f64.powi(-(thin as i32));
            }
            // The first rows repeat the next ones.
            for c in 0..copies.min(n - 1) {
                let src = (c + 1) * k;
                let row: Vec<f64> = rows[src..src + k].to_vec();
                rows[c * k..(c + 1) * k].copy_from_slice(&row);
            }
            for r in rows.chunks_exact_mut(k) {
                normalize(r);
            }
            let eps = 1e-7;
            let mut buf = Vec::new();
            let fast = spans(&rows, n, k, eps, &mut buf);
            let slow = rank_of((0..n).map(|i| &rows[i * k..(i + 1) * k]), k, k, eps, &mut buf) == k;
            prop_assert_eq!(fast, slow);
        }
    }
}
