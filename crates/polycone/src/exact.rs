//! Exact arithmetic: the double description and its certificate over the integers.
//!
//! # Math
//!
//! Every `f64` is a dyadic rational `m 2^e`, so a generator scaled by a power of two is an
//! integer vector (a positive scaling: the same ray). On integers everything is exact:
//!
//! - `span(V)` is spanned by `r` independent generators `B` (fraction-free elimination), and the
//!   generators in those coordinates are `G = V B^T` (integer, full column rank `r`); the polar
//!   `{y : G y <= 0}` is pointed and its extreme rays `y` give the facets `u = B^T y`;
//! - the double description iteration is the one of [`crate::dd`] with exact signs: the slack of
//!   a ray on a row is an integer dot product, new rays `(a . p) n - (a . n) p` are divided by the
//!   gcd of their entries to keep them small;
//! - equations and lineality are exact null spaces (rational Gauss-Jordan), rounded to `f64` and
//!   orthonormalized only for output.
//!
//! The certificate is decided exactly too: soundness (`G y <= 0`), support (rank of the tight
//! generators), lineality (the generators in the lineality space positively span it: an exact
//! double description in it returns no ray) and completeness (each ridge of each facet lies in
//! exactly two facets; ridges from an exact double description of each facet's tight generators
//! in the quotient by the lineality space).
//!
//! The facets are exact for the input **as given** (the rounded `f64` generators): near
//! degenerate inputs may have many more facets than the intended geometry.

use nalgebra::DMatrix;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Float, One, Signed, ToPrimitive, Zero};

use crate::dd::bitset;
use crate::linalg::orthonormal_rows;
use crate::tol::Tolerances;
use crate::{Arithmetic, Certificate, ConeError};

/// New rays whose longest entry exceeds this many bits are divided by their content (the gcd
/// of their entries). Not a tolerance: any value gives the same exact answer; it trades gcd
/// work against the length of the integers. 192 bits: three machine words.
const PRIMITIVE_BITS: u64 = 192;

/// An exact ray with its zero set.
struct Ray {
    x: Vec<BigInt>,
    z: Vec<u64>,
}

/// `xs` as integers, all multiplied by one power of two (exact: every double is an integer
/// times a power of two); all zero when `xs` is.
pub(crate) fn floats_to_ints(xs: impl Iterator<Item = f64>) -> Vec<BigInt> {
    let dec: Vec<(u64, i16, i8)> = xs.map(|x| x.integer_decode()).collect();
    let Some(emin) = dec.iter().filter(|d| d.0 != 0).map(|d| d.1).min() else {
        return vec![BigInt::zero(); dec.len()];
    };
    dec.iter()
        .map(|&(m, e, s)| {
            if m == 0 {
                BigInt::zero()
            } else {
                let v = BigInt::from(m) << ((e - emin) as usize);
                if s < 0 {
                    -v
                } else {
                    v
                }
            }
        })
        .collect()
}

/// The integer generator `row` scaled by a power of two.
fn row_to_int(row: &[f64]) -> Vec<BigInt> {
    let mut out = floats_to_ints(row.iter().copied());
    primitive(&mut out);
    out
}

fn gcd(a: &BigInt, b: &BigInt) -> BigInt {
    let (mut a, mut b) = (a.abs(), b.abs());
    while !b.is_zero() {
        let r = &a % &b;
        a = b;
        b = r;
    }
    a
}

/// Divides `v` by the gcd of its entries. Starts from the smallest entry, so that every
/// Euclid step after the first works on numbers of its size, and stops as soon as the gcd is 1.
fn primitive(v: &mut [BigInt]) {
    let Some(start) = v
        .iter()
        .enumerate()
        .filter(|(_, x)| !x.is_zero())
        .min_by_key(|(_, x)| x.bits())
        .map(|(i, _)| i)
    else {
        return;
    };
    let mut g = v[start].abs();
    if g.is_one() {
        return;
    }
    for (i, x) in v.iter().enumerate() {
        if i == start || x.is_zero() {
            continue;
        }
        g = gcd(&g, x);
        if g.is_one() {
            return;
        }
    }
    for x in v.iter_mut() {
        *x = &*x / &g;
    }
}

fn dot(a: &[BigInt], b: &[BigInt]) -> BigInt {
    let mut s = BigInt::zero();
    for (x, y) in a.iter().zip(b) {
        if !x.is_zero() && !y.is_zero() {
            s += x * y;
        }
    }
    s
}

