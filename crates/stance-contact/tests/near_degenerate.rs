//! Near-degenerate stances through the whole pipeline (GIWC, CoM tests, QP): a world origin far
//! away, a foot rolled by a tiny angle, tiny contact patches. The GIWC either comes back
//! certified and then agrees with the QP outside the band, or the conversion reports an error:
//! never a silently wrong answer. The direct static-equilibrium polygon (no `U_stance`) agrees
//! with the QP on the same CoMs.

use nalgebra::{Rotation3, Vector3};
use stance_contact::equilibrium::{PolygonWorkspace, StaticEquilibrium};
use stance_contact::{
    supporting_forces, w_gi_static, Contact, ForcesOutcome, FrictionModel, Shape, Stance,
};

const FACE_BAND: f64 = 1e-6;

fn foot(name: &str, p: [f64; 3], roll_deg: f64, half: (f64, f64)) -> Contact {
    let r = Rotation3::from_axis_angle(&Vector3::x_axis(), roll_deg.to_radians());
    let m = r.matrix();
    let rot = [
        [m[(0, 0)], m[(0, 1)], m[(0, 2)]],
        [m[(1, 0)], m[(1, 1)], m[(1, 2)]],
        [m[(2, 0)], m[(2, 1)], m[(2, 2)]],
    ];
    let shape = Shape::Rectangle {
        half_length: half.0,
        half_width: half.1,
    };
    Contact::new(name, p, rot, shape, 0.7, &Default::default()).unwrap()
}

/// The CoMs tested around `origin`: a 41 x 9 grid 0.8 m above it.
fn com_grid(origin: [f64; 3]) -> impl Iterator<Item = [f64; 3]> {
    (0..41).flat_map(move |i| {
        (0..9).map(move |j| {
            [
                origin[0] - 0.25 + 0.0125 * i as f64,
                origin[1] - 0.2 + 0.05 * j as f64,
                origin[2] + 0.8,
            ]
        })
    })
}

/// Two flat feet 20 cm apart (the second `dz` higher), centred on `o`.
fn two_feet(o: [f64; 3], dz: f64, roll_deg: f64, half: (f64, f64)) -> Stance {
    Stance::new(
        vec![
            foot("LF", [o[0], o[1] + 0.1, o[2]], 0.0, half),
            foot("RF", [o[0], o[1] - 0.1, o[2] + dz], roll_deg, half),
        ],
        FrictionModel::default(),
    )
    .unwrap()
}

fn check(stance: &Stance, origin: [f64; 3], what: &str) {
    check_direct_polygon(stance, origin, what);
    let giwc = match stance.u_stance(&Default::default()) {
        Ok(g) => g,
        Err(e) => {
            // An error is an acceptable outcome; a wrong cone is not.
            eprintln!("{what}: conversion refused: {e}");
            return;
        }
    };
    assert!(giwc.certified, "{what}: uncertified cone returned");
    let g = [0.0, 0.0, -9.81];
    let eq = StaticEquilibrium::new(&giwc, g, &Default::default()).unwrap();
    let mut agreed = 0;
    for p in com_grid(origin) {
        let w = w_gi_static(1.0, g, p);
        let n = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        let v = giwc.max_violation(&w) / n;
        if v.abs() <= FACE_BAND {
            continue;
        }
        let qp = supporting_forces(stance, &w, &Default::default()).unwrap();
        let want = if v < 0.0 {
            ForcesOutcome::Feasible
        } else {
            ForcesOutcome::Infeasible
        };
        assert_eq!(qp.outcome, want, "{what}: CoM {p:?}, face value {v}");
        assert_eq!(eq.contains(p), v < 0.0, "{what}: half-spaces at {p:?}");
        agreed += 1;
    }
    assert!(
        agreed > 300,
        "{what}: too few CoMs outside the band ({agreed})"
    );
}

