//! Actuator limits in whole-body motions (`[limits]`, `stance_motion::limits`): limits that do
//! not bind change nothing; each kind binds alone, lengthens the motion and is named in the
//! per-segment binding counts; the optimum with limits is never shorter than without; a torque
//! limit below what gravity needs at rest makes the motion infeasible and names the joint and
//! the segment; the independent checks keep every ratio at most one at 1 ms samples; the
//! checks' joint torques equal Pinocchio's inverse dynamics for the chosen contact wrenches
//! (testdata/robot/jvrc1.json). The small humanoid's motion needs no Python; the JVRC-1
//! gallery motions (gallery/) skip, saying why, without the project virtualenv.

use std::path::{Path, PathBuf};

use stance_motion::limits::{AccelerationSpec, Scale};
use stance_motion::result::{MotionResult, MotionStatus};
use stance_motion::{experiments, run, spec::MotionSpec, RunOptions};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn sway() -> MotionSpec {
    experiments::by_name("small-sway").unwrap()
}

fn with(mut s: MotionSpec, velocity: Scale, acc: Option<f64>, torque: Scale) -> MotionSpec {
    s.limits.velocity = velocity;
    s.limits.acceleration = acc.map(AccelerationSpec::All);
    s.limits.torque = torque;
    s
}

fn duration(r: &MotionResult) -> f64 {
    assert_eq!(r.status, MotionStatus::Optimal, "{:?}", r.failure);
    r.duration.unwrap()
}

fn quick() -> RunOptions {
    RunOptions {
        skip_checks: true,
        ..Default::default()
    }
}

/// Sums of the per-segment binding counts: (velocity, acceleration, torque).
fn bound(r: &MotionResult) -> (usize, usize, usize) {
    r.segments.iter().fold((0, 0, 0), |(v, a, t), s| {
        let b = s.binding.as_ref().unwrap();
        (v + b.velocity, a + b.acceleration, t + b.torque)
    })
}

#[test]
fn limits_that_do_not_bind_leave_the_duration_unchanged() {
    let none = run(with(sway(), Scale::Off, None, Scale::Off), &quick()).unwrap();
    let loose = run(
        with(
            sway(),
            Scale::Fraction(100.0),
            Some(1e6),
            Scale::Fraction(100.0),
        ),
        &quick(),
    )
    .unwrap();
    let (a, b) = (duration(&none), duration(&loose));
    eprintln!("small-sway: no limits {a:.9} s, limits 100 times the URDF's {b:.9} s");
    assert!((a - b).abs() <= 1e-9 * a, "{a} vs {b}");
    assert_eq!(bound(&loose), (0, 0, 0));
    // and --no-limits is the same as no limits in the file
    let flag = run(
        sway(),
        &RunOptions {
            no_limits: true,
            ..quick()
        },
    )
    .unwrap();
    assert_eq!(duration(&flag), a);
}

#[test]
fn each_kind_of_limit_binds_alone_and_lengthens_the_motion() {
    let base = duration(&run(with(sway(), Scale::Off, None, Scale::Off), &quick()).unwrap());
    for (name, spec, which) in [
        (
            "velocity at 20 % of the URDF's",
            with(sway(), Scale::Fraction(0.2), None, Scale::Off),
            0,
        ),
        (
            "acceleration 20 rad/s^2",
            with(sway(), Scale::Off, Some(20.0), Scale::Off),
            1,
        ),
        (
            "torque at the URDF's efforts",
            with(sway(), Scale::Off, None, Scale::Fraction(1.0)),
            2,
        ),
    ] {
        let r = run(spec, &quick()).unwrap();
        let d = duration(&r);
        let b = bound(&r);
        eprintln!("small-sway, {name}: {d:.4} s (no limits {base:.4} s), bound {b:?}");
        assert!(d > base * 1.01, "{name}: {d} vs {base}");
        assert!([b.0, b.1, b.2][which] > 0, "{name}: {b:?}");
    }
}

