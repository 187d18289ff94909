//! Special stances and invariants: two point contacts (a 5-D GIWC), opposing walls (non-pointed),
//! rigid motions of the scene, CoM independence, a flat single foot.

mod common;

use common::*;
use nalgebra::{DMatrix, Matrix3, Matrix6, Rotation3, Unit, Vector3};
use polycone::polytope::RegionStatus;
use proptest::prelude::*;
use stance_contact::equilibrium::{RobustRegion, StaticEquilibrium};
use stance_contact::{
    supporting_forces, w_gi_static, Approximation, Contact, ForcesOutcome, FrictionModel, Shape,
    Stance,
};

const G: [f64; 3] = [0.0, 0.0, -9.81];
/// The four gravity-like vectors of the robust region (the paper's tilted gravities).
const GS: [[f64; 3]; 4] = [
    [0.15, 0.0, -9.81],
    [-0.15, 0.0, -9.81],
    [0.0, 0.15, -9.81],
    [0.0, -0.15, -9.81],
];
const EYE: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn point(name: &str, p: [f64; 3], mu: f64) -> Contact {
    Contact::new(name, p, EYE, Shape::Point, mu, &Default::default()).unwrap()
}

#[test]
fn two_point_contacts_give_a_5d_giwc_with_its_equation() {
    let stance = Stance::new(
        vec![
            point("a", [0.0, 0.2, 0.0], 0.7),
            point("b", [0.0, -0.2, 0.0], 0.7),
        ],
        FrictionModel::default(),
    )
    .unwrap();
    let giwc = stance.u_stance(&Default::default()).unwrap();
    assert!(giwc.certified);
    assert_eq!(giwc.equations.nrows(), 1, "the 5-D GIWC has one equation");
    // The equation: no torque about the line through both points (the y axis here).
    let e = giwc.equations.row(0);
    assert!((e[4].abs() - 1.0).abs() < 1e-9, "equation {e}");
    // CoM above the segment: stable (with forces); 1 cm off the vertical plane: unstable,
    // which a solver that drops the equation would accept.
    for (p, stable) in [([0.0, 0.05, 0.9], true), ([0.01, 0.05, 0.9], false)] {
        let w = w_gi_static(40.0, G, p);
        assert_eq!(giwc.contains(&w, 1e-9), stable, "face test at {p:?}");
        let qp = supporting_forces(&stance, &w, &Default::default()).unwrap();
        let want = if stable {
            ForcesOutcome::Feasible
        } else {
            ForcesOutcome::Infeasible
        };
        assert_eq!(qp.outcome, want, "QP at {p:?}");
    }
    // The static-equilibrium "polygon" is the segment between the two points.
    let eq = StaticEquilibrium::new(&giwc, G, &Default::default()).unwrap();
    let poly = eq.polygon(0.0).unwrap();
    assert_eq!((poly.status, poly.dim), (RegionStatus::Bounded, 1));
    let ys: Vec<f64> = poly.vertices.iter().map(|v| v[1]).collect();
    assert!(ys.iter().any(|y| (y - 0.2).abs() < 1e-6) && ys.iter().any(|y| (y + 0.2).abs() < 1e-6));
}

#[test]
fn opposing_walls_are_non_pointed_and_agree_with_the_qp() {
    let v = fixture("opposing_walls_frictionless");
    let stance = fixture_stance(&v);
    let giwc = stance.u_stance(&Default::default()).unwrap();
    assert_eq!(giwc.lineality.nrows(), 3);
    let eq = StaticEquilibrium::new(&giwc, G, &Default::default()).unwrap();
    for p in [
        [0.0, 0.0, 0.9],
        [0.05, 0.3, 0.5],
        [0.3, 0.0, 0.9],
        [-0.2, 0.0, 1.0],
    ] {
        let w = w_gi_static(40.0, G, p);
        let qp = supporting_forces(&stance, &w, &Default::default()).unwrap();
        let face = giwc.contains(&w, 1e-9);
        assert_eq!(eq.contains(p), face, "halfspaces vs face at {p:?}");
        assert_eq!(
            qp.outcome,
            if face {
                ForcesOutcome::Feasible
            } else {
                ForcesOutcome::Infeasible
            },
            "QP vs face at {p:?}"
        );
    }
    // With friction on the walls the GIWC is the whole space: every CoM is stable.
    let all = fixture_stance(&fixture("opposing_walls_friction"))
        .u_stance(&Default::default())
        .unwrap();
    assert_eq!((all.facets.nrows(), all.lineality.nrows()), (0, 6));
    let eq = StaticEquilibrium::new(&all, G, &Default::default()).unwrap();
    assert!(eq.contains([5.0, -3.0, 0.0]));
    assert_eq!(eq.polygon(0.0).unwrap().status, RegionStatus::Unbounded);
}

