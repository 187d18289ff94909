//! Golden tests: span -> face of the shared 6-D wrench cones against the cdd exact references
//! (see `testdata/cones/README.md`).

mod common;

use common::*;
use polycone::{span_to_face, DdOptions};

const CASES: [&str; 7] = [
    "single_support_flat",
    "surface_cwc_foot",
    "double_support_flat",
    "double_support_stairs",
    "tilted_foot_hand_ledge",
    "opposing_walls_frictionless",
    "opposing_walls_friction",
];

/// Largest angle between a reference facet and ours.
const MAX_ANGLE: f64 = 1e-9;

#[test]
fn golden_span_to_face_matches_cdd_exact() {
    for case in CASES {
        let j = load(case);
        let d = j["dim"].as_u64().unwrap() as usize;
        let v = matrix_hex(&j["generators"]["float64_hex"], d);
        let reference = &j["reference_cdd_gmp_exact_input"];
        let ref_facets = matrix_f64(&reference["facets_float64"], d);
        let ref_eq = matrix_f64(&reference["equations"], d);
        let lin_dim = reference["lineality_dim"].as_u64().unwrap() as usize;
        let r = span_to_face(&v, &DdOptions::default()).unwrap_or_else(|e| panic!("{case}: {e}"));
        assert!(r.certificate.certified, "{case}: {:?}", r.certificate);
        // Solved by the floating-point engine, not rescued by the exact fallback.
        assert_eq!(
            r.certificate.arithmetic,
            polycone::Arithmetic::Tolerance,
            "{case}"
        );
        let worst = same_rows_up_to_scaling(&r.face.facets, &normalized(&ref_facets), MAX_ANGLE);
        assert!(
            worst.is_some(),
            "{case}: {} facets, reference {}",
            r.face.facets.nrows(),
            ref_facets.nrows()
        );
        assert_eq!(
            r.face.equations.nrows(),
            ref_eq.nrows(),
            "{case}: equations"
        );
        assert!(
            same_span(&r.face.equations, &ref_eq, 1e-9),
            "{case}: equation span"
        );
        assert_eq!(r.lineality.nrows(), lin_dim, "{case}: lineality dimension");
        if let Some(n) = j["summary"]["extreme_generators_exact"].as_u64() {
            assert_eq!(
                r.extreme_generators.len(),
                n as usize,
                "{case}: extreme generators"
            );
        }
        eprintln!(
            "{case}: {} facets, worst angle {:.2e}",
            r.face.facets.nrows(),
            worst.unwrap()
        );
    }
}