#[test]
fn the_optimum_with_limits_is_never_shorter_than_without() {
    let none = run(with(sway(), Scale::Off, None, Scale::Off), &quick()).unwrap();
    assert!(none.limits.is_none(), "no limit enforced, none reported");
    let base = duration(&none);
    for (v, a, t) in [
        (1.0, Some(50.0), 1.0),
        (0.5, None, 2.0),
        (2.0, Some(100.0), 1.2),
    ] {
        let r = run(
            with(sway(), Scale::Fraction(v), a, Scale::Fraction(t)),
            &quick(),
        )
        .unwrap();
        let d = duration(&r);
        assert!(d >= base * (1.0 - 1e-12), "{v} {a:?} {t}: {d} < {base}");
        // the limits as enforced, per joint: the URDF's scaled, the acceleration as given
        let joints = r.limits.as_ref().expect("the enforced limits");
        let hip = joints.iter().find(|j| j.name == "l_hip_p").unwrap();
        assert!((hip.velocity.unwrap() - 8.0 * v).abs() < 1e-12, "{hip:?}");
        assert!((hip.torque.unwrap() - 150.0 * t).abs() < 1e-9, "{hip:?}");
        assert_eq!(hip.acceleration, a);
    }
}

#[test]
fn a_torque_limit_below_gravity_at_rest_is_infeasible_and_named() {
    // the torso lift (prismatic, 200 N) holds the upper body: at 20 % of its effort it cannot
    let r = run(
        with(sway(), Scale::Off, None, Scale::Fraction(0.2)),
        &quick(),
    )
    .unwrap();
    assert_eq!(r.status, MotionStatus::NotRetimable);
    let f = r.failure.unwrap();
    eprintln!("{f:?}");
    assert!(
        f.constraints.iter().any(|c| c.starts_with("torque of ")),
        "{f:?}"
    );
    assert!(
        f.reason.contains("segment 1 (shift onto the left foot)"),
        "{}",
        f.reason
    );
    assert!(f.reason.contains("raise"), "{}", f.reason);
}

/// Every ratio at most one at 1 ms samples with the limits enforced, and above one without
/// them (the checks have teeth), on the small humanoid and, with JVRC-1, on the gallery.
#[test]
fn the_checks_keep_every_ratio_at_most_one() {
    let mut cases: Vec<(String, MotionSpec, Option<PathBuf>)> = vec![(
        "small-sway with a 20 rad/s^2 acceleration limit".into(),
        with(
            sway(),
            Scale::Fraction(1.0),
            Some(20.0),
            Scale::Fraction(1.0),
        ),
        None,
    )];
    let root = root();
    match stance_robot::jvrc1::locate_urdf(Some(&root)) {
        Ok(_) => {
            for name in ["squat", "side-step", "hand-on-wall"] {
                let path = root.join("gallery").join(format!("{name}.toml"));
                let spec: MotionSpec = stance_motion::input::read_file(&path).unwrap();
                cases.push((name.into(), spec, path.parent().map(Path::to_path_buf)));
            }
        }
        Err(why) => {
            eprintln!("SKIPPED the gallery in the_checks_keep_every_ratio_at_most_one: {why}")
        }
    }
    for (name, spec, base_dir) in cases {
        let mut s = spec.clone();
        s.retiming.dt = 0.001;
        let opts = RunOptions {
            base_dir: base_dir.clone(),
            ..Default::default()
        };
        let r = run(s.clone(), &opts).unwrap();
        let c = r.checks.as_ref().unwrap();
        let ratios = [
            c.max_velocity_ratio.unwrap(),
            c.max_acceleration_ratio.unwrap(),
            c.max_torque_ratio.unwrap(),
        ];
        eprintln!(
            "{name}: {:.3} s, ratios {ratios:.4?}, largest joint acceleration {:.1} rad/s^2",
            duration(&r),
            c.max_joint_acceleration
        );
        for (kind, x) in ["velocity", "acceleration", "torque"].iter().zip(ratios) {
            assert!(x <= 1.0 + 1e-6, "{name}: {kind} ratio {x}");
        }
        assert_eq!(c.samples_without_forces, 0);
        let free = run(
            s,
            &RunOptions {
                no_limits: true,
                ..opts
            },
        )
        .unwrap();
        let fc = free.checks.as_ref().unwrap();
        let top = fc
            .max_acceleration_ratio
            .unwrap()
            .max(fc.max_torque_ratio.unwrap())
            .max(fc.max_velocity_ratio.unwrap());
        eprintln!(
            "  without limits: {:.3} s, largest ratio {top:.2}, largest joint acceleration {:.1}",
            duration(&free),
            fc.max_joint_acceleration
        );
        assert!(
            top > 1.0,
            "{name}: the motion without limits never exceeds them"
        );
    }
}

