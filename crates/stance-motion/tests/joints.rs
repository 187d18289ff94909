//! Joint-path retiming of a fixed-base robot under its actuator limits (`stance_motion::joints`), on the
//! project's three-link arm (`models/three_link_arm.urdf`): limits that do not bind change
//! nothing, each kind of limit binds alone and lengthens the motion, gravity beyond a torque
//! limit is infeasible with the joint named, the independent checks agree with the rows,
//! re-parameterizing the path changes nothing, and bad input is refused with the key named.

use std::path::{Path, PathBuf};

use stance_motion::joints::{retime_joints, JointPathSpec, JointRetiming};

fn arm() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/three_link_arm.urdf")
}

/// A path of the arm: yaw swing, shoulder and elbow moves, a wrist roll; `limits` is the
/// `[limits]` section's TOML.
fn spec(limits: &str) -> JointPathSpec {
    let text = format!(
        "urdf = {:?}\nwaypoints = [[0.0, 0.3, 0.5, 0.0], [1.0, -0.5, 1.2, 2.0], [2.0, 0.4, 0.3, 4.0]]\n\
         [limits]\n{limits}\n",
        arm().display().to_string()
    );
    toml::from_str(&text).unwrap()
}

fn run(s: &JointPathSpec) -> JointRetiming {
    retime_joints(s, None).unwrap()
}

fn duration(r: &JointRetiming) -> f64 {
    assert_eq!(r.status, "optimal", "{:?}", r.failure);
    r.duration.unwrap()
}

#[test]
fn limits_that_do_not_bind_leave_the_duration_unchanged() {
    let base = run(&spec(
        "velocity = false\ntorque = false\nacceleration = 5.0",
    ));
    // torque and velocity limits 1000 times the URDF's never bind
    let loose = run(&spec(
        "velocity = 1000.0\ntorque = 1000.0\nacceleration = 5.0",
    ));
    let (d0, d1) = (duration(&base), duration(&loose));
    assert!((d0 - d1).abs() <= 1e-12 * d0, "{d0} vs {d1}");
    assert_eq!(loose.binding.velocity + loose.binding.torque, 0);
    assert!(loose.binding.acceleration > 0);
}

#[test]
fn each_kind_of_limit_binds_alone_and_lengthens_the_motion() {
    // a loose acceleration limit alone
    let loose = run(&spec(
        "velocity = false\ntorque = false\nacceleration = 40.0",
    ));
    let d0 = duration(&loose);
    // + the URDF's velocity limits
    let vel = run(&spec("velocity = 1.0\ntorque = false\nacceleration = 40.0"));
    assert!(duration(&vel) > d0 * 1.01, "{} vs {d0}", duration(&vel));
    assert!(vel.binding.velocity > 0);
    // + a tight acceleration limit
    let acc = run(&spec(
        "velocity = false\ntorque = false\nacceleration = 4.0",
    ));
    assert!(duration(&acc) > d0 * 1.01);
    assert!(acc.binding.acceleration > 0);
    // + torque limits at 60 % of the URDF's efforts
    let tau = run(&spec("velocity = false\ntorque = 0.6\nacceleration = 40.0"));
    assert!(duration(&tau) > d0 * 1.01, "{} vs {d0}", duration(&tau));
    assert!(tau.binding.torque > 0, "{:?}", tau.binding);
    // all together: never shorter than any of them alone
    let all = run(&spec("velocity = 1.0\ntorque = 0.6\nacceleration = 4.0"));
    for r in [&vel, &acc, &tau] {
        assert!(duration(&all) >= duration(r) * (1.0 - 1e-9));
    }
}

#[test]
fn gravity_beyond_a_torque_limit_is_infeasible_and_names_the_joint() {
    // the elbow holds the forearm and the tool against gravity (up to 5.6 N m with the forearm
    // horizontal): at 5 % of its 12 N m it cannot at the start, whatever the timing
    let r = run(&spec("velocity = 1.0\ntorque = 0.05\nacceleration = 10.0"));
    assert_eq!(r.status, "feasible_set_empty");
    let f = r.failure.unwrap();
    assert!(
        f.constraints.iter().any(|c| c.contains("torque of elbow")),
        "{f:?}"
    );
    assert!(f.reason.contains("raise that limit"), "{}", f.reason);
}

#[test]
fn the_independent_checks_agree_with_the_rows() {
    for limits in [
        "velocity = 1.0\ntorque = 0.6\nacceleration = 6.0",
        "velocity = 0.5\ntorque = 1.0",
    ] {
        let mut s = spec(limits);
        s.dt = 0.001;
        let r = run(&s);
        let c = r.checks.clone().unwrap();
        // refined to within 0.1 % of every limit between grid points (the default)
        for (what, ratio) in [
            ("velocity", c.max_velocity_ratio),
            ("acceleration", c.max_acceleration_ratio),
            ("torque", c.max_torque_ratio),
        ] {
            assert!(ratio <= 1.0 + 1e-3, "{limits}: {what} ratio {ratio}");
        }
        // and the binding limit is reached (the profile is not slower than it must be)
        let top = c
            .max_velocity_ratio
            .max(c.max_acceleration_ratio)
            .max(c.max_torque_ratio);
        assert!(top > 0.99, "{limits}: largest ratio {top}");
        assert_eq!(r.trajectory.unwrap().t.len(), c.samples);
    }
}

