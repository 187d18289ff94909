//! Near-simplicial facets in closed form: the ridges of a facet with `t` tight generators in
//! dimension `t - 1`, from the signs of their unique linear dependency.

use super::*;

/// Ridges of a near-simplicial facet: `rows` holds `k + 1` unit vectors `g_i` of `R^k` (the
/// facet's tight generators in coordinates of its hyperplane). On success, `drops` lists the
/// pairs `(i, j)` (`i <= j`, indices into `rows`) such that the ridges of `cone(g)` are exactly
/// `G \ {g_i, g_j}` (module doc, "Near-simplicial facets"): `i < j` with
/// `lambda_i lambda_j < 0`, and `i = j` with `lambda_i = 0`. Returns `Some(false)` when the
/// non-zero `lambda_i` all have one sign (the cone contains a line: not pointed). Entries
/// with `c |lambda_i| >= certificate` are non-zero, entries with
/// `|lambda_i| <= (incidence^2 / certificate) min |lambda_j|` (over the non-zero ones) are
/// zero (module doc: margins of ten around the double description's `incidence`). `None`
/// (decide with a double description instead) when the vectors have rank below `k` or an
/// entry lies between the two.
pub(super) fn near_simplicial_ridges(
    rows: &[f64],
    k: usize,
    tol: &Tolerances,
    lambda: &mut [f64],
    scratch: &mut Vec<f64>,
    drops: &mut Vec<(usize, usize)>,
) -> Option<bool> {
    near_simplicial(rows, k, tol, lambda, scratch, drops).map(|(pointed, _)| pointed)
}

/// [`near_simplicial_ridges`], also returning `c = sqrt(sum_q det(G \ {g_q})^2)` (so that
/// `|det(G \ {g_q})| = c |lambda_q|`).
pub(crate) fn near_simplicial(
    rows: &[f64],
    k: usize,
    tol: &Tolerances,
    lambda: &mut [f64],
    scratch: &mut Vec<f64>,
    drops: &mut Vec<(usize, usize)>,
) -> Option<(bool, f64)> {
    drops.clear();
    let c = dependency(rows, k, tol.support_rank, lambda, scratch)?;
    ridges_from_dependency(&lambda[..k + 1], c, tol, drops).map(|pointed| (pointed, c))
}

/// The sign logic of [`near_simplicial_ridges`], given the unit dependency `lambda` (`k + 1`
/// entries) and `c`. Fills `drops`; `None` when a sign is not clear.
pub(crate) fn ridges_from_dependency(
    lambda: &[f64],
    c: f64,
    tol: &Tolerances,
    drops: &mut Vec<(usize, usize)>,
) -> Option<bool> {
    drops.clear();
    let m = lambda.len();
    // Non-zero: every slack it implies off a ridge is at least `certificate` (ten times
    // `incidence`); zero: the slacks it implies are at most `incidence^2 / certificate` (a
    // tenth of `incidence`). Margins of ten either way, so that the double description,
    // deciding at `incidence`, takes the same decisions despite rounding.
    let min_nonzero = lambda
        .iter()
        .map(|x| x.abs())
        .filter(|&x| c * x >= tol.certificate)
        .fold(f64::INFINITY, f64::min);
    let zero_cut = tol.incidence * (tol.incidence / tol.certificate) * min_nonzero;
    let sign = |x: f64| -> Option<i8> {
        if c * x.abs() >= tol.certificate {
            Some(if x > 0.0 { 1 } else { -1 })
        } else if x.abs() <= zero_cut {
            Some(0)
        } else {
            None
        }
    };
    for &x in lambda {
        sign(x)?;
    }
    let mut pointed = false;
    for a in 0..m {
        let sa = sign(lambda[a])?;
        if sa == 0 {
            drops.push((a, a));
            continue;
        }
        for b in a + 1..m {
            let sb = sign(lambda[b])?;
            if sa * sb < 0 {
                drops.push((a, b));
                pointed = true;
            }
        }
    }
    if !pointed {
        drops.clear();
    }
    Some(pointed)
}

