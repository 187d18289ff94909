//! Invariance as a contract: a cone does not change when one of its generators, facet rows or
//! equation rows is multiplied by a positive number, so neither may the answer.
//!
//! - factors `2^k` (any `k` that keeps the row finite and its entries from underflowing): the
//!   answer is **bit for bit** the same (every row is scaled to its largest entry in
//!   `[0.5, 1)` by a power of two before any decision);
//! - any positive factor from `1e-200` to `1e200`: the same cone up to the rounding of the
//!   scaled row (same extreme generators, equations, lineality; facets within `1e-9` rad);
//! - the inputs of the robustness sweep that used to give certified wrong answers
//!   (relative scales `1e-10` and below).

mod common;

use common::*;
use polycone::nalgebra::DMatrix;
use polycone::{
    certify_span_to_face, face_to_span, span_to_face, Arithmetic, Continuation, DdOptions, FaceForm,
};
use proptest::prelude::*;

/// Random generators (`n x d`, possibly in a subspace and with a line), as in `properties.rs`.
fn cone_strategy() -> impl Strategy<Value = DMatrix<f64>> {
    (
        2usize..=6,
        1usize..=12,
        0usize..=2,
        any::<bool>(),
        any::<u64>(),
    )
        .prop_map(|(d, n, drop, line, seed)| {
            let mut next = xorshift(seed);
            let k = d.saturating_sub(drop).max(1);
            let basis = DMatrix::from_fn(k, d, |_, _| next());
            let mut v = DMatrix::from_fn(n, k, |_, _| next()) * &basis;
            if line {
                let l = DMatrix::from_fn(1, k, |_, _| next()) * &basis;
                v = v.resize_vertically(n + 2, 0.0);
                v.row_mut(n).copy_from(&l.row(0));
                v.row_mut(n + 1).copy_from(&(-l.row(0)));
            }
            v
        })
}

fn xorshift(seed: u64) -> impl FnMut() -> f64 {
    let mut rng = seed | 1;
    move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// Row `i` of `v` multiplied by `factor(i)`.
fn scale_rows(v: &DMatrix<f64>, factor: impl Fn(usize) -> f64) -> DMatrix<f64> {
    DMatrix::from_fn(v.nrows(), v.ncols(), |i, j| v[(i, j)] * factor(i))
}

/// Per-row exponents in `[-lo, hi]` drawn from `seed`.
fn exponents(n: usize, seed: u64, range: i32) -> Vec<i32> {
    let mut next = xorshift(seed);
    (0..n)
        .map(|_| (next() * range as f64).round() as i32)
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, .. ProptestConfig::default() })]

    /// Powers of two from 2^-900 to 2^900 per generator: the same answer, bit for bit.
    #[test]
    fn generator_scaling_by_powers_of_two_changes_nothing(v in cone_strategy(), seed in any::<u64>()) {
        let opts = DdOptions::default();
        let e = exponents(v.nrows(), seed, 900);
        let scaled = scale_rows(&v, |i| 2f64.powi(e[i]));
        let r = span_to_face(&v, &opts).unwrap();
        let r2 = span_to_face(&scaled, &opts).unwrap();
        prop_assert_eq!(&r, &r2);
        // The certificate of the answer does not depend on the scales either.
        let c = certify_span_to_face(&scaled, &r.face, &r.lineality, &opts).unwrap();
        prop_assert!(c.certified);
    }

    /// Powers of two per facet and equation row: face -> span gives the same answer, bit for
    /// bit.
    #[test]
    fn facet_scaling_by_powers_of_two_changes_nothing(v in cone_strategy(), seed in any::<u64>()) {
        let opts = DdOptions::default();
        let face = span_to_face(&v, &opts).unwrap().face;
        let ef = exponents(face.facets.nrows(), seed, 900);
        let ee = exponents(face.equations.nrows(), seed ^ 0x5555, 900);
        let scaled = FaceForm::new(
            scale_rows(&face.facets, |i| 2f64.powi(ef[i])),
            scale_rows(&face.equations, |i| 2f64.powi(ee[i])),
        ).unwrap();
        let s = face_to_span(&face, &opts).unwrap();
        let s2 = face_to_span(&scaled, &opts).unwrap();
        prop_assert_eq!(s, s2);
    }

    /// Any positive factor from 1e-200 to 1e200 per generator: the same cone (the scaled row
    /// is rounded, so facets agree to rounding, not bit for bit).
    #[test]
    fn generator_scaling_by_any_factor_keeps_the_cone(v in cone_strategy(), seed in any::<u64>()) {
        let opts = DdOptions::default();
        let mut next = xorshift(seed);
        let f: Vec<f64> = (0..v.nrows()).map(|_| 10f64.powf(200.0 * next()) * (1.5 + next())).collect();
        let r = span_to_face(&v, &opts).unwrap();
        let r2 = span_to_face(&scale_rows(&v, |i| f[i]), &opts).unwrap();
        prop_assert!(r2.certificate.certified);
        prop_assert_eq!(&r.extreme_generators, &r2.extreme_generators);
        prop_assert_eq!(r.lineality.nrows(), r2.lineality.nrows());
        prop_assert!(same_span(&r.face.equations, &r2.face.equations, 1e-9));
        prop_assert!(
            same_rows_up_to_scaling(&r.face.facets, &r2.face.facets, 1e-9).is_some(),
            "{} facets against {}", r.face.facets.nrows(), r2.face.facets.nrows()
        );
    }

    /// A continuation fed the generators at other scales (powers of two), in two batches,
    /// gives the answer of the unscaled continuation, bit for bit.
    #[test]
    fn continuation_is_scale_invariant(v in cone_strategy(), seed in any::<u64>()) {
        prop_assume!(v.nrows() >= 2);
        let opts = DdOptions::default();
        let e = exponents(v.nrows(), seed, 600);
        let scaled = scale_rows(&v, |i| 2f64.powi(e[i]));
        let k = v.nrows() / 2;
        let run = |m: &DMatrix<f64>| {
            let mut c = Continuation::new(&m.rows(0, k).into_owned(), &opts).unwrap();
            c.add_generators(&m.rows(k, m.nrows() - k).into_owned()).unwrap().clone()
        };
        prop_assert_eq!(run(&v), run(&scaled));
    }
}

