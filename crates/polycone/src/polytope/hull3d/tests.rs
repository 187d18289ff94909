//! Tests of the direct 3-D hull: exact small cases against a brute-force hull in rational
//! arithmetic, round trips through the half-space routine, hard shapes (needles, slabs,
//! clusters, far from the origin), and the fallback.

use super::*;
use crate::polytope::polyhedron_from_halfspaces;
use num_traits::Signed;
use proptest::prelude::*;

/// The direct route, required to pass the check (no fallback).
fn direct_checked(pts: &[[f64; 3]], opts: &PolytopeOptions) -> Polyhedron {
    let mut p = pts.to_vec();
    dedup_points(&mut p, opts.merge_tol);
    let poly = hull3_direct(&p, opts).unwrap_or_else(|e| panic!("direct route failed: {e}"));
    check_hull(&p, &poly, opts).unwrap_or_else(|e| panic!("direct route fails its check: {e}"));
    poly
}

use super::predicates::tests::orient_rational;

/// Brute-force hull in rational arithmetic: the triangles `i j k` (counter-clockwise from
/// outside) with no point above them. For points in general position these are the facets.
fn brute_facets(pts: &[[f64; 3]]) -> Vec<[usize; 3]> {
    let n = pts.len();
    let mut out = vec![];
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                if !(i < j && i < k && j != k) {
                    continue;
                }
                let signs: Vec<i8> = (0..n)
                    .map(|l| orient_rational(&pts[i], &pts[j], &pts[k], &pts[l]))
                    .collect();
                if signs.iter().all(|&s| s <= 0) && signs.iter().any(|&s| s < 0) {
                    out.push([i, j, k]);
                }
            }
        }
    }
    out
}

fn same_point(a: [f64; 3], b: [f64; 3]) -> bool {
    a == b
}

fn face_points(poly: &Polyhedron, f: usize) -> Vec<[f64; 3]> {
    poly.faces[f].iter().map(|&v| poly.vertices[v]).collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Random points (general position with probability 1): the same facets as the brute
    /// force, as vertex triples in the same orientation.
    #[test]
    fn small_hulls_match_brute_force(
        pts in prop::collection::vec([-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0], 4..11)
    ) {
        let opts = PolytopeOptions::default();
        prop_assume!(affine_dim(&pts, 1e-3) == 3);
        let poly = direct_checked(&pts, &opts);
        let brute = brute_facets(&pts);
        prop_assert_eq!(poly.faces.len(), brute.len());
        for f in 0..poly.faces.len() {
            let fp = face_points(&poly, f);
            prop_assert_eq!(fp.len(), 3);
            // Some rotation of the brute triangle equals the face loop.
            let found = brute.iter().any(|t| {
                (0..3).any(|r| (0..3).all(|q| same_point(fp[q], pts[t[(q + r) % 3]])))
            });
            prop_assert!(found, "face {:?} is not a brute-force facet", fp);
        }
    }
}

use crate::polytope::tests::halfspaces3;

