//! Tests of the 2-D/3-D routines against brute force (all pairs / triples of lines / planes)
//! and invariants.

use super::*;
use proptest::prelude::*;

const TOL: f64 = 1e-7;

fn brute2(a: &[[f64; 2]], b: &[f64]) -> Vec<[f64; 2]> {
    let mut out = vec![];
    for i in 0..a.len() {
        for j in i + 1..a.len() {
            let det = a[i][0] * a[j][1] - a[i][1] * a[j][0];
            if det.abs() < 1e-9 {
                continue;
            }
            let x = (b[i] * a[j][1] - a[i][1] * b[j]) / det;
            let y = (a[i][0] * b[j] - b[i] * a[j][0]) / det;
            if a.iter()
                .zip(b)
                .all(|(r, &c)| r[0] * x + r[1] * y - c <= 1e-9 * (1.0 + c.abs()))
            {
                out.push([x, y]);
            }
        }
    }
    out
}

fn brute3(a: &[[f64; 3]], b: &[f64]) -> Vec<[f64; 3]> {
    let mut out = vec![];
    let n = a.len();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let m = nalgebra::Matrix3::from_rows(&[
                    nalgebra::RowVector3::from(a[i]),
                    nalgebra::RowVector3::from(a[j]),
                    nalgebra::RowVector3::from(a[k]),
                ]);
                if m.determinant().abs() < 1e-6 {
                    continue;
                }
                let Some(p) = m.lu().solve(&nalgebra::Vector3::new(b[i], b[j], b[k])) else {
                    continue;
                };
                if a.iter().zip(b).all(|(r, &c)| {
                    r[0] * p[0] + r[1] * p[1] + r[2] * p[2] - c <= 1e-9 * (1.0 + c.abs())
                }) {
                    out.push([p[0], p[1], p[2]]);
                }
            }
        }
    }
    out
}

fn near2(p: [f64; 2], set: &[[f64; 2]]) -> bool {
    let scale = 1.0 + p[0].abs().max(p[1].abs());
    set.iter()
        .any(|q| (p[0] - q[0]).hypot(p[1] - q[1]) < TOL * scale)
}
fn near3(p: [f64; 3], set: &[[f64; 3]]) -> bool {
    let scale = 1.0 + p[0].abs().max(p[1].abs()).max(p[2].abs());
    set.iter().any(|q| {
        ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt() < TOL * scale
    })
}

/// Random half-planes tangent to the unit circle around a random centre: bounded when the
/// directions surround the origin.
fn halfplanes2() -> impl Strategy<Value = (Vec<[f64; 2]>, Vec<f64>)> {
    (
        prop::collection::vec((0.0..std::f64::consts::TAU, 0.2f64..2.0), 3..12),
        -1.0f64..1.0,
        -1.0f64..1.0,
    )
        .prop_map(|(rows, cx, cy)| {
            let a: Vec<[f64; 2]> = rows.iter().map(|(t, _)| [t.cos(), t.sin()]).collect();
            let b = rows
                .iter()
                .zip(&a)
                .map(|((_, r), n)| r + n[0] * cx + n[1] * cy)
                .collect();
            (a, b)
        })
}