/// Indices of a maximal set of linearly independent rows (greedy, in order), at most `cap`.
fn row_basis(rows: &[Vec<BigInt>], cap: usize) -> Vec<usize> {
    let mut ech: Vec<(usize, Vec<BigInt>)> = Vec::new();
    let mut basis = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        if basis.len() == cap {
            break;
        }
        let mut r = row.clone();
        for (c, e) in &ech {
            if !r[*c].is_zero() {
                let (a, b) = (e[*c].clone(), r[*c].clone());
                // Entries grow by one pivot per step (at most `d` steps): no gcd needed, only
                // the independence decision is used.
                for t in 0..r.len() {
                    r[t] = &r[t] * &a - &e[t] * &b;
                }
            }
        }
        if let Some(c) = r.iter().position(|x| !x.is_zero()) {
            ech.push((c, r));
            basis.push(i);
        }
    }
    basis
}

/// Integer basis of the null space `{x : rows x = 0}` in `Z^d`.
fn null_space(rows: &[Vec<BigInt>], d: usize) -> Vec<Vec<BigInt>> {
    let mut m: Vec<Vec<BigRational>> = rows
        .iter()
        .map(|r| {
            r.iter()
                .map(|x| BigRational::from_integer(x.clone()))
                .collect()
        })
        .collect();
    let mut pivots: Vec<(usize, usize)> = Vec::new();
    let mut ri = 0;
    for col in 0..d {
        let Some(p) = (ri..m.len()).find(|&r| !m[r][col].is_zero()) else {
            continue;
        };
        m.swap(ri, p);
        let inv = m[ri][col].recip();
        for x in m[ri].iter_mut() {
            *x = &*x * &inv;
        }
        for r in 0..m.len() {
            if r != ri && !m[r][col].is_zero() {
                let f = m[r][col].clone();
                for t in 0..d {
                    let v = &m[ri][t] * &f;
                    m[r][t] -= v;
                }
            }
        }
        pivots.push((ri, col));
        ri += 1;
        if ri == m.len() {
            break;
        }
    }
    let is_pivot = |c: usize| pivots.iter().any(|&(_, pc)| pc == c);
    let mut out = Vec::new();
    for f in (0..d).filter(|&c| !is_pivot(c)) {
        let mut x = vec![BigRational::zero(); d];
        x[f] = BigRational::one();
        for &(r, pc) in &pivots {
            x[pc] = -m[r][f].clone();
        }
        out.push(rational_to_int(&x));
    }
    out
}

/// A positive integer multiple of a rational vector, primitive.
fn rational_to_int(x: &[BigRational]) -> Vec<BigInt> {
    let mut l = BigInt::one();
    for v in x {
        let d = v.denom();
        l = &l / gcd(&l, d) * d;
    }
    let mut out: Vec<BigInt> = x.iter().map(|v| (v * &l).to_integer()).collect();
    primitive(&mut out);
    out
}

/// `f64` approximation of an integer vector's direction (scaled to avoid overflow).
fn to_f64_dir(v: &[BigInt]) -> Vec<f64> {
    let bits = v.iter().map(|x| x.bits()).max().unwrap_or(0);
    let shift = bits.saturating_sub(900) as usize;
    let mut out: Vec<f64> = v
        .iter()
        .map(|x| (x >> shift).to_f64().unwrap_or(0.0))
        .collect();
    crate::linalg::normalize(&mut out);
    out
}