/// The wrench transform of a rigid motion `x -> Q x + t` applied to the whole scene:
/// `w' = X w`, `X = [Q 0; [t]x Q  Q]` (wrenches at the world origin).
fn wrench_map(q: &Matrix3<f64>, t: &Vector3<f64>) -> Matrix6<f64> {
    let mut x = Matrix6::zeros();
    let tq = t.cross_matrix() * q;
    x.fixed_view_mut::<3, 3>(0, 0).copy_from(q);
    x.fixed_view_mut::<3, 3>(3, 0).copy_from(&tq);
    x.fixed_view_mut::<3, 3>(3, 3).copy_from(q);
    x
}

fn moved(stance: &Stance, q: &Matrix3<f64>, t: &Vector3<f64>) -> Stance {
    let contacts = stance
        .contacts()
        .iter()
        .map(|c| {
            let p = q * Vector3::from(c.position()) + t;
            let r = q * c.rotation();
            let rot = [
                [r[(0, 0)], r[(0, 1)], r[(0, 2)]],
                [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
                [r[(2, 0)], r[(2, 1)], r[(2, 2)]],
            ];
            Contact::new(
                c.name(),
                [p[0], p[1], p[2]],
                rot,
                c.shape().clone(),
                c.friction(),
                &Default::default(),
            )
            .unwrap()
        })
        .collect();
    Stance::new(contacts, *stance.friction_model()).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// Moving the whole scene by `(Q, t)` maps U_stance to `U X^{-1}` (rows renormalized).
    #[test]
    fn rigid_motion_transforms_u_stance(
        axis in (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), angle in 0.0f64..3.0,
        t in (-2.0f64..2.0, -2.0f64..2.0, -2.0f64..2.0),
        case in 0usize..3,
    ) {
        let name = ["double_support_flat", "double_support_stairs", "tilted_foot_hand_ledge"][case];
        let stance = fixture_stance(&fixture(name));
        let axis = Vector3::new(axis.0, axis.1, axis.2);
        prop_assume!(axis.norm() > 0.1);
        let q = *Rotation3::from_axis_angle(&Unit::new_normalize(axis), angle).matrix();
        let t = Vector3::new(t.0, t.1, t.2);
        let u = stance.u_stance(&Default::default()).unwrap().facets;
        let u2 = moved(&stance, &q, &t).u_stance(&Default::default()).unwrap().facets;
        let xinv = wrench_map(&q, &t).try_inverse().unwrap();
        let expected = &u * DMatrix::from_iterator(6, 6, xinv.iter().copied());
        let r = same_rows(&u2, &expected, 1e-7);
        prop_assert!(r.is_ok(), "{}: {:?}", name, r);
    }

    /// A flat single foot anywhere on the ground (any yaw): its polygon is the foot rectangle.
    #[test]
    fn flat_single_foot_polygon_is_the_foot(
        x in -1.0f64..1.0, y in -1.0f64..1.0, yaw in -3.1f64..3.1,
        hl in 0.03f64..0.2, hw in 0.03f64..0.2, mu in 0.2f64..1.0,
    ) {
        let r = *Rotation3::from_axis_angle(&Vector3::z_axis(), yaw).matrix();
        let rot = [[r[(0, 0)], r[(0, 1)], 0.0], [r[(1, 0)], r[(1, 1)], 0.0], [0.0, 0.0, 1.0]];
        let foot = Contact::new("LF", [x, y, 0.0], rot, Shape::Rectangle { half_length: hl, half_width: hw }, mu, &Default::default()).unwrap();
        let corners: Vec<[f64; 3]> = foot.vertices_world();
        let stance = Stance::new(vec![foot], FrictionModel::default()).unwrap();
        let giwc = stance.u_stance(&Default::default()).unwrap();
        let poly = StaticEquilibrium::new(&giwc, G, &Default::default()).unwrap().polygon(0.0).unwrap();
        prop_assert_eq!(poly.vertices.len(), 4);
        for c in &corners {
            prop_assert!(poly.vertices.iter().any(|v| (v[0] - c[0]).abs() < 1e-7 && (v[1] - c[1]).abs() < 1e-7));
        }
        prop_assert!((poly.margin([x, y]) - hl.min(hw)).abs() < 1e-7);
    }

    /// U_stance does not depend on the CoM: the CoM half-spaces (computed once) and the face
    /// test of `w_GI(p)` agree for CoMs anywhere, at any height, for vertical gravity.
    #[test]
    fn static_test_is_independent_of_com_height(px in -0.3f64..0.3, py in -0.3f64..0.3, z1 in 0.0f64..2.0, z2 in 0.0f64..2.0) {
        let stance = fixture_stance(&fixture("double_support_stairs"));
        let giwc = stance.u_stance(&Default::default()).unwrap();
        let eq = StaticEquilibrium::new(&giwc, G, &Default::default()).unwrap();
        let (a, b) = ([px, py, z1], [px, py, z2]);
        prop_assert_eq!(eq.halfspaces().max_residual(a).signum(), eq.halfspaces().max_residual(b).signum());
        let fa = giwc.max_violation(&w_gi_static(1.0, G, a));
        let fb = giwc.max_violation(&w_gi_static(1.0, G, b));
        prop_assert!((fa - fb).abs() < 1e-9);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// Oblique gravity: the polygon at height h is the cross-section of the prism along g,
    /// checked against the face test of the 3-D CoM, and it translates with the height.
    #[test]
    fn oblique_gravity_polygon_is_the_prism_cross_section(gx in -3.0f64..3.0, gy in -3.0f64..3.0, h in 0.0f64..1.5) {
        let giwc = fixture_stance(&fixture("tilted_foot_hand_ledge")).u_stance(&Default::default()).unwrap();
        let g = [gx, gy, -9.81];
        let eq = StaticEquilibrium::new(&giwc, g, &Default::default()).unwrap();
        let poly = eq.polygon(h).unwrap();
        prop_assume!(poly.status == RegionStatus::Bounded && poly.dim == 2);
        let n = poly.vertices.len() as f64;
        let c = poly.vertices.iter().fold([0.0, 0.0], |a, v| [a[0] + v[0] / n, a[1] + v[1] / n]);
        let face = |p: [f64; 3]| {
            let w = w_gi_static(1.0, g, p);
            giwc.max_violation(&w) / w.iter().map(|x| x * x).sum::<f64>().sqrt()
        };
        prop_assert!(face([c[0], c[1], h]) <= 1e-9);
        for v in &poly.vertices {
            prop_assert!(face([v[0], v[1], h]).abs() <= 1e-7);
            // 1 cm outward from the centroid through a vertex: unstable.
            let d = ((v[0] - c[0]).powi(2) + (v[1] - c[1]).powi(2)).sqrt();
            let out = [v[0] + 0.01 * (v[0] - c[0]) / d, v[1] + 0.01 * (v[1] - c[1]) / d, h];
            prop_assert!(face(out) > 0.0);
        }
        // Moving up by dz shifts the section by (gx, gy) / gz * dz.
        let up = eq.polygon(h + 0.5).unwrap();
        let shift = [g[0] / g[2] * 0.5, g[1] / g[2] * 0.5];
        for v in &poly.vertices {
            prop_assert!(up.vertices.iter().any(|u| (u[0] - v[0] - shift[0]).abs() < 1e-7 && (u[1] - v[1] - shift[1]).abs() < 1e-7));
        }
    }
}

#[test]
fn robust_region_sign_sanity_of_eq_12() {
    // docs/math.md section 4: one flat foot at the origin, CoM (0, 0, 0.8) stable, (0.2, 0, 0.8) not.
    let stance = fixture_stance(&fixture("single_support_flat"));
    let giwc = stance.u_stance(&Default::default()).unwrap();
    let m = RobustRegion::new(&giwc, &GS, &Default::default()).unwrap();
    assert_eq!(m.polyhedron.status, RegionStatus::Bounded);
    assert!(m.contains([0.0, 0.0, 0.8]));
    assert!(!m.contains([0.2, 0.0, 0.8]));
    // Eq. (12) as printed (>= 0 with g pointing down) would accept the opposite.
    let w = w_gi_static(1.0, GS[0], [0.0, 0.0, 0.8]);
    assert!(giwc.max_violation(&w) <= 0.0);
}

#[test]
fn bad_inputs_are_errors_with_a_fix() {
    let t = Default::default();
    let err = |r: Result<Contact, stance_contact::ContactError>| r.unwrap_err().to_string();
    assert!(
        err(Contact::new("c", [0.0; 3], EYE, Shape::Point, -0.1, &t)).contains("mu must be >= 0")
    );
    assert!(err(Contact::new(
        "c",
        [f64::NAN, 0.0, 0.0],
        EYE,
        Shape::Point,
        0.5,
        &t
    ))
    .contains("non-finite"));
    let scaled = [[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    assert!(
        err(Contact::new("c", [0.0; 3], scaled, Shape::Point, 0.5, &t)).contains("not a rotation")
    );
    let mirror = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]];
    assert!(
        err(Contact::new("c", [0.0; 3], mirror, Shape::Point, 0.5, &t)).contains("not a rotation")
    );
    let dart = Shape::Polygon(vec![[0.0, 0.0], [1.0, 0.0], [0.2, 0.2], [0.0, 1.0]]);
    assert!(err(Contact::new("c", [0.0; 3], EYE, dart, 0.5, &t)).contains("not convex"));
    // bounded work: a polygon of more vertices than supported is refused, naming the limit
    let ngon = |n: usize| {
        Shape::Polygon(
            (0..n)
                .map(|i| {
                    let a = std::f64::consts::TAU * i as f64 / n as f64;
                    [0.1 * a.cos(), 0.05 * a.sin()]
                })
                .collect(),
        )
    };
    let max = stance_contact::tol::MAX_POLYGON_VERTICES;
    assert!(Contact::new("c", [0.0; 3], EYE, ngon(max), 0.5, &t).is_ok());
    let e = err(Contact::new("c", [0.0; 3], EYE, ngon(1000), 0.5, &t));
    assert!(e.contains("1000 vertices given, at most 64"), "{e}");
    let flat = Shape::Polygon(vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]);
    assert!(err(Contact::new("c", [0.0; 3], EYE, flat, 0.5, &t)).contains("zero"));
    let star = Shape::Polygon(vec![
        [1.0, 0.0],
        [-0.8, 0.6],
        [0.3, -0.95],
        [0.3, 0.95],
        [-0.8, -0.6],
    ]);
    assert!(Contact::new("c", [0.0; 3], EYE, star, 0.5, &t).is_err());
    let thin = Shape::Rectangle {
        half_length: 0.1,
        half_width: 0.0,
    };
    assert!(err(Contact::new("c", [0.0; 3], EYE, thin, 0.5, &t)).contains("> 0"));
    assert!(Stance::new(vec![], FrictionModel::default()).is_err());
    let bad_model = FrictionModel {
        sides: 2,
        ..Default::default()
    };
    assert!(Stance::new(vec![point("a", [0.0; 3], 0.5)], bad_model).is_err());
    // Scenes: zero mass, unknown keys.
    let mut scene = stance_contact::examples::single_support_flat();
    scene.mass = 0.0;
    assert!(scene.stance().unwrap_err().to_string().contains("mass"));
    let unknown = r#"{"mass": 1, "contacts": [], "colour": "red"}"#;
    assert!(serde_json::from_str::<stance_contact::Scene>(unknown).is_err());
    // Gravity without vertical component has no polygon; zero gravity is an error.
    let giwc = stance_contact::examples::single_support_flat()
        .stance()
        .unwrap()
        .u_stance(&Default::default())
        .unwrap();
    let side = StaticEquilibrium::new(&giwc, [9.81, 0.0, 0.0], &Default::default()).unwrap();
    assert!(side.polygon(0.0).is_err());
    // Regression: a gravity with a vertical component below the zero threshold used to make
    // `new` itself fail (it computes the polygon to reduce its rows); now only `polygon` does.
    let almost = StaticEquilibrium::new(&giwc, [9.81, 0.0, 1e-14], &Default::default()).unwrap();
    assert!(almost.polygon(0.0).is_err());
    assert!(!almost.contains([0.0, 0.0, 0.8]));
    assert!(StaticEquilibrium::new(&giwc, [0.0; 3], &Default::default()).is_err());
}

#[test]
fn scenes_read_from_json_and_toml() {
    let json = r#"{"mass": 39, "gravity": [0, 0, -9.81], "contacts": [
        {"name": "LF", "position": [0, 0.1, 0], "rotation": [[1,0,0],[0,1,0],[0,0,1]],
         "shape": {"rectangle": {"half_length": 0.11, "half_width": 0.065}}, "friction": 0.7},
        {"name": "H", "position": [0.3, 0, 1], "shape": "point", "friction": 0.5},
        {"name": "P", "position": [0, -0.1, 0], "shape": {"polygon": [[0.1, 0], [0, 0.1], [-0.1, 0]]}, "friction": 0.5}],
        "friction_model": {"sides": 6, "approximation": "inner"}}"#;
    let scene: stance_contact::Scene = serde_json::from_str(json).unwrap();
    let s = scene.stance().unwrap();
    assert_eq!(s.giwc_span().nrows(), 6 * (4 + 1 + 3));
    let toml_text = r#"