/// Half-spaces -> polyhedron -> direct hull of its vertices: the check passes, and every hull
/// plane is a plane of the polyhedron (normals to 1e-7, offsets to 1e-7 of the size). When the
/// polyhedron has no vertices closer than `min_sep`, the face and vertex counts agree too.
///
/// The vertices of the polyhedron carry a relative error of about 1e-11 (a corner 3e5 m from
/// the origin is off its planes by 2e-6 m), so the hull's tolerances are relative to the size
/// (`1e-9 scale`): with an absolute 1e-9 such a face is, correctly, not one plane.
fn round_trip_direct(a: &[[f64; 3]], b: &[f64], min_sep: f64) -> Result<(), TestCaseError> {
    let poly = polyhedron_from_halfspaces(a, b, &PolytopeOptions::default()).unwrap();
    prop_assume!(poly.status == RegionStatus::Bounded && poly.dim == 3);
    let v = &poly.vertices;
    let scale = v
        .iter()
        .flat_map(|p| p.iter().map(|x| x.abs()))
        .fold(1.0, f64::max);
    let opts = PolytopeOptions {
        dist_tol: 1e-9 * scale,
        merge_tol: 1e-9 * scale,
        ..Default::default()
    };
    let sep = (0..v.len())
        .flat_map(|i| (i + 1..v.len()).map(move |j| (i, j)))
        .map(|(i, j)| {
            ((v[i][0] - v[j][0]).powi(2)
                + (v[i][1] - v[j][1]).powi(2)
                + (v[i][2] - v[j][2]).powi(2))
            .sqrt()
        })
        .fold(f64::INFINITY, f64::min);
    let hull = direct_checked(v, &opts);
    if sep > min_sep {
        prop_assert_eq!(hull.vertices.len(), poly.vertices.len());
        prop_assert_eq!(hull.faces.len(), poly.faces.len());
        for (n, d) in &hull.planes {
            let found = poly.planes.iter().any(|(m, e)| {
                (n[0] - m[0]).abs()
                    + (n[1] - m[1]).abs()
                    + (n[2] - m[2]).abs()
                    + (d - e).abs() / scale
                    < 1e-7
            });
            prop_assert!(
                found,
                "hull plane {:?} {} not a face of the polyhedron",
                n,
                d
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn round_trip_through_halfspaces((a, b) in halfspaces3()) {
        round_trip_direct(&a, &b, 0.0)?;
    }
}

/// Deterministic uniform numbers in `[-1, 1)` for the fixed-shape tests.
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// Volume of a checked polyhedron (divergence theorem over its faces, around its first
/// vertex to avoid cancellation far from the origin).
fn volume(poly: &Polyhedron) -> f64 {
    let o = poly.vertices[0];
    let mut vol = 0.0;
    for (face, &(n, d)) in poly.faces.iter().zip(&poly.planes) {
        let d = d - (n[0] * o[0] + n[1] * o[1] + n[2] * o[2]);
        let p0 = poly.vertices[face[0]];
        let mut area = 0.0;
        for i in 1..face.len() - 1 {
            let (a, b) = (poly.vertices[face[i]], poly.vertices[face[i + 1]]);
            let e = [a[0] - p0[0], a[1] - p0[1], a[2] - p0[2]];
            let f = [b[0] - p0[0], b[1] - p0[1], b[2] - p0[2]];
            let c = [
                e[1] * f[2] - e[2] * f[1],
                e[2] * f[0] - e[0] * f[2],
                e[0] * f[1] - e[1] * f[0],
            ];
            area += 0.5 * (c[0] * n[0] + c[1] * n[1] + c[2] * n[2]);
        }
        vol += d * area / 3.0;
    }
    vol
}

/// A box with half-sizes `h`, rotated by `r` and moved to `c`, with points inside and on its
/// faces: its corners, plus `extra` random points.
fn box_points(
    h: [f64; 3],
    r: &nalgebra::Rotation3<f64>,
    c: [f64; 3],
    extra: usize,
) -> Vec<[f64; 3]> {
    let mut rng = Lcg(7);
    let place = |x: [f64; 3]| {
        let p = r * nalgebra::Vector3::new(x[0], x[1], x[2]);
        [p[0] + c[0], p[1] + c[1], p[2] + c[2]]
    };
    let mut pts = vec![];
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                pts.push(place([sx * h[0], sy * h[1], sz * h[2]]));
            }
        }
    }
    for k in 0..extra {
        let mut x = [rng.next() * h[0], rng.next() * h[1], rng.next() * h[2]];
        if k % 2 == 0 {
            // On a face.
            let axis = k % 3;
            x[axis] = if rng.next() > 0.0 { h[axis] } else { -h[axis] };
        }
        pts.push(place(x));
    }
    pts
}

