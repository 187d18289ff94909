//! The edge cases of docs/math.md section 1: zero cone, whole space, half-space, lower-dimensional,
//! non-pointed cones; dimensions 1 to 12; errors on bad input.

mod common;

use common::*;
use polycone::nalgebra::DMatrix;
use polycone::{face_to_span, span_to_face, ConeError, DdOptions, FaceForm};

fn opts() -> DdOptions {
    DdOptions::default()
}

#[test]
fn zero_cone_has_identity_equations() {
    for d in 1..=6 {
        let r = span_to_face(&DMatrix::zeros(0, d), &opts()).unwrap();
        assert_eq!(r.face.facets.nrows(), 0);
        assert_eq!(r.face.equations.nrows(), d);
        assert!(same_span(
            &r.face.equations,
            &DMatrix::identity(d, d),
            1e-12
        ));
        assert_eq!(r.lineality.nrows(), 0);
        assert!(r.extreme_generators.is_empty());
        assert!(r.certificate.certified);
        // Only zero generators: the same cone.
        let r = span_to_face(&DMatrix::zeros(3, d), &opts()).unwrap();
        assert_eq!(r.face.equations.nrows(), d);
    }
}

#[test]
fn whole_space_has_full_lineality() {
    for d in 1..=8 {
        let mut v = DMatrix::zeros(2 * d, d);
        for i in 0..d {
            v[(2 * i, i)] = 1.0;
            v[(2 * i + 1, i)] = -1.0;
        }
        let r = span_to_face(&v, &opts()).unwrap();
        assert_eq!(r.face.facets.nrows(), 0, "d = {d}");
        assert_eq!(r.face.equations.nrows(), 0);
        assert_eq!(r.lineality.nrows(), d);
        assert!(r.extreme_generators.is_empty());
        assert!(r.certificate.certified);
        // And back: no facet, no equation -> lineality = everything.
        let f = FaceForm::new(DMatrix::zeros(0, d), DMatrix::zeros(0, d)).unwrap();
        let s = face_to_span(&f, &opts()).unwrap();
        assert_eq!(s.span.generators.nrows(), 0);
        assert_eq!(s.span.lineality.nrows(), d);
    }
}

#[test]
fn half_space_and_simplex_corner_in_every_dimension_to_12() {
    for d in 1..=12 {
        // Orthant: d facets, d extreme rays.
        let r = span_to_face(&DMatrix::identity(d, d), &opts()).unwrap();
        assert_eq!(r.face.facets.nrows(), d);
        assert_eq!(r.extreme_generators, (0..d).collect::<Vec<_>>());
        assert!(r.certificate.certified);
        // Half-space x_0 >= 0: e_0 and +-e_i.
        let mut v = DMatrix::zeros(2 * d - 1, d);
        v[(0, 0)] = 1.0;
        for i in 1..d {
            v[(2 * i - 1, i)] = 1.0;
            v[(2 * i, i)] = -1.0;
        }
        let r = span_to_face(&v, &opts()).unwrap();
        assert_eq!(r.face.facets.nrows(), 1, "d = {d}");
        assert!((r.face.facets[(0, 0)] + 1.0).abs() < 1e-12);
        assert_eq!(r.lineality.nrows(), d - 1);
        assert_eq!(r.extreme_generators, vec![0]);
        assert!(r.certificate.certified);
    }
}

#[test]
fn lower_dimensional_cone_gets_equations() {
    // Two rays in the plane z = 0 of R^3, seen in a rotated frame.
    let v = DMatrix::from_row_slice(3, 3, &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0]);
    let r = span_to_face(&v, &opts()).unwrap();
    assert_eq!(r.face.equations.nrows(), 1);
    assert!(r.face.equations[(0, 2)].abs() > 1.0 - 1e-12);
    assert_eq!(r.face.facets.nrows(), 2);
    assert_eq!(r.extreme_generators, vec![0, 1]);
    // Facets are orthogonal to the equations.
    for i in 0..2 {
        assert!(r.face.facets[(i, 2)].abs() < 1e-12);
    }
    // A single ray in R^4: 3 equations, one facet.
    let v = DMatrix::from_row_slice(1, 4, &[1.0, 2.0, 3.0, 4.0]);
    let r = span_to_face(&v, &opts()).unwrap();
    assert_eq!(r.face.equations.nrows(), 3);
    assert_eq!(r.face.facets.nrows(), 1);
    assert!(r.certificate.certified);
}