/// The check's joint torques (`tau = rnea(q, v, a) - sum_k J_k^T w_k`) against Pinocchio's
/// inverse dynamics and frame Jacobians (LOCAL) for the same wrenches on both soles of JVRC-1.
#[test]
fn joint_torques_with_contact_wrenches_match_pinocchio() {
    use stance_motion::limit_checks::joint_torques;
    use stance_robot::{jvrc1, Data, Model};
    let path = match jvrc1::locate_urdf(Some(&root())) {
        Ok(p) => p,
        Err(why) => {
            eprintln!("SKIPPED joint_torques_with_contact_wrenches_match_pinocchio: {why}");
            return;
        }
    };
    let model = Model::from_urdf_file(path, &jvrc1::urdf_options()).unwrap();
    let fx: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("testdata/robot/jvrc1.json")).unwrap(),
    )
    .unwrap();
    let vecf = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let mut data = Data::new(&model);
    let mut worst = 0.0f64;
    for (c, case) in fx["cases"].as_array().unwrap().iter().enumerate() {
        let (q, v) = (vecf(&case["q"]), vecf(&case["v"]));
        let a = vecf(&case["path_terms"]["q_ss"]);
        let wrenches = [
            ("R_ANKLE_P_S", [10.0, -20.0, 300.0, 4.0, -6.0, 1.0]),
            ("L_ANKLE_P_S", [-5.0, 15.0, 250.0, -3.0, 2.0, -0.5]),
        ];
        let mut reference = vecf(&case["rnea"]);
        let mut contacts = Vec::new();
        for (frame, w) in wrenches {
            let jac: Vec<Vec<f64>> = case["frames"][frame]["jacobian_local"]
                .as_array()
                .unwrap()
                .iter()
                .map(vecf)
                .collect();
            for (k, t) in reference.iter_mut().enumerate() {
                *t -= (0..6).map(|r| jac[r][k] * w[r]).sum::<f64>();
            }
            contacts.push((model.frame_id(frame).unwrap(), w));
        }
        let tau =
            joint_torques(&model, &mut data, &q, &v, &a, [0.0, 0.0, -9.81], &contacts).unwrap();
        let scale = reference.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        for (k, (x, y)) in tau.iter().zip(&reference).enumerate() {
            let e = (x - y).abs() / scale;
            worst = worst.max(e);
            assert!(e < 1e-9, "case {c}, entry {k}: {x} vs Pinocchio {y}");
        }
    }
    eprintln!("joint torques with contact wrenches: worst relative error {worst:.1e}");
}

