//! The direct static-equilibrium polygon (support-function expansion over the contact forces,
//! `equilibrium::direct`) against the polygon through `U_stance` and against the
//! supporting-forces QP, on the paper's scenes and on random stances, for vertical and oblique
//! gravity.

mod common;

use common::stance_strategy;
use polycone::polytope::RegionStatus;
use proptest::prelude::*;
use stance_contact::equilibrium::{PolygonRoute, PolygonWorkspace, StaticPolygon};
use stance_contact::{examples, supporting_forces, w_gi_static, ForcesOutcome, Stance};

/// Band (m) between the two routes: each is within its own tolerance (1e-9 m) of the truth,
/// the `U_stance` route after a cone conversion accurate to about 1e-12 relative.
const ROUTE_BAND: f64 = 1e-7;
/// Distance (m) inside/outside the polygon at which the QP must agree.
const QP_BAND: f64 = 1e-3;
/// Relative face value (`max(U w) / |w|`) above which the QP must find no forces (as in
/// `agreement.rs`).
const FACE_BAND: f64 = 1e-6;

fn inside(p: [f64; 2], poly: &StaticPolygon) -> bool {
    poly.halfplanes
        .iter()
        .all(|(a, b)| a[0] * p[0] + a[1] * p[1] <= *b)
}