mass = 39.0
[[contacts]]
name = "LF"
position = [0.0, 0.0, 0.0]
shape = { rectangle = { half_length = 0.11, half_width = 0.065 } }
friction = 0.7
"#;
    let scene: stance_contact::Scene = toml::from_str(toml_text).unwrap();
    assert_eq!(scene.gravity, [0.0, 0.0, -9.81]);
    assert_eq!(scene.stance().unwrap().contacts().len(), 1);
}

/// The robust region M of the paper's box-climbing and stair stances against the QP over
/// contact forces: its centroid is supported under every g_k, and a point 5 mm outside the
/// middle of each face is not supported under some g_k.
#[test]
fn robust_region_faces_against_the_qp() {
    for name in ["box-climbing", "stairs"] {
        let stance = stance_contact::examples::by_name(name)
            .unwrap()
            .stance()
            .unwrap();
        let giwc = stance.u_stance(&Default::default()).unwrap();
        let m = RobustRegion::new(&giwc, &GS, &Default::default()).unwrap();
        assert_eq!(m.polyhedron.status, RegionStatus::Bounded, "{name}");
        let v = &m.polyhedron.vertices;
        let n = v.len() as f64;
        let c = v.iter().fold([0.0; 3], |a, p| {
            [a[0] + p[0] / n, a[1] + p[1] / n, a[2] + p[2] / n]
        });
        let qp = |p: [f64; 3], g: [f64; 3]| {
            supporting_forces(&stance, &w_gi_static(39.0, g, p), &Default::default())
                .unwrap()
                .outcome
        };
        for g in GS {
            assert_eq!(
                qp(c, g),
                ForcesOutcome::Feasible,
                "{name}: centroid under {g:?}"
            );
        }
        for (face, (nrm, _)) in m.polyhedron.faces.iter().zip(&m.polyhedron.planes) {
            let k = face.len() as f64;
            let mid = face.iter().fold([0.0; 3], |a, &i| {
                [a[0] + v[i][0] / k, a[1] + v[i][1] / k, a[2] + v[i][2] / k]
            });
            let out = [
                mid[0] + 0.005 * nrm[0],
                mid[1] + 0.005 * nrm[1],
                mid[2] + 0.005 * nrm[2],
            ];
            assert!(!m.contains(out));
            assert!(
                GS.iter().any(|&g| qp(out, g) == ForcesOutcome::Infeasible),
                "{name}: 5 mm outside a face of M, yet supported under every g_k"
            );
            let inside = [
                mid[0] - 0.005 * nrm[0],
                mid[1] - 0.005 * nrm[1],
                mid[2] - 0.005 * nrm[2],
            ];
            if m.margin(inside) > 1e-4 {
                for g in GS {
                    assert_eq!(
                        qp(inside, g),
                        ForcesOutcome::Feasible,
                        "{name}: 5 mm inside a face under {g:?}"
                    );
                }
            }
        }
    }
}

