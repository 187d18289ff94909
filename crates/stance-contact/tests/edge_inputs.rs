//! Inputs at the edges of contact stability, each test named after its case: frictionless
//! contacts cannot pull, scene arrays of the wrong length, a polygon corner where many rows meet,
//! huge friction, a stance far from the world origin, gravity of any magnitude.

use stance_contact::{
    supporting_forces, w_gi_static, Approximation, Contact, ForcesOutcome, FrictionModel, Scene,
    Shape, Stance,
};

const EYE: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// With mu = 0 the pyramid's side faces only say `f_x = f_y = 0`: the supporting-forces QP
/// used to return pulling forces (`f_z < 0`) as `Feasible` for gravity pointing up.
#[test]
fn frictionless_contacts_cannot_pull() {
    for sides in [4, 3, 7] {
        for approximation in [Approximation::Outer, Approximation::Inner] {
            let model = FrictionModel {
                sides,
                approximation,
            };
            let foot = Contact::new(
                "LF",
                [0.0; 3],
                EYE,
                Shape::Rectangle {
                    half_length: 0.11,
                    half_width: 0.065,
                },
                0.0,
                &Default::default(),
            )
            .unwrap();
            let stance = Stance::new(vec![foot], model).unwrap();
            let giwc = stance.u_stance(&Default::default()).unwrap();
            for (g, stable) in [([0.0, 0.0, -9.81], true), ([0.0, 0.0, 9.81], false)] {
                let w = w_gi_static(30.0, g, [0.0, 0.0, 0.8]);
                assert_eq!(
                    giwc.contains(&w, 1e-9),
                    stable,
                    "{model:?}: face test, g {g:?}"
                );
                let qp = supporting_forces(&stance, &w, &Default::default()).unwrap();
                let want = if stable {
                    ForcesOutcome::Feasible
                } else {
                    ForcesOutcome::Infeasible
                };
                assert_eq!(qp.outcome, want, "{model:?}: QP, g {g:?}");
                if stable {
                    for f in &qp.contacts[0].forces_local {
                        assert!(f[2] >= -1e-6, "{model:?}: pulling force {f:?}");
                    }
                }
            }
        }
    }
}

/// A TOML scene with too many numbers in a fixed-size array used to be accepted, the extra
/// numbers dropped (the TOML reader does not check lengths): a 4-number position, a ragged or
/// 4-row rotation, a 4-number gravity, a 3-number polygon vertex. JSON said "trailing
/// characters". Both now reject them with the expected length.
#[test]
fn scene_arrays_of_the_wrong_length_are_rejected() {
    let contact = |position: &str, rotation: &str, shape: &str| {
        format!(
            "mass = 39.0\n[[contacts]]\nname = \"a\"\nposition = {position}\n{rotation}shape = {shape}\nfriction = 0.5\n"
        )
    };
    let rect = "{ rectangle = { half_length = 0.1, half_width = 0.1 } }";
    let ok = contact("[0, 0, 0]", "", rect);
    assert!(toml::from_str::<Scene>(&ok).is_ok());
    let tri = "{ polygon = [[0.0, 0.0], [0.1, 0.0], [0.0, 0.1]] }";
    assert!(toml::from_str::<Scene>(&contact("[0, 0, 0]", "", tri)).is_ok());
    let bad = [
        (contact("[0, 0, 0, 5]", "", rect), "invalid length 4"),
        (contact("[0, 0]", "", rect), "invalid length 2"),
        (
            contact(
                "[0, 0, 0]",
                "rotation = [[1, 0, 0, 7], [0, 1, 0], [0, 0, 1]]\n",
                rect,
            ),
            "matrix row",
        ),
        (
            contact(
                "[0, 0, 0]",
                "rotation = [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]]\n",
                rect,
            ),
            "3 rows",
        ),
        (
            contact(
                "[0, 0, 0]",
                "",
                "{ polygon = [[0.0, 0.0], [0.1, 0.0, 3.0], [0.0, 0.1]] }",
            ),
            "vertex",
        ),
        (
            format!("gravity = [0.0, 0.0, -9.81, 1.0]\n{ok}"),
            "invalid length 4",
        ),
    ];
    for (text, want) in &bad {
        let err = toml::from_str::<Scene>(text).expect_err(text).to_string();
        assert!(err.contains(want), "{text}\n-> {err}");
    }
    let json = r#"{"mass": 39, "contacts": [{"name": "a", "position": [0, 0, 0, 5], "shape": "point", "friction": 0.5}]}"#;
    let err = serde_json::from_str::<Scene>(json).unwrap_err().to_string();
    assert!(
        err.contains("invalid length 4, expected 3 numbers"),
        "{err}"
    );
}