#[test]
fn reparameterizing_the_path_does_not_change_the_duration() {
    let base = spec("velocity = 1.0\ntorque = 0.6\nacceleration = 6.0");
    let mut scaled = base.clone();
    scaled.knots = Some(vec![10.0, 13.0, 16.0]); // s' = 3 s + 10
    let mut unscaled = base.clone();
    unscaled.knots = Some(vec![0.0, 0.5, 1.0]);
    unscaled.max_violation_fraction = stance_motion::joints::spec::FractionOrOff::Off;
    scaled.max_violation_fraction = stance_motion::joints::spec::FractionOrOff::Off;
    let (d0, d1) = (duration(&run(&unscaled)), duration(&run(&scaled)));
    assert!((d0 - d1).abs() <= 1e-9 * d0, "{d0} vs {d1}");
}

/// The grid refinement reads each limit's excess between grid points as a fraction of the
/// limit (the velocity row included): it refines the same grid whatever the path parameter's
/// unit (the sweep found 13, 7,658 and 16,145 points added at knots x3, x1000 and x1e6 when the
/// velocity row was a bound on `x` itself, in the unit of `s'^2`).
#[test]
fn the_refinement_does_not_depend_on_the_knots_unit() {
    let base = spec("velocity = 1.0\ntorque = 1.0\nacceleration = 10.0");
    let reference = run(&base);
    for (scale, shift) in [(1e-6, 0.0), (3.0, -2.0), (1e3, 1e3), (1e6, 0.0)] {
        let mut s = base.clone();
        s.knots = Some(vec![shift, shift + 0.5 * scale, shift + scale]);
        let r = run(&s);
        let added = |r: &JointRetiming| r.refinement.as_ref().map_or(0, |f| f.points_added);
        assert_eq!(added(&r), added(&reference), "knots x{scale} + {shift}");
        let (d0, d1) = (duration(&reference), duration(&r));
        assert!(
            (d0 - d1).abs() <= 1e-9 * d0,
            "knots x{scale} + {shift}: {d0} vs {d1}"
        );
        let (b0, b1) = (
            reference.between.as_ref().unwrap().max_excess,
            r.between.as_ref().unwrap().max_excess,
        );
        assert!(
            (b0 - b1).abs() <= 1e-9,
            "knots x{scale}: excess {b0} vs {b1}"
        );
    }
}

#[test]
fn bad_input_names_what_to_fix() {
    let err = |s: &JointPathSpec| retime_joints(s, None).unwrap_err().to_string();
    let e = err(&spec("acceleration = { elbw = 3.0 }"));
    assert!(e.contains("elbw") && e.contains("elbow"), "{e}");
    let e = err(&spec("acceleration = -3.0"));
    assert!(e.contains("limits.acceleration") && e.contains("-3"), "{e}");
    let e = err(&spec("acceleration = nan"));
    assert!(
        e.contains("limits.acceleration") && e.contains("NaN"),
        "{e}"
    );
    let e = err(&spec("torque = 0.0"));
    assert!(e.contains("limits.torque"), "{e}");
    let mut s = spec("");
    s.waypoints[1].pop();
    let e = err(&s);
    assert!(e.contains("waypoint 1") && e.contains("4 joint"), "{e}");
    let mut s = spec("");
    s.joints = Some(vec!["yaw".into(), "shoulder".into(), "elbow".into()]);
    let e = err(&s);
    assert!(e.contains("wrist") && e.contains("locked"), "{e}");
    let e = err(&spec("velocity = false\ntorque = false"));
    assert!(e.contains("no limit applies"), "{e}");
}

/// A URDF joint without an effort limit has no torque limit with `torque = 1.0` (documented),
/// and the result says so with `null`.
#[test]
fn a_joint_without_an_effort_limit_has_no_torque_limit() {
    let text = std::fs::read_to_string(arm())
        .unwrap()
        .replace(r#"effort="2" velocity="6.0""#, r#"velocity="6.0""#);
    let dir = std::env::temp_dir().join(format!("stance-joints-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let urdf = dir.join("arm_no_wrist_effort.urdf");
    std::fs::write(&urdf, text).unwrap();
    let mut s = spec("acceleration = 6.0");
    s.urdf = urdf.display().to_string();
    let r = run(&s);
    let wrist = r.limits.iter().find(|j| j.name == "wrist").unwrap();
    assert_eq!(wrist.torque, None);
    assert_eq!(wrist.velocity, Some(6.0));
    let shoulder = r.limits.iter().find(|j| j.name == "shoulder").unwrap();
    assert_eq!(shoulder.torque, Some(40.0));
}
