//! On random stances (1 to 4 contacts, random poses, shapes and mu) and random CoMs, the
//! face-form test, the CoM half-spaces, the static-equilibrium polygon, the robust region and
//! the supporting-forces QP (an LP-type check over contact forces, independent of the double
//! description) agree with each other outside a stated band.

mod common;

use common::stance_strategy;
use polycone::polytope::RegionStatus;
use proptest::prelude::*;
use stance_contact::equilibrium::{RobustRegion, StaticEquilibrium};
use stance_contact::{supporting_forces, w_gi_static, ForcesOutcome, Stance};

/// Band (relative, on `max(U w) / |w|`) inside which face test and QP may disagree.
const FACE_BAND: f64 = 1e-6;
/// Band (m) for the CoM regions.
const REGION_BAND: f64 = 1e-6;

const G: [f64; 3] = [0.0, 0.0, -9.81];
const GS: [[f64; 3]; 4] = [
    [0.15, 0.0, -9.81],
    [-0.15, 0.0, -9.81],
    [0.0, 0.15, -9.81],
    [0.0, -0.15, -9.81],
];

fn coms() -> impl Strategy<Value = Vec<[f64; 3]>> {
    prop::collection::vec(
        (-0.5f64..0.5, -0.5f64..0.5, 0.3f64..1.2).prop_map(|(x, y, z)| [x, y, z]),
        6,
    )
}

/// Relative face value of a static CoM.
fn face_value(giwc: &stance_contact::Giwc, g: [f64; 3], p: [f64; 3]) -> f64 {
    let w = w_gi_static(1.0, g, p);
    let n = w.iter().map(|x| x * x).sum::<f64>().sqrt();
    giwc.max_violation(&w) / n
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]

    #[test]
    fn face_test_regions_and_qp_agree(stance in stance_strategy(), points in coms()) {
        check_agreement(stance, points)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    /// The same sweep, 3000 stances (about a minute in debug):
    /// `cargo test -p stance-contact --test agreement -- --ignored`.
    #[test]
    #[ignore]
    fn heavy_agreement_sweep(stance in stance_strategy(), points in coms()) {
        check_agreement(stance, points)?;
    }
}

fn check_agreement(stance: Stance, points: Vec<[f64; 3]>) -> Result<(), TestCaseError> {
    let giwc = stance.u_stance(&Default::default()).unwrap();
    prop_assert!(giwc.certified);
    let opts = Default::default();
    let eq = StaticEquilibrium::new(&giwc, G, &opts).unwrap();
    let poly = eq.polygon(0.0).unwrap();
    let robust = RobustRegion::new(&giwc, &GS, &opts).unwrap();
    for p in points {
        let v = face_value(&giwc, G, p);
        // 1. The QP over contact forces.
        let qp = supporting_forces(&stance, &w_gi_static(1.0, G, p), &Default::default()).unwrap();
        if v < -FACE_BAND {
            prop_assert_eq!(
                qp.outcome,
                ForcesOutcome::Feasible,
                "face says stable ({}), QP disagrees: {} res {} fric {}",
                v,
                qp.solver_status,
                qp.residual,
                qp.friction_violation
            );
        } else if v > FACE_BAND {
            prop_assert_eq!(
                qp.outcome,
                ForcesOutcome::Infeasible,
                "face says unstable ({}), QP disagrees: {} res {} fric {}",
                v,
                qp.solver_status,
                qp.residual,
                qp.friction_violation
            );
        }
        // 2. The CoM half-spaces (metres): same sign as the face value outside the band.
        let r = -eq.halfspaces().max_residual(p);
        if v < -FACE_BAND {
            prop_assert!(r >= -REGION_BAND);
        }
        if v > FACE_BAND {
            prop_assert!(r <= REGION_BAND);
        }
        if r > REGION_BAND {
            prop_assert!(eq.contains(p));
            prop_assert!(v <= FACE_BAND);
        }
        if r < -REGION_BAND {
            prop_assert!(!eq.contains(p));
            prop_assert!(v >= -FACE_BAND);
        }
        // 3. The polygon (vertical gravity: the prism's cross-section).
        if poly.status == RegionStatus::Bounded && poly.dim == 2 {
            let m = poly.margin([p[0], p[1]]);
            if m > REGION_BAND {
                prop_assert!(r >= -REGION_BAND, "inside polygon but residual {}", r);
            }
            if m < -REGION_BAND {
                prop_assert!(r <= REGION_BAND, "outside polygon but residual {}", r);
            }
        }
        // 4. The robust region against the K face tests.
        let worst = GS
            .iter()
            .map(|&g| face_value(&giwc, g, p))
            .fold(f64::NEG_INFINITY, f64::max);
        let mr = robust.margin(p);
        if worst < -FACE_BAND {
            prop_assert!(mr >= -REGION_BAND, "robust: face {} margin {}", worst, mr);
        }
        if worst > FACE_BAND {
            prop_assert!(mr <= REGION_BAND, "robust: face {} margin {}", worst, mr);
        }
        if mr > REGION_BAND {
            prop_assert!(robust.contains(p));
        }
        if mr < -REGION_BAND {
            prop_assert!(!robust.contains(p));
        }
    }
    // 5. The robust polyhedron's vertices are robustly stable (face tests), and it lies
    // inside the static prism of each g_k.
    if robust.polyhedron.status == RegionStatus::Bounded {
        for v in &robust.polyhedron.vertices {
            for &g in &GS {
                let fv = face_value(&giwc, g, *v);
                prop_assert!(
                    fv <= FACE_BAND,
                    "vertex {:?} g {:?} face {} poly {:?}",
                    v,
                    g,
                    fv,
                    robust.polyhedron
                );
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]

    /// A stable CoM found by the polygon is confirmed by the QP (checks the positive side
    /// where random CoMs rarely land).
    #[test]
    fn polygon_interior_points_have_supporting_forces(stance in stance_strategy()) {
        let giwc = stance.u_stance(&Default::default()).unwrap();
        let eq = StaticEquilibrium::new(&giwc, G, &Default::default()).unwrap();
        let poly = eq.polygon(0.9).unwrap();
        prop_assume!(poly.status == RegionStatus::Bounded && poly.dim == 2);
        let n = poly.vertices.len() as f64;
        let c = poly.vertices.iter().fold([0.0, 0.0], |a, v| [a[0] + v[0] / n, a[1] + v[1] / n]);
        let p = [c[0], c[1], 0.9];
        prop_assert!(eq.contains(p));
        let qp = supporting_forces(&stance, &w_gi_static(1.0, G, p), &Default::default()).unwrap();
        if poly.margin(c) > REGION_BAND {
            prop_assert_eq!(qp.outcome, ForcesOutcome::Feasible);
        }
        // Just outside every edge: the QP must fail when the face test says so.
        for (a, b) in poly.halfplanes.iter() {
            let mid = [c[0] + a[0] * (b - a[0] * c[0] - a[1] * c[1] + 1e-3), c[1] + a[1] * (b - a[0] * c[0] - a[1] * c[1] + 1e-3)];
            let q = [mid[0], mid[1], 0.9];
            let v = face_value(&giwc, G, q);
            prop_assert!(v > 0.0, "a point 1 mm outside an edge passes the face test ({})", v);
            let qp = supporting_forces(&stance, &w_gi_static(1.0, G, q), &Default::default()).unwrap();
            if v > FACE_BAND {
                prop_assert_eq!(qp.outcome, ForcesOutcome::Infeasible);
            }
        }
    }
}