/// Elongated boxes (1 km x 1 m x 1 mm and thinner), tilted, at and far from the origin, with
/// points inside and on the faces: 8 corners, 6 faces, the box's normals.
#[test]
fn elongated_boxes() {
    let r = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1);
    for h in [
        [500.0, 0.5, 5e-4],
        [5e4, 0.5, 5e-3],
        [0.5, 5e-4, 5e-4],
        [5e2, 5e2, 1e-6],
    ] {
        for c in [[0.0; 3], [1e3, -2e3, 5e2], [1e5, 1e5, -1e5]] {
            let pts = box_points(h, &r, c, 40);
            let poly = direct_checked(&pts, &PolytopeOptions::default());
            assert_eq!(
                (poly.vertices.len(), poly.faces.len()),
                (8, 6),
                "box {h:?} at {c:?}"
            );
            for (n, _) in &poly.planes {
                let local = r.inverse() * nalgebra::Vector3::new(n[0], n[1], n[2]);
                let axis = local.iamax();
                assert!(
                    (local[axis].abs() - 1.0).abs() < 1e-9,
                    "normal {local:?} of box {h:?}"
                );
            }
            // Each face may sit up to dist_tol off: the volume within area x dist_tol.
            let vol = volume(&poly);
            let true_vol = 8.0 * h[0] * h[1] * h[2];
            let area = 8.0 * (h[0] * h[1] + h[1] * h[2] + h[0] * h[2]);
            assert!(
                (vol - true_vol).abs() <= 1e-9 * area,
                "volume {vol} vs {true_vol}"
            );
        }
    }
}

/// The unit cube with each corner replaced by a cluster of nearly coincident points (radius
/// `r` from 1e-12, below the merge distance, to 1e-4): the direct route passes the check; the
/// clusters below the tolerances leave the cube; larger ones add small faces and at most
/// `O(r)` volume.
#[test]
fn clusters_of_nearly_coincident_points() {
    let mut rng = Lcg(11);
    for r in [1e-12, 1e-10, 1e-9, 3e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4] {
        let mut pts = vec![];
        for x in [0.0, 1.0] {
            for y in [0.0, 1.0] {
                for z in [0.0, 1.0] {
                    for _ in 0..5 {
                        pts.push([x + r * rng.next(), y + r * rng.next(), z + r * rng.next()]);
                    }
                }
            }
        }
        let opts = PolytopeOptions::default();
        eprintln!("r = {r}");
        let poly = direct_checked(&pts, &opts);
        if r < opts.merge_tol {
            assert_eq!((poly.vertices.len(), poly.faces.len()), (8, 6), "r = {r}");
        }
        assert!((volume(&poly) - 1.0).abs() <= 12.0 * r + 1e-12, "r = {r}");
    }
}

/// Points far from the origin: a cube with points on its faces and inside, 1e4 and 1e6 away.
#[test]
fn far_from_the_origin() {
    let r = nalgebra::Rotation3::identity();
    for c in [[1e4, -1e4, 1e4], [1e6, 2e6, -1e6]] {
        let pts = box_points([0.5, 0.5, 0.5], &r, c, 60);
        let poly = direct_checked(&pts, &PolytopeOptions::default());
        assert_eq!((poly.vertices.len(), poly.faces.len()), (8, 6));
        for face in &poly.faces {
            assert_eq!(face.len(), 4);
        }
    }
}

/// A 3x3x3 grid (exactly coplanar and collinear points everywhere): the cube, with its
/// normals exactly on the axes.
#[test]
fn grid_gives_the_cube() {
    let mut pts = vec![];
    for x in [0.0, 0.5, 1.0] {
        for y in [0.0, 0.5, 1.0] {
            for z in [0.0, 0.5, 1.0] {
                pts.push([x, y, z]);
            }
        }
    }
    let poly = direct_checked(&pts, &PolytopeOptions::default());
    assert_eq!((poly.vertices.len(), poly.faces.len()), (8, 6));
    for (n, d) in &poly.planes {
        assert!(
            n.iter().filter(|x| x.abs() == 1.0).count() == 1,
            "normal {n:?}"
        );
        assert!(*d == 0.0 || *d == 1.0);
    }
}