/// A random two-contact stance of the agreement test (with its seed after mu = 0 joined the
/// strategy): the polygon's polish collapsed three vertices onto one corner and the edges
/// between them gave a garbage half-plane, so `StaticPolygon::margin` called the CoM (0, 0),
/// 1.87 cm inside, outside (fixed in `polycone::polytope`).
#[test]
fn polygon_margin_of_a_corner_where_many_rows_meet() {
    use stance_contact::equilibrium::StaticEquilibrium;
    let a = Contact::new(
        "a",
        [0.0, 0.13916163812471996, 0.3373013434277288],
        [
            [0.9844403935296494, 0.0, -0.17571884243640168],
            [0.0, 1.0, 0.0],
            [0.17571884243640168, 0.0, 0.9844403935296494],
        ],
        Shape::Rectangle {
            half_length: 0.07841116725259901,
            half_width: 0.02,
        },
        0.1,
        &Default::default(),
    )
    .unwrap();
    let b = Contact::new(
        "b",
        [
            0.23915348283612084,
            -0.25807617037479796,
            0.3096082065927114,
        ],
        [
            [0.9638421270475357, -0.0334075388030715, -0.2643715008838953],
            [
                -0.0334075388030715,
                0.9691335922788937,
                -0.24426218837087393,
            ],
            [0.2643715008838953, 0.24426218837087393, 0.9329757193264293],
        ],
        Shape::Rectangle {
            half_length: 0.13142465875448914,
            half_width: 0.07367963631024074,
        },
        1.1722280476165439,
        &Default::default(),
    )
    .unwrap();
    let stance = Stance::new(vec![a, b], FrictionModel::default()).unwrap();
    let giwc = stance.u_stance(&Default::default()).unwrap();
    let eq = StaticEquilibrium::new(&giwc, [0.0, 0.0, -9.81], &Default::default()).unwrap();
    let poly = eq.polygon(0.0).unwrap();
    let inside = -eq.halfspaces().max_residual([0.0, 0.0, 0.3]);
    assert!((inside - 0.018683340241552996).abs() < 1e-9, "{inside}");
    assert!((poly.margin([0.0, 0.0]) - inside).abs() < 1e-9);
    for (h, c) in &poly.halfplanes {
        for v in &poly.vertices {
            assert!(
                h[0] * v[0] + h[1] * v[1] - c <= 1e-9,
                "{h:?} {c} cuts {v:?}"
            );
        }
    }
}

/// A friction coefficient of 1e9 (a user's "infinite friction") gave a flat foot a segment as
/// its static-equilibrium polygon, and 1e10 an empty one, both from a cone reported as
/// certified: the normal force is a 1e-9 part of the pyramid's edges and the cone conversion's
/// rank decisions dropped it. Such a mu is now an error; up to `MAX_FRICTION` the foot is right.
#[test]
fn huge_friction_is_an_error_not_a_wrong_cone() {
    use stance_contact::contact::MAX_FRICTION;
    use stance_contact::equilibrium::StaticEquilibrium;
    let foot = |mu: f64| {
        Contact::new(
            "LF",
            [0.0; 3],
            EYE,
            Shape::Rectangle {
                half_length: 0.11,
                half_width: 0.065,
            },
            mu,
            &Default::default(),
        )
    };
    for mu in [1e3, MAX_FRICTION] {
        let stance = Stance::new(vec![foot(mu).unwrap()], FrictionModel::default()).unwrap();
        let giwc = stance.u_stance(&Default::default()).unwrap();
        assert_eq!(
            (giwc.facets.nrows(), giwc.equations.nrows()),
            (16, 0),
            "mu {mu}"
        );
        let eq = StaticEquilibrium::new(&giwc, [0.0, 0.0, -9.81], &Default::default()).unwrap();
        let poly = eq.polygon(0.0).unwrap();
        assert_eq!(poly.vertices.len(), 4, "mu {mu}");
        assert!((poly.margin([0.0, 0.0]) - 0.065).abs() < 1e-9, "mu {mu}");
        for (p, want) in [
            ([0.0, 0.0, 0.8], ForcesOutcome::Feasible),
            ([0.2, 0.0, 0.8], ForcesOutcome::Infeasible),
        ] {
            let w = w_gi_static(39.0, [0.0, 0.0, -9.81], p);
            let qp = supporting_forces(&stance, &w, &Default::default()).unwrap();
            assert_eq!(qp.outcome, want, "mu {mu}, CoM {p:?}");
        }
    }
    for mu in [1e9, 1e12, f64::MAX] {
        let err = foot(mu).unwrap_err().to_string();
        assert!(err.contains("friction coefficient"), "{err}");
    }
}