/// The torque limits with the contact forces as unknowns enter the retiming as cuts of a
/// separation oracle (`stance_motion::separation`). Against the exact projections of every
/// lifted side (`stance_topp::lifted::Projector`, the expanding polygon, an independent
/// algorithm): every cut kept is valid (the projection lies on its side), and adding the exact
/// projections to the solved constraints changes nothing (the cuts were enough: the profile is
/// the one of the exact sets). On the box climbing (JVRC-1, two and three contacts, torque
/// limits binding with the forces); skipped without the project virtualenv.
#[test]
fn cuts_give_the_profile_of_the_exact_projections() {
    use stance_motion::run_full;
    use stance_topp::lifted::{Projection, Projector};
    use stance_topp::lp2::{self, Box2, Lp2, Lp2Stats, StageLines};
    use stance_topp::{CanonicalConstraints, Row, SolveOptions, Tolerances};
    if let Err(why) = stance_robot::jvrc1::locate_urdf(Some(&root())) {
        eprintln!("SKIPPED cuts_give_the_profile_of_the_exact_projections: {why}");
        return;
    }
    let spec = experiments::by_name("box-climbing").unwrap();
    let run = run_full(spec.clone(), &quick()).unwrap();
    let rt = run.retimed.as_ref().unwrap();
    let d_cuts = duration(&run.result);
    let k = &rt.constraints;
    let bbox = Box2 {
        u_lo: -1e4,
        u_hi: 1e4,
        x_lo: 0.0,
        x_hi: 1e4,
    };
    // per point, the exact projections that hold on both sides of it, and those that hold
    // with the interval after it only (at a stance switch: the module doc of the chained
    // retiming; the stance before a switch at the point before, in that interval's state)
    let mut extra: Vec<Vec<Row>> = vec![Vec::new(); k.num_points()];
    let mut extra_here: Vec<Vec<Row>> = vec![Vec::new(); k.num_points()];
    let nseg = run.rows.len();
    let (mut projector, mut out) = (Projector::new(), Projection::default());
    let (mut sides, mut cuts, mut worst) = (0, 0, 0.0f64);
    for (seg, r) in run.rows.iter().enumerate() {
        let last = r.grid.len() - 1;
        for (i, &j) in r.grid.iter().enumerate() {
            let Some(both) = r.sides[j].as_ref() else {
                continue;
            };
            for (left, on) in [(false, i < last), (true, i > 0)] {
                let side = &both[usize::from(left)];
                let Some(lifted) = side.lifted.as_ref().filter(|_| on) else {
                    continue;
                };
                projector.reset();
                projector
                    .project(&lifted.rows, bbox, 1e-10, &mut out)
                    .unwrap();
                assert!(!out.empty, "segment {seg}, sample {j}: empty projection");
                sides += 1;
                // the cuts are valid: the polygon's support in their normal is at most -c
                for cut in &side.rows[side.explicit..] {
                    let n = cut.a.hypot(cut.b);
                    let dir = [cut.a / n, cut.b / n];
                    let Lp2::Optimal { u, x, .. } = lp2::solve(
                        &StageLines::from_rows(&out.rows),
                        bbox,
                        dir,
                        [-dir[1], dir[0]],
                        &[],
                        &Tolerances::default(),
                        &mut Lp2Stats::default(),
                    ) else {
                        panic!("segment {seg}, sample {j}: the projection's rows are empty")
                    };
                    let support = cut.a * u + cut.b * x;
                    let excess = (support + cut.c) / n.max(1e-300);
                    worst = worst.max(excess);
                    assert!(
                        excess <= 1e-7 * (1.0 + support.abs() / n.max(1e-300)),
                        "segment {seg}, sample {j}: cut {cut:?} cuts the projection by {excess}"
                    );
                    cuts += 1;
                }
                let g = rt.seg_start[seg] + i;
                if left && i == last && seg + 1 < nseg {
                    let two_delta = 2.0
                        * (run.paths[seg].samples[j].s - run.paths[seg].samples[r.grid[i - 1]].s);
                    extra_here[g - 1].extend(out.rows.iter().map(|row| Row {
                        a: row.a + two_delta * row.b,
                        b: row.b,
                        c: row.c,
                    }));
                } else if !left && i == 0 && seg > 0 {
                    extra_here[g].extend_from_slice(&out.rows);
                } else {
                    extra[g].extend_from_slice(&out.rows);
                }
            }
        }
    }
    let mut rows = Vec::new();
    let mut offsets = vec![0];
    let mut next = Vec::new();
    for i in 0..k.num_points() {
        let both = k.next_rows_at(i);
        rows.extend_from_slice(both);
        rows.extend_from_slice(&extra[i]);
        next.push(both.len() + extra[i].len());
        rows.extend_from_slice(&k.rows_at(i)[both.len()..]);
        rows.extend_from_slice(&extra_here[i]);
        offsets.push(rows.len());
    }
    let bounds = (0..k.num_points()).map(|i| k.x_bounds_at(i)).collect();
    let exact = CanonicalConstraints::new(k.grid().to_vec(), offsets, rows)
        .unwrap()
        .with_x_bounds(bounds)
        .unwrap()
        .with_next_rows(next)
        .unwrap();
    let sol = stance_topp::solve(&exact, &SolveOptions::new(spec.retiming.discretization)).unwrap();
    let d_exact = sol.duration().unwrap();
    eprintln!(
        "box climbing: {sides} lifted sides, {cuts} cuts kept (worst excess {worst:.1e}); \
         {d_cuts:.9} s with the cuts, {d_exact:.9} s with the exact projections added"
    );
    assert!(cuts > 0, "no cut: the test tests nothing");
    assert!(
        (d_exact - d_cuts).abs() <= 1e-7 * d_cuts,
        "{d_cuts} with the cuts, {d_exact} with the exact projections"
    );
}