/// Lower-dimensional inputs keep the previous behaviour: the distinct points, no faces.
#[test]
fn flat_inputs_have_no_faces() {
    let o = PolytopeOptions::default();
    let square = [
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
        [0.5, 0.5, 1.0],
    ];
    let h = hull3(&square, &o).unwrap();
    assert_eq!((h.dim, h.vertices.len(), h.faces.len()), (2, 5, 0));
    let h = hull3(&[[1.0, 2.0, 3.0], [1.0, 2.0, 3.0]], &o).unwrap();
    assert_eq!((h.dim, h.vertices.len()), (0, 1));
}

/// A slab only 1.5 `dist_tol` thick is degenerate at the scale of the tolerance: whatever
/// the route, the answer is checked (or an error), never an unchecked polytope.
#[test]
fn slab_at_the_tolerance_is_checked_or_an_error() {
    let o = PolytopeOptions::default();
    let mut rng = Lcg(3);
    let mut pts = vec![];
    for _ in 0..30 {
        let z = if rng.next() > 0.0 { 1.5e-9 } else { 0.0 };
        pts.push([rng.next(), rng.next(), z]);
    }
    match hull3(&pts, &o) {
        Ok(h) => {
            if h.dim == 3 {
                check_hull(&pts, &h, &o).unwrap();
            }
        }
        Err(e) => assert!(matches!(e, PolytopeError::HullCheck { .. }), "{e}"),
    }
}

