//! Exact mode: certified combinatorics for the input as given, checked against pycddlib's GMP
//! mode on the same (rounded) inputs, and on the edge cases.

mod common;

use common::*;
use polycone::nalgebra::DMatrix;
use polycone::{span_to_face, Arithmetic, DdOptions};

fn exact() -> DdOptions {
    DdOptions {
        arithmetic: Arithmetic::Exact,
        ..DdOptions::default()
    }
}

/// Facet counts of cddlib in GMP mode on the `float64` inputs (pycddlib 3.0.2,
/// `cdd.gmp.matrix_from_array` of `Fraction(x)`), which differ from the intended geometry's
/// where rounding breaks a degeneracy.
const ROUNDED_INPUT_FACETS: [(&str, usize); 5] = [
    ("single_support_flat", 16),
    ("surface_cwc_foot", 16),
    ("double_support_flat", 32),
    ("opposing_walls_frictionless", 4),
    ("opposing_walls_friction", 0),
];

#[test]
fn exact_mode_matches_cdd_gmp_on_the_rounded_input() {
    for (case, count) in ROUNDED_INPUT_FACETS {
        let j = load(case);
        let v = matrix_hex(&j["generators"]["float64_hex"], 6);
        let r = span_to_face(&v, &exact()).unwrap_or_else(|e| panic!("{case}: {e}"));
        assert!(r.certificate.certified, "{case}");
        assert_eq!(r.certificate.arithmetic, Arithmetic::Exact);
        assert_eq!(r.face.facets.nrows(), count, "{case}");
        let reference = &j["reference_cdd_gmp_exact_input"];
        assert_eq!(
            r.lineality.nrows(),
            reference["lineality_dim"].as_u64().unwrap() as usize
        );
        // Where rounding does not matter, the facets are the reference ones.
        if reference["facets_float64"].as_array().unwrap().len() == count {
            let rf = normalized(&matrix_f64(&reference["facets_float64"], 6));
            assert!(
                same_rows_up_to_scaling(&r.face.facets, &rf, 1e-9).is_some(),
                "{case}"
            );
        }
    }
}

/// The larger cases take seconds in exact mode; run with `cargo test -p polycone --release
/// --test exact -- --ignored`.
#[test]
#[ignore]
fn exact_mode_matches_cdd_gmp_on_large_rounded_inputs() {
    for (case, count) in [
        ("double_support_stairs", 282),
        ("tilted_foot_hand_ledge", 249),
    ] {
        let j = load(case);
        let v = matrix_hex(&j["generators"]["float64_hex"], 6);
        let r = span_to_face(&v, &exact()).unwrap();
        assert!(r.certificate.certified);
        assert_eq!(r.face.facets.nrows(), count, "{case}");
    }
}

#[test]
fn exact_mode_edge_cases() {
    // Zero cone, whole space, half-space, lower-dimensional and non-pointed.
    let r = span_to_face(&DMatrix::zeros(0, 3), &exact()).unwrap();
    assert_eq!(r.face.equations.nrows(), 3);
    let mut v = DMatrix::zeros(6, 3);
    for i in 0..3 {
        v[(2 * i, i)] = 1.0;
        v[(2 * i + 1, i)] = -1.0;
    }
    let r = span_to_face(&v, &exact()).unwrap();
    assert_eq!((r.face.facets.nrows(), r.lineality.nrows()), (0, 3));
    let v = DMatrix::from_row_slice(
        3,
        4,
        &[1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
    );
    let r = span_to_face(&v, &exact()).unwrap();
    assert_eq!(r.face.equations.nrows(), 2);
    assert_eq!(r.lineality.nrows(), 1);
    assert_eq!(r.face.facets.nrows(), 1);
    assert_eq!(r.extreme_generators, vec![2]);
    assert!(r.certificate.certified);
    for d in 1..=8 {
        let r = span_to_face(&DMatrix::identity(d, d), &exact()).unwrap();
        assert_eq!(r.face.facets.nrows(), d);
        assert!(r.certificate.certified);
    }
}

#[test]
fn exact_and_tolerance_agree_on_a_generic_stance() {
    // A foot rolled by 1 degree: generic enough that rounding changes nothing.
    let mut right = Contact::flat([0.05, -0.1, 0.0], [0.11, 0.065], 0.7);
    right.rot = rotation([1.0, 0.0, 0.0], 1f64.to_radians());
    let v = giwc_generators(&[Contact::flat([0.0, 0.1, 0.0], [0.11, 0.065], 0.7), right]);
    let rt = span_to_face(&v, &DdOptions::default()).unwrap();
    let re = span_to_face(&v, &exact()).unwrap();
    eprintln!(
        "tolerance {} facets, exact {}",
        rt.face.facets.nrows(),
        re.face.facets.nrows()
    );
    assert!(re.certificate.certified);
    if rt.face.facets.nrows() == re.face.facets.nrows() {
        assert!(same_rows_up_to_scaling(&rt.face.facets, &re.face.facets, 1e-9).is_some());
    }
}
