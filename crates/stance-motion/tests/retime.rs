//! The retiming glue against an independent check: at every grid point of the retimed motion,
//! the gravito-inertial wrench `w_GI = (m (g - p''), p x m (g - p''))` must be realizable by
//! contact forces (the supporting-forces LP/QP of stance-contact, which uses the friction
//! pyramids in face form and no double description).

use stance_contact::{examples, supporting_forces, ForcesOutcome};
use stance_motion::retime::{
    retime, ComMotionSpec, Discretization, Interpolation, PathSpec, SceneRef,
};
use stance_topp::path::PathCurve;

/// Relative L1 distance (in wrench space) from `w_GI` to the contact wrench cone that we accept
/// as "realizable": the profile satisfies its rows to about 1e-9 N and the LP solves to about
/// 1e-8 relative; 1e-6 leaves a margin of two orders of magnitude over both.
const DISTANCE_BAND: f64 = 1e-6;

fn spec(scene: &str, waypoints: Vec<[f64; 3]>, disc: Discretization) -> ComMotionSpec {
    ComMotionSpec {
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
        angular_momentum: None,
    }
}

/// `L' = l1(s) u + l2(s) x` from the motion's samples (zero without them).
fn angular_rate(spec: &ComMotionSpec, s: f64, u: f64, x: f64) -> [f64; 3] {
    let Some(l) = &spec.angular_momentum else {
        return [0.0; 3];
    };
    let knots = l.s.clone().unwrap_or_else(|| spec.path.knots());
    let k = (0..knots.len() - 1)
        .find(|&k| s <= knots[k + 1])
        .unwrap_or(knots.len() - 2);
    let t = ((s - knots[k]) / (knots[k + 1] - knots[k])).clamp(0.0, 1.0);
    let lerp = |v: &[[f64; 3]], d: usize| v[k][d] + t * (v[k + 1][d] - v[k][d]);
    [0, 1, 2].map(|d| lerp(&l.l1, d) * u + lerp(&l.l2, d) * x)
}

fn check_forces_along(spec: &ComMotionSpec) -> f64 {
    let r = retime(spec).unwrap();
    assert_eq!(r.status, "optimal", "{spec:?}");
    distance_along(spec, &r)
}