/// Random point clouds with random clusters of nearly coincident points (spacing `10^e` for
/// `e` in `logs`), stretched and moved.
fn clouds(logs: std::ops::Range<f64>) -> impl Strategy<Value = Vec<[f64; 3]>> {
    (
        prop::collection::vec([-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0], 4..40),
        prop::collection::vec(
            (0usize..40, logs, [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0]),
            0..20,
        ),
        [-3.0f64..3.0, -3.0f64..3.0, -3.0f64..3.0],
        [-4.0f64..4.0, -4.0f64..4.0, -4.0f64..4.0],
        -1.0f64..1.0,
    )
        .prop_map(|(mut pts, near, logs, shift, angle)| {
            for (i, e, d) in near {
                let p = pts[i % pts.len()];
                let r = 10f64.powf(e);
                pts.push([p[0] + r * d[0], p[1] + r * d[1], p[2] + r * d[2]]);
            }
            let rot = nalgebra::Rotation3::from_euler_angles(angle, 2.0 * angle, -angle);
            pts.iter()
                .map(|p| {
                    let q = rot
                        * nalgebra::Vector3::new(
                            p[0] * 10f64.powf(logs[0]),
                            p[1] * 10f64.powf(logs[1]),
                            p[2] * 10f64.powf(logs[2]),
                        );
                    [
                        q[0] + 10f64.powf(shift[0]),
                        q[1] - 10f64.powf(shift[1]),
                        q[2] + 10f64.powf(shift[2]),
                    ]
                })
                .collect()
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Clustered, stretched and moved clouds: the direct route passes the check (no fallback).
    #[test]
    fn clusters_stretched_and_moved_pass_the_check(pts in clouds(-13.0..-4.0)) {
        let opts = PolytopeOptions::default();
        let mut p = pts.clone();
        dedup_points(&mut p, opts.merge_tol);
        prop_assume!(affine_dim(&p, opts.dist_tol) == 3);
        direct_checked(&pts, &opts);
    }

    /// The public contract on the same clouds: a checked solid, or the `HullCheck` error.
    #[test]
    fn clusters_stretched_and_moved_are_checked_or_an_error(pts in clouds(-13.0..-4.0)) {
        let opts = PolytopeOptions::default();
        match hull3(&pts, &opts) {
            Ok(h) => {
                if h.dim == 3 {
                    let mut p = pts.clone();
                    dedup_points(&mut p, opts.merge_tol);
                    prop_assert_eq!(check_hull(&p, &h, &opts), Ok(()));
                }
            }
            Err(e) => prop_assert!(matches!(e, PolytopeError::HullCheck { .. }), "{}", e),
        }
    }

    /// Where the polar route passes the check, both routes find the same facets.
    #[test]
    fn same_facets_as_the_polar_route(
        pts in prop::collection::vec([-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0], 4..60)
    ) {
        let opts = PolytopeOptions::default();
        prop_assume!(affine_dim(&pts, 1e-3) == 3);
        let direct = direct_checked(&pts, &opts);
        let polar = hull3_polar(&pts, &opts).unwrap();
        prop_assume!(check_hull(&pts, &polar, &opts).is_ok());
        prop_assert_eq!(direct.faces.len(), polar.faces.len());
        prop_assert_eq!(direct.vertices.len(), polar.vertices.len());
        for (n, d) in &direct.planes {
            let found = polar.planes.iter().any(|(m, e)| {
                (n[0] - m[0]).abs() + (n[1] - m[1]).abs() + (n[2] - m[2]).abs() + (d - e).abs() < 1e-7
            });
            prop_assert!(found, "direct plane {:?} {} not a polar plane", n, d);
        }
    }
}

/// How often the direct route fails its check on clustered clouds, by cluster spacing (run
/// with `cargo test -p polycone --lib direct_failure_rates -- --ignored --nocapture`).
#[test]
#[ignore]
fn direct_failure_rates() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let opts = PolytopeOptions::default();
    for (lo, hi) in [
        (-13.0, -9.5),
        (-9.5, -8.0),
        (-8.0, -6.0),
        (-6.0, -4.0),
        (-13.0, -4.0),
    ] {
        let mut runner = TestRunner::deterministic();
        let strat = clouds(lo..hi);
        let (mut n, mut direct_fail, mut polar_ok, mut errors) = (0, 0, 0, 0);
        let mut reasons: Vec<&'static str> = vec![];
        for _ in 0..10000 {
            let pts = strat.new_tree(&mut runner).unwrap().current();
            let mut p = pts.clone();
            dedup_points(&mut p, opts.merge_tol);
            if affine_dim(&p, opts.dist_tol) < 3 {
                continue;
            }
            n += 1;
            let why = hull3_direct(&p, &opts).and_then(|h| check_hull(&p, &h, &opts));
            if let Err(why) = why {
                reasons.push(why);
                direct_fail += 1;
                match hull3(&pts, &opts) {
                    Ok(_) => polar_ok += 1,
                    Err(_) => errors += 1,
                }
            }
        }
        eprintln!(
            "spacing 1e{lo}..1e{hi}: {n} clouds, direct route fails {direct_fail}, \
             polar fallback passes {polar_ok}, errors {errors}"
        );
        reasons.sort_unstable();
        reasons.dedup();
        eprintln!("  direct route failures: {reasons:?}");
    }
}

/// The robust static-equilibrium regions `M` of the example scenes (`testdata/polytope`): the
/// direct hull of their vertices passes the check and finds the region's faces again.
#[test]
fn robust_region_vertices_round_trip() {
    for (scene, faces, pts) in robust_regions() {
        let poly = direct_checked(&pts, &PolytopeOptions::default());
        assert_eq!(poly.vertices.len(), pts.len(), "{scene}");
        assert_eq!(poly.faces.len(), faces, "{scene}");
    }
}

fn robust_regions() -> Vec<(String, usize, Vec<[f64; 3]>)> {
    let text = include_str!("../../../../../testdata/polytope/robust_region_vertices.json");
    let v: serde_json::Value = serde_json::from_str(text).unwrap();
    v["regions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            (
                r["scene"].as_str().unwrap().to_string(),
                r["faces"].as_u64().unwrap() as usize,
                serde_json::from_value(r["vertices"].clone()).unwrap(),
            )
        })
        .collect()
}

