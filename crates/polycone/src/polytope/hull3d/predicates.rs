//! The exact orientation predicate of the direct hull.
//!
//! `orient(a, b, c, d) = sign det [b - a; c - a; d - a] = sign ((b - a) x (c - a)) . (d - a)`:
//! positive when `d` lies above the plane of the triangle `a b c` (on the side its normal
//! `(b - a) x (c - a)` points to, i.e. the triangle is counter-clockwise seen from `d`),
//! negative below, zero when the four points are coplanar. Every `f64` is a dyadic rational,
//! so the sign is well defined for the input as given.
//!
//! Method: a floating-point filter (the determinant in `f64` with a forward error bound in the
//! style of Shewchuk 1997, "Adaptive precision floating-point arithmetic and fast robust
//! geometric predicates"); when the bound does not decide the sign, the exact determinant as
//! a floating-point expansion (exact differences by two-sum, exact products by fused
//! multiply-add, summed into a nonoverlapping expansion, no allocation); for coordinates so
//! small or large that a product could underflow or overflow, the determinant in big
//! integers (the 12 coordinates written `m 2^e` and scaled by a common power of two).

use num_bigint::BigInt;
use num_traits::Signed;

use crate::polytope::tol::{ORIENT_ERR_BOUND, ORIENT_RANGE_HI, ORIENT_RANGE_LO};