/// Extreme rays of `{y : a y <= 0}` (`a` integer, full column rank `k`), exactly.
fn exact_dd(a: &[Vec<BigInt>], k: usize) -> Result<Vec<Ray>, ConeError> {
    let m = a.len();
    let words = bitset::words_for(m);
    if k == 0 {
        return Ok(Vec::new());
    }
    let basis = row_basis(a, k);
    if basis.len() < k {
        return Err(ConeError::Uncertified(
            "exact double description: the rows are not of full column rank".into(),
        ));
    }
    // Rays of the simplicial cone {A_K y <= 0}: the columns of -A_K^{-1}.
    let rows_k: Vec<Vec<BigInt>> = basis.iter().map(|&i| a[i].clone()).collect();
    let cols = neg_inverse_columns(&rows_k);
    let mut rays: Vec<Ray> = cols
        .into_iter()
        .enumerate()
        .map(|(i, x)| {
            let mut z = vec![0u64; words];
            for (t, &row) in basis.iter().enumerate() {
                if t != i {
                    bitset::set(&mut z, row);
                }
            }
            Ray { x, z }
        })
        .collect();
    let need = k.saturating_sub(2) as u32;
    let mut tmp = vec![0u64; words];
    for j in (0..m).filter(|j| !basis.contains(j)) {
        let s: Vec<BigInt> = rays.iter().map(|r| dot(&a[j], &r.x)).collect();
        if s.iter().all(|v| !v.is_positive()) {
            for (r, v) in rays.iter_mut().zip(&s) {
                if v.is_zero() {
                    bitset::set(&mut r.z, j);
                }
            }
            continue;
        }
        // New rays first (they need their parents), then the survivors are moved, not cloned.
        let mut created: Vec<Ray> = Vec::new();
        for p in (0..rays.len()).filter(|&i| s[i].is_positive()) {
            for q in (0..rays.len()).filter(|&i| s[i].is_negative()) {
                let mut c = 0;
                for t in 0..words {
                    tmp[t] = rays[p].z[t] & rays[q].z[t];
                    c += tmp[t].count_ones();
                }
                if c < need {
                    continue;
                }
                let blocked = (0..rays.len()).any(|o| {
                    o != p && o != q && tmp.iter().zip(&rays[o].z).all(|(a, b)| a & !b == 0)
                });
                if blocked {
                    continue;
                }
                let mut x: Vec<BigInt> = (0..k)
                    .map(|t| &s[p] * &rays[q].x[t] - &s[q] * &rays[p].x[t])
                    .collect();
                // Divide out the content only when the entries get long: gcds dominate the
                // cost, and most combinations stay short.
                if x.iter().map(|v| v.bits()).max().unwrap_or(0) > PRIMITIVE_BITS {
                    primitive(&mut x);
                }
                let mut z = tmp.clone();
                bitset::set(&mut z, j);
                created.push(Ray { x, z });
            }
        }
        let mut next: Vec<Ray> = Vec::with_capacity(rays.len() + created.len());
        for (i, mut r) in rays.into_iter().enumerate() {
            if !s[i].is_positive() {
                if s[i].is_zero() {
                    bitset::set(&mut r.z, j);
                }
                next.push(r);
            }
        }
        next.extend(created);
        rays = next;
        if rays.is_empty() {
            break;
        }
    }
    Ok(rays)
}

/// Positive integer multiples of the columns of `-A^{-1}` for an invertible integer `k x k`
/// matrix `A` (rows given), by fraction-free Gauss-Jordan elimination on `[A | I]`: every
/// intermediate entry is a minor of the input, so the divisions by the previous pivot are
/// exact; at the end the left block is `D_r e_r` row by row and the right block `R`, so
/// `A^{-1} e_i = (R_{ri} / D_r)_r`.
fn neg_inverse_columns(a: &[Vec<BigInt>]) -> Vec<Vec<BigInt>> {
    let k = a.len();
    let w = 2 * k;
    let mut m: Vec<Vec<BigInt>> = a
        .iter()
        .enumerate()
        .map(|(r, row)| {
            let mut v = row.clone();
            v.extend((0..k).map(|c| BigInt::from((c == r) as i32)));
            v
        })
        .collect();
    let mut prev = BigInt::one();
    for c in 0..k {
        let p = (c..k).find(|&r| !m[r][c].is_zero()).expect("invertible");
        m.swap(c, p);
        for r in 0..k {
            if r == c {
                continue;
            }
            let f = m[r][c].clone();
            for t in 0..w {
                if t == c {
                    continue;
                }
                let v = (&m[c][c] * &m[r][t] - &f * &m[c][t]) / &prev;
                m[r][t] = v;
            }
            m[r][c] = BigInt::zero();
        }
        prev = m[c][c].clone();
    }
    // Scale: x_r = -R_{ri} / D_r; multiply by prod |D_s| > 0 to stay integer.
    let d: Vec<BigInt> = (0..k).map(|r| m[r][r].clone()).collect();
    let all_equal = d.iter().all(|x| *x == d[0]);
    (0..k)
        .map(|i| {
            let mut x: Vec<BigInt> = (0..k)
                .map(|r| {
                    if all_equal {
                        if d[0].is_positive() {
                            -m[r][k + i].clone()
                        } else {
                            m[r][k + i].clone()
                        }
                    } else {
                        let mut v = -m[r][k + i].clone();
                        if d[r].is_negative() {
                            v = -v;
                        }
                        for (s, ds) in d.iter().enumerate() {
                            if s != r {
                                v *= ds.abs();
                            }
                        }
                        v
                    }
                })
                .collect();
            primitive(&mut x);
            x
        })
        .collect()
}