/// Timing of the direct and polar routes (and the public `hull3`, checked) on the vertices of
/// the robust regions. Run in release:
/// `cargo test -p polycone --release --lib hull3_timing -- --ignored --nocapture`.
#[test]
#[ignore]
fn hull3_timing() {
    let opts = PolytopeOptions::default();
    let time = |f: &dyn Fn()| {
        let mut best = f64::INFINITY;
        for _ in 0..7 {
            let reps = 200;
            let t = std::time::Instant::now();
            for _ in 0..reps {
                f();
            }
            best = best.min(t.elapsed().as_secs_f64() / reps as f64);
        }
        best * 1e6
    };
    eprintln!(
        "scene            points faces  polar_us  exact_us  direct_us  check_us  hull3_us  hull3/polar"
    );
    for (scene, faces, pts) in robust_regions() {
        let polar = time(&|| {
            std::hint::black_box(hull3_polar(&pts, &opts).unwrap());
        });
        let direct = time(&|| {
            std::hint::black_box(hull3_direct(&pts, &opts).unwrap());
        });
        let exact = time(&|| {
            std::hint::black_box(incremental::exact_hull(&pts, opts.dist_tol).unwrap());
        });
        let h = hull3_direct(&pts, &opts).unwrap();
        let check = time(&|| {
            check_hull(&pts, &h, &opts).unwrap();
        });
        let public = time(&|| {
            std::hint::black_box(hull3(&pts, &opts).unwrap());
        });
        eprintln!(
            "{scene:16} {:6} {faces:5} {polar:9.1} {exact:9.1} {direct:10.1} {check:9.1} {public:9.1} {:12.2}",
            pts.len(),
            public / polar
        );
    }
}

/// Found by the round-trip proptest (30 000 cases, seed `61864d09` in
/// `proptest-regressions/polytope/tests.txt`): the polar route returned a face plane off by
/// 5e-8 in its normal and 9e-6 in its offset (a facet split by the polar's rounding). The
/// direct route finds the polyhedron's faces.
#[test]
fn regression_polar_route_plane_off_seed_61864d09() {
    let a = [
        [0.6332484730829973, -0.7655401029627865, 0.11377487461552709],
        [0.5806521320453847, 0.5836526030298433, -0.5676202432327774],
        [
            -0.19275043840213843,
            -0.8109829025923304,
            -0.552407458493006,
        ],
        [-0.5786884133766269, 0.7648909749849084, -0.2829514386078967],
        [-0.6130893333412604, 0.5407956963253205, -0.5759005853263051],
        [-0.6546447568458916, -0.4994092694269996, 0.5674774215284463],
    ];
    let b = [
        0.25251374044360997,
        1.4399266978789091,
        0.3103146289285515,
        1.5985392791131385,
        0.30249578183219283,
        1.343821346632104,
    ];
    round_trip_direct(&a, &b, 0.0).unwrap();
    // The check catches the polar route's answer (a face vertex 9e-6 off its plane).
    let o = PolytopeOptions::default();
    let poly = polyhedron_from_halfspaces(&a, &b, &o).unwrap();
    let polar = hull3_polar(&poly.vertices, &o).unwrap();
    assert_eq!(
        check_hull(&poly.vertices, &polar, &o),
        Err("a face vertex is farther than dist_tol from the face plane")
    );
    // And through the public function, with absolute default tolerances.
    let poly = polyhedron_from_halfspaces(&a, &b, &PolytopeOptions::default()).unwrap();
    let hull = hull3(&poly.vertices, &PolytopeOptions::default()).unwrap();
    assert_eq!(hull.faces.len(), poly.faces.len());
    for (n, d) in &hull.planes {
        assert!(poly.planes.iter().any(|(m, e)| {
            (n[0] - m[0]).abs() + (n[1] - m[1]).abs() + (n[2] - m[2]).abs() + (d - e).abs() < 1e-7
        }));
    }
}