/// Largest relative distance of `w_GI` (with the `L'` of `spec`) to the contact wrench cone at
/// the grid points of the retiming `r`.
fn distance_along(spec: &ComMotionSpec, r: &stance_motion::retime::Retiming) -> f64 {
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
        if i > 0 && (spec.discretization == Discretization::Interpolation || i == n) {
            pairs.push(r.sdd[i - 1]);
        }
        let q = curve.eval(r.s[i]);
        let x = r.sd[i] * r.sd[i];
        for u in pairs {
            let acc = [0, 1, 2].map(|k| q.ps[k] * u + q.pss[k] * x);
            let f = [0, 1, 2].map(|k| m * (g[k] - acc[k]));
            let p = q.p;
            // L' = l1 u + l2 x, linear between the samples (evaluated here independently of
            // the crate's interpolation).
            let ld = angular_rate(spec, r.s[i], u, x);
            let w = [
                f[0],
                f[1],
                f[2],
                p[1] * f[2] - p[2] * f[1] - ld[0],
                p[2] * f[0] - p[0] * f[2] - ld[1],
                p[0] * f[1] - p[1] * f[0] - ld[2],
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
    for disc in [Discretization::Collocation, Discretization::Interpolation] {
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
        Discretization::Interpolation,
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
        Discretization::Interpolation,
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
        Discretization::Collocation,
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
        Discretization::Collocation,
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
    let e = retime(&s).unwrap_err().to_string();
    assert!(e.contains("at least 2 CoM waypoints"), "{e}");
}

/// Values from the motion file that used to reach an allocation of their own size or a panic:
/// a tiny `dt` (usize::MAX samples: capacity overflow), a huge grid, a huge or zero sample count.
#[test]
fn motion_fields_that_would_exhaust_memory_are_errors() {
    let base = spec(
        "double-support",
        vec![[0.0, 0.05, 0.8], [0.0, -0.05, 0.8]],
        Discretization::Interpolation,
    );
    let mut s = base.clone();
    s.dt = Some(1e-300);
    let e = retime(&s).unwrap_err().to_string();
    assert!(e.contains("dt"), "{e}");
    let mut s = base.clone();
    s.grid_points = 1_000_000_000_000;
    let e = retime(&s).unwrap_err().to_string();
    assert!(e.contains("grid_points"), "{e}");
    for n in [0, usize::MAX] {
        let mut s = base.clone();
        s.samples_per_interval = n;
        let e = retime(&s).unwrap_err().to_string();
        assert!(e.contains("samples_per_interval"), "{n}: {e}");
    }
}

/// `dt` and `max_violation_fraction` are checked whatever the outcome: an infeasible motion
/// with a bad `dt` used to return a status instead of the error.
#[test]
fn bad_dt_is_an_error_even_when_the_motion_is_infeasible() {
    let mut s = spec(
        "single-support",
        vec![[0.0, 0.0, 0.8], [0.0, 1.0, 0.8]],
        Discretization::Interpolation,
    );
    s.dt = Some(-1.0);
    assert!(retime(&s).unwrap_err().to_string().contains("dt"));
    s.dt = None;
    s.max_violation_fraction = Some(f64::NAN);
    assert!(retime(&s)
        .unwrap_err()
        .to_string()
        .contains("max_violation_fraction"));
}

/// The times, speeds and accelerations line up with the grid (one time and speed per grid
/// point, one acceleration per interval), and resampling lands on the duration.
#[test]
fn retimed_arrays_line_up_with_the_grid() {
    let mut s = spec(
        "double-support",
        vec![[0.0, 0.05, 0.8], [0.0, -0.05, 0.8]],
        Discretization::Interpolation,
    );
    s.dt = Some(0.01);
    let r = retime(&s).unwrap();
    assert_eq!(r.status, "optimal");
    assert_eq!(r.t.len(), r.s.len());
    assert_eq!(r.sd.len(), r.s.len());
    assert_eq!(r.sdd.len(), r.s.len() - 1);
    let d = r.duration.unwrap();
    assert_eq!(*r.t.last().unwrap(), d);
    let last = r.samples.last().unwrap();
    assert_eq!(last[0], d);
    assert!((last[1] - r.s[r.s.len() - 1]).abs() < 1e-12);
}

/// Angular-momentum terms (issue 4 item 5): a whole-body motion whose `L'` opposes the tipping
/// torque of the CoM motion retimes differently from the point-mass model, and its profile is
/// supported by contact forces once `L'` is included in `w_GI` (and, as a control, not with
/// `L' = 0`: the terms are really used).
#[test]
fn angular_momentum_terms_change_the_retiming_and_are_supported_by_forces() {
    use stance_motion::retime::AngularSpec;
    let point_mass = spec(
        "double-support",
        vec![[0.0, 0.08, 0.8], [0.03, 0.0, 0.78], [0.0, -0.08, 0.8]],
        Discretization::Interpolation,
    );
    let r0 = retime(&point_mass).unwrap();
    let mut whole_body = point_mass.clone();
    whole_body.angular_momentum = Some(AngularSpec {
        s: Some(vec![0.0, 0.5, 1.0]),
        l1: vec![[4.0, 0.0, 0.0], [0.0, 2.0, 1.0], [-4.0, 0.0, 0.0]],
        l2: vec![[0.0, 3.0, 0.0], [1.0, 0.0, 0.0], [0.0, -3.0, 0.0]],
    });
    let r1 = retime(&whole_body).unwrap();
    let (d0, d1) = (r0.duration.unwrap(), r1.duration.unwrap());
    assert!((d1 - d0).abs() > 1e-3 * d0, "durations {d0} vs {d1}");
    let d = check_forces_along(&whole_body);
    assert!(d <= DISTANCE_BAND, "distance {d:e}");
    let mut ignoring_l = whole_body.clone();
    ignoring_l.angular_momentum = None;
    let d_ignoring = distance_along(&ignoring_l, &r1);
    assert!(
        d_ignoring > 100.0 * DISTANCE_BAND,
        "distance without L' {d_ignoring:e}"
    );
    // Zero samples give exactly the point-mass answer.
    let mut zero = point_mass.clone();
    zero.angular_momentum = Some(AngularSpec {
        s: None,
        l1: vec![[0.0; 3]; 3],
        l2: vec![[0.0; 3]; 3],
    });
    assert_eq!(retime(&zero).unwrap().duration, r0.duration);
    // Samples that do not cover the path, or of the wrong length, are errors.
    let mut bad = whole_body.clone();
    bad.angular_momentum.as_mut().unwrap().s = Some(vec![0.0, 0.5, 0.9]);
    let e = retime(&bad).unwrap_err().to_string();
    assert!(e.contains("cover"), "{e}");
    bad.angular_momentum.as_mut().unwrap().s = None;
    bad.angular_momentum.as_mut().unwrap().l2.pop();
    let e = retime(&bad).unwrap_err().to_string();
    assert!(e.contains("l2"), "{e}");
}

/// A CoM path that does not move leaves the speed unbounded: the answer is decided by the
/// solver's box, which the output now says (it used to look like an ordinary optimum of
/// 0.2 ms); knots so close that the derivatives overflow are an error naming the knots.
#[test]
fn unbounded_or_overflowing_paths_are_reported() {
    let mut s = spec(
        "double-support",
        vec![[0.0, 0.0, 0.8], [0.0, 0.0, 0.8]],
        Discretization::Interpolation,
    );
    let r = retime(&s).unwrap();
    assert!(r.speed_at_box);
    s.path.waypoints = vec![[0.0, 0.05, 0.8], [0.0, -0.05, 0.8]];
    assert!(!retime(&s).unwrap().speed_at_box);
    s.path.knots = Some(vec![0.0, 1e-300]);
    let e = retime(&s).unwrap_err().to_string();
    assert!(e.contains("knots"), "{e}");
}

/// The facade's errors carry the inner error in their message only, so an error chain (the CLI
/// prints `{:#}`) does not repeat it.
#[test]
fn inner_errors_are_not_repeated_as_sources() {
    use std::error::Error;
    let mut s = spec(
        "double-support",
        vec![[0.0, 0.0, 1e200], [0.0, 0.0, -1e200]],
        Discretization::Interpolation,
    );
    s.grid_points = 3;
    let e = retime(&s).unwrap_err();
    assert!(matches!(e, stance_motion::StanceError::Topp(_)), "{e}");
    assert!(e.source().is_none());
}

/// With a zero gravity, a bound given as a fraction of the weight cannot be met: the refinement
/// used to fail with "bound 0 and scale 0", which names neither field.
#[test]
fn a_weight_fraction_without_gravity_is_an_error_naming_the_field() {
    let mut scene = examples::by_name("double-support").unwrap();
    scene.gravity = [0.0; 3];
    let mut s = spec(
        "double-support",
        vec![[0.0, 0.05, 0.8], [0.0, -0.05, 0.8]],
        Discretization::Interpolation,
    );
    s.scene = SceneRef::Inline(Box::new(scene));
    s.max_violation_fraction = Some(0.01);
    let e = retime(&s).unwrap_err().to_string();
    assert!(
        e.contains("max_violation_fraction") && e.contains("gravity"),
        "{e}"
    );
}

/// Scenes are read by name or in full (TOML: `tests/retime_cli.rs`); a typo inside a full scene is
/// reported by the scene's own field name.
#[test]
fn scene_refs_read_by_name_or_in_full_with_the_scenes_own_errors() {
    let named: ComMotionSpec = serde_json::from_str(
        r#"{"scene": "stairs", "path": {"waypoints": [[0, 0, 0.8], [0.1, 0, 0.8]]}}"#,
    )
    .unwrap();
    assert_eq!(named.scene, SceneRef::Named("stairs".into()));
    let scene = examples::by_name("double-support").unwrap();
    let text = format!(
        r#"{{"scene": {}, "path": {{"waypoints": [[0, 0, 0.8], [0.1, 0, 0.8]]}}}}"#,
        serde_json::to_string(&scene).unwrap()
    );
    let inline: ComMotionSpec = serde_json::from_str(&text).unwrap();
    assert_eq!(inline.scene, SceneRef::Inline(Box::new(scene.clone())));
    let e = serde_json::from_str::<ComMotionSpec>(
        r#"{"scene": {"mass": 38, "gravty": [0, 0, -9.81], "contacts": []},
            "path": {"waypoints": [[0, 0, 0.8], [0.1, 0, 0.8]]}}"#,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("gravty"), "{e}");
    let e = serde_json::from_str::<ComMotionSpec>(r#"{"scene": 3, "path": {"waypoints": []}}"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("example name"), "{e}");
}

/// The retiming does not depend on the path parameter's unit or origin (knots `[0, 1e6]` gave
/// 102 s and `[0, 1e-6]` 0.50 s where `[0, 1]` gives 0.77 s) nor on the robot's mass (1e-9 kg
/// failed, 1e-12 kg gave 0.0002 s): the same duration to 1e-9, from 1e-12 kg to 1e9 kg and
/// knots from `[0, 1e-6]` to `[1e6, 2e6]`.
#[test]
fn retiming_is_invariant_to_knots_and_mass() {
    let text = |mass: f64, knots: [f64; 2]| {
        format!(
            r#"{{"scene": {{"mass": {mass:e}, "contacts": [
                {{"name": "l", "position": [0, 0.1, 0], "shape": {{"rectangle": {{"half_length": 0.1, "half_width": 0.05}}}}, "friction": 0.7}},
                {{"name": "r", "position": [0, -0.1, 0], "shape": {{"rectangle": {{"half_length": 0.1, "half_width": 0.05}}}}, "friction": 0.7}}]}},
              "path": {{"waypoints": [[0, 0, 0.8], [0.05, 0.02, 0.8], [0.08, -0.01, 0.78]], "knots": [{:e}, {:e}, {:e}]}}}}"#,
            knots[0],
            (knots[0] + knots[1]) / 2.0,
            knots[1]
        )
    };
    let duration = |mass: f64, knots: [f64; 2]| {
        let spec: ComMotionSpec = serde_json::from_str(&text(mass, knots)).unwrap();
        let r = retime(&spec).unwrap();
        assert_eq!(r.status, "optimal", "mass {mass:e}, knots {knots:?}");
        r.duration.unwrap()
    };
    let reference = duration(60.0, [0.0, 1.0]);
    for mass in [1e-12, 1e-9, 1e-3, 1.0, 1e3, 1e9] {
        let d = duration(mass, [0.0, 1.0]);
        assert!(
            (d - reference).abs() < 1e-9 * reference,
            "mass {mass:e}: {d} against {reference}"
        );
    }
    for knots in [
        [0.0, 1e-6],
        [0.0, 1e-3],
        [0.0, 1e3],
        [0.0, 1e6],
        [5.0, 6.0],
        [1e6, 2e6],
    ] {
        let d = duration(60.0, knots);
        assert!(
            (d - reference).abs() < 1e-9 * reference,
            "knots {knots:?}: {d} against {reference}"
        );
    }
}