/// The positive orthant with one generator at relative scale 1e-11 to 1e-300: still the
/// orthant (it was two facets and the equation x = 0, certified).
#[test]
fn a_tiny_generator_is_a_generator() {
    for s in [1e-10, 1e-11, 1e-20, 1e-100, 1e-300, 5e-324] {
        let v = DMatrix::from_row_slice(3, 3, &[s, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
        for arithmetic in [Arithmetic::Tolerance, Arithmetic::Exact] {
            let opts = DdOptions {
                arithmetic,
                ..DdOptions::default()
            };
            let r = span_to_face(&v, &opts).unwrap();
            assert_eq!(r.face.facets.nrows(), 3, "{s:e} {arithmetic:?}: {r:?}");
            assert_eq!(r.face.equations.nrows(), 0, "{s:e} {arithmetic:?}");
            assert_eq!(r.extreme_generators, vec![0, 1, 2]);
            let expected = -DMatrix::<f64>::identity(3, 3);
            assert!(same_rows_up_to_scaling(&r.face.facets, &expected, 1e-15).is_some());
        }
    }
}

/// `{x : 1e-11 x <= 0, -y <= 0}` is `x <= 0, y >= 0` (it lost `x <= 0`): generators `-e_x`
/// and `e_y`, lineality `e_z`.
#[test]
fn a_tiny_facet_row_is_a_facet() {
    for s in [1e-11, 1e-100, 1e-300] {
        let face = FaceForm::new(
            DMatrix::from_row_slice(2, 3, &[s, 0.0, 0.0, 0.0, -1.0, 0.0]),
            DMatrix::zeros(0, 3),
        )
        .unwrap();
        let r = face_to_span(&face, &DdOptions::default()).unwrap();
        let expected = DMatrix::from_row_slice(2, 3, &[-1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
        assert!(
            same_rows_up_to_scaling(&r.span.generators, &expected, 1e-15).is_some(),
            "{s:e}: {r:?}"
        );
        assert_eq!(r.span.lineality.nrows(), 1);
        assert_eq!(r.irredundant_facets, vec![0, 1]);
    }
}

/// Exact mode with entries down to the subnormals in mixed rows: unit facet rows (they were
/// all zero: the integer facets' norm overflowed when converted back to `f64`).
#[test]
fn exact_answers_with_tiny_entries_are_unit_rows() {
    for e in [1e-100, 1e-200, 1e-310] {
        let v =
            DMatrix::from_row_slice(4, 3, &[e, 2e-100, 0.0, 0.0, e, 1.0, 3.0, 0.0, e, e, e, -e]);
        let opts = DdOptions {
            arithmetic: Arithmetic::Exact,
            ..DdOptions::default()
        };
        let r = span_to_face(&v, &opts).unwrap();
        let float = span_to_face(&v, &DdOptions::default()).unwrap();
        assert_eq!(r.face.facets.nrows(), 4, "{e:e}");
        for i in 0..r.face.facets.nrows() {
            assert!(
                (r.face.facets.row(i).norm() - 1.0).abs() < 1e-15,
                "{e:e}: {r:?}"
            );
        }
        assert!(same_rows_up_to_scaling(&r.face.facets, &float.face.facets, 1e-12).is_some());
    }
}

/// Half-spaces of a random convex polytope about `centre`: `n . (p - centre) <= r` for random
/// unit `n` and `r` in [0.1, 1).
fn random_halfspaces<const D: usize>(seed: u64, rows: usize) -> (Vec<[f64; D]>, Vec<f64>) {
    let mut next = xorshift(seed);
    let mut normals = Vec::new();
    let mut offsets = Vec::new();
    for _ in 0..rows {
        let mut a = [0.0; D];
        for x in &mut a {
            *x = 2.0 * next() - 1.0;
        }
        let n = a.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-3);
        for x in &mut a {
            *x /= n;
        }
        normals.push(a);
        offsets.push(0.1 + 0.9 * next());
    }
    (normals, offsets)
}

fn moved<const D: usize>(normals: &[[f64; D]], offsets: &[f64], t: &[f64; D]) -> Vec<f64> {
    normals
        .iter()
        .zip(offsets)
        .map(|(a, &b)| b + (0..D).map(|k| a[k] * t[k]).sum::<f64>())
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Moving a region by `t` (1 m to 1e12 m) moves its polygon or polyhedron by `t`: same
    /// status and, bounded, the same vertices moved, within the rounding of the coordinates.
    /// (Beyond the 1e6 m starting box, the regions were called empty.) Unbounded regions are
    /// cut by that box about a point near them, so only their status is compared.
    #[test]
    fn polytopes_move_with_their_rows(
        seed in 1u64..u64::MAX,
        exponent in 0i32..=12,
        dir in prop::collection::vec(-1.0..1.0f64, 3),
        rows in 4usize..24,
    ) {
        use polycone::polytope::{polygon_from_halfplanes, polyhedron_from_halfspaces, PolytopeOptions};
        let opts = PolytopeOptions::default();
        let scale = 10f64.powi(exponent);
        // The moved rows are rounded to eps |t| (absolute); a vertex moves by that over the
        // sine of the angles between its planes (random rows: down to about 1e-2), in every
        // coordinate.
        let size = scale * dir.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let tol = |_t: f64| 1e-9 + 1e4 * f64::EPSILON * size;
        // 2-D
        let (n2, b2) = random_halfspaces::<2>(seed, rows);
        let t2 = [dir[0] * scale, dir[1] * scale];
        let here = polygon_from_halfplanes(&n2, &b2, &opts).unwrap();
        let there = polygon_from_halfplanes(&n2, &moved(&n2, &b2, &t2), &opts).unwrap();
        prop_assert_eq!(here.status, there.status);
        let bounded = here.status == polycone::polytope::RegionStatus::Bounded;
        prop_assert!(!bounded || here.vertices.len() == there.vertices.len());
        for (p, q) in here.vertices.iter().zip(&there.vertices).filter(|_| bounded) {
            for k in 0..2 {
                prop_assert!((p[k] + t2[k] - q[k]).abs() <= tol(t2[k]), "{p:?} + {t2:?} vs {q:?}");
            }
        }
        // 3-D
        let (n3, b3) = random_halfspaces::<3>(seed ^ 0x5555, rows);
        let t3 = [dir[0] * scale, dir[1] * scale, dir[2] * scale];
        let here = polyhedron_from_halfspaces(&n3, &b3, &opts).unwrap();
        let there = polyhedron_from_halfspaces(&n3, &moved(&n3, &b3, &t3), &opts).unwrap();
        prop_assert_eq!(here.status, there.status);
        if here.status != polycone::polytope::RegionStatus::Bounded {
            return Ok(());
        }
        prop_assert_eq!(here.vertices.len(), there.vertices.len());
        prop_assert_eq!(here.faces.len(), there.faces.len());
        let mut a: Vec<[f64; 3]> = here.vertices.iter().map(|p| [p[0] + t3[0], p[1] + t3[1], p[2] + t3[2]]).collect();
        let mut b = there.vertices.clone();
        a.sort_by(|p, q| p.partial_cmp(q).unwrap());
        b.sort_by(|p, q| p.partial_cmp(q).unwrap());
        for (p, q) in a.iter().zip(&b) {
            for k in 0..3 {
                prop_assert!((p[k] - q[k]).abs() <= tol(t3[k]), "{p:?} vs {q:?}");
            }
        }
    }
}

/// The generators of a stance as a user's program computes them (rounded), and the same
/// stance's generators scaled to integers (exact: the intended geometry), from
/// [`rational_stance`].
type Stance = (DMatrix<f64>, DMatrix<f64>);

/// A contact of a stance with rational geometry: centre `c` and half-sizes `h` in integer
/// multiples of the stance's length unit, contact frame `r / den` (integer entries: a rotation,
/// or a rotation times `sqrt(1 + s^2)` for a frame `I + s J`, which rotates the friction
/// pyramid alike), friction pyramid of apothem 0.7.
struct RationalContact {
    c: [i64; 3],
    h: [i64; 2],
    r: [[i64; 3]; 3],
    den: i64,
}

const IDENTITY: [[i64; 3]; 3] = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];

fn flat(c: [i64; 3], h: [i64; 2]) -> RationalContact {
    RationalContact {
        c,
        h,
        r: IDENTITY,
        den: 1,
    }
}

/// The contact wrench generators `(e, p x e)` of a stance (corners `p`, pyramid edges `e`):
/// `.0` in metres and newtons, computed in floating point as a user's program does (so rounded);
/// `.1` the same generators with every entry an integer below `2^53`: the row of a contact with
/// frame denominator `D` is `(D f, p' x f)` with `f = r (+-7, +-7, 10)` and `p' = D c + r h`,
/// that is `10 D^2 (e, p x e / unit)`, a positive row scaling and a change of the torque unit,
/// which keep the number of facets. So the exact conversion of `.1` is the cone of the
/// *intended* geometry (no rounding).
fn rational_stance(contacts: &[RationalContact], unit: f64) -> Stance {
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let cross_i = |a: [i128; 3], b: [i128; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let exact = |x: i128| {
        assert!(x.unsigned_abs() < 1 << 53, "{x} is not exact in f64");
        x as f64
    };
    let (mut float, mut int) = (Vec::new(), Vec::new());
    for k in contacts {
        let frame = k.r.map(|row| row.map(|x| x as f64 / k.den as f64));
        let apply = |v: [f64; 3]| frame.map(|row| row[0] * v[0] + row[1] * v[1] + row[2] * v[2]);
        let apply_i = |v: [i128; 3]| {
            k.r.map(|row| row[0] as i128 * v[0] + row[1] as i128 * v[1] + row[2] as i128 * v[2])
        };
        for (sx, sy) in [(1, 1), (-1, 1), (-1, -1), (1, -1)] {
            let corner = [
                (sx * k.h[0]) as f64 * unit,
                (sy * k.h[1]) as f64 * unit,
                0.0,
            ];
            let offset = apply(corner);
            let p: [f64; 3] = std::array::from_fn(|a| k.c[a] as f64 * unit + offset[a]);
            let corner_i = [(sx * k.h[0]) as i128, (sy * k.h[1]) as i128, 0];
            let offset_i = apply_i(corner_i);
            let p_i: [i128; 3] =
                std::array::from_fn(|a| k.den as i128 * k.c[a] as i128 + offset_i[a]);
            for (a, b) in [(1, 1), (-1, 1), (-1, -1), (1, -1)] {
                let e = apply([0.7 * a as f64, 0.7 * b as f64, 1.0]);
                float.extend(e);
                float.extend(cross(p, e));
                let f_i = apply_i([7 * a as i128, 7 * b as i128, 10]);
                int.extend(f_i.map(|x| exact(k.den as i128 * x)));
                int.extend(cross_i(p_i, f_i).map(exact));
            }
        }
    }
    (
        DMatrix::from_row_slice(float.len() / 6, 6, &float),
        DMatrix::from_row_slice(int.len() / 6, 6, &int),
    )
}

/// Two flat rectangular feet (0.22 x 0.13 m, 0.2 m apart) with the right one raised by `dz`
/// (a multiple of 1 nm): [`rational_stance`] in nanometres.
fn two_feet(dz: f64) -> Stance {
    let h = [110_000_000, 65_000_000];
    let feet = [
        flat([0, 100_000_000, 0], h),
        flat([0, -100_000_000, (dz * 1e9).round() as i64], h),
    ];
    rational_stance(&feet, 1e-9)
}

/// The contact wrench generators of [`two_feet`], rounded as a user's program computes them.
fn two_feet_wrench_span(dz: f64) -> DMatrix<f64> {
    two_feet(dz).0
}

/// The stairs stance of the paper's stair climbing (left foot at `(0, 0.1, 0)`, right foot at
/// `(0.28, -0.1, 0.24)` turned by 10.0004 degrees about z, `cos = 6351 / 6449`), with square
/// contact patches of half-size `half` (a multiple of 0.1 um): [`rational_stance`] in 0.1 um.
fn stairs_with_patches(half: f64) -> Stance {
    let h = (half * 1e7).round() as i64;
    let turned = RationalContact {
        c: [2_800_000, -1_000_000, 2_400_000],
        h: [h, h],
        r: [[6351, -1120, 0], [1120, 6351, 0], [0, 0, 6449]],
        den: 6449,
    };
    rational_stance(&[flat([0, 1_000_000, 0], [h, h]), turned], 1e-7)
}

/// Three flat feet (0.22 x 0.13 m), the third rolled about x by `atan(1 / 5730)` = 0.0099995
/// degrees (frame `I + J / 5730`): [`rational_stance`] in millimetres.
fn three_contacts_rolled() -> Stance {
    let h = [110, 65];
    let rolled = RationalContact {
        c: [300, 0, 0],
        h,
        r: [[5730, 0, 0], [0, 5730, -1], [0, 1, 5730]],
        den: 5730,
    };
    rational_stance(
        &[flat([0, 100, 0], h), flat([50, -100, 0], h), rolled],
        1e-3,
    )
}

/// A continuation whose conversion falls back to exact arithmetic merges the fallback's slivers
/// as a conversion from scratch does: the same rows, the same certificate of the merge.
#[test]
fn a_continuation_merges_the_slivers_of_its_exact_fallback() {
    for dz in [1e-5, 1e-7, 1e-9] {
        let v = two_feet_wrench_span(dz);
        let scratch = span_to_face(&v, &DdOptions::default()).unwrap();
        let c = polycone::Continuation::new(&v, &DdOptions::default()).unwrap();
        let r = c.result();
        assert_eq!(
            r.certificate.fallback.is_some(),
            scratch.certificate.fallback.is_some(),
            "{dz}"
        );
        assert_eq!(
            r.certificate.merged_rows, scratch.certificate.merged_rows,
            "{dz}"
        );
        assert_eq!(r.face.facets, scratch.face.facets, "{dz}");
    }
}

/// After an exact fallback the default mode merges the slivers of the rounded input. Checks,
/// on the stance `stance` ([`rational_stance`]), with exact arithmetic on the output: the
/// answer is certified; when it came from an exact fallback, it keeps at most as many rows as
/// the exact cone of the intended (unrounded) geometry, no two rows within the tolerance, every
/// generator inside (the merged cone contains the exact one), and every extreme ray of the
/// merged cone (exact face -> span) violates the exact facets by at most the certificate's
/// merge distance, itself within the tolerance. Returns the intended geometry's facets, the
/// exact answer's and the default answer's, or `None` when there was no fallback.
fn check_merge(name: &str, stance: &Stance) -> Option<[usize; 3]> {
    let wrench = DdOptions {
        wrench: true,
        ..DdOptions::default()
    };
    check_merge_with(&format!("{name} (wrench)"), stance, &wrench);
    check_merge_with(name, stance, &DdOptions::default())
}

/// [`check_merge`] with the options `opts`: the bound is checked in the input's coordinates
/// whatever the route (the wrench preconditioning maps its answer back before merging).
fn check_merge_with(name: &str, stance: &Stance, opts: &DdOptions) -> Option<[usize; 3]> {
    let exact_opts = DdOptions {
        arithmetic: Arithmetic::Exact,
        ..DdOptions::default()
    };
    let delta = opts.tol.certificate;
    let (v, v_intended) = stance;
    let intended = span_to_face(v_intended, &exact_opts)
        .unwrap()
        .face
        .facets
        .nrows();
    let merged = span_to_face(v, opts).unwrap();
    let c = &merged.certificate;
    assert!(c.certified, "{name}");
    let m = merged.face.facets.nrows();
    let exact = span_to_face(v, &exact_opts).unwrap();
    let n = exact.face.facets.nrows();
    let fell_back = c.fallback.is_some();
    eprintln!(
        "{name}: intended geometry {intended} facets, rounded input {n}, default {m} ({})",
        if fell_back {
            format!(
                "exact fallback, {} merged within {:.1e}",
                c.merged_rows, c.merge_distance
            )
        } else {
            "certified in floating point".to_string()
        }
    );
    assert!(
        m <= intended,
        "{name}: {m} rows, the intended geometry has {intended}"
    );
    // The contract's bound: the proven merge distance after a fallback (whose rows are exact
    // facets, so every generator satisfies them up to their rounding), the tolerance
    // otherwise.
    let (bound, inside) = if fell_back {
        if !opts.wrench {
            // (The wrench route's exact answer is that of the re-centred input, mapped back.)
            assert_eq!(m + c.merged_rows, n, "{name}");
        }
        assert!(c.merged_rows > 0 && c.merge_distance <= delta, "{name}");
        (c.merge_distance, 1e-12)
    } else {
        (delta, delta)
    };
    let unit = |r: nalgebra::DMatrixView<f64>| r.clone_owned() / r.norm();
    let f = &merged.face.facets;
    // On the wrench route, rows are compared in its frame too (`(u_f - o x u_t, L u_t)`):
    // a row is dropped only when both distances are within the tolerance.
    let in_frame = c.wrench_frame.map(|w| {
        let o = nalgebra::Vector3::from(w.center);
        DMatrix::from_fn(m, 6, |i, j| {
            let uf = nalgebra::Vector3::new(f[(i, 0)], f[(i, 1)], f[(i, 2)]);
            let ut = nalgebra::Vector3::new(f[(i, 3)], f[(i, 4)], f[(i, 5)]);
            if j < 3 {
                (uf - o.cross(&ut))[j]
            } else {
                w.length * ut[j - 3]
            }
        })
    });
    assert_eq!(in_frame.is_some(), opts.wrench, "{name}");
    for i in 0..m {
        for k in 0..i {
            let d = (unit(f.rows(i, 1)) - unit(f.rows(k, 1))).norm();
            let d_frame = in_frame
                .as_ref()
                .map_or(d, |g| (unit(g.rows(i, 1)) - unit(g.rows(k, 1))).norm());
            // A row is dropped when its distance plus its rounding bound (a few eps) is
            // within the tolerance.
            assert!(
                d > delta - 1e-14 || d_frame > delta - 1e-14,
                "{name}: rows {i} and {k} are {d:.1e} apart ({d_frame:.1e} in the frame)"
            );
        }
    }
    // The answer contains every generator.
    for g in v.row_iter() {
        for u in f.row_iter() {
            assert!(u.dot(&g) <= inside * g.norm() * u.norm(), "{name}");
        }
    }
    // Every extreme ray of the answer is within the bound of the exact cone.
    let rays = face_to_span(&merged.face, &exact_opts)
        .unwrap()
        .span
        .generators;
    for r in rays.row_iter() {
        let r = r.clone_owned() / r.norm();
        for u in exact.face.facets.row_iter() {
            let u = u.clone_owned() / u.norm();
            assert!(
                u.dot(&r) <= bound * (1.0 + 1e-9) + 1e-15,
                "{name}: violation {:.2e} > {bound:.2e}",
                u.dot(&r),
            );
        }
    }
    fell_back.then_some([intended, n, m])
}

/// Two flat feet, one raised by 1e-9 to 1e-5 m: the merge keeps at most the intended geometry's
/// rows, and feet 1e-9 m apart (coplanar within the tolerance) get the coplanar 16.
#[test]
fn slivers_of_raised_feet_are_merged_within_the_stated_bound() {
    let exact_opts = DdOptions {
        arithmetic: Arithmetic::Exact,
        ..DdOptions::default()
    };
    // The coplanar feet: 16 facets intended, 40 for the rounded input, 16 by default.
    let flat = span_to_face(&two_feet(0.0).1, &exact_opts).unwrap();
    assert_eq!(flat.face.facets.nrows(), 16);
    let flat_default = span_to_face(&two_feet(0.0).0, &DdOptions::default()).unwrap();
    assert_eq!(flat_default.face.facets.nrows(), 16);
    let mut fell_back = 0;
    for dz in [1e-5, 1e-7, 1e-8, 1e-9] {
        if let Some([_, _, m]) = check_merge(&format!("dz = {dz}"), &two_feet(dz)) {
            fell_back += 1;
            if dz <= 1e-9 {
                assert_eq!(m, 16, "{dz}");
            }
        }
    }
    assert!(
        fell_back >= 3,
        "the raised feet no longer exercise the fallback"
    );
}

/// The stairs stance with contact patches of 10 to 100 um (the issue had 314 rows for 168), and
/// three contacts, one rolled by 0.01 degree (222 rows for 218 before this merge).
#[test]
fn slivers_of_tiny_patches_and_small_rolls_are_merged_within_the_stated_bound() {
    let mut fell_back = 0;
    for half in [5e-6, 1e-5, 2.5e-5, 5e-5] {
        let name = format!("stairs, patches of half-size {half} m");
        fell_back += check_merge(&name, &stairs_with_patches(half)).is_some() as usize;
    }
    fell_back +=
        check_merge("three contacts, one rolled", &three_contacts_rolled()).is_some() as usize;
    assert!(
        fell_back >= 4,
        "the stances no longer exercise the fallback"
    );
}

/// The stress corpus of `tests/stress.rs` (issue 2) written with rational geometry, so that the
/// intended geometry's facets are known exactly: both routes' default answers, from a
/// floating-point certificate or an exact fallback, keep at most those facets, no two rows
/// within the tolerance, every generator inside and every ray within the bound of the exact
/// cone of the input ([`check_merge`]). Rolls are `atan(1 / 57)`, `atan(1 / 573)` and
/// `atan(1 / 5730)` (1.005, 0.09999 and 0.0099995 degrees).
#[test]
fn the_stress_corpus_keeps_the_intended_geometry() {
    let mm = [110, 65];
    let roll = |d: i64| [[d, 0, 0], [0, d, -1], [0, 1, d]];
    let rolled = |c: [i64; 3], d: i64| RationalContact {
        c,
        h: mm,
        r: roll(d),
        den: d,
    };
    let mut corpus: Vec<(String, Stance)> = Vec::new();
    for (name, o) in [
        ("here", [0, 0, 0]),
        ("50 m away", [50_000, 0, 0]),
        ("1 km away", [1_000_000, -700_000, 30_000]),
    ] {
        let feet = [
            flat([o[0], o[1] + 100, o[2]], mm),
            flat([o[0] + 50, o[1] - 100, o[2]], mm),
        ];
        corpus.push((
            format!("double support {name}"),
            rational_stance(&feet, 1e-3),
        ));
    }
    for (name, h) in [("1 mm", 5_000), ("10 um", 50)] {
        let feet = [
            flat([0, 1_000_000, 0], [h, h]),
            flat([500_000, -1_000_000, 0], [h, h]),
        ];
        corpus.push((format!("patches of {name}"), rational_stance(&feet, 1e-7)));
    }
    for dz in [10_000, 1_000, 100, 10, 1] {
        let h = [110_000_000, 65_000_000];
        let feet = [
            flat([0, 100_000_000, 0], h),
            flat([50_000_000, -100_000_000, dz], h),
        ];
        corpus.push((format!("feet {dz} nm apart"), rational_stance(&feet, 1e-9)));
    }
    for d in [57, 573, 5730] {
        let two = [flat([0, 100, 0], mm), rolled([50, -100, 0], d)];
        corpus.push((
            format!("double support rolled 1/{d}"),
            rational_stance(&two, 1e-3),
        ));
        let three = [
            flat([0, 100, 0], mm),
            flat([50, -100, 0], mm),
            rolled([300, 0, 0], d),
        ];
        corpus.push((
            format!("three contacts rolled 1/{d}"),
            rational_stance(&three, 1e-3),
        ));
    }
    let fell_back = corpus
        .iter()
        .filter(|(name, stance)| check_merge(name, stance).is_some())
        .count();
    eprintln!(
        "{fell_back} of {} fell back to exact arithmetic",
        corpus.len()
    );
}
