//! U_stance against the cdd GMP-exact references (testdata/contact, see its README), and the
//! closed-form 16-row face of a rectangle (docs/math.md section 2, Caron et al. ICRA 2015).

mod common;

use common::*;
use nalgebra::DMatrix;
use stance_contact::{Contact, FrictionModel, Shape};

/// Largest accepted difference between unit rows of ours and of the exact reference.
const ROW_TOL: f64 = 1e-9;

fn check_case(name: &str) {
    let v = fixture(name);
    let stance = fixture_stance(&v);
    // Our span form is the fixture's generator set (same construction; order may differ).
    let span = stance.giwc_span();
    let gens = rows(&v["generators"]);
    assert_eq!(span.shape(), gens.shape(), "{name}: span shape");
    same_rows(&span, &gens, 1e-12).unwrap_or_else(|e| panic!("{name}: span: {e}"));
    let giwc = stance.u_stance(&Default::default()).unwrap();
    assert!(giwc.certified, "{name}: not certified");
    same_rows(&giwc.facets, &rows(&v["reference_facets"]), ROW_TOL)
        .unwrap_or_else(|e| panic!("{name}: facets: {e}"));
    let eq = rows(&v["reference_equations"]);
    assert_eq!(giwc.equations.nrows(), eq.nrows(), "{name}: equations");
    assert!((projector(&giwc.equations, 6) - projector(&eq, 6)).amax() < 1e-9);
    assert_eq!(
        giwc.lineality.nrows() as u64,
        v["reference_lineality_dim"].as_u64().unwrap(),
        "{name}: lineality"
    );
}

#[test]
fn single_support_flat_matches_cdd_exact() {
    check_case("single_support_flat");
}
#[test]
fn double_support_flat_matches_cdd_exact() {
    check_case("double_support_flat");
}
#[test]
fn double_support_stairs_matches_cdd_exact() {
    check_case("double_support_stairs");
}
#[test]
fn tilted_foot_hand_ledge_matches_cdd_exact() {
    check_case("tilted_foot_hand_ledge");
}
#[test]
fn opposing_walls_frictionless_matches_cdd_exact() {
    check_case("opposing_walls_frictionless");
}
#[test]
fn opposing_walls_friction_is_the_whole_space() {
    check_case("opposing_walls_friction");
}

/// The surface cone of one foot: our `V_surf` rows equal the fixture's generators.
#[test]
fn surface_cone_matches_fixture() {
    let v = fixture("surface_cwc_foot");
    let stance = fixture_stance(&v);
    let vs = stance.contacts()[0].v_surf(stance.friction_model());
    let gens = rows(&v["generators"]);
    same_rows(&vs, &gens, 1e-12).unwrap();
    let face = polycone::span_to_face(&vs, &Default::default()).unwrap();
    same_rows(&face.face.facets, &rows(&v["reference_facets"]), ROW_TOL).unwrap();
}

/// The 16 closed-form rows of a rectangle's surface wrench cone, `u . w <= 0`.
fn closed_form(x: f64, y: f64, mu: f64) -> DMatrix<f64> {
    let mut r: Vec<[f64; 6]> = vec![
        [1.0, 0.0, -mu, 0.0, 0.0, 0.0],
        [-1.0, 0.0, -mu, 0.0, 0.0, 0.0],
        [0.0, 1.0, -mu, 0.0, 0.0, 0.0],
        [0.0, -1.0, -mu, 0.0, 0.0, 0.0],
        [0.0, 0.0, -y, 1.0, 0.0, 0.0],
        [0.0, 0.0, -y, -1.0, 0.0, 0.0],
        [0.0, 0.0, -x, 0.0, 1.0, 0.0],
        [0.0, 0.0, -x, 0.0, -1.0, 0.0],
    ];
    // tz >= -mu (X + Y) fz + |Y fx - mu tx| + |X fy - mu ty|
    for s1 in [-1.0, 1.0] {
        for s2 in [-1.0, 1.0] {
            r.push([s1 * y, s2 * x, -mu * (x + y), -s1 * mu, -s2 * mu, -1.0]);
        }
    }
    // tz <= mu (X + Y) fz - |Y fx + mu tx| - |X fy + mu ty|
    for s1 in [-1.0, 1.0] {
        for s2 in [-1.0, 1.0] {
            r.push([s1 * y, s2 * x, -mu * (x + y), s1 * mu, s2 * mu, 1.0]);
        }
    }
    DMatrix::from_row_iterator(16, 6, r.into_iter().flatten())
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]
    #[test]
    fn rectangle_face_equals_closed_form(x in 0.01f64..0.3, y in 0.01f64..0.3, mu in 0.1f64..1.5) {
        let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let c = Contact::new("c", [0.0; 3], eye, Shape::Rectangle { half_length: x, half_width: y }, mu, &Default::default()).unwrap();
        let vs = c.v_surf(&FrictionModel::default());
        let face = polycone::span_to_face(&vs, &Default::default()).unwrap();
        proptest::prop_assert!(face.certificate.certified);
        let r = same_rows(&face.face.facets, &closed_form(x, y, mu), 1e-9);
        proptest::prop_assert!(r.is_ok(), "{:?}", r);
    }
}
