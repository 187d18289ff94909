//! Exact arithmetic: the double description and its certificate over the integers.
//!
//! # Math
//!
//! Every `f64` is a dyadic rational `m 2^e`, so a generator scaled by a power of two is an
//! integer vector (a positive scaling: the same ray). On integers everything is exact:
//!
//! - `span(V)` is spanned by `r` independent generators `B` (fraction-free elimination), and the
//!   generators in those coordinates are `G = V B^T` (integer, full column rank `r`); the polar
//!   `{y : G y <= 0}` is pointed and its extreme rays `y` give the facets `u = B^T y` (when
//!   `V` spans `R^d`, `B` is the identity: the integers keep their size);
//! - the double description iteration is the one of [`crate::dd`] with exact signs: the slack of
//!   a ray on a row is an integer dot product, new rays `(a . p) n - (a . n) p` are divided by the
//!   gcd of their entries to keep them small;
//! - equations and lineality are exact null spaces (fraction-free elimination), rounded to `f64` and
//!   orthonormalized only for output.
//!
//! The certificate is decided exactly too: soundness (`G y <= 0`), support (rank of the tight
//! generators), lineality (the generators in the lineality space positively span it: an exact
//! double description in it returns no ray) and completeness (each ridge of each facet lies in
//! exactly two facets; the ridges of a simplicial facet are its drop-one subsets, those of the
//! others come from an exact double description of the facet's tight generators in the
//! quotient by the lineality space, in the coordinates of independent columns: a coordinate
//! projection injective on their span keeps the integers as they are).
//!
//! Rays are kept primitive with a binary gcd on 64-bit limbs (one division first when the
//! sizes differ by more than a word); the null spaces run on a row basis, not on every row.
//!
//! The facets are exact for the input **as given** (the rounded `f64` generators): near
//! degenerate inputs may have many more facets than the intended geometry.

use nalgebra::DMatrix;
use num_bigint::BigInt;
use num_traits::{Float, One, Signed, ToPrimitive, Zero};

use crate::dd::{self, bitset};
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

/// The gcd of `|a|` and `|b|`: the binary algorithm (Stein's: shifts and subtractions) in
/// place on 64-bit limbs, and on `u128` once both numbers fit in two limbs.
fn gcd(a: &BigInt, b: &BigInt) -> BigInt {
    if a.is_zero() {
        return b.abs();
    }
    if b.is_zero() {
        return a.abs();
    }
    // One division first when the sizes differ much (the binary steps remove about one bit
    // each: reducing the larger number modulo the smaller one is cheaper then).
    let (mut a, mut b) = (a.magnitude().clone(), b.magnitude().clone());
    if a.bits() < b.bits() {
        std::mem::swap(&mut a, &mut b);
    }
    if a.bits() > b.bits() + 64 {
        a %= &b;
        if a.is_zero() {
            return BigInt::from(b);
        }
    }
    let mut x = a.to_u64_digits();
    let mut y = b.to_u64_digits();
    let shift = limbs::trailing_zeros(&x).min(limbs::trailing_zeros(&y));
    limbs::shr_odd(&mut x);
    let g = loop {
        if x.len() <= 2 && y.len() <= 2 {
            let g = gcd_u128(limbs::to_u128(&x), limbs::to_u128(&y));
            break vec![g as u64, (g >> 64) as u64];
        }
        limbs::shr_odd(&mut y);
        if limbs::greater(&x, &y) {
            std::mem::swap(&mut x, &mut y);
        }
        limbs::sub_assign(&mut y, &x);
        if y.is_empty() {
            break x;
        }
    };
    BigInt::from(num_bigint::BigUint::from_slice(&limbs::to_u32(&g))) << shift
}

/// Unsigned integers as little-endian `u64` limbs without leading zeros (empty: zero), for
/// [`gcd`].
mod limbs {
    /// Number of trailing zero bits (of a non-zero number).
    pub(super) fn trailing_zeros(x: &[u64]) -> u64 {
        let w = x.iter().position(|&l| l != 0).unwrap_or(0);
        w as u64 * 64 + x[w].trailing_zeros() as u64
    }