/// Ridges (as sets of member indices) of the cone spanned by `rows` (integer, rank `k - 1` in
/// `Z^k`... any rank `q`): the facets of the cone within its span, by reduction to its row
/// space and an exact double description. Returns `None` when the rank is not `want_rank`.
fn facets_of(rows: &[Vec<BigInt>], want_rank: usize) -> Result<Option<Vec<Vec<usize>>>, ConeError> {
    let b = row_basis(rows, usize::MAX);
    if b.len() != want_rank {
        return Ok(None);
    }
    let h: Vec<Vec<BigInt>> = rows
        .iter()
        .map(|r| b.iter().map(|&i| dot(r, &rows[i])).collect())
        .collect();
    let rays = exact_dd(&h, want_rank)?;
    Ok(Some(
        rays.iter()
            .map(|ray| {
                (0..rows.len())
                    .filter(|&i| ray.z[i / 64] >> (i % 64) & 1 == 1)
                    .collect()
            })
            .collect(),
    ))
}

/// What the exact conversion returns.
pub(crate) struct ExactResult {
    pub facets: DMatrix<f64>,
    pub equations: DMatrix<f64>,
    pub lineality: DMatrix<f64>,
    pub extreme: Vec<usize>,
    pub certificate: Certificate,
}

fn rows_to_matrix(rows: &[Vec<f64>], d: usize) -> DMatrix<f64> {
    DMatrix::from_fn(rows.len(), d, |i, j| rows[i][j])
}

