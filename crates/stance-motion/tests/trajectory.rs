//! The output trajectory is consistent (every two consecutive samples' positions agree with the
//! trapezoid of their velocities within `tol::TRAJECTORY_TRAPEZOID`, which samples at a fixed
//! step alone do not: the path acceleration jumps at the grid points and IK samples), keeps
//! every multiple of `dt`, and the checks run at their own step (`check_dt`), whatever the
//! output step. The small humanoid needs no Python; the box climbing (JVRC-1) skips, saying
//! why, without the virtualenv.

use stance_motion::trajectory::{trapezoid_error, uniform};
use stance_motion::{experiments, run, run_full, MotionSpec, RunOptions};

fn check_output(name: &str, mut spec: MotionSpec, dt: f64) {
    spec.retiming.dt = dt;
    let run = run_full(
        spec,
        &RunOptions {
            skip_checks: true,
            ..Default::default()
        },
    )
    .unwrap();
    let m = &run.plan.robot.model;
    let out = &run.samples;
    let tol = stance_motion::tol::TRAJECTORY_TRAPEZOID;
    let worst = out
        .windows(2)
        .map(|w| trapezoid_error(m, &w[0], &w[1]))
        .fold(0.0, f64::max);
    assert!(worst <= tol, "{name} at {dt} s: {worst}");
    assert!(out.windows(2).all(|w| w[1].t > w[0].t));
    // every multiple of dt is a sample
    let duration = run.result.duration.unwrap();
    let n = (duration / dt).floor() as usize;
    let mut j = 0;
    for i in 0..=n {
        let t = i as f64 * dt;
        while out[j].t < t - 1e-12 {
            j += 1;
        }
        assert!((out[j].t - t).abs() <= 1e-12, "{name}: no sample at {t}");
    }
    assert!((out.last().unwrap().t - duration).abs() <= 1e-12);
    // the fixed step alone disagrees: the added samples are needed
    let r = run.retimed.as_ref().unwrap();
    let fixed = uniform(&run.plan, &run.paths, r, r.profile.as_ref().unwrap(), dt).unwrap();
    let fixed_worst = fixed
        .windows(2)
        .map(|w| trapezoid_error(m, &w[0], &w[1]))
        .fold(0.0, f64::max);
    eprintln!(
        "{name} at {dt} s: {} samples ({} at the fixed step alone, disagreeing by up to \
         {fixed_worst:.2e}), agreeing within {worst:.2e}",
        out.len(),
        fixed.len()
    );
    assert!(fixed_worst > tol, "{name} at {dt} s: {fixed_worst}");
}

#[test]
fn consecutive_samples_agree_with_the_trapezoid_of_their_velocities() {
    check_output(
        "small-sway",
        experiments::by_name("small-sway").unwrap(),
        0.05,
    );
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    match stance_robot::jvrc1::locate_urdf(Some(&root)) {
        Ok(_) => check_output(
            "box-climbing",
            experiments::by_name("box-climbing").unwrap(),
            0.01,
        ),
        Err(why) => eprintln!("SKIPPED the box climbing: {why}"),
    }
}

/// The checks sample every `check_dt` (1 ms by default), not at the output step: two output
/// steps give the same checks.
#[test]
fn the_checks_do_not_depend_on_the_output_step() {
    let checks = |dt: f64| {
        let mut spec = experiments::by_name("small-sway").unwrap();
        spec.retiming.dt = dt;
        let r = run(spec, &RunOptions::default()).unwrap();
        (r.duration.unwrap(), r.checks.unwrap())
    };
    let (duration, a) = checks(0.01);
    let (_, b) = checks(0.05);
    // every millisecond, and the end
    let per_ms = duration / 0.001;
    assert!(
        a.samples as f64 >= per_ms && a.samples as f64 <= per_ms + 2.0,
        "{}",
        a.samples
    );
    assert_eq!(a.samples, b.samples);
    assert_eq!(a.samples_without_forces, b.samples_without_forces);
    assert_eq!(a.max_friction_usage, b.max_friction_usage);
    assert_eq!(a.max_contact_drift, b.max_contact_drift);
    assert_eq!(a.max_torque_ratio, b.max_torque_ratio);
    assert_eq!(a.max_joint_acceleration, b.max_joint_acceleration);
    assert_eq!(a.max_penetration, b.max_penetration);
}