/// Talos's URDF in the project virtualenv, or why not.
fn talos_urdf() -> Result<PathBuf, String> {
    stance_test_support::robots::talos_urdf(&root())
}

/// Another robot, from PyPI, with motions written for it (gallery/talos-*.toml): Talos squats,
/// steps aside and steps up a platform under its URDF's velocity and effort limits and a 20 rad/s^2 acceleration limit,
/// every ratio at most one at 1 ms samples and supporting forces at every sample; with 60 % of
/// its efforts the squat's knees bind with the contact forces as unknowns (cuts), still within
/// the limits. Skipped without example-robot-data in the virtualenv.
#[test]
fn talos_from_example_robot_data_keeps_its_limits() {
    use stance_motion::spec::RobotRef;
    let urdf = match talos_urdf() {
        Ok(p) => p,
        Err(why) => {
            eprintln!("SKIPPED talos_from_example_robot_data_keeps_its_limits: {why}");
            return;
        }
    };
    let load = |name: &str| -> MotionSpec {
        let path = root().join("gallery").join(format!("talos-{name}.toml"));
        let mut spec: MotionSpec = stance_motion::input::read_file(&path).unwrap();
        let RobotRef::Urdf(r) = &mut spec.robot else {
            panic!("talos-{name}.toml names its URDF")
        };
        r.urdf = urdf.display().to_string();
        spec.retiming.dt = 0.001;
        spec
    };
    let mut squat_weak = load("squat");
    squat_weak.limits.torque = Scale::Fraction(0.6);
    for (name, spec) in [
        ("squat", load("squat")),
        ("step", load("step")),
        ("step-up", load("step-up")),
        ("squat at 60 % of the efforts", squat_weak),
    ] {
        let r = run(spec, &RunOptions::default()).unwrap();
        let c = r.checks.as_ref().unwrap();
        let ratios = [
            c.max_velocity_ratio.unwrap(),
            c.max_acceleration_ratio.unwrap(),
            c.max_torque_ratio.unwrap(),
        ];
        let cuts: usize = r.segments.iter().map(|s| s.torque_cuts).sum();
        eprintln!(
            "Talos {name}: {:.3} s, ratios {ratios:.4?}, {cuts} torque cuts",
            duration(&r)
        );
        for (kind, x) in ["velocity", "acceleration", "torque"].iter().zip(ratios) {
            assert!(x <= 1.0 + 1e-6, "Talos {name}: {kind} ratio {x}");
        }
        assert_eq!(c.samples_without_forces, 0, "Talos {name}");
        if name.contains("60 %") {
            assert!(
                cuts > 0 && ratios[2] > 0.99,
                "the torque limits bind: {cuts} cuts"
            );
        }
    }
}