    /// Divides a non-zero `x` by its largest power-of-two factor (makes it odd), in place.
    pub(super) fn shr_odd(x: &mut Vec<u64>) {
        let tz = trailing_zeros(x);
        let (words, bits) = ((tz / 64) as usize, (tz % 64) as u32);
        if words > 0 {
            x.drain(..words);
        }
        if bits > 0 {
            for i in 0..x.len() {
                let hi = if i + 1 < x.len() {
                    x[i + 1] << (64 - bits)
                } else {
                    0
                };
                x[i] = (x[i] >> bits) | hi;
            }
        }
        trim(x);
    }

    /// `x > y`.
    pub(super) fn greater(x: &[u64], y: &[u64]) -> bool {
        if x.len() != y.len() {
            return x.len() > y.len();
        }
        for (a, b) in x.iter().rev().zip(y.iter().rev()) {
            if a != b {
                return a > b;
            }
        }
        false
    }

    /// `y -= x`, for `y >= x`.
    pub(super) fn sub_assign(y: &mut Vec<u64>, x: &[u64]) {
        let mut borrow = false;
        for i in 0..y.len() {
            let xi = x.get(i).copied().unwrap_or(0);
            let (d1, b1) = y[i].overflowing_sub(xi);
            let (d2, b2) = d1.overflowing_sub(borrow as u64);
            y[i] = d2;
            borrow = b1 || b2;
        }
        debug_assert!(!borrow);
        trim(y);
    }

    fn trim(x: &mut Vec<u64>) {
        while x.last() == Some(&0) {
            x.pop();
        }
    }

    /// A number of at most two limbs.
    pub(super) fn to_u128(x: &[u64]) -> u128 {
        x.iter()
            .rev()
            .fold(0u128, |acc, &l| (acc << 64) | l as u128)
    }

    /// The same number as `u32` digits (little-endian), for `BigUint::from_slice`.
    pub(super) fn to_u32(x: &[u64]) -> Vec<u32> {
        x.iter()
            .flat_map(|&l| [l as u32, (l >> 32) as u32])
            .collect()
    }
}