/// The check rejects each kind of broken polyhedron (so that it can fail).
#[test]
fn check_rejects_broken_polyhedra() {
    let mut pts = vec![];
    for x in [0.0, 1.0] {
        for y in [0.0, 1.0] {
            for z in [0.0, 1.0] {
                pts.push([x, y, z]);
            }
        }
    }
    let o = PolytopeOptions::default();
    let cube = direct_checked(&pts, &o);
    let broken = |f: &dyn Fn(&mut Polyhedron)| {
        let mut p = cube.clone();
        f(&mut p);
        check_hull(&pts, &p, &o).unwrap_err()
    };
    assert_eq!(
        broken(&|p| p.planes[0].1 -= 1e-6),
        "a point lies outside a face plane by more than dist_tol"
    );
    assert_eq!(
        broken(&|p| p.planes[0].1 += 1e-6),
        "a face vertex is farther than dist_tol from the face plane"
    );
    assert_eq!(
        broken(&|p| p.vertices[0][0] -= 1e-6),
        "a vertex is not an input point"
    );
    assert_eq!(
        broken(&|p| p.planes.iter_mut().for_each(|q| q.0[0] *= 1.0 + 1e-6)),
        "a face normal is not a unit vector"
    );
    assert_eq!(
        broken(&|p| p.faces[0].reverse()),
        "a face is not convex (a vertex inside by more than dist_tol / sin)"
    );
    assert_eq!(
        broken(&|p| {
            p.faces.pop();
            p.planes.pop();
            p.active.pop();
        }),
        "a vertex lies on fewer than three faces"
    );
    assert_eq!(
        broken(&|p| p.faces[0].swap(0, 1)),
        "a face is not convex (a vertex inside by more than dist_tol / sin)"
    );
    assert_eq!(
        broken(&|p| {
            p.faces.push(p.faces[0].clone());
            p.planes.push(p.planes[0]);
            p.active.push(None);
        }),
        "a directed edge appears twice"
    );
    // A pentagonal prism whose top face is walked as a pentagram (winds twice).
    let mut prism = vec![];
    for z in [0.0, 1.0] {
        for k in 0..5 {
            let t = std::f64::consts::TAU * k as f64 / 5.0;
            prism.push([t.cos(), t.sin(), z]);
        }
    }
    let mut p = direct_checked(&prism, &o);
    let top = p.planes.iter().position(|(n, _)| n[2] > 0.5).unwrap();
    let f = p.faces[top].clone();
    p.faces[top] = vec![f[0], f[2], f[4], f[1], f[3]];
    assert_eq!(
        check_hull(&prism, &p, &o).unwrap_err(),
        "a face loop does not wind once around its normal"
    );
    // An input point listed as a vertex but on no face.
    let mut inside = pts.clone();
    inside.push([0.5, 0.5, 0.5]);
    let mut p = cube.clone();
    p.vertices.push([0.5, 0.5, 0.5]);
    assert_eq!(
        check_hull(&inside, &p, &o).unwrap_err(),
        "a vertex lies on fewer than three faces"
    );
}

/// How often the direct route fails on random slabs barely thicker than `dist_tol` (run with
/// `cargo test -p polycone --release --lib slab_failure_rates -- --ignored --nocapture`).
#[test]
#[ignore]
fn slab_failure_rates() {
    let o = PolytopeOptions::default();
    for th in [1.1e-9, 1.5e-9, 2e-9, 3e-9, 5e-9, 1e-8] {
        let mut rng = Lcg(3);
        let (mut ok, mut n) = (0, 0);
        for _ in 0..200 {
            let mut pts = vec![];
            for _ in 0..30 {
                let z = if rng.next() > 0.0 { th } else { 0.0 };
                pts.push([rng.next(), rng.next(), z]);
            }
            let mut p = pts.clone();
            dedup_points(&mut p, o.merge_tol);
            if affine_dim(&p, o.dist_tol) < 3 {
                continue;
            }
            n += 1;
            if hull3_direct(&p, &o)
                .and_then(|h| check_hull(&p, &h, &o))
                .is_ok()
            {
                ok += 1;
            }
        }
        eprintln!("slab thickness {th:e}: the direct route passes on {ok} of {n}");
    }
}
