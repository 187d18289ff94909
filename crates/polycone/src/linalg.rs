//! Small dense linear-algebra helpers on row-major slices and `DMatrix` (rank, bases).

use nalgebra::DMatrix;

/// Full SVD of an `n x d` matrix, sorted: returns the `min(n, d)`... padded to `d` singular
/// values in decreasing order and the `d x d` orthogonal matrix whose rows are the matching
/// right singular vectors (a basis of `R^d`: the row space first, its complement after).
pub(crate) fn sorted_svd(m: &DMatrix<f64>) -> (Vec<f64>, DMatrix<f64>) {
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