/// M of flat double support equals the brute-force intersection of all 4 x 16 half-spaces
/// (every feasible triple intersection), not only of the prisms' irredundant rows.
#[test]
fn robust_region_vertices_match_brute_force_over_all_rows() {
    let giwc = stance_contact::examples::double_support_flat()
        .stance()
        .unwrap()
        .u_stance(&Default::default())
        .unwrap();
    let m = RobustRegion::new(&giwc, &GS, &Default::default()).unwrap();
    let mut a = vec![];
    let mut d = vec![];
    for g in GS {
        let h = stance_contact::com_halfspaces(&giwc, g, 1e-12, 1e-9).unwrap();
        a.extend(h.normals);
        d.extend(h.offsets);
    }
    let mut brute: Vec<[f64; 3]> = vec![];
    for i in 0..a.len() {
        for j in i + 1..a.len() {
            for k in j + 1..a.len() {
                let mat = Matrix3::from_rows(&[
                    Vector3::from(a[i]).transpose(),
                    Vector3::from(a[j]).transpose(),
                    Vector3::from(a[k]).transpose(),
                ]);
                if mat.determinant().abs() < 1e-9 {
                    continue;
                }
                let Some(p) = mat.lu().solve(&Vector3::new(d[i], d[j], d[k])) else {
                    continue;
                };
                let ok = a
                    .iter()
                    .zip(&d)
                    .all(|(n, c)| n[0] * p[0] + n[1] * p[1] + n[2] * p[2] <= c + 1e-9);
                if ok && !brute.iter().any(|q| (Vector3::from(*q) - p).norm() < 1e-7) {
                    brute.push([p[0], p[1], p[2]]);
                }
            }
        }
    }
    assert_eq!(brute.len(), m.polyhedron.vertices.len());
    for q in &brute {
        assert!(m
            .polyhedron
            .vertices
            .iter()
            .any(|v| (Vector3::from(*v) - Vector3::from(*q)).norm() < 1e-7));
    }
}