/// The stair stance (176 facets) moved 30 km and 100 km from the world origin came back as a
/// certified 38-facet cone with two equations, and its static-equilibrium polygon as a point:
/// the conversion now runs at the first contact's origin. The polygon is the one near the
/// origin, translated.
#[test]
fn stance_far_from_the_world_origin_keeps_its_cone() {
    use stance_contact::equilibrium::StaticEquilibrium;
    let stairs = |o: f64| {
        let sh = Shape::Rectangle {
            half_length: 0.11,
            half_width: 0.065,
        };
        let yaw = [
            [0.9848038455574508, -0.17367033648627694, 0.0],
            [0.17367033648627694, 0.9848038455574508, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let t = Default::default();
        let a = Contact::new("LF", [o, o + 0.1, 0.0], EYE, sh.clone(), 0.7, &t).unwrap();
        let b = Contact::new("RF", [o + 0.28, o - 0.1, 0.24], yaw, sh, 0.7, &t).unwrap();
        Stance::new(vec![a, b], FrictionModel::default()).unwrap()
    };
    let polygon = |o: f64| {
        let giwc = stairs(o).u_stance(&Default::default()).unwrap();
        assert!(giwc.certified);
        assert_eq!(
            (giwc.facets.nrows(), giwc.equations.nrows()),
            (176, 0),
            "at {o} m"
        );
        let eq = StaticEquilibrium::new(&giwc, [0.0, 0.0, -9.81], &Default::default()).unwrap();
        eq.polygon(0.0).unwrap().vertices
    };
    let near = polygon(0.0);
    for o in [3e4, 1e5] {
        let far = polygon(o);
        assert_eq!(far.len(), near.len(), "at {o} m");
        for v in &far {
            let moved = [v[0] - o, v[1] - o];
            assert!(
                near.iter()
                    .any(|w| (w[0] - moved[0]).abs() < 1e-6 && (w[1] - moved[1]).abs() < 1e-6),
                "at {o} m: vertex {v:?}"
            );
        }
    }
}

/// The sets do not depend on |g|, but |g| itself overflowed (1e200, 1e160) or underflowed
/// (1e-200): a CoM 7 m away was called robustly stable, the polygon was refused with "no
/// vertical component" or "the zero vector".
#[test]
fn gravity_of_any_magnitude_gives_the_same_sets() {
    use stance_contact::equilibrium::{
        PolygonRoute, PolygonWorkspace, RobustRegion, StaticEquilibrium,
    };
    let scene = stance_contact::examples::single_support_flat();
    let stance = scene.stance().unwrap();
    let giwc = stance.u_stance(&Default::default()).unwrap();
    let opts = Default::default();
    let mut ws = PolygonWorkspace::new();
    for s in [1e200, 1e160, 1.0, 1e-200, 1e-300] {
        let g = [0.0, 0.0, -9.81 * s];
        let tilted = [0.15 * s, 0.0, -9.81 * s];
        let region = RobustRegion::new(&giwc, &[g, tilted], &opts).unwrap();
        assert!(region.contains([0.0, 0.0, 0.8]), "g scaled by {s:e}");
        assert!(!region.contains([5.0, 5.0, 0.8]), "g scaled by {s:e}");
        let eq = StaticEquilibrium::new(&giwc, g, &opts).unwrap();
        assert!(eq.contains([0.0, 0.0, 0.8]) && !eq.contains([0.2, 0.0, 0.8]));
        let poly = eq.polygon(0.0).unwrap();
        assert_eq!(poly.vertices.len(), 4, "g scaled by {s:e}");
        let direct = ws.static_polygon(&stance, g, 0.0, &opts).unwrap();
        assert_eq!(direct.route, PolygonRoute::Direct, "g scaled by {s:e}");
        assert_eq!(direct.polygon.vertices.len(), 4, "g scaled by {s:e}");
        assert!((direct.polygon.margin([0.0, 0.0]) - 0.065).abs() < 1e-9);
    }
}
