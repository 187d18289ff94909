//! The retiming glue against an independent check: at every grid point of the retimed motion,
//! the gravito-inertial wrench `w_GI = (m (g - p''), p x m (g - p''))` must be realizable by
//! contact forces (the supporting-forces LP/QP of stance-contact, which uses the friction
//! pyramids in face form and no double description).

use stance::retime::{retime, DiscretizationName, Interpolation, MotionSpec, PathSpec, SceneRef};
use stance::stance_contact::{examples, supporting_forces, ForcesOutcome};
use stance::stance_topp::path::PathCurve;

/// Relative L1 distance (in wrench space) from `w_GI` to the contact wrench cone that we accept
/// as "realizable": the profile satisfies its rows to about 1e-9 N and the LP solves to about
/// 1e-8 relative; 1e-6 leaves a margin of two orders of magnitude over both.
const DISTANCE_BAND: f64 = 1e-6;

fn spec(scene: &str, waypoints: Vec<[f64; 3]>, disc: DiscretizationName) -> MotionSpec {
    MotionSpec {
        scene: SceneRef::Named(scene.into()),
        path: PathSpec {
            waypoints,
            knots: None,
            interpolation: Interpolation::Spline,
        },
        grid_points: 51,
        sd_start: 0.0,
        sd_end: 0.0,
        discretization: disc,
        max_violation_fraction: None,
        samples_per_interval: 10,
        dt: None,
    }
}

fn check_forces_along(spec: &MotionSpec) -> f64 {
    let r = retime(spec).unwrap();
    assert_eq!(r.status, "optimal", "{spec:?}");
    let scene = examples::by_name(match &spec.scene {
        SceneRef::Named(n) => n,
        SceneRef::Inline(_) => unreachable!(),
    })
    .unwrap();
    let stance = scene.stance().unwrap();
    let curve = spec.path.curve().unwrap();
    let (m, g) = (scene.mass, scene.gravity);
    let mut worst: f64 = 0.0;
    let n = r.s.len() - 1;
    for i in 0..=n {
        // States at grid point i: (u_i, x_i); with interpolation also (u_{i-1}, x_i).
        let mut pairs = vec![];
        if i < n {
            pairs.push(r.sdd[i]);
        }
        if i > 0 && (spec.discretization == DiscretizationName::Interpolation || i == n) {
            pairs.push(r.sdd[i - 1]);
        }
        let q = curve.eval(r.s[i]);
        let x = r.sd[i] * r.sd[i];
        for u in pairs {
            let acc = [0, 1, 2].map(|k| q.ps[k] * u + q.pss[k] * x);
            let f = [0, 1, 2].map(|k| m * (g[k] - acc[k]));
            let p = q.p;
            let w = [
                f[0],
                f[1],
                f[2],
                p[1] * f[2] - p[2] * f[1],
                p[2] * f[0] - p[0] * f[2],
                p[0] * f[1] - p[1] * f[0],
            ];
            let sf = supporting_forces(&stance, &w, &Default::default()).unwrap();
            assert_ne!(
                sf.outcome,
                ForcesOutcome::Unknown,
                "solver status {}",
                sf.solver_status
            );
            worst = worst.max(sf.distance);
        }
    }
    worst
}

#[test]
fn retimed_double_support_sway_is_supported_by_contact_forces() {
    for disc in [
        DiscretizationName::Collocation,
        DiscretizationName::Interpolation,
    ] {
        let s = spec(
            "double-support",
            vec![[0.0, 0.08, 0.8], [0.03, 0.0, 0.78], [0.0, -0.08, 0.8]],
            disc,
        );
        let d = check_forces_along(&s);
        assert!(d <= DISTANCE_BAND, "{disc:?}: distance {d:e}");
    }
}

#[test]
fn retimed_box_climbing_motion_is_supported_by_contact_forces() {
    let s = spec(
        "box-climbing",
        vec![[0.2, 0.0, 0.8], [0.25, -0.05, 0.85], [0.3, -0.1, 0.9]],
        DiscretizationName::Interpolation,
    );
    let d = check_forces_along(&s);
    assert!(d <= DISTANCE_BAND, "distance {d:e}");
}

#[test]
fn a_com_path_far_outside_the_support_is_infeasible_at_a_grid_point() {
    // The CoM walks 1 m sideways off a single foot: statically impossible, and the motion
    // cannot be fast enough to make it dynamically possible with this mu.
    let s = spec(
        "single-support",
        vec![[0.0, 0.0, 0.8], [0.0, 1.0, 0.8]],
        DiscretizationName::Interpolation,
    );
    let r = retime(&s).unwrap();
    assert_ne!(r.status, "optimal");
    let index = r.index.expect("a failing grid point");
    assert!(index < r.s.len());
    assert!(r.duration.is_none());
}

#[test]
fn refinement_keeps_the_between_grid_violation_below_the_bound() {
    let mut s = spec(
        "stairs",
        vec![[0.0, 0.08, 0.8], [0.12, 0.0, 0.9], [0.26, -0.08, 1.02]],
        DiscretizationName::Collocation,
    );
    s.grid_points = 11;
    s.max_violation_fraction = Some(1e-3);
    let r = retime(&s).unwrap();
    assert_eq!(r.status, "optimal");
    let refine = r.refinement.expect("refinement asked for");
    assert!(refine.converged);
    assert!(r.between.unwrap().fraction_of_weight <= 1e-3);
}

#[test]
fn bad_motions_are_errors_that_say_what_to_fix() {
    let mut s = spec(
        "moon",
        vec![[0.0; 3], [0.1, 0.0, 0.8]],
        DiscretizationName::Collocation,
    );
    let e = retime(&s).unwrap_err().to_string();
    assert!(e.contains("box-climbing"), "{e}");
    s.scene = SceneRef::Named("stairs".into());
    s.grid_points = 1;
    assert!(retime(&s).unwrap_err().to_string().contains("grid_points"));
    s.grid_points = 11;
    s.sd_start = f64::NAN;
    assert!(retime(&s).unwrap_err().to_string().contains("sd_start"));
    s.sd_start = 0.0;
    s.path.waypoints = vec![[0.0; 3]];
    assert!(retime(&s).is_err());
}