fn seg_dist(p: [f64; 2], s: [f64; 2], e: [f64; 2]) -> f64 {
    let d = [e[0] - s[0], e[1] - s[1]];
    let l2 = d[0] * d[0] + d[1] * d[1];
    let t = if l2 > 0.0 {
        (((p[0] - s[0]) * d[0] + (p[1] - s[1]) * d[1]) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - s[0] - t * d[0]).hypot(p[1] - s[1] - t * d[1])
}

/// Hausdorff distance between two convex polygons (vertices counter-clockwise).
fn hausdorff(a: &StaticPolygon, b: &StaticPolygon) -> f64 {
    let one_way = |x: &StaticPolygon, y: &StaticPolygon| {
        x.vertices
            .iter()
            .map(|&p| {
                if inside(p, y) {
                    0.0
                } else {
                    let n = y.vertices.len();
                    (0..n)
                        .map(|i| seg_dist(p, y.vertices[i], y.vertices[(i + 1) % n]))
                        .fold(f64::INFINITY, f64::min)
                }
            })
            .fold(0.0, f64::max)
    };
    one_way(a, b).max(one_way(b, a))
}

/// The polygon through `U_stance`, as the library's `U_stance` route computes it (in the
/// stance's length frame, like the direct route; the QP checks below are the independent,
/// world-frame oracle).
fn via_u(stance: &Stance, g: [f64; 3], height: f64) -> StaticPolygon {
    PolygonWorkspace::new()
        .static_polygon_via_u_stance(stance, g, height, &Default::default())
        .unwrap()
}

#[test]
fn paper_scenes_take_the_direct_route_and_match_u_stance() {
    let mut ws = PolygonWorkspace::new();
    for name in examples::NAMES {
        let scene = examples::by_name(name).unwrap();
        let stance = scene.stance().unwrap();
        for g in [scene.gravity, [0.5, -0.3, -9.81]] {
            for height in [0.0, 0.85] {
                let out = ws
                    .static_polygon(&stance, g, height, &Default::default())
                    .unwrap();
                assert_eq!(out.route, PolygonRoute::Direct, "{name}, g = {g:?}");
                assert!(out.gap <= 1e-9, "{name}: gap {}", out.gap);
                let reference = via_u(&stance, g, height);
                let h = hausdorff(&out.polygon, &reference);
                assert!(h <= ROUTE_BAND, "{name}, g = {g:?}: Hausdorff {h:.3e} m");
                assert_eq!(
                    out.polygon.vertices.len(),
                    reference.vertices.len(),
                    "{name}"
                );
                // Every vertex on its two edges' lines, inside all others.
                let p = &out.polygon;
                let n = p.vertices.len();
                for k in 0..n {
                    for (j, (a, b)) in p.halfplanes.iter().enumerate() {
                        let s = a[0] * p.vertices[k][0] + a[1] * p.vertices[k][1] - b;
                        assert!(s <= 1e-9, "{name}: vertex {k} outside edge {j} by {s:e}");
                        if j == k || (j + 1) % n == k {
                            assert!(s >= -1e-9, "{name}: vertex {k} off its edge {j} ({s:e})");
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn flat_single_foot_gives_the_foot_rectangle() {
    let scene = examples::single_support_flat();
    let stance = scene.stance().unwrap();
    let out = PolygonWorkspace::new()
        .static_polygon(&stance, scene.gravity, 0.0, &Default::default())
        .unwrap();
    let foot = stance.contacts()[0].vertices_world();
    assert_eq!(out.polygon.vertices.len(), 4);
    for q in foot {
        let near = out
            .polygon
            .vertices
            .iter()
            .map(|v| (v[0] - q[0]).hypot(v[1] - q[1]))
            .fold(f64::INFINITY, f64::min);
        assert!(near < 1e-12, "corner {q:?} missing ({near:e})");
    }
}

#[test]
fn fallbacks_are_named_and_answers_stay_those_of_u_stance() {
    use stance_contact::{Contact, FrictionModel, Shape};
    let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let point = |x: f64| {
        Contact::new(
            "p",
            [x, 0.0, 0.0],
            eye,
            Shape::Point,
            0.5,
            &Default::default(),
        )
        .unwrap()
    };
    let mut ws = PolygonWorkspace::new();
    // Two point contacts: a segment (5-D GIWC), not a 2-D polygon.
    let two = Stance::new(vec![point(0.0), point(0.3)], FrictionModel::default()).unwrap();
    let out = ws
        .static_polygon(&two, [0.0, 0.0, -9.81], 0.0, &Default::default())
        .unwrap();
    assert!(
        matches!(out.route, PolygonRoute::ViaUStance(_)),
        "{:?}",
        out.route
    );
    assert_eq!(out.polygon, via_u(&two, [0.0, 0.0, -9.81], 0.0));
    // Opposing walls (a non-pointed GIWC): the contact forces are unbounded.
    let wall = |y: f64, s: f64| {
        let rot = [[1.0, 0.0, 0.0], [0.0, 0.0, -s], [0.0, s, 0.0]];
        Contact::new(
            "w",
            [0.0, y, 1.0],
            rot,
            Shape::Rectangle {
                half_length: 0.1,
                half_width: 0.1,
            },
            0.8,
            &Default::default(),
        )
        .unwrap()
    };
    let walls = Stance::new(
        vec![wall(0.5, 1.0), wall(-0.5, -1.0)],
        FrictionModel::default(),
    )
    .unwrap();
    let out = ws
        .static_polygon(&walls, [0.0, 0.0, -9.81], 1.0, &Default::default())
        .unwrap();
    assert!(
        matches!(out.route, PolygonRoute::ViaUStance(_)),
        "{:?}",
        out.route
    );
    assert_eq!(out.polygon, via_u(&walls, [0.0, 0.0, -9.81], 1.0));
    // Bad gravity is an error, as through U_stance.
    assert!(ws
        .static_polygon(&walls, [1.0, 0.0, 0.0], 0.0, &Default::default())
        .is_err());
    assert!(ws
        .static_polygon(&walls, [0.0, f64::NAN, -9.81], 0.0, &Default::default())
        .is_err());
}

/// Feet on the floor and two frictionless hands squeezing opposing walls at the same height:
/// the squeeze is an internal force along the line of the hands (zero moment), so the contact
/// forces are unbounded while the polygon is bounded (the feet's). The direct route handles it
/// with the face-band dual check and matches `U_stance`.
#[test]
fn squeezing_hands_give_unbounded_forces_and_a_bounded_polygon() {
    use stance_contact::{Contact, FrictionModel, Shape};
    let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let rect = |l: f64, w: f64| Shape::Rectangle {
        half_length: l,
        half_width: w,
    };
    let foot = |y: f64| {
        Contact::new(
            "foot",
            [0.0, y, 0.0],
            eye,
            rect(0.11, 0.065),
            0.7,
            &Default::default(),
        )
        .unwrap()
    };
    // Walls at y = +-0.5 facing the robot: contact z axis = -+y.
    let hand = |s: f64| {
        let rot = [[1.0, 0.0, 0.0], [0.0, 0.0, -s], [0.0, s, 0.0]];
        Contact::new(
            "hand",
            [0.3, 0.5 * s, 1.0],
            rot,
            Shape::Point,
            0.0,
            &Default::default(),
        )
        .unwrap()
    };
    let stance = Stance::new(
        vec![foot(0.1), foot(-0.1), hand(1.0), hand(-1.0)],
        FrictionModel::default(),
    )
    .unwrap();
    let mut ws = PolygonWorkspace::new();
    for g in [[0.0, 0.0, -9.81], [0.4, 0.2, -9.81]] {
        let out = ws
            .static_polygon(&stance, g, 0.9, &Default::default())
            .unwrap();
        let reference = via_u(&stance, g, 0.9);
        assert_eq!(reference.status, RegionStatus::Bounded);
        assert_eq!(out.route, PolygonRoute::Direct, "g = {g:?}");
        let h = hausdorff(&out.polygon, &reference);
        assert!(h <= ROUTE_BAND, "g = {g:?}: Hausdorff {h:.3e} m");
    }
}

fn gravity_strategy() -> impl Strategy<Value = [f64; 3]> {
    prop_oneof![
        2 => Just([0.0, 0.0, -9.81]),
        1 => (-3.0f64..3.0, -3.0f64..3.0).prop_map(|(x, y)| [x, y, -9.81]),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// On random stances the direct polygon equals the one through U_stance; the QP confirms
    /// a point inside and rejects points outside each edge.
    #[test]
    fn direct_polygon_agrees_with_u_stance_and_the_qp(
        stance in stance_strategy(),
        g in gravity_strategy(),
        height in 0.3f64..1.2,
    ) {
        let out = PolygonWorkspace::new()
            .static_polygon(&stance, g, height, &Default::default())
            .unwrap();
        let reference = via_u(&stance, g, height);
        match out.route {
            PolygonRoute::Direct => {
                prop_assert_eq!(reference.status, RegionStatus::Bounded);
                prop_assert_eq!(reference.dim, 2);
                let h = hausdorff(&out.polygon, &reference);
                prop_assert!(h <= ROUTE_BAND, "Hausdorff {:.3e} m", h);
            }
            PolygonRoute::ViaUStance(_) => prop_assert_eq!(&out.polygon, &reference),
        }
        let poly = &out.polygon;
        if poly.status != RegionStatus::Bounded || poly.dim != 2 {
            return Ok(());
        }
        let n = poly.vertices.len() as f64;
        let c = poly.vertices.iter().fold([0.0, 0.0], |a, v| [a[0] + v[0] / n, a[1] + v[1] / n]);
        // CoM at the cross-section height: p = (c, height).
        if poly.margin(c) > QP_BAND {
            let w = w_gi_static(1.0, g, [c[0], c[1], height]);
            let qp = supporting_forces(&stance, &w, &Default::default()).unwrap();
            prop_assert_eq!(qp.outcome, ForcesOutcome::Feasible);
        }
        // 1 mm outside each edge: outside the GIWC, and the QP agrees whenever the wrench is
        // clearly out (far from the contacts a millimetre of CoM can be a tiny wrench distance,
        // below the QP's tolerance).
        let giwc = stance.u_stance(&Default::default()).unwrap();
        for (a, b) in &poly.halfplanes {
            let s = b - a[0] * c[0] - a[1] * c[1] + QP_BAND;
            let q = [c[0] + a[0] * s, c[1] + a[1] * s, height];
            let w = w_gi_static(1.0, g, q);
            let wn = w.iter().map(|x| x * x).sum::<f64>().sqrt();
            let v = giwc.max_violation(&w) / wn;
            prop_assert!(v > 0.0, "1 mm outside edge {:?} passes the face test ({})", (a, b), v);
            if v > FACE_BAND {
                let qp = supporting_forces(&stance, &w, &Default::default()).unwrap();
                prop_assert_eq!(qp.outcome, ForcesOutcome::Infeasible, "outside edge {:?}", (a, b));
            }
        }
    }
}

/// How often each route is taken on random stances (run with `--ignored --nocapture`).
#[test]
#[ignore]
fn route_statistics() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let mut counts = std::collections::BTreeMap::new();
    let mut ws = PolygonWorkspace::new();
    for _ in 0..2000 {
        let stance = stance_strategy().new_tree(&mut runner).unwrap().current();
        let out = ws
            .static_polygon(&stance, [0.0, 0.0, -9.81], 0.8, &Default::default())
            .unwrap();
        let what = format!(
            "{:?} -> {:?} dim {}",
            out.route, out.polygon.status, out.polygon.dim
        );
        *counts.entry(what).or_insert(0) += 1;
    }
    println!("{counts:#?}");
}