/// The direct polygon (at the CoM height used below) against the QP, outside a 1e-6 m band.
fn check_direct_polygon(stance: &Stance, origin: [f64; 3], what: &str) {
    let g = [0.0, 0.0, -9.81];
    let out = PolygonWorkspace::new()
        .static_polygon(stance, g, origin[2] + 0.8, &Default::default())
        .unwrap();
    eprintln!("{what}: direct polygon route {:?}", out.route);
    let mut agreed = 0;
    for p in com_grid(origin) {
        let m = out.polygon.margin([p[0], p[1]]);
        if m.abs() <= 1e-6 {
            continue;
        }
        let qp = supporting_forces(stance, &w_gi_static(1.0, g, p), &Default::default()).unwrap();
        let want = if m > 0.0 {
            ForcesOutcome::Feasible
        } else {
            ForcesOutcome::Infeasible
        };
        assert_eq!(
            qp.outcome, want,
            "{what}: direct polygon at {p:?}, margin {m:e}"
        );
        agreed += 1;
    }
    assert!(
        agreed > 300,
        "{what}: too few CoMs outside the band ({agreed})"
    );
}

#[test]
fn far_origin_1_km_direct_polygon() {
    let o = [1000.0, -600.0, 3.0];
    check_direct_polygon(&two_feet(o, 0.0, 0.0, (0.11, 0.065)), o, "1 km origin");
}

#[test]
fn out_of_plane_feet_direct_polygon() {
    for dz in [1e-5, 1e-7, 1e-9] {
        let s = two_feet([0.0; 3], dz, 0.0, (0.11, 0.065));
        check_direct_polygon(&s, [0.0; 3], &format!("{dz} m out of plane"));
    }
}

#[test]
fn far_origin_50_m() {
    let o = [50.0, -30.0, 2.0];
    check(&two_feet(o, 0.0, 0.0, (0.11, 0.065)), o, "50 m origin");
}

/// A stance 1 km from the world origin (the torques of `w_GI` are 1e3 times the forces).
#[test]
fn far_origin_1_km() {
    let o = [700.0, -700.0, 150.0];
    let s = Stance::new(
        vec![
            foot("LF", [o[0], o[1] + 0.1, o[2]], 0.0, (0.11, 0.065)),
            foot(
                "RF",
                [o[0] + 0.1, o[1] - 0.1, o[2] + 0.05],
                10.0,
                (0.11, 0.065),
            ),
        ],
        FrictionModel::default(),
    )
    .unwrap();
    let giwc = s.u_stance(&Default::default()).unwrap();
    assert!(giwc.certified);
    assert_eq!(giwc.equations.nrows(), 0);
    let g = [0.0, 0.0, -9.81];
    let eq = StaticEquilibrium::new(&giwc, g, &Default::default()).unwrap();
    // The metric CoM test (half-spaces in metres) against the QP, outside a 0.1 mm band.
    // (Not the face value: it is relative to |w_GI| at the world origin, whose torque is 1e3
    // times its force here, so its 1e-6 band is about 1 m wide. Regression: the QP also
    // worked at the world origin and called CoMs 14 cm outside the support feasible.)
    const BAND_M: f64 = 1e-4;
    let (mut stable, mut unstable) = (0, 0);
    for i in 0..41 {
        for j in 0..9 {
            let p = [
                o[0] - 0.25 + 0.0125 * i as f64,
                o[1] - 0.2 + 0.05 * j as f64,
                o[2] + 0.8,
            ];
            let r = eq.halfspaces().max_residual(p);
            if r.abs() <= BAND_M {
                continue;
            }
            let qp = supporting_forces(&s, &w_gi_static(1.0, g, p), &Default::default()).unwrap();
            let want = if r < 0.0 {
                stable += 1;
                ForcesOutcome::Feasible
            } else {
                unstable += 1;
                ForcesOutcome::Infeasible
            };
            assert_eq!(
                qp.outcome, want,
                "CoM {p:?}, residual {r} m; {} {} {} {}",
                qp.distance, qp.residual, qp.friction_violation, qp.solver_status
            );
            assert_eq!(eq.contains(p), r < 0.0);
        }
    }
    assert!(
        stable > 50 && unstable > 50,
        "{stable} stable, {unstable} unstable"
    );
}