/// Regression (heavy agreement sweep, seed 20261121): a rectangle and two point contacts whose
/// robust region M made the 3-D clipping of `polyhedron_from_halfspaces` run for minutes.
#[test]
fn robust_region_of_a_three_contact_sweep_case_ends() {
    let rect = Contact::new(
        "rect",
        [0.10982279579743626, -0.3925687074512466, 0.2065511719246182],
        [
            [
                -0.7987471630911659,
                -0.37019771509149685,
                0.47429592154566275,
            ],
            [
                0.36913319696461616,
                -0.9240266828573178,
                -0.0995759622920299,
            ],
            [0.47512488079713994, 0.09554235243459745, 0.8747159576335436],
        ],
        Shape::Rectangle {
            half_length: 0.14428849446583045,
            half_width: 0.05065259478288799,
        },
        0.3091549115882365,
        &Default::default(),
    )
    .unwrap();
    let p1 = Contact::new(
        "p1",
        [
            -0.08346296251980546,
            0.13036765535731948,
            0.14398922514974122,
        ],
        [
            [
                -0.5485703323868691,
                0.46845788957012957,
                -0.6925444362093021,
            ],
            [0.4670832545820175, -0.5152960926492869, -0.7185423927573429],
            [
                -0.6934722948424328,
                -0.7176469484362611,
                0.06386731312723493,
            ],
        ],
        Shape::Point,
        0.967781043764694,
        &Default::default(),
    )
    .unwrap();
    let p2 = Contact::new(
        "p2",
        [0.1403431221379, -0.3572088332045055, 0.462471009835796],
        [
            [0.4360769235579881, 0.8654265339555056, -0.2467262269519811],
            [-0.4053783515497753, 0.43368592176645104, 0.8047266078342199],
            [0.8034334501593691, -0.25090523228371236, 0.5399456042766428],
        ],
        Shape::Point,
        0.23213325845426963,
        &Default::default(),
    )
    .unwrap();
    let model = FrictionModel {
        sides: 8,
        approximation: Approximation::Inner,
    };
    let stance = Stance::new(vec![rect, p1, p2], model).unwrap();
    let giwc = stance.u_stance(&Default::default()).unwrap();
    let t = std::time::Instant::now();
    let m = RobustRegion::new(&giwc, &GS, &Default::default()).unwrap();
    let took = t.elapsed();
    assert!(took.as_secs_f64() < 5.0, "took {took:?}");
    // Independent check (exact double description, no clipping): M = {p : a_i . p <= d_i} is
    // empty iff the cone {(p, s) : a_i . p - d_i s <= 0, s >= 0} has no ray with s > 0.
    let h = &m.halfspaces;
    let mut rows: Vec<f64> = Vec::new();
    for (a, d) in h.normals.iter().zip(&h.offsets) {
        rows.extend_from_slice(&[a[0], a[1], a[2], -d]);
    }
    rows.extend_from_slice(&[0.0, 0.0, 0.0, -1.0]);
    let face = polycone::FaceForm::new(
        DMatrix::from_row_slice(rows.len() / 4, 4, &rows),
        DMatrix::zeros(0, 4),
    )
    .unwrap();
    let exact = polycone::DdOptions {
        arithmetic: polycone::Arithmetic::Exact,
        ..Default::default()
    };
    let span = polycone::face_to_span(&face, &exact).unwrap().span;
    let has_point = span.generators.row_iter().any(|r| r[3] > 0.0);
    assert_eq!(m.polyhedron.status == RegionStatus::Empty, !has_point);
}