/// The linear dependency `lambda` (unit norm) of `k + 1` vectors of `R^k` (`rows`, row-major)
/// of rank `k`, by Gaussian elimination with partial pivoting on the `k x (k + 1)` matrix whose
/// columns are the vectors. Also returns `c = sqrt(sum_q det(G \ {g_q})^2)` (so that
/// `|det(G \ {g_q})| = c |lambda_q|`: `lambda` is the vector of signed cofactors divided by
/// `c`), from the product of the pivots. `None` when the rank is below `k` (pivot at most
/// `eps`).
pub(super) fn dependency(
    rows: &[f64],
    k: usize,
    eps: f64,
    lambda: &mut [f64],
    m: &mut Vec<f64>,
) -> Option<f64> {
    // Fixed-size elimination for the usual dimensions (same operations, stack arrays).
    macro_rules! fixed {
        ($k:literal) => {{
            let mut y = [[0.0f64; $k]; $k + 1];
            for (yi, r) in y.iter_mut().zip(rows.chunks_exact($k)) {
                yi.copy_from_slice(r);
            }
            let (l, c) = neighbours::dependency_k::<$k>(&y, eps)?;
            lambda[..$k + 1].copy_from_slice(&l.0[..$k + 1]);
            Some(c)
        }};
    }
    match k {
        2 => fixed!(2),
        3 => fixed!(3),
        4 => fixed!(4),
        5 => fixed!(5),
        6 => fixed!(6),
        7 => fixed!(7),
        8 => fixed!(8),
        _ => dependency_dyn(rows, k, eps, lambda, m),
    }
}

/// [`dependency`] for any `k` (heap scratch `m`); the reference the fixed-size version is
/// tested against.
pub(super) fn dependency_dyn(
    rows: &[f64],
    k: usize,
    eps: f64,
    lambda: &mut [f64],
    m: &mut Vec<f64>,
) -> Option<f64> {
    let n = k + 1;
    let mut det = 1.0;
    m.clear();
    m.resize(k * n, 0.0);
    for i in 0..n {
        for r in 0..k {
            m[r * n + i] = rows[i * k + r];
        }
    }
    // Row echelon with column pivots; the free column is the last non-pivot one.
    // Pivot columns: on the stack for the dimensions of wrench cones and far beyond.
    let mut piv_small = [usize::MAX; 16];
    let mut piv_big = Vec::new();
    let piv_col: &mut [usize] = if k <= piv_small.len() {
        &mut piv_small[..k]
    } else {
        piv_big.resize(k, usize::MAX);
        &mut piv_big
    };
    let mut row = 0;
    let mut free = usize::MAX;
    for c in 0..n {
        if row == k {
            if free == usize::MAX {
                free = c;
            }
            continue;
        }
        let mut p = row;
        for r in row + 1..k {
            if m[r * n + c].abs() > m[p * n + c].abs() {
                p = r;
            }
        }
        if m[p * n + c].abs() <= eps {
            if free != usize::MAX {
                return None;
            }
            free = c;
            continue;
        }
        for t in 0..n {
            m.swap(p * n + t, row * n + t);
        }
        det *= m[row * n + c].abs();
        let inv = 1.0 / m[row * n + c];
        for t in 0..n {
            m[row * n + t] *= inv;
        }
        for r in 0..k {
            if r != row {
                let f = m[r * n + c];
                if f != 0.0 {
                    for t in 0..n {
                        m[r * n + t] -= f * m[row * n + t];
                    }
                }
            }
        }
        piv_col[row] = c;
        row += 1;
    }
    if row < k || free == usize::MAX {
        return None;
    }
    lambda[..n].fill(0.0);
    lambda[free] = 1.0;
    for r in 0..k {
        lambda[piv_col[r]] = -m[r * n + free];
    }
    // With `lambda_free = 1`, `lambda` is the cofactor vector divided by `det(G \ {g_free})`.
    Some(normalize(&mut lambda[..n]) * det)
}