#[test]
fn foot_rolled_by_small_angles() {
    for roll in [1.0, 0.1, 0.01] {
        let s = two_feet([0.0; 3], 0.0, roll, (0.11, 0.065));
        check(&s, [0.0; 3], &format!("roll {roll} deg"));
    }
}

#[test]
fn tiny_patches() {
    // 1 mm patches: the polygon is almost the segment between the two patches.
    let s = Stance::new(
        vec![
            foot("LF", [0.0, 0.1, 0.0], 0.0, (0.001, 0.001)),
            foot("RF", [0.0, -0.1, 0.0], 0.0, (0.001, 0.001)),
            foot("H", [0.3, 0.0, 0.0], 0.0, (0.001, 0.001)),
        ],
        FrictionModel::default(),
    )
    .unwrap();
    check(&s, [0.0; 3], "1 mm patches");
}

/// The robust region of a foot 3000 km from the world origin is the region of the foot at the
/// origin, moved (it was "empty": the polytope routines started from a box of 1e6 m about the
/// origin). One gravity: an unbounded vertical prism; four tilted gravities: a bounded solid.
#[test]
fn far_origin_3000_km_robust_region() {
    use polycone::polytope::RegionStatus;
    use stance_contact::equilibrium::RobustRegion;
    let tilted = [
        [0.98, 0.0, -9.81],
        [-0.98, 0.0, -9.81],
        [0.0, 0.98, -9.81],
        [0.0, -0.98, -9.81],
    ];
    for o in [[3e6, 0.0, 0.0], [-2e6, 4e6, 1e5]] {
        let region = |p: [f64; 3], gs: &[[f64; 3]]| {
            let s = Stance::new(
                vec![foot("LF", p, 0.0, (0.11, 0.065))],
                FrictionModel::default(),
            )
            .unwrap();
            let giwc = s.u_stance(&Default::default()).unwrap();
            RobustRegion::new(&giwc, gs, &Default::default()).unwrap()
        };
        let here = region([0.0; 3], &[[0.0, 0.0, -9.81]]);
        let there = region(o, &[[0.0, 0.0, -9.81]]);
        assert_eq!(here.polyhedron.status, RegionStatus::Unbounded);
        assert_eq!(there.polyhedron.status, RegionStatus::Unbounded, "{o:?}");
        for (dx, inside) in [(0.0, true), (0.1, true), (0.12, false), (-0.12, false)] {
            let p = [o[0] + dx, o[1], o[2] + 0.8];
            assert_eq!(there.contains(p), inside, "{o:?} + {dx}");
        }
        let here = region([0.0; 3], &tilted);
        let there = region(o, &tilted);
        assert_eq!(here.polyhedron.status, RegionStatus::Bounded);
        assert_eq!(there.polyhedron.status, RegionStatus::Bounded, "{o:?}");
        // The two vertex sets are within 1 um of each other both ways (Hausdorff): the foot's
        // own coordinates are rounded to 1e-16 of 4e6 m, about 1e-9 m, which the GIWC and the
        // region's conditioning amplify, so a vertex may come as two closer than 1 um (8
        // vertices at the origin, 11 at [-2e6, 4e6, 1e5]).
        let moved: Vec<[f64; 3]> = here
            .polyhedron
            .vertices
            .iter()
            .map(|p| [p[0] + o[0], p[1] + o[1], p[2] + o[2]])
            .collect();
        let gap = |a: &[[f64; 3]], b: &[[f64; 3]]| {
            a.iter()
                .map(|p| {
                    b.iter()
                        .map(|q| (0..3).map(|k| (p[k] - q[k]).abs()).fold(0.0, f64::max))
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(0.0, f64::max)
        };
        let far = &there.polyhedron.vertices;
        assert!(gap(&moved, far) < 1e-6, "{o:?}: {}", gap(&moved, far));
        assert!(gap(far, &moved) < 1e-6, "{o:?}: {}", gap(far, &moved));
    }
}