/// Physics across the range of doubles: a duration scales as `1 / sqrt(|g|)` and does not depend
/// on the mass (the rows are a cone in the wrench: dividing it by the mass changes nothing; a
/// change of time units multiplies it by `1 / tau^2`). Checked from 1e-300 to 1e300 for both,
/// with angular-momentum terms (which scale with the mass) and a dt; exactly (bit for bit) where
/// the ratio is a power of four for gravity or a power of two for the mass, to 1e-9 elsewhere.
/// Before the retiming worked in normalized units, a gravity of 1e-10 answered 20 % off and a
/// mass of 1e-300 kg a duration 2,700 times too short, with nothing flagged.
#[test]
fn durations_scale_with_gravity_and_not_with_mass_across_the_double_range() {
    let base = |mass: f64, g: f64| {
        let mut scene = examples::by_name("double-support").unwrap();
        scene.mass = mass;
        scene.gravity = [0.0, 0.0, -g];
        let mut s = spec(
            "double-support",
            vec![[0.0, 0.08, 0.8], [0.03, 0.0, 0.78], [0.0, -0.08, 0.8]],
            Discretization::Interpolation,
        );
        s.scene = SceneRef::Inline(Box::new(scene));
        // L' = l1 s'' + l2 s'^2 of a body of this mass (terms proportional to it)
        s.angular_momentum = serde_json::from_value(serde_json::json!({
            "l1": [[0.0, 0.2 * mass, 0.0], [0.1 * mass, 0.0, 0.0], [0.0, -0.2 * mass, 0.0]],
            "l2": [[0.0, 0.0, 0.1 * mass], [0.0, 0.0, 0.0], [0.0, 0.0, -0.1 * mass]],
        }))
        .unwrap();
        s.dt = Some(0.05 / g.sqrt());
        s
    };
    let reference = retime(&base(39.0, 9.81)).unwrap();
    let d0 = reference.duration.unwrap();
    for k in [-300, -200, -100, -30, -10, -1, 1, 10, 30, 100, 200, 300] {
        let g = 9.81 * 10f64.powi(k);
        let r = retime(&base(39.0, g)).unwrap();
        assert_eq!(r.status, "optimal", "g = {g:e}");
        let d = r.duration.unwrap() * (g / 9.81).sqrt();
        assert!((d - d0).abs() <= 1e-9 * d0, "g = {g:e}: {d} vs {d0}");
        // the samples and the speeds in the same units
        let last = r.samples.last().unwrap();
        assert!(
            (last[0] * (g / 9.81).sqrt() - d0).abs() <= 1e-9 * d0,
            "{last:?}"
        );
        let top = r.sd.iter().fold(0.0f64, |m, x| m.max(*x)) / (g / 9.81).sqrt();
        let top0 = reference.sd.iter().fold(0.0f64, |m, x| m.max(*x));
        assert!(
            (top - top0).abs() <= 1e-8 * top0,
            "g = {g:e}: {top} vs {top0}"
        );
        let m = 39.0 * 10f64.powi(k);
        let r = retime(&base(m, 9.81)).unwrap();
        let d = r.duration.unwrap();
        assert!((d - d0).abs() <= 1e-9 * d0, "m = {m:e}: {d} vs {d0}");
    }
    // powers of four (gravity) and two (mass): the same problem in normalized units
    let g = 9.81 * 4f64.powi(-400);
    let r = retime(&base(39.0, g)).unwrap();
    assert_eq!(r.duration.unwrap(), d0 * 2f64.powi(400));
    // every field in the scene's units: times x tau, speeds / tau, accelerations and
    // x = s'^2 / tau^2, newtons / tau^2 (tau = 2^400)
    let (tau, tau2) = (2f64.powi(400), 2f64.powi(400) * 2f64.powi(400));
    let same = |a: &[f64], b: &[f64], f: &dyn Fn(f64) -> f64, what: &str| {
        assert_eq!(a.len(), b.len(), "{what}");
        for (x, y) in a.iter().zip(b) {
            assert_eq!(*x, f(*y), "{what}");
        }
    };
    same(&r.t, &reference.t, &|x| x * tau, "t");
    same(&r.sd, &reference.sd, &|x| x / tau, "sd");
    same(&r.sdd, &reference.sdd, &|x| x / tau2, "sdd");
    for (sets, sets0) in [
        (&r.controllable_sets, &reference.controllable_sets),
        (&r.feasible_sets, &reference.feasible_sets),
    ] {
        let flat = |v: &Vec<Option<[f64; 2]>>| -> Vec<f64> {
            v.iter().flatten().flatten().copied().collect()
        };
        same(&flat(sets), &flat(sets0), &|x| x / tau2, "x sets");
    }
    assert_eq!(r.samples.len(), reference.samples.len());
    for (a, b) in r.samples.iter().zip(&reference.samples) {
        assert_eq!(*a, [b[0] * tau, b[1], b[2] / tau, b[3] / tau2]);
    }
    assert_eq!(
        r.between.unwrap().max_violation_newtons,
        reference.between.unwrap().max_violation_newtons / tau2
    );
    let r = retime(&base(39.0 * 2f64.powi(-900), 9.81)).unwrap();
    assert_eq!(r.duration.unwrap(), d0);
    assert_eq!(r.sd, reference.sd);
    assert_eq!(
        r.between.unwrap().max_violation_newtons,
        reference.between.unwrap().max_violation_newtons * 2f64.powi(-900)
    );
    assert_eq!(
        r.between.unwrap().fraction_of_weight,
        reference.between.unwrap().fraction_of_weight
    );
}