/// Binary (Stein's) gcd of two `u128`.
fn gcd_u128(mut a: u128, mut b: u128) -> u128 {
    if a == 0 {
        return b;
    }
    if b == 0 {
        return a;
    }
    let shift = (a | b).trailing_zeros();
    a >>= a.trailing_zeros();
    loop {
        b >>= b.trailing_zeros();
        if a > b {
            std::mem::swap(&mut a, &mut b);
        }
        b -= a;
        if b == 0 {
            return a << shift;
        }
    }
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

/// A basis of the integer null space `{x : rows x = 0}` (`d` columns), one primitive vector
/// per free column, by fraction-free elimination: forward elimination to an echelon form
/// (each row step `r <- p r - q e`, entries stay integers), then back-substitution with the
/// free entry set to the product of the pivots, which makes every division exact (each pivot
/// variable is a multiple of the pivots not yet divided out).
fn null_space(rows: &[Vec<BigInt>], d: usize) -> Vec<Vec<BigInt>> {
    // Reduced echelon form: (pivot column, row), each pivot column zero in the other rows.
    let mut ech: Vec<(usize, Vec<BigInt>)> = Vec::new();
    for row in rows {
        let mut r = row.clone();
        for (c, e) in &ech {
            if !r[*c].is_zero() {
                let (a, b) = (e[*c].clone(), r[*c].clone());
                for t in 0..d {
                    r[t] = &r[t] * &a - &e[t] * &b;
                }
                primitive(&mut r);
            }
        }
        if let Some(c) = r.iter().position(|x| !x.is_zero()) {
            // Eliminate the new pivot column from the earlier rows too (reduced form keeps
            // the back-substitution short and the pivot columns distinct).
            for (_, e) in ech.iter_mut() {
                if !e[c].is_zero() {
                    let (a, b) = (r[c].clone(), e[c].clone());
                    for t in 0..d {
                        e[t] = &e[t] * &a - &r[t] * &b;
                    }
                    primitive(e);
                }
            }
            ech.push((c, r));
        }
    }
    let is_pivot = |c: usize| ech.iter().any(|&(pc, _)| pc == c);
    let mut out = Vec::new();
    for f in (0..d).filter(|&c| !is_pivot(c)) {
        // Reduced rows: e[pc] x_pc + sum_free e[j] x_j = 0 with only x_f free and non-zero.
        let prod = ech.iter().fold(BigInt::one(), |acc, (pc, e)| acc * &e[*pc]);
        let mut x = vec![BigInt::zero(); d];
        x[f] = prod.clone();
        for (pc, e) in &ech {
            // Exact: `prod` is a multiple of `e[pc]`.
            x[*pc] = -(&e[f] * &prod) / &e[*pc];
        }
        primitive(&mut x);
        out.push(x);
    }
    out
}

/// `f64` approximation of an integer vector's direction: each entry `x` as `x / 2^bits` with
/// `bits` those of the largest (so the largest is in `[0.5, 1)` and the norm cannot overflow
/// however wide the integers are), from its leading 64 bits, then normalized. Entries more than
/// `2^1074` times smaller than the largest become 0.
fn to_f64_dir(v: &[BigInt]) -> Vec<f64> {
    let bits = v.iter().map(|x| x.bits()).max().unwrap_or(0) as i64;
    let mut out: Vec<f64> = v
        .iter()
        .map(|x| {
            let b = x.bits() as i64;
            let drop = (b - 64).max(0);
            let lead = (x >> drop as usize).to_f64().unwrap_or(0.0);
            // x ~ lead 2^drop, divided by 2^bits: two exact steps of the power of two.
            let e = (drop - bits).clamp(-2200, 0) as i32;
            lead * 2f64.powi(e / 2) * 2f64.powi(e - e / 2)
        })
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
    let (mut z_all, mut zp, mut zn, mut cand) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
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
        // The adjacent pairs of R+ x R-, in the order and by the combinatorial test of the
        // floating-point step (`crate::dd::step`), on exact signs.
        let plus: Vec<usize> = (0..rays.len()).filter(|&i| s[i].is_positive()).collect();
        let minus: Vec<usize> = (0..rays.len()).filter(|&i| s[i].is_negative()).collect();
        z_all.clear();
        rays.iter().for_each(|r| z_all.extend_from_slice(&r.z));
        zp.clear();
        plus.iter().for_each(|&p| zp.extend_from_slice(&rays[p].z));
        zn.clear();
        minus.iter().for_each(|&q| zn.extend_from_slice(&rays[q].z));
        cand.clear();
        dd::candidate_pairs(&zp, &zn, words, need, &mut cand);
        // New rays first (they need their parents), then the survivors are moved, not cloned.
        let mut created: Vec<Ray> = Vec::new();
        for &(pi, ni) in &cand {
            let (p, q) = (plus[pi as usize], minus[ni as usize]);
            for t in 0..words {
                tmp[t] = rays[p].z[t] & rays[q].z[t];
            }
            if !dd::adjacent(&tmp, &z_all, words, rays.len(), [p, q]) {
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
    // Coordinates of span(rows): a set of `want_rank` independent columns (the coordinate
    // projection onto them is injective on the span, so the cone keeps its combinatorics),
    // which keeps the entries as they are (dot products with basis rows would square them).
    let ncols = rows.first().map_or(0, Vec::len);
    let cols: Vec<Vec<BigInt>> = (0..ncols)
        .map(|c| rows.iter().map(|r| r[c].clone()).collect())
        .collect();
    // (The column rank is the rank of the rows: it must be `want_rank`.)
    let cb = row_basis(&cols, usize::MAX);
    if cb.len() != want_rank {
        return Ok(None);
    }
    let h: Vec<Vec<BigInt>> = rows
        .iter()
        .map(|r| cb.iter().map(|&c| r[c].clone()).collect())
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

/// The ridge check of completeness in exact arithmetic: for each claimed facet `f` (tight
/// generators `tight[f]`, among `candidates`), its ridges, from the coordinates `ghat` of the
/// generators modulo the lineality space (dimension `t`), must each lie in exactly two claimed
/// facets. Returns the number of ridges that do not (a facet whose tight generators do not
/// span a hyperplane counts one). Simplicial facets (`t - 1` independent tight generators) have
/// the drop-one subsets as ridges; the others get an exact double description. Up to `t - 2`
/// facets are left out by Balinski's theorem: their support must be checked by the caller, and
/// the theorem needs at least `t` claimed facets (a pointed `t`-cone has that many; fewer
/// count as open: `usize::MAX`).
fn open_ridges(
    ghat: &[Vec<BigInt>],
    tight: &[Vec<bool>],
    candidates: &[usize],
    t: usize,
) -> Result<usize, ConeError> {
    let nf = tight.len();
    if nf < t {
        // Not a pointed t-cone's face form; and Balinski's argument below needs `t` facets.
        return Ok(usize::MAX);
    }
    let mut open = 0usize;
    let members_of = |f: usize| -> Vec<usize> {
        candidates
            .iter()
            .copied()
            .filter(|&i| tight[f][i])
            .collect()
    };
    // Balinski's theorem (as in the floating-point certificate, `crate::certificate`): the
    // claimed facets adjacent to any set of missing ones number at least `t - 1`, so up to
    // `t - 2` facets need no ridge check (their support is checked by the caller). Those with
    // the most tight generators (beyond simplicial) are the expensive ones.
    let mut by_size: Vec<(usize, usize)> = (0..nf)
        .map(|f| (members_of(f).len(), f))
        .filter(|&(m, _)| m > t - 1)
        .collect();
    by_size.sort_unstable_by(|a, b| b.cmp(a));
    let skip: Vec<usize> = by_size.iter().take(t - 2).map(|&(_, f)| f).collect();
    for f in 0..nf {
        if skip.contains(&f) {
            continue;
        }
        let members = members_of(f);
        let rows: Vec<Vec<BigInt>> = members.iter().map(|&i| ghat[i].clone()).collect();
        let covered = |ridge: &mut dyn Iterator<Item = usize>| -> usize {
            let ridge: Vec<usize> = ridge.map(|loc| members[loc]).collect();
            (0..nf)
                .filter(|&f2| ridge.iter().all(|&i| tight[f2][i]))
                .count()
        };
        if rows.len() == t - 1 {
            // Simplicial (independent tight generators): the ridges drop one each.
            if row_basis(&rows, t - 1).len() != t - 1 {
                open += 1;
                continue;
            }
            for drop in 0..rows.len() {
                if covered(&mut (0..rows.len()).filter(|&loc| loc != drop)) != 2 {
                    open += 1;
                }
            }
            continue;
        }
        match facets_of(&rows, t - 1)? {
            None => open += 1,
            Some(ridges) => {
                for ridge in ridges {
                    if covered(&mut ridge.into_iter()) != 2 {
                        open += 1;
                    }
                }
            }
        }
    }
    Ok(open)
}

/// The identity rows of `R^d`, as integers.
fn identity(d: usize) -> Vec<Vec<BigInt>> {
    (0..d)
        .map(|i| (0..d).map(|j| BigInt::from((i == j) as i32)).collect())
        .collect()
}

/// The generators as primitive integer rows: `kept` the indices of the non-zero input rows,
/// `ints` their integer rows, `distinct` the indices into `ints` of the distinct rays
/// (primitive integer rows are equal iff positively parallel).
struct IntGenerators {
    kept: Vec<usize>,
    ints: Vec<Vec<BigInt>>,
    distinct: Vec<usize>,
}

impl IntGenerators {
    fn of(v: &DMatrix<f64>) -> Self {
        let mut kept: Vec<usize> = Vec::new();
        let mut ints: Vec<Vec<BigInt>> = Vec::new();
        for i in 0..v.nrows() {
            let row: Vec<f64> = v.row(i).iter().copied().collect();
            let r = row_to_int(&row);
            if r.iter().any(|x| !x.is_zero()) {
                kept.push(i);
                ints.push(r);
            }
        }
        let mut distinct: Vec<usize> = Vec::new();
        for i in 0..ints.len() {
            if !distinct.iter().any(|&j| ints[j] == ints[i]) {
                distinct.push(i);
            }
        }
        IntGenerators {
            kept,
            ints,
            distinct,
        }
    }
}

/// Exact span -> face of the rows of `v` (finite, `d >= 1` columns), in phases: integer
/// generators, a basis `B` of their span (`r` rows) and the equations (its orthogonal
/// complement), the double description in the coordinates `y = B x`, the facets back in
/// `x`-space and the lineality, then the exact certificate ([`certify_exact`]) and the extreme
/// generators.
pub(crate) fn exact_span_to_face(
    v: &DMatrix<f64>,
    tol: &Tolerances,
) -> Result<ExactResult, ConeError> {
    let d = v.ncols();
    let gens = IntGenerators::of(v);
    let dist_rows: Vec<Vec<BigInt>> = gens
        .distinct
        .iter()
        .map(|&i| gens.ints[i].clone())
        .collect();
    let bsel = row_basis(&dist_rows, d);
    let r = bsel.len();
    let b: Vec<Vec<BigInt>> = if r == d {
        // Full-dimensional: any basis of R^d will do, and the standard one keeps the integers
        // as they are (basis rows would multiply their size).
        identity(d)
    } else {
        bsel.iter().map(|&i| dist_rows[i].clone()).collect()
    };
    let eq_int = if r == 0 {
        identity(d)
    } else {
        null_space(&b, d)
    };
    // Generators in the basis coordinates.
    let g: Vec<Vec<BigInt>> = gens
        .ints
        .iter()
        .map(|x| b.iter().map(|bc| dot(x, bc)).collect())
        .collect();
    let gd: Vec<Vec<BigInt>> = gens.distinct.iter().map(|&i| g[i].clone()).collect();
    let rays = exact_dd(&gd, r)?;
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
        identity(d)
    } else {
        // The null space of the rows is that of a row basis (at most `d` rows): the
        // elimination then runs on those rows only, not on every facet.
        let sel: Vec<Vec<BigInt>> = row_basis(&stacked, d)
            .into_iter()
            .map(|i| stacked[i].clone())
            .collect();
        null_space(&sel, d)
    };
    let l = lin_int.len();
    let exact = certify_exact(&gens, &g, &rays, r, l)?;
    let extreme = extreme_generators(&gens, &exact.tight, &exact.in_l, r - l.min(r));
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
        for &i in &gens.kept {
            let row = v.row(i);
            let nv = row.norm();
            max_violation = max_violation.max(facets_m.row(f).dot(&row) / nv);
        }
    }
    let support = exact.unsupported.is_empty();
    let completeness = exact.open == 0;
    let certificate = Certificate {
        certified: exact.sound && support && exact.lineality && completeness,
        arithmetic: Arithmetic::Exact,
        max_violation,
        max_equation_residual: 0.0,
        soundness: exact.sound,
        support,
        unsupported_facets: exact.unsupported,
        lineality: exact.lineality,
        completeness,
        open_ridges: exact.open,
        fallback: None,
        merged_rows: 0,
        merge_distance: 0.0,
        wrench_frame: None,
    };
    Ok(ExactResult {
        facets: facets_m,
        equations: orthonormal_rows(&rows_to_matrix(&eq_f, d), tol.rank),
        lineality: orthonormal_rows(&rows_to_matrix(&lin_f, d), tol.rank),
        extreme,
        certificate,
    })
}

/// The exact certificate of an exact conversion, and the incidence it was decided on.
struct ExactChecks {
    /// `tight[f][i]`: generator `i` (of `IntGenerators::ints`) is on facet `f`.
    tight: Vec<Vec<bool>>,
    /// Generators in the lineality space (tight on every facet).
    in_l: Vec<bool>,
    /// Soundness: no generator strictly outside a facet.
    sound: bool,
    /// Facets whose tight generators do not have rank `r - 1`.
    unsupported: Vec<usize>,
    /// The generators in the lineality space positively span it.
    lineality: bool,
    /// Ridges not shared by exactly two facets (`usize::MAX`: the facet count cannot be right).
    open: usize,
}

/// The certificate's four checks in exact arithmetic, for the facets `rays` (coordinates `y`)
/// of the generators `g` (same coordinates) spanning dimension `r`, lineality dimension `l`.
fn certify_exact(
    gens: &IntGenerators,
    g: &[Vec<BigInt>],
    rays: &[Ray],
    r: usize,
    l: usize,
) -> Result<ExactChecks, ConeError> {
    let (nf, ng) = (rays.len(), g.len());
    let t = r - l.min(r);
    let slack: Vec<Vec<BigInt>> = rays
        .iter()
        .map(|ray| g.iter().map(|gi| dot(gi, &ray.x)).collect())
        .collect();
    let sound = slack.iter().all(|row| row.iter().all(|s| !s.is_positive()));
    let tight: Vec<Vec<bool>> = slack
        .iter()
        .map(|row| row.iter().map(|s| s.is_zero()).collect())
        .collect();
    let in_l: Vec<bool> = (0..ng).map(|i| (0..nf).all(|f| tight[f][i])).collect();
    // Support: the tight generators of each facet have rank r - 1.
    let mut unsupported = Vec::new();
    for (f, on_f) in tight.iter().enumerate() {
        let rows: Vec<Vec<BigInt>> = (0..ng).filter(|&i| on_f[i]).map(|i| g[i].clone()).collect();
        if row_basis(&rows, r).len() + 1 != r {
            unsupported.push(f);
        }
    }
    // Lineality: the generators in L positively span L. facets_of runs the double description
    // of the polar of cone(rows) in its span: no ray means the cone is the whole span.
    let mut lineality = true;
    if l > 0 {
        let rows: Vec<Vec<BigInt>> = (0..ng)
            .filter(|&i| in_l[i])
            .map(|i| gens.ints[i].clone())
            .collect();
        lineality = matches!(facets_of(&rows, l)?, Some(f) if f.is_empty());
    }
    // Completeness: ridges, in coordinates modulo L (generators evaluated on t independent
    // facets).
    let dims_ok = match t {
        0 => nf == 0,
        1 => nf == 1,
        2 => nf == 2,
        _ => nf >= t,
    };
    let open = if !dims_ok {
        usize::MAX
    } else if t >= 3 {
        let ghat: Vec<Vec<BigInt>> = if l == 0 {
            // Pointed: the basis coordinates already are coordinates modulo L = {0}.
            g.to_vec()
        } else {
            let ys: Vec<Vec<BigInt>> = rays.iter().map(|r| r.x.clone()).collect();
            let yb = row_basis(&ys, t);
            g.iter()
                .map(|gi| yb.iter().map(|&f| dot(gi, &ys[f])).collect())
                .collect()
        };
        let candidates: Vec<usize> = gens
            .distinct
            .iter()
            .copied()
            .filter(|&i| !in_l[i])
            .collect();
        open_ridges(&ghat, &tight, &candidates, t)?
    } else {
        0
    };
    Ok(ExactChecks {
        tight,
        in_l,
        sound,
        unsupported,
        lineality,
        open,
    })
}

/// Input indices of the extreme generators: not in L, and no generator tight on a strict
/// superset of their facets (one per set of facets). None when the cone is a linear space
/// (`t = 0`, the dimension modulo the lineality).
fn extreme_generators(
    gens: &IntGenerators,
    tight: &[Vec<bool>],
    in_l: &[bool],
    t: usize,
) -> Vec<usize> {
    let ng = gens.ints.len();
    let mut extreme_kept: Vec<usize> = Vec::new();
    if t > 0 {
        let sets: Vec<Vec<bool>> = (0..ng)
            .map(|i| tight.iter().map(|on_f| on_f[i]).collect())
            .collect();
        for &gi in &gens.distinct {
            if in_l[gi] {
                continue;
            }
            let dominated = gens.distinct.iter().any(|&h| {
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
    let mut extreme: Vec<usize> = extreme_kept.iter().map(|&i| gens.kept[i]).collect();
    extreme.sort_unstable();
    extreme
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic integers uniform in `[-m, m]` (xorshift).
    fn uniform(mut s: u64) -> impl FnMut(i64) -> i64 {
        move |m: i64| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s % (2 * m as u64 + 1)) as i64 - m
        }
    }

    fn ints(rows: &[Vec<i64>]) -> Vec<Vec<BigInt>> {
        rows.iter()
            .map(|r| r.iter().map(|&x| BigInt::from(x)).collect())
            .collect()
    }

    /// Integer wrench generators `(f, p x f)` of a rectangular contact: friction pyramid
    /// edges `(±1, 0, 2)`, `(0, ±1, 2)` in the frame `(e1, e2, n)` at the four corners
    /// `c ± a e1 ± b e2`.
    fn contact(
        c: [i64; 3],
        e1: [i64; 3],
        e2: [i64; 3],
        n: [i64; 3],
        a: i64,
        b: i64,
    ) -> Vec<Vec<i64>> {
        let cross = |p: [i64; 3], f: [i64; 3]| {
            [
                p[1] * f[2] - p[2] * f[1],
                p[2] * f[0] - p[0] * f[2],
                p[0] * f[1] - p[1] * f[0],
            ]
        };
        let mut out = Vec::new();
        for (sa, sb) in [(1, 1), (1, -1), (-1, 1), (-1, -1)] {
            let p: [i64; 3] = std::array::from_fn(|i| c[i] + sa * a * e1[i] + sb * b * e2[i]);
            for (t1, t2) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                let f: [i64; 3] = std::array::from_fn(|i| t1 * e1[i] + t2 * e2[i] + 2 * n[i]);
                let tau = cross(p, f);
                out.push(vec![f[0], f[1], f[2], tau[0], tau[1], tau[2]]);
            }
        }
        out
    }

    /// Pointed full-dimensional integer cones of several kinds: one rectangle (every facet
    /// with 8 or 9 tight generators), two rectangles (flat; one raised and tilted), and 4-D/5-D
    /// cones with generators on common faces (sums of two or three others).
    fn cones() -> Vec<(&'static str, Vec<Vec<BigInt>>)> {
        let one = contact([0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], 3, 2);
        let mut flat = one.clone();
        flat.extend(contact([0, 10, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], 3, 2));
        let mut tilted = one.clone();
        tilted.extend(contact([4, 9, 3], [1, 0, 0], [0, 3, 4], [0, -4, 3], 3, 2));
        let mut out = vec![
            ("one rectangle", ints(&one)),
            ("two flat rectangles", ints(&flat)),
            ("raised, tilted rectangle", ints(&tilted)),
        ];
        // Deterministic pseudo-random small cones with points on faces.
        let mut next = uniform(0x9e37_79b9_7f4a_7c15);
        for (k, n) in [(4usize, 9usize), (5, 10), (5, 12)] {
            for _ in 0..3 {
                let mut rows: Vec<Vec<i64>> = (0..n)
                    .map(|_| {
                        let mut r: Vec<i64> = (0..k - 1).map(|_| next(4)).collect();
                        r.push(6); // last coordinate positive: pointed
                        r
                    })
                    .collect();
                for q in 0..3 {
                    let (a, b) = (q % n, (q * 3 + 1) % n);
                    let sum: Vec<i64> = rows[a].iter().zip(&rows[b]).map(|(x, y)| x + y).collect();
                    rows.push(sum);
                }
                out.push(("random with face points", ints(&rows)));
            }
        }
        out
    }

    /// The exact facets (rays of the polar) and the incidence of a pointed full-dimensional
    /// cone given by integer generators.
    fn incidence(g: &[Vec<BigInt>]) -> (usize, Vec<Vec<bool>>) {
        let d = g[0].len();
        let rays = exact_dd(g, d).unwrap();
        let tight = rays
            .iter()
            .map(|y| g.iter().map(|gi| dot(gi, &y.x).is_zero()).collect())
            .collect();
        (d, tight)
    }

    /// The complete face form passes; removing any one facet (or two) fails: the exact ridge
    /// check of completeness has teeth, on simplicial and degenerate facets alike.
    #[test]
    fn open_ridges_is_zero_exactly_when_no_facet_is_missing() {
        for (name, g) in cones() {
            let (t, tight) = incidence(&g);
            let cand: Vec<usize> = (0..g.len()).collect();
            assert_eq!(open_ridges(&g, &tight, &cand, t).unwrap(), 0, "{name}");
            // Only the first few facets: never complete (a pointed t-cone has t at least).
            for keep in 1..=t {
                let few = tight[..keep].to_vec();
                assert!(
                    open_ridges(&g, &few, &cand, t).unwrap() > 0,
                    "{name}: {keep} facets"
                );
            }
            let nf = tight.len();
            for drop in 0..nf {
                let mut partial = tight.clone();
                partial.remove(drop);
                assert!(
                    open_ridges(&g, &partial, &cand, t).unwrap() > 0,
                    "{name}: facet {drop}"
                );
                let mut two = partial.clone();
                two.remove((drop * 7 + 3) % two.len());
                assert!(
                    open_ridges(&g, &two, &cand, t).unwrap() > 0,
                    "{name}: facet {drop} and another"
                );
            }
        }
    }

    /// The binary gcd on limbs equals Euclid's (the former code) on numbers of 1 to 40 limbs
    /// with common factors, powers of two and very different sizes.
    #[test]
    fn binary_gcd_equals_euclid() {
        let euclid = |a: &BigInt, b: &BigInt| {
            let (mut a, mut b) = (a.abs(), b.abs());
            while !b.is_zero() {
                let r = &a % &b;
                a = b;
                b = r;
            }
            a
        };
        let mut next = uniform(0x1234_5678_9abc_def1);
        let mut big = |limbs: usize| -> BigInt {
            (0..limbs).fold(BigInt::from(next(1 << 30) + (1 << 30) + 1), |acc, _| {
                (acc << 62) + BigInt::from(next(1 << 40) + (1 << 40))
            })
        };
        for trial in 0..400 {
            let (la, lb, lc) = (trial % 7, (trial * 5) % 40, (trial * 3) % 5);
            let c = big(lc) << (trial % 130);
            let a = big(la) * &c;
            let b = -(big(lb) * &c) << (trial % 3);
            assert_eq!(gcd(&a, &b), euclid(&a, &b), "trial {trial}");
            assert_eq!(gcd(&b, &a), euclid(&a, &b), "trial {trial}");
        }
        let zero = BigInt::zero();
        let seven = BigInt::from(-7);
        assert_eq!(gcd(&zero, &seven), BigInt::from(7));
        assert_eq!(gcd(&seven, &zero), BigInt::from(7));
    }

    /// The fraction-free null space: `d - rank` independent primitive vectors, each
    /// annihilated by every row, on random integer matrices of every rank (rows repeated and
    /// combined to lower it).
    #[test]
    fn null_space_is_the_kernel() {
        let mut next = uniform(0x2545_f491_4f6c_dd1d);
        for trial in 0..200 {
            let d = 2 + trial % 6;
            let r = trial % (d + 1);
            let mut rows: Vec<Vec<i64>> = (0..r)
                .map(|_| (0..d).map(|_| next(1 << 20)).collect())
                .collect();
            if r >= 2 {
                let comb: Vec<i64> = (0..d).map(|j| 3 * rows[0][j] - 7 * rows[1][j]).collect();
                rows.push(comb);
            }
            let rows = ints(&rows);
            let rank = row_basis(&rows, usize::MAX).len();
            let ns = null_space(&rows, d);
            assert_eq!(ns.len(), d - rank, "trial {trial}");
            for x in &ns {
                assert!(x.iter().any(|v| !v.is_zero()));
                for row in &rows {
                    assert!(dot(row, x).is_zero(), "trial {trial}");
                }
            }
            assert_eq!(
                row_basis(&ns, usize::MAX).len(),
                ns.len(),
                "trial {trial}: dependent"
            );
        }
    }

    /// The ridges of a facet from the column-coordinate projection equal those from the Gram
    /// coordinates (the former code), facet by facet.
    #[test]
    fn facets_of_is_independent_of_the_coordinates() {
        let gram = |rows: &[Vec<BigInt>], want: usize| -> Option<Vec<Vec<usize>>> {
            let b = row_basis(rows, usize::MAX);
            if b.len() != want {
                return None;
            }
            let h: Vec<Vec<BigInt>> = rows
                .iter()
                .map(|r| b.iter().map(|&i| dot(r, &rows[i])).collect())
                .collect();
            let rays = exact_dd(&h, want).unwrap();
            let mut out: Vec<Vec<usize>> = rays
                .iter()
                .map(|ray| {
                    (0..rows.len())
                        .filter(|&i| ray.z[i / 64] >> (i % 64) & 1 == 1)
                        .collect()
                })
                .collect();
            out.sort();
            Some(out)
        };
        let mut checked = 0;
        for (name, g) in cones() {
            let (t, tight) = incidence(&g);
            for row in &tight {
                let rows: Vec<Vec<BigInt>> = (0..g.len())
                    .filter(|&i| row[i])
                    .map(|i| g[i].clone())
                    .collect();
                let mut ours = facets_of(&rows, t - 1).unwrap();
                if let Some(r) = ours.as_mut() {
                    r.sort();
                }
                assert_eq!(ours, gram(&rows, t - 1), "{name}");
                checked += 1;
            }
        }
        assert!(checked > 100, "{checked}");
    }
}