#[test]
fn non_pointed_and_lower_dimensional_together() {
    // A line along x plus the ray +y, in R^4 (z = w = 0).
    let v = DMatrix::from_row_slice(
        3,
        4,
        &[1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
    );
    let r = span_to_face(&v, &opts()).unwrap();
    assert_eq!(r.face.equations.nrows(), 2);
    assert_eq!(r.lineality.nrows(), 1);
    assert_eq!(r.face.facets.nrows(), 1);
    assert!((r.face.facets[(0, 1)] + 1.0).abs() < 1e-12);
    assert_eq!(r.extreme_generators, vec![2]);
    assert!(r.certificate.certified);
    // Face -> span of the result gives the same cone back.
    let s = face_to_span(&r.face, &opts()).unwrap();
    assert_eq!(s.span.lineality.nrows(), 1);
    assert_eq!(s.span.generators.nrows(), 1);
    assert!((s.span.generators[(0, 1)] - 1.0).abs() < 1e-12);
}

#[test]
fn duplicates_and_zero_generators_are_dropped() {
    let v = DMatrix::from_row_slice(5, 2, &[0.0, 0.0, 1.0, 0.0, 2.0, 0.0, 0.0, 3.0, 1.0, 1.0]);
    let r = span_to_face(&v, &opts()).unwrap();
    assert_eq!(r.face.facets.nrows(), 2);
    assert_eq!(r.extreme_generators, vec![1, 3]);
}

#[test]
fn bad_input_is_an_error_with_a_message() {
    let e = span_to_face(&DMatrix::zeros(2, 0), &opts()).unwrap_err();
    assert_eq!(e, ConeError::ZeroDimension);
    let v = DMatrix::from_row_slice(1, 2, &[1.0, f64::NAN]);
    let e = span_to_face(&v, &opts()).unwrap_err();
    assert!(matches!(e, ConeError::NonFinite { row: 0, col: 1, .. }));
    assert!(e.to_string().contains("finite"));
    let v = DMatrix::from_row_slice(1, 2, &[1.0, f64::INFINITY]);
    assert!(span_to_face(&v, &opts()).is_err());
    let mut o = opts();
    o.tol.incidence = -1.0;
    let e = span_to_face(&DMatrix::identity(2, 2), &o).unwrap_err();
    assert!(matches!(
        e,
        ConeError::BadTolerance {
            name: "incidence",
            ..
        }
    ));
    let f = FaceForm {
        dim: 3,
        facets: DMatrix::zeros(1, 2),
        equations: DMatrix::zeros(0, 3),
    };
    assert!(matches!(
        face_to_span(&f, &opts()).unwrap_err(),
        ConeError::DimensionMismatch { .. }
    ));
}

#[test]
fn face_to_span_with_equations_and_redundant_facets() {
    // {x in R^3 : x >= 0, y >= 0, x + y >= 0 (redundant), z = 0}.
    let u = DMatrix::from_row_slice(3, 3, &[-1.0, 0.0, 0.0, 0.0, -1.0, 0.0, -1.0, -1.0, 0.0]);
    let e = DMatrix::from_row_slice(1, 3, &[0.0, 0.0, 1.0]);
    let r = face_to_span(&FaceForm::new(u, e).unwrap(), &opts()).unwrap();
    assert_eq!(r.span.generators.nrows(), 2);
    assert_eq!(r.span.lineality.nrows(), 0);
    assert_eq!(r.irredundant_facets, vec![0, 1]);
    assert!(r.certificate.certified);
    // Implicit equality: x <= 0 and -x <= 0 in R^2 with y free -> the line y.
    let u = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, -1.0, 0.0]);
    let r = face_to_span(&FaceForm::new(u, DMatrix::zeros(0, 2)).unwrap(), &opts()).unwrap();
    assert_eq!(r.span.generators.nrows(), 0);
    assert_eq!(r.span.lineality.nrows(), 1);
    assert!(r.span.lineality[(0, 0)].abs() < 1e-12);
    // Infeasible except 0: x >= 0, y >= 0, x + y <= 0 -> the zero cone.
    let u = DMatrix::from_row_slice(3, 2, &[-1.0, 0.0, 0.0, -1.0, 1.0, 1.0]);
    let r = face_to_span(&FaceForm::new(u, DMatrix::zeros(0, 2)).unwrap(), &opts()).unwrap();
    assert_eq!(r.span.generators.nrows(), 0);
    assert_eq!(r.span.lineality.nrows(), 0);
}