/// The sign of the orientation of `d` against the triangle `a b c` (see the module doc): `1`,
/// `-1` or `0`, exactly.
pub(crate) fn orient(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> i8 {
    let (bx, by, bz) = (b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    let (cx, cy, cz) = (c[0] - a[0], c[1] - a[1], c[2] - a[2]);
    let (dx, dy, dz) = (d[0] - a[0], d[1] - a[1], d[2] - a[2]);
    let (cydz, czdy) = (cy * dz, cz * dy);
    let (czdx, cxdz) = (cz * dx, cx * dz);
    let (cxdy, cydx) = (cx * dy, cy * dx);
    let det = bx * (cydz - czdy) + by * (czdx - cxdz) + bz * (cxdy - cydx);
    let perm = bx.abs() * (cydz.abs() + czdy.abs())
        + by.abs() * (czdx.abs() + cxdz.abs())
        + bz.abs() * (cxdy.abs() + cydx.abs());
    let bound = ORIENT_ERR_BOUND * perm;
    // The bound assumes no underflow: below the normal range the exact path decides.
    if det.is_finite() && perm.is_finite() && perm >= f64::MIN_POSITIVE * 1e20 {
        if det > bound {
            return 1;
        }
        if -det > bound {
            return -1;
        }
    }
    if let Some(sign) = orient_expansion(a, b, c, d) {
        return sign;
    }
    orient_exact(a, b, c, d)
}

/// `a + b` with its rounding error: `a + b = s + e` exactly (Knuth's two-sum).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bv = s - a;
    let av = s - bv;
    (s, (a - av) + (b - bv))
}

/// `a b` with its rounding error: `a b = p + e` exactly, when no underflow occurs.
#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// Capacity of [`Expansion`]: the determinant has at most 6 x 8 x 4 = 192 parts.
const EXPANSION_CAP: usize = 192;

/// An exact sum of doubles as a nonoverlapping expansion in increasing magnitude, zero
/// components removed (Shewchuk 1997, GROW-EXPANSION-ZEROELIM), on the stack.
struct Expansion {
    c: [f64; EXPANSION_CAP],
    len: usize,
}

impl Expansion {
    /// Adds `b` exactly.
    #[inline]
    fn add(&mut self, b: f64) {
        if b == 0.0 {
            return;
        }
        let mut q = b;
        let mut k = 0;
        for i in 0..self.len {
            let (s, h) = two_sum(q, self.c[i]);
            q = s;
            if h != 0.0 {
                self.c[k] = h;
                k += 1;
            }
        }
        if q != 0.0 {
            self.c[k] = q;
            k += 1;
        }
        self.len = k;
    }

    /// The sign of the sum: that of its largest component, which dominates the others.
    fn sign(&self) -> i8 {
        match self.len.checked_sub(1).map(|k| self.c[k]) {
            Some(x) if x > 0.0 => 1,
            Some(x) if x < 0.0 => -1,
            _ => 0,
        }
    }
}

/// The exact sign of [`orient`] in floating-point expansions (no allocation): the differences
/// as exact two-term sums, each of the six triple products of the determinant as an exact sum
/// of doubles (`two_prod`), all added into one [`Expansion`]. `None` when a non-zero part of
/// a difference lies outside [`ORIENT_RANGE_LO`] to [`ORIENT_RANGE_HI`] in magnitude (where
/// a product could underflow or overflow): the big-integer path decides then.
fn orient_expansion(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> Option<i8> {
    let ok = |x: f64| x == 0.0 || (x.abs() >= ORIENT_RANGE_LO && x.abs() <= ORIENT_RANGE_HI);
    let diff = |p: &[f64; 3]| -> Option<[[f64; 2]; 3]> {
        let mut out = [[0.0; 2]; 3];
        for k in 0..3 {
            let (hi, lo) = two_sum(p[k], -a[k]);
            if !(ok(hi) && ok(lo)) {
                return None;
            }
            out[k] = [hi, lo];
        }
        Some(out)
    };
    let (u, v, w) = (diff(b)?, diff(c)?, diff(d)?);
    let mut e = Expansion {
        c: [0.0; EXPANSION_CAP],
        len: 0,
    };
    // det = sum of sign * u[i] v[j] w[k] over the permutations (i, j, k) of (0, 1, 2).
    let terms: [(f64, usize, usize, usize); 6] = [
        (1.0, 0, 1, 2),
        (-1.0, 0, 2, 1),
        (1.0, 1, 2, 0),
        (-1.0, 1, 0, 2),
        (1.0, 2, 0, 1),
        (-1.0, 2, 1, 0),
    ];
    for (sg, i, j, k) in terms {
        for &x in &u[i] {
            if x == 0.0 {
                continue;
            }
            for &y in &v[j] {
                if y == 0.0 {
                    continue;
                }
                let (p, q) = two_prod(sg * x, y);
                for &z in &w[k] {
                    if z == 0.0 {
                        continue;
                    }
                    let (r1, r2) = two_prod(p, z);
                    let (r3, r4) = two_prod(q, z);
                    e.add(r1);
                    e.add(r2);
                    e.add(r3);
                    e.add(r4);
                }
            }
        }
    }
    Some(e.sign())
}

/// [`orient`] in big integers (no filter).
pub(crate) fn orient_exact(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> i8 {
    let ints = crate::exact::floats_to_ints([a, b, c, d].into_iter().flatten().copied());
    let p = |k: usize, j: usize| &ints[3 * k + j];
    let diff =
        |k: usize| -> [BigInt; 3] { [p(k, 0) - p(0, 0), p(k, 1) - p(0, 1), p(k, 2) - p(0, 2)] };
    let (u, v, w) = (diff(1), diff(2), diff(3));
    let det = &u[0] * (&v[1] * &w[2] - &v[2] * &w[1])
        + &u[1] * (&v[2] * &w[0] - &v[0] * &w[2])
        + &u[2] * (&v[0] * &w[1] - &v[1] * &w[0]);
    if det.is_positive() {
        1
    } else if det.is_negative() {
        -1
    } else {
        0
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use num_rational::BigRational;
    use proptest::prelude::*;

    /// Independent reference: the determinant in big rationals (also used by the hull tests).
    pub(in crate::polytope::hull3d) fn orient_rational(
        a: &[f64; 3],
        b: &[f64; 3],
        c: &[f64; 3],
        d: &[f64; 3],
    ) -> i8 {
        let r = |x: f64| BigRational::from_float(x).unwrap();
        let diff = |p: &[f64; 3]| [r(p[0]) - r(a[0]), r(p[1]) - r(a[1]), r(p[2]) - r(a[2])];
        let (u, v, w) = (diff(b), diff(c), diff(d));
        let det = &u[0] * (&v[1] * &w[2] - &v[2] * &w[1])
            + &u[1] * (&v[2] * &w[0] - &v[0] * &w[2])
            + &u[2] * (&v[0] * &w[1] - &v[1] * &w[0]);
        if det.is_positive() {
            1
        } else if det.is_negative() {
            -1
        } else {
            0
        }
    }

    #[test]
    fn orient_signs_of_a_unit_tetrahedron() {
        let o = [0.0; 3];
        let (x, y, z) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        assert_eq!(orient(&o, &x, &y, &z), 1);
        assert_eq!(orient(&o, &y, &x, &z), -1);
        assert_eq!(orient(&o, &x, &y, &[0.3, 0.3, 0.0]), 0);
    }

    /// Exactly coplanar points far from the origin: the filter must defer and the exact path
    /// say 0; a one-ulp move of `d` must give a non-zero sign equal to the rational one.
    #[test]
    fn orient_is_exact_on_coplanar_points_far_away() {
        let a = [1e6 + 0.125, 3e5, -7e5];
        let b = [a[0] + 1.0, a[1] + 2.0, a[2] + 0.5];
        let c = [a[0] - 3.0, a[1] + 0.25, a[2] + 1.0];
        // d = a + 2 (b - a) - 3 (c - a): dyadic, exactly representable, coplanar.
        let d = [a[0] + 2.0 + 9.0, a[1] + 4.0 - 0.75, a[2] + 1.0 - 3.0];
        assert_eq!(orient(&a, &b, &c, &d), 0);
        let d_up = [d[0], d[1], f64::from_bits(d[2].to_bits() + 1)];
        let s = orient(&a, &b, &c, &d_up);
        assert_ne!(s, 0);
        assert_eq!(s, orient_rational(&a, &b, &c, &d_up));
    }

    /// Exactly degenerate quadruples on a grid of quarter units (coplanar, collinear, repeated
    /// points): the floating-point exact path and the rational determinant agree.
    #[test]
    fn orient_on_a_grid_matches_rationals() {
        let g = |k: i32| {
            [
                (k % 3) as f64 * 0.25 - 0.25,
                (k / 3 % 3) as f64 * 0.5,
                (k / 9) as f64 - 1.0,
            ]
        };
        for i in 0..27 {
            for j in (0..27).step_by(2) {
                for k in (1..27).step_by(3) {
                    for l in (0..27).step_by(5) {
                        let (a, b, c, d) = (g(i), g(j), g(k), g(l));
                        assert_eq!(orient(&a, &b, &c, &d), orient_rational(&a, &b, &c, &d));
                        if let Some(s) = orient_expansion(&a, &b, &c, &d) {
                            assert_eq!(s, orient_rational(&a, &b, &c, &d));
                        }
                    }
                }
            }
        }
    }

    /// Coordinates so small or large that products underflow or overflow: the big-integer
    /// path decides, and agrees with the rationals.
    #[test]
    fn orient_at_extreme_scales_matches_rationals() {
        for scale in [1e-200, 1e-120, 1e120, 1e200] {
            let g = |k: i32| {
                [
                    (k % 3) as f64 * scale,
                    (k / 3 % 3) as f64 * scale,
                    ((k / 9) as f64 - 0.5) * scale,
                ]
            };
            for (i, j, k, l) in [(0, 1, 3, 9), (0, 1, 2, 5), (4, 13, 22, 8), (1, 5, 9, 26)] {
                let (a, b, c, d) = (g(i), g(j), g(k), g(l));
                assert_eq!(
                    orient(&a, &b, &c, &d),
                    orient_rational(&a, &b, &c, &d),
                    "scale {scale}"
                );
            }
        }
    }

    fn coord() -> impl Strategy<Value = f64> {
        prop_oneof![
            -1e3f64..1e3,
            -1.0f64..1.0,
            (-1e-6f64..1e-6).prop_map(|x| 1e4 + x)
        ]
    }
    fn point() -> impl Strategy<Value = [f64; 3]> {
        [coord(), coord(), coord()]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        /// Random and nearly coplanar quadruples (the fourth point an affine combination of the
        /// first three, rounded): the filtered predicate equals the rational determinant.
        #[test]
        fn orient_matches_rationals(a in point(), b in point(), c in point(), d in point(),
                                     s in -2.0f64..2.0, t in -2.0f64..2.0, near in any::<bool>()) {
            let d = if near {
                [0, 1, 2].map(|k| a[k] + s * (b[k] - a[k]) + t * (c[k] - a[k]))
            } else {
                d
            };
            prop_assert_eq!(orient(&a, &b, &c, &d), orient_rational(&a, &b, &c, &d));
            prop_assert_eq!(orient(&a, &b, &c, &d), -orient(&b, &a, &c, &d));
            let s = orient_expansion(&a, &b, &c, &d);
            prop_assert_eq!(s, Some(orient_rational(&a, &b, &c, &d)));
            prop_assert_eq!(orient_exact(&a, &b, &c, &d), orient_rational(&a, &b, &c, &d));
        }
    }
}