/// The torque check solves its linear program only where a sample's upper bound (the force
/// check's fast forces) may exceed the largest exact ratio (module `limit_checks`): the largest
/// ratio equals the exhaustive one (the program at every sample), at 1 ms, on the small humanoid
/// with its URDF's efforts as retimed and 1.3 times faster (where the limits break) and, with
/// JVRC-1, on the gallery's hand on a wall (three contacts); and most samples with supporting
/// forces are not solved (those without are, to say so).
#[test]
fn the_torque_check_prunes_to_the_exhaustive_largest_ratio() {
    use stance_motion::limit_checks::{check_limits, exact_torque_ratio, planned_contacts};
    let mut cases: Vec<(String, MotionSpec, Option<PathBuf>, f64)> = vec![
        ("small-sway".into(), sway(), None, 1.0),
        ("small-sway x1.3".into(), sway(), None, 1.3),
    ];
    let root = root();
    if stance_robot::jvrc1::locate_urdf(Some(&root)).is_ok() {
        let path = root.join("gallery").join("hand-on-wall.toml");
        let spec: MotionSpec = stance_motion::input::read_file(&path).unwrap();
        cases.push((
            "hand-on-wall".into(),
            spec,
            path.parent().map(Path::to_path_buf),
            1.0,
        ));
    }
    for (name, mut spec, base_dir, k) in cases {
        spec.retiming.dt = 0.001;
        let run = stance_motion::run_full(
            spec,
            &RunOptions {
                base_dir,
                skip_checks: true,
                time_scale: Some(k),
                ..Default::default()
            },
        )
        .unwrap();
        let plan = &run.plan;
        let lp = plan.actuator_limits.as_ref().unwrap();
        let stances: Vec<&stance_contact::Stance> = run.rows.iter().map(|r| &r.stance).collect();
        let contacts = planned_contacts(plan, &run.paths);
        let pruned = check_limits(plan, lp, &stances, &contacts, &run.samples).unwrap();
        let mut exhaustive = 0.0f64;
        let mut bound_below = 0;
        for (smp, x) in run.samples.iter().zip(&pruned) {
            let exact =
                exact_torque_ratio(plan, lp, stances[smp.segment], &contacts[smp.segment], smp)
                    .unwrap();
            if let Some((r, _)) = exact {
                exhaustive = exhaustive.max(r);
                // a bound is a bound
                if x.torque_ratio < r - 1e-6 {
                    bound_below += 1;
                }
            } else {
                assert!(x.torque_ratio.is_nan(), "{name} t = {}", smp.t);
            }
        }
        let largest = pruned
            .iter()
            .filter(|x| !x.torque_ratio.is_nan())
            .map(|x| x.torque_ratio)
            .fold(0.0f64, f64::max);
        // samples without supporting forces are solved exactly (the program says so)
        let with_forces = pruned.iter().filter(|x| !x.torque_ratio.is_nan()).count();
        let solved = pruned
            .iter()
            .filter(|x| x.torque_exact && !x.torque_ratio.is_nan())
            .count();
        eprintln!(
            "{name}: largest torque ratio {largest:.9} (exhaustive {exhaustive:.9}), {solved} of \
             the {with_forces} samples with forces solved exactly ({} samples)",
            pruned.len()
        );
        assert_eq!(
            bound_below, 0,
            "{name}: an upper bound below the exact ratio"
        );
        assert!(
            (largest - exhaustive).abs() <= 1e-12,
            "{name}: {largest} against {exhaustive}"
        );
        assert!(solved * 2 < with_forces, "{name}: {solved} solved");
    }
}