/// Random bounded-or-not half-spaces `a . p <= b` (unit normals), also used by the hull3 tests.
pub(super) fn halfspaces3() -> impl Strategy<Value = (Vec<[f64; 3]>, Vec<f64>)> {
    prop::collection::vec(
        (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0, 0.2f64..2.0),
        4..14,
    )
    .prop_filter_map("zero normal", |rows| {
        let mut a = vec![];
        let mut b = vec![];
        for (x, y, z, r) in rows {
            let n = (x * x + y * y + z * z).sqrt();
            if n < 0.1 {
                return None;
            }
            a.push([x / n, y / n, z / n]);
            b.push(r);
        }
        Some((a, b))
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// The error of a vertex grows with its distance from the origin (ill-conditioned
    /// intersections of nearly parallel lines); tolerances below are relative to that distance.
    #[test]
    fn polygon_matches_brute_force((a, b) in halfplanes2()) {
        let opts = PolytopeOptions::default();
        let poly = polygon_from_halfplanes(&a, &b, &opts).unwrap();
        // Boundedness, independently: the largest angular gap between normals is below pi.
        let mut ang: Vec<f64> = a.iter().map(|n| n[1].atan2(n[0])).collect();
        ang.sort_by(f64::total_cmp);
        let mut gap = ang[0] + std::f64::consts::TAU - ang[ang.len() - 1];
        for w in ang.windows(2) { gap = gap.max(w[1] - w[0]); }
        let bounded = gap < std::f64::consts::PI - 1e-6;
        let unbounded = gap > std::f64::consts::PI + 1e-6;
        if poly.status == RegionStatus::Bounded {
            let brute = brute2(&a, &b);
            for v in &poly.vertices { prop_assert!(near2(*v, &brute), "vertex {v:?} not a brute vertex"); }
            for v in &brute { prop_assert!(near2(*v, &poly.vertices), "brute vertex {v:?} missed"); }
            // Counter-clockwise and convex.
            let n = poly.vertices.len();
            for i in 0..n {
                let (p, q, r) = (poly.vertices[i], poly.vertices[(i + 1) % n], poly.vertices[(i + 2) % n]);
                let cr = (q[0] - p[0]) * (r[1] - q[1]) - (q[1] - p[1]) * (r[0] - q[0]);
                prop_assert!(cr > 0.0);
            }
            // Active half-planes are tight on their edge.
            for (i, act) in poly.active.iter().enumerate() {
                let k = act.expect("bounded polygons have no box edge");
                for v in [poly.vertices[i], poly.vertices[(i + 1) % n]] {
                    prop_assert!((a[k][0] * v[0] + a[k][1] * v[1] - b[k]).abs() < TOL);
                }
            }
        }
        if bounded { prop_assert_ne!(poly.status, RegionStatus::Unbounded); }
        if unbounded { prop_assert_eq!(poly.status, RegionStatus::Unbounded); }
    }

    #[test]
    fn polygon_round_trip_through_hull((a, b) in halfplanes2()) {
        let opts = PolytopeOptions::default();
        let poly = polygon_from_halfplanes(&a, &b, &opts).unwrap();
        prop_assume!(poly.status == RegionStatus::Bounded && poly.dim == 2);
        let hull = hull2(&poly.vertices, &opts).unwrap();
        prop_assert_eq!(hull.vertices.len(), poly.vertices.len());
        prop_assert!((hull.area() - poly.area()).abs() < 1e-9);
        let hp = hull.halfplanes();
        let (ha, hb): (Vec<_>, Vec<_>) = hp.into_iter().unzip();
        let back = polygon_from_halfplanes(&ha, &hb, &opts).unwrap();
        for v in &back.vertices { prop_assert!(near2(*v, &poly.vertices)); }
        prop_assert_eq!(back.vertices.len(), poly.vertices.len());
    }

    #[test]
    fn polyhedron_matches_brute_force((a, b) in halfspaces3()) {
        let opts = PolytopeOptions::default();
        let poly = polyhedron_from_halfspaces(&a, &b, &opts).unwrap();
        // The origin is strictly inside (all offsets >= 0.2): never empty.
        prop_assert_ne!(poly.status, RegionStatus::Empty);
        if poly.status == RegionStatus::Bounded {
            prop_assert_eq!(poly.dim, 3);
            let brute = brute3(&a, &b);
            for v in &poly.vertices { prop_assert!(near3(*v, &brute), "vertex {v:?} not a brute vertex"); }
            for v in &brute { prop_assert!(near3(*v, &poly.vertices), "brute vertex {v:?} missed"); }
            // Faces: planar, outward, counter-clockwise seen from outside.
            for ((face, act), (n, d)) in poly.faces.iter().zip(&poly.active).zip(&poly.planes) {
                let k = act.unwrap();
                prop_assert!((n[0] * a[k][0] + n[1] * a[k][1] + n[2] * a[k][2] - 1.0).abs() < 1e-12);
                let m = face.len();
                for i in 0..m {
                    let (p, q, r) = (poly.vertices[face[i]], poly.vertices[face[(i + 1) % m]], poly.vertices[face[(i + 2) % m]]);
                    prop_assert!((n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - d).abs() < TOL);
                    let c = polyhedron::cross([q[0] - p[0], q[1] - p[1], q[2] - p[2]], [r[0] - q[0], r[1] - q[1], r[2] - q[2]]);
                    prop_assert!(c[0] * n[0] + c[1] * n[1] + c[2] * n[2] > 0.0);
                }
            }
            // Euler's formula for a convex polyhedron.
            let edges: usize = poly.faces.iter().map(|f| f.len()).sum::<usize>() / 2;
            prop_assert_eq!(poly.vertices.len() + poly.faces.len(), edges + 2);
        }
    }

    #[test]
    fn hull3_round_trip((a, b) in halfspaces3()) {
        hull3_round_trip_case(&a, &b)?;
    }
}

/// Half-spaces -> polyhedron -> `hull3` of its vertices gives back the same faces. Plane offsets
/// are compared relative to the size of the polyhedron: a plane fitted through vertices at
/// distance `r` from the origin carries an offset error proportional to `r` (the same scaling
/// as the vertex tolerances of the brute-force tests above).
fn hull3_round_trip_case(a: &[[f64; 3]], b: &[f64]) -> Result<(), TestCaseError> {
    let opts = PolytopeOptions::default();
    let poly = polyhedron_from_halfspaces(a, b, &opts).unwrap();
    prop_assume!(poly.status == RegionStatus::Bounded);
    // Clusters of vertices make facets that are coplanar only to rounding (a quad may come back
    // as two triangles): keep vertices apart here.
    let v = &poly.vertices;
    let scale = v
        .iter()
        .flat_map(|p| p.iter().map(|x| x.abs()))
        .fold(1.0, f64::max);
    let min_sep = (0..v.len())
        .flat_map(|i| (i + 1..v.len()).map(move |j| (i, j)))
        .map(|(i, j)| {
            ((v[i][0] - v[j][0]).powi(2)
                + (v[i][1] - v[j][1]).powi(2)
                + (v[i][2] - v[j][2]).powi(2))
            .sqrt()
        })
        .fold(f64::INFINITY, f64::min);
    prop_assume!(min_sep > 1e-3);
    let hull = hull3(&poly.vertices, &opts).unwrap();
    prop_assert_eq!(hull.vertices.len(), poly.vertices.len());
    prop_assert_eq!(hull.faces.len(), poly.faces.len());
    for (n, d) in &hull.planes {
        let found = poly.planes.iter().any(|(m, e)| {
            (n[0] - m[0]).abs() + (n[1] - m[1]).abs() + (n[2] - m[2]).abs() + (d - e).abs() / scale
                < 1e-7
        });
        prop_assert!(
            found,
            "hull plane {:?} {} not a face of the polyhedron",
            n,
            d
        );
    }
    Ok(())
}

/// Found by proptest: a polyhedron with vertices 2 km from the origin; the hull's plane offsets
/// differ from the input's by 1.2e-6 m (6e-10 relative), which the round-trip test compared
/// with an absolute 1e-7.
#[test]
fn regression_hull3_round_trip_far_vertices() {
    let a = [
        [
            -0.4697358662224341,
            -0.8828012420200645,
            0.0031910926170841463,
        ],
        [
            -0.9361209038090397,
            -0.3133545792705108,
            -0.15964510985917346,
        ],
        [-0.6460684069143499, 0.7632795120970783, 0.0],
        [-0.7893899490148999, -0.3403624738848521, 0.5108981256231393],
        [-0.1669439416783118, 0.8647340595388566, 0.4736715387379291],
        [-0.9150577348993584, 0.1783089870269515, 0.36176684058420555],
        [
            0.4900906572028414,
            0.8716700484033102,
            0.0015730349829637619,
        ],
    ];
    let b = [
        0.792519987468679,
        0.8714950343023092,
        0.45128524708427314,
        1.9865530951185457,
        0.9004685706874486,
        1.651470597862961,
        0.8146463260159146,
    ];
    hull3_round_trip_case(&a, &b).unwrap();
}

#[test]
fn degenerate_and_unbounded_outcomes() {
    let o = PolytopeOptions::default();
    // A segment: 0 <= x <= 0, -1 <= y <= 1.
    let seg = polygon_from_halfplanes(
        &[[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]],
        &[0.0, 0.0, 1.0, 1.0],
        &o,
    )
    .unwrap();
    assert_eq!((seg.status, seg.dim), (RegionStatus::Bounded, 1));
    // A strip is unbounded, with box edges marked.
    let strip = polygon_from_halfplanes(&[[1.0, 0.0], [-1.0, 0.0]], &[1.0, 1.0], &o).unwrap();
    assert_eq!(strip.status, RegionStatus::Unbounded);
    assert!(strip.active.contains(&None) && strip.active.contains(&Some(0)));
    // No constraint at all: the whole plane.
    let all = polygon_from_halfplanes(&[], &[], &o).unwrap();
    assert_eq!(all.status, RegionStatus::Unbounded);
    // Zero normals: constant constraints.
    let never = polygon_from_halfplanes(&[[0.0, 0.0]], &[-1.0], &o).unwrap();
    assert_eq!(never.status, RegionStatus::Empty);
    // 3-D: a flat square (0 <= z <= 0), an empty pair, an unbounded octant.
    let mut a = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
    ];
    let mut b = vec![1.0, 1.0, 1.0, 1.0];
    a.extend([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]);
    b.extend([0.0, 0.0]);
    let flat = polyhedron_from_halfspaces(&a, &b, &o).unwrap();
    assert_eq!((flat.status, flat.dim), (RegionStatus::Bounded, 2));
    let none =
        polyhedron_from_halfspaces(&[[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]], &[0.0, -1.0], &o).unwrap();
    assert_eq!(none.status, RegionStatus::Empty);
    let octant = polyhedron_from_halfspaces(
        &[[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]],
        &[0.0, 0.0, 0.0],
        &o,
    )
    .unwrap();
    assert_eq!(octant.status, RegionStatus::Unbounded);
    assert_eq!(octant.active.iter().filter(|a| a.is_some()).count(), 3);
}

#[test]
fn bad_input_is_an_error() {
    let o = PolytopeOptions::default();
    assert_eq!(
        polygon_from_halfplanes(&[[f64::NAN, 0.0]], &[0.0], &o),
        Err(PolytopeError::NonFinite { row: 0 })
    );
    assert!(matches!(
        polyhedron_from_halfspaces(&[[1.0, 0.0, 0.0]], &[], &o),
        Err(PolytopeError::LengthMismatch { .. })
    ));
    assert_eq!(hull3(&[], &o), Err(PolytopeError::NoPoints));
    let bad = PolytopeOptions { far: -1.0, ..o };
    assert_eq!(hull2(&[[0.0, 0.0]], &bad), Err(PolytopeError::BadOptions));
}

/// Regression: once the region became flat, later half-spaces were ignored (found by the
/// robust-region tests of stance-contact on a single point contact).
#[test]
fn regression_flat_region_is_clipped_by_later_planes() {
    let o = PolytopeOptions::default();
    let a = [
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
    ];
    let b = [0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.5];
    let p = polyhedron_from_halfspaces(&a, &b, &o).unwrap();
    assert_eq!((p.status, p.dim), (RegionStatus::Bounded, 2));
    assert_eq!(p.vertices.len(), 5);
    for v in &p.vertices {
        assert!(v[0] + v[1] <= 0.5 + 1e-12 && v[2].abs() < 1e-12);
    }
    // A segment then a point: x = y = 0 (as four half-spaces), then z <= 0 and z >= 0.
    let a = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let p = polyhedron_from_halfspaces(&a, &[0.0; 6], &o).unwrap();
    assert_eq!((p.status, p.dim), (RegionStatus::Bounded, 0));
    assert_eq!(p.vertices.len(), 1);
    // And empty when a later plane excludes the flat piece.
    let mut b = [0.0; 6];
    b[5] = -1.0; // z >= 1
    let p = polyhedron_from_halfspaces(&a, &b, &o).unwrap();
    assert_eq!(p.status, RegionStatus::Empty);
}

/// Regression: a chain of three vertices about 1e-9 apart (just above the merge distance) lost
/// the label of the long edge leaving it, and the polish then intersected the wrong lines,
/// returning a vertex 5 cm outside the region (found by stance-contact's oblique-gravity test).
#[test]
fn regression_chain_of_close_vertices_keeps_the_long_edge() {
    let text =
        include_str!("../../../../testdata/polytope/regression_chain_of_close_vertices.json");
    let v: serde_json::Value = serde_json::from_str(text).unwrap();
    let rows: Vec<[f64; 3]> = serde_json::from_value(v["halfplanes"].clone()).unwrap();
    let a: Vec<[f64; 2]> = rows.iter().map(|r| [r[0], r[1]]).collect();
    let b: Vec<f64> = rows.iter().map(|r| r[2]).collect();
    let poly = polygon_from_halfplanes(&a, &b, &PolytopeOptions::default()).unwrap();
    assert_eq!(poly.status, RegionStatus::Bounded);
    let brute = brute2(&a, &b);
    for v in &poly.vertices {
        assert!(
            near2(*v, &brute),
            "vertex {v:?} is not a vertex of the region"
        );
        for (r, c) in a.iter().zip(&b) {
            assert!(r[0] * v[0] + r[1] * v[1] - c <= 1e-9);
        }
    }
    assert_eq!(poly.vertices.len(), 14); // as the brute force (pairs of lines) finds
}

/// Many lines tangent to an ellipse (dense, nearly parallel neighbours, tiny edges): the kind of
/// input the static-equilibrium prisms produce.
fn dense2() -> impl Strategy<Value = (Vec<[f64; 2]>, Vec<f64>)> {
    (
        prop::collection::vec(0.0..std::f64::consts::TAU, 20..120),
        0.05f64..1.0,
        0.05f64..1.0,
        -1.0f64..1.0,
    )
        .prop_map(|(ts, ra, rb, c)| {
            let a: Vec<[f64; 2]> = ts.iter().map(|t| [t.cos(), t.sin()]).collect();
            // Support function of the ellipse (ra cos, rb sin) shifted by (c, 0).
            let b = a
                .iter()
                .map(|n| ((ra * n[0]).powi(2) + (rb * n[1]).powi(2)).sqrt() + c * n[0])
                .collect();
            (a, b)
        })
}

fn dense3() -> impl Strategy<Value = (Vec<[f64; 3]>, Vec<f64>)> {
    prop::collection::vec((-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), 30..70).prop_filter_map(
        "zero normal",
        |rows| {
            let mut a = vec![];
            let mut b = vec![];
            for (x, y, z) in rows {
                let n = (x * x + y * y + z * z).sqrt();
                if n < 0.1 {
                    return None;
                }
                let u = [x / n, y / n, z / n];
                // Tangent to the ellipsoid with semi-axes (1, 0.3, 0.1).
                b.push(((u[0]).powi(2) + (0.3 * u[1]).powi(2) + (0.1 * u[2]).powi(2)).sqrt());
                a.push(u);
            }
            Some((a, b))
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn dense_polygons_match_brute_force((a, b) in dense2()) {
        let poly = polygon_from_halfplanes(&a, &b, &PolytopeOptions::default()).unwrap();
        prop_assume!(poly.status == RegionStatus::Bounded);
        let brute = brute2(&a, &b);
        for v in &poly.vertices {
            prop_assert!(near2(*v, &brute), "vertex {v:?} not a brute vertex");
            for (r, c) in a.iter().zip(&b) {
                prop_assert!(r[0] * v[0] + r[1] * v[1] - c <= 1e-9, "vertex {v:?} violates a half-plane by {:e}", r[0] * v[0] + r[1] * v[1] - c);
            }
        }
        // Every brute vertex is a polygon vertex or within the merge band of an edge.
        for w in &brute {
            let on_boundary = poly.halfplanes().iter().any(|(n, c)| (n[0] * w[0] + n[1] * w[1] - c).abs() < 1e-7);
            prop_assert!(on_boundary, "brute vertex {w:?} not on the boundary");
        }
    }

    #[test]
    fn dense_polyhedra_match_brute_force((a, b) in dense3()) {
        let poly = polyhedron_from_halfspaces(&a, &b, &PolytopeOptions::default()).unwrap();
        prop_assume!(poly.status == RegionStatus::Bounded);
        let brute = brute3(&a, &b);
        for v in &poly.vertices {
            prop_assert!(near3(*v, &brute), "vertex {v:?} not a brute vertex");
            for (r, c) in a.iter().zip(&b) {
                prop_assert!(r[0] * v[0] + r[1] * v[1] + r[2] * v[2] - c <= 1e-9);
            }
        }
        for w in &brute {
            let on_boundary = poly.planes.iter().any(|(n, c)| (n[0] * w[0] + n[1] * w[1] + n[2] * w[2] - c).abs() < 1e-7);
            prop_assert!(on_boundary, "brute vertex {w:?} not on the boundary");
        }
    }
}

/// A region entirely beyond `far` from the origin is found (it was reported empty before the
/// rows were moved to the region), with or without a larger `far`.
#[test]
fn region_beyond_far_is_found() {
    let a = [[-1.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, -1.0]];
    let b = [-2e6, 2e6 + 1.0, 1.0, 1.0]; // 2e6 <= x <= 2e6 + 1, |y| <= 1
    let o = PolytopeOptions::default();
    for opts in [o, PolytopeOptions { far: 1e7, ..o }] {
        let p = polygon_from_halfplanes(&a, &b, &opts).unwrap();
        assert_eq!((p.status, p.vertices.len()), (RegionStatus::Bounded, 4));
        for v in &p.vertices {
            assert!((v[0] - 2e6).abs() <= 1.0 + 1e-9 && v[1].abs() <= 1.0 + 1e-9);
        }
    }
}

/// Regression: through the polar around the centroid alone, needles lost thin faces; the
/// whitening makes them round. A 1e5 x 1 x 0.01 box, tilted, with interior points.
#[test]
fn regression_hull3_of_a_needle() {
    let r = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1);
    let mut pts = vec![];
    for x in [-5e4, 5e4] {
        for y in [-0.5, 0.5] {
            for z in [-0.005, 0.005] {
                let p = r * nalgebra::Vector3::new(x, y, z);
                pts.push([p[0], p[1], p[2]]);
            }
        }
    }
    for t in [-0.9, -0.3, 0.2, 0.8] {
        let p = r * nalgebra::Vector3::new(4e4 * t, 0.3 * t, 0.001 * t);
        pts.push([p[0], p[1], p[2]]);
    }
    let h = hull3(&pts, &PolytopeOptions::default()).unwrap();
    assert_eq!((h.vertices.len(), h.faces.len()), (8, 6));
    for (n, d) in &h.planes {
        for p in &pts {
            assert!(n[0] * p[0] + n[1] * p[1] + n[2] * p[2] <= d + 1e-9);
        }
    }
}

/// Regression: the polish recomputed three clipped vertices (more than `merge_tol` apart) as
/// the same corner, where many lines meet; the 1e-14 edges left between them gave
/// [`Polygon::halfplanes`] a garbage half-plane that cut the polygon's interior (found by
/// stance-contact's agreement test in the review of issue 3: a CoM 1.9 cm inside the
/// static-equilibrium polygon got a negative margin).
#[test]
fn regression_polish_collapses_vertices_merges_them() {
    let text =
        include_str!("../../../../testdata/polytope/regression_polish_collapses_vertices.json");
    let v: serde_json::Value = serde_json::from_str(text).unwrap();
    let rows: Vec<[f64; 3]> = serde_json::from_value(v["halfplanes"].clone()).unwrap();
    let a: Vec<[f64; 2]> = rows.iter().map(|r| [r[0], r[1]]).collect();
    let b: Vec<f64> = rows.iter().map(|r| r[2]).collect();
    let o = PolytopeOptions::default();
    let poly = polygon_from_halfplanes(&a, &b, &o).unwrap();
    assert_eq!((poly.status, poly.dim), (RegionStatus::Bounded, 2));
    let n = poly.vertices.len();
    for i in 0..n {
        let (p, q) = (poly.vertices[i], poly.vertices[(i + 1) % n]);
        assert!(
            (p[0] - q[0]).hypot(p[1] - q[1]) > o.merge_tol,
            "vertices {i} and {} coincide: {p:?} {q:?}",
            (i + 1) % n
        );
    }
    // Every edge's half-plane holds every vertex (and so the interior).
    for (h, c) in poly.halfplanes() {
        for v in &poly.vertices {
            assert!(
                h[0] * v[0] + h[1] * v[1] - c <= 1e-9,
                "{h:?} {c} cuts {v:?}"
            );
        }
    }
    let brute = brute2(&a, &b);
    for v in &poly.vertices {
        assert!(
            near2(*v, &brute),
            "vertex {v:?} is not a vertex of the region"
        );
    }
}