/// Exact span -> face of the rows of `v` (finite, `d >= 1` columns).
pub(crate) fn exact_span_to_face(
    v: &DMatrix<f64>,
    tol: &Tolerances,
) -> Result<ExactResult, ConeError> {
    let (n, d) = v.shape();
    let mut kept: Vec<usize> = Vec::new();
    let mut ints: Vec<Vec<BigInt>> = Vec::new();
    for i in 0..n {
        let row: Vec<f64> = v.row(i).iter().copied().collect();
        let r = row_to_int(&row);
        if r.iter().any(|x| !x.is_zero()) {
            kept.push(i);
            ints.push(r);
        }
    }
    // Distinct rays (primitive integer rows are equal iff positively parallel).
    let mut distinct: Vec<usize> = Vec::new();
    for i in 0..ints.len() {
        if !distinct.iter().any(|&j| ints[j] == ints[i]) {
            distinct.push(i);
        }
    }
    let dist_rows: Vec<Vec<BigInt>> = distinct.iter().map(|&i| ints[i].clone()).collect();
    let bsel = row_basis(&dist_rows, d);
    let b: Vec<Vec<BigInt>> = bsel.iter().map(|&i| dist_rows[i].clone()).collect();
    let r = b.len();
    let eq_int = if r == 0 {
        (0..d)
            .map(|i| (0..d).map(|j| BigInt::from((i == j) as i32)).collect())
            .collect()
    } else {
        null_space(&b, d)
    };
    // Generators in the basis coordinates.
    let g: Vec<Vec<BigInt>> = ints
        .iter()
        .map(|x| b.iter().map(|bc| dot(x, bc)).collect())
        .collect();
    let gd: Vec<Vec<BigInt>> = distinct.iter().map(|&i| g[i].clone()).collect();
    let rays = exact_dd(&gd, r)?;
    let nf = rays.len();
    // Facets in x-space: u = B^T y.
    let u_int: Vec<Vec<BigInt>> = rays
        .iter()
        .map(|ray| {
            let mut u = vec![BigInt::zero(); d];
            for (c, bc) in b.iter().enumerate() {
                for t in 0..d {
                    u[t] += &ray.x[c] * &bc[t];
                }
            }
            primitive(&mut u);
            u
        })
        .collect();
    // Lineality: null space of [U; E].
    let mut stacked = u_int.clone();
    stacked.extend(eq_int.iter().cloned());
    let lin_int = if stacked.is_empty() {
        (0..d)
            .map(|i| (0..d).map(|j| BigInt::from((i == j) as i32)).collect())
            .collect()
    } else {
        null_space(&stacked, d)
    };
    let l = lin_int.len();
    let t = r - l.min(r);
    // Exact incidence, over all kept generators.
    let ng = ints.len();
    let slack: Vec<Vec<BigInt>> = rays
        .iter()
        .map(|ray| g.iter().map(|gi| dot(gi, &ray.x)).collect())
        .collect();
    let sound = slack.iter().all(|row| row.iter().all(|s| !s.is_positive()));
    let tight = |f: usize, i: usize| slack[f][i].is_zero();
    let in_l: Vec<bool> = (0..ng).map(|i| (0..nf).all(|f| tight(f, i))).collect();
    // Support: the tight generators of each facet have rank r - 1.
    let mut unsupported = Vec::new();
    for f in 0..nf {
        let rows: Vec<Vec<BigInt>> = (0..ng)
            .filter(|&i| tight(f, i))
            .map(|i| g[i].clone())
            .collect();
        if row_basis(&rows, r).len() + 1 != r {
            unsupported.push(f);
        }
    }
    // Lineality: the generators in L positively span L.
    let mut lineality_ok = true;
    if l > 0 {
        let rows: Vec<Vec<BigInt>> = (0..ng)
            .filter(|&i| in_l[i])
            .map(|i| ints[i].clone())
            .collect();
        match facets_of(&rows, l)? {
            Some(f) => lineality_ok = f.is_empty(),
            None => lineality_ok = false,
        }
        // facets_of runs the double description of the polar of cone(rows) in its span: no
        // ray means the cone is the whole span.
    }
    // Completeness: ridges, in coordinates modulo L (generators evaluated on t independent
    // facets).
    let mut open = 0usize;
    let dims_ok = match t {
        0 => nf == 0,
        1 => nf == 1,
        2 => nf == 2,
        _ => nf >= t,
    };
    if !dims_ok {
        open = usize::MAX;
    } else if t >= 3 {
        let ys: Vec<Vec<BigInt>> = rays.iter().map(|r| r.x.clone()).collect();
        let yb = row_basis(&ys, t);
        let ghat: Vec<Vec<BigInt>> = g
            .iter()
            .map(|gi| yb.iter().map(|&f| dot(gi, &ys[f])).collect())
            .collect();
        for f in 0..nf {
            let members: Vec<usize> = distinct
                .iter()
                .copied()
                .filter(|&i| !in_l[i] && tight(f, i))
                .collect();
            let rows: Vec<Vec<BigInt>> = members.iter().map(|&i| ghat[i].clone()).collect();
            match facets_of(&rows, t - 1)? {
                None => open += 1,
                Some(ridges) => {
                    for ridge in ridges {
                        let cover = (0..nf)
                            .filter(|&f2| ridge.iter().all(|&loc| tight(f2, members[loc])))
                            .count();
                        if cover != 2 {
                            open += 1;
                        }
                    }
                }
            }
        }
    }
    // Extreme generators: not in L, no generator tight on a strict superset of facets.
    let tight_set = |i: usize| -> Vec<bool> { (0..nf).map(|f| tight(f, i)).collect() };
    let mut extreme_kept: Vec<usize> = Vec::new();
    if t > 0 {
        let sets: Vec<Vec<bool>> = (0..ng).map(tight_set).collect();
        for &gi in &distinct {
            if in_l[gi] {
                continue;
            }
            let dominated = distinct.iter().any(|&h| {
                h != gi
                    && !in_l[h]
                    && sets[h] != sets[gi]
                    && sets[gi].iter().zip(&sets[h]).all(|(a, b)| !a || *b)
            });
            if !dominated && !extreme_kept.iter().any(|&o| sets[o] == sets[gi]) {
                extreme_kept.push(gi);
            }
        }
    }
    let mut extreme: Vec<usize> = extreme_kept.iter().map(|&i| kept[i]).collect();
    extreme.sort_unstable();
    // Output in f64.
    let mut facets: Vec<Vec<f64>> = u_int.iter().map(|u| to_f64_dir(u)).collect();
    facets.sort_by(|a, b| {
        a.iter()
            .zip(b)
            .map(|(x, y)| x.total_cmp(y))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let eq_f: Vec<Vec<f64>> = eq_int.iter().map(|e| to_f64_dir(e)).collect();
    let lin_f: Vec<Vec<f64>> = lin_int.iter().map(|e| to_f64_dir(e)).collect();
    let facets_m = rows_to_matrix(&facets, d);
    // Informative float violation (the decision above is exact).
    let mut max_violation: f64 = 0.0;
    for f in 0..facets_m.nrows() {
        for &i in &kept {
            let row = v.row(i);
            let nv = row.norm();
            max_violation = max_violation.max(facets_m.row(f).dot(&row) / nv);
        }
    }
    let support = unsupported.is_empty();
    let completeness = open == 0;
    let certificate = Certificate {
        certified: sound && support && lineality_ok && completeness,
        arithmetic: Arithmetic::Exact,
        max_violation,
        max_equation_residual: 0.0,
        soundness: sound,
        support,
        unsupported_facets: unsupported,
        lineality: lineality_ok,
        completeness,
        open_ridges: open,
    };
    Ok(ExactResult {
        facets: facets_m,
        equations: orthonormal_rows(&rows_to_matrix(&eq_f, d), tol.rank),
        lineality: orthonormal_rows(&rows_to_matrix(&lin_f, d), tol.rank),
        extreme,
        certificate,
    })
}