#[test]
fn results_and_workspace_are_send_and_sync() {
    fn check<T: Send + Sync>() {}
    check::<polycone::Workspace>();
    check::<polycone::SpanToFace>();
    check::<polycone::FaceToSpan>();
    check::<polycone::Certificate>();
    check::<ConeError>();
    check::<DdOptions>();
}

#[test]
fn output_order_is_deterministic_and_workspace_reuse_is_stable() {
    let j = load("tilted_foot_hand_ledge");
    let v = matrix_hex(&j["generators"]["float64_hex"], 6);
    let mut ws = polycone::Workspace::new();
    let a = ws.span_to_face(&v, &opts()).unwrap();
    let b = ws.span_to_face(&v, &opts()).unwrap();
    let c = span_to_face(&v, &opts()).unwrap();
    assert_eq!(a, b);
    assert_eq!(a, c);
}

/// Regression: the transposed-incidence adjacency test once kept stale bits past the last ray,
/// so two rays with an empty common zero set (always the case in 2-D) looked blocked and the
/// 2-D double description lost a ray; the certificate caught it (lineality check), this test
/// pins the fix.
#[test]
fn regression_adjacency_mask_past_last_ray_2d() {
    // Generators chosen so that the greedy basis leaves the middle generator for last.
    for v in [
        DMatrix::from_row_slice(3, 2, &[1.0, 0.0, 0.0, 1.0, 1.0, 1.0]),
        DMatrix::from_row_slice(3, 3, &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0]),
        DMatrix::from_row_slice(4, 2, &[1.0, 0.2, 0.3, 1.0, 1.0, 1.0, 0.9, 0.8]),
    ] {
        // The floating-point engine itself, without the exact fallback that would hide the bug.
        let o = DdOptions {
            exact_fallback: false,
            ..opts()
        };
        let r = span_to_face(&v, &o).unwrap();
        assert_eq!(r.certificate.arithmetic, polycone::Arithmetic::Tolerance);
        assert_eq!(r.face.facets.nrows(), 2);
        assert_eq!(r.lineality.nrows(), 0);
        assert!(r.certificate.certified);
    }
}

/// Regression: row norms of generators with entries near 1e300 overflowed to infinity and the
/// generators were dropped as "zero"; huge and tiny inputs now give the same cone.
#[test]
fn regression_huge_and_tiny_generators() {
    let j = load("double_support_stairs");
    let v = matrix_hex(&j["generators"]["float64_hex"], 6);
    let r = span_to_face(&v, &opts()).unwrap();
    for s in [1e300, 1e-300, 1e-310] {
        let vs = &v * s;
        let rs = span_to_face(&vs, &opts()).unwrap();
        assert!(rs.certificate.certified);
        assert!(
            same_rows_up_to_scaling(&r.face.facets, &rs.face.facets, 1e-9).is_some(),
            "scale {s}: {} facets",
            rs.face.facets.nrows()
        );
    }
}

/// More than 64 constraint rows: the zero sets take several words and the double description
/// takes its multi-word path (every test above stays within one word). Known answers: a
/// polygonal cone over `n` points of a circle has `n` facets and `n` extreme generators; the
/// cone over `n` points of the moment curve in `R^3` (cyclic polytope `C(n, 3)`) has
/// `2n - 4` facets. Both directions are checked.
#[test]
fn more_than_64_rows_take_the_multi_word_path() {
    let n = 100;
    let circle = DMatrix::from_fn(n, 3, |i, j| {
        let a = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
        [1.0, a.cos(), a.sin()][j]
    });
    let r = span_to_face(&circle, &opts()).unwrap();
    assert!(r.certificate.certified);
    assert_eq!(r.certificate.arithmetic, polycone::Arithmetic::Tolerance);
    assert_eq!(r.face.facets.nrows(), n);
    assert_eq!(r.extreme_generators, (0..n).collect::<Vec<_>>());
    // Back: 100 facet rows in 3-D give the 100 generators again.
    let back = face_to_span(&r.face, &opts()).unwrap();
    assert!(back.certificate.certified);
    assert_eq!(back.span.generators.nrows(), n);

    let n = 70;
    let cyclic = DMatrix::from_fn(n, 4, |i, j| {
        let t = -1.0 + 2.0 * i as f64 / (n - 1) as f64;
        t.powi(j as i32)
    });
    let r = span_to_face(&cyclic, &opts()).unwrap();
    assert!(r.certificate.certified);
    assert_eq!(r.certificate.arithmetic, polycone::Arithmetic::Tolerance);
    assert_eq!(r.face.facets.nrows(), 2 * n - 4);
    assert_eq!(r.extreme_generators.len(), n);
}
