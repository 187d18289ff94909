//! The data of `stance view` against independent computations: the library's polygons and
//! regions, forward kinematics, and the motion's own result (the page itself is tested in a
//! browser by scripts/test-view.sh).

use stance_contact::equilibrium::{PolygonWorkspace, RobustRegion};
use stance_contact::examples;
use stance_motion::{experiments, run_full, RunOptions};
use stance_robot::{center_of_mass, Data};
use stance_view::{motion_view, render, scene_view, MotionRecord, SceneViewOptions};

fn small_sway() -> stance_motion::MotionRun {
    let options = RunOptions {
        skip_checks: true,
        ..Default::default()
    };
    run_full(experiments::by_name("small-sway").unwrap(), &options).unwrap()
}

#[test]
fn scene_view_draws_the_library_polygon_and_a_region_inside_the_robust_region() {
    for name in examples::NAMES {
        let scene = examples::by_name(name).unwrap();
        let v = scene_view(&scene, name, &SceneViewOptions::default()).unwrap();
        let stance = scene.stance().unwrap();
        assert_eq!(v.stances[0].contacts.len(), stance.contacts().len());
        let p = v.stances[0].polygon.as_ref().unwrap();
        let lib = PolygonWorkspace::new()
            .static_polygon(&stance, scene.gravity, p.height, &Default::default())
            .unwrap()
            .polygon;
        assert_eq!(p.vertices.len(), lib.vertices.len(), "{name}");
        for (a, b) in p.vertices.iter().zip(&lib.vertices) {
            assert!((a[0] - b[0]).abs() <= 0.6e-4 && (a[1] - b[1]).abs() <= 0.6e-4);
        }
        // The drawn region is M above the lowest contact: its vertices pass M's own test
        // (within the rounding of the page, 0.1 mm) and lie above the floor.
        let r = v.region.as_ref().unwrap();
        let giwc = stance.u_stance(&Default::default()).unwrap();
        let m = RobustRegion::new(&giwc, &r.gravities, &Default::default()).unwrap();
        let floor = v.stances[0]
            .contacts
            .iter()
            .flat_map(|c| c.vertices.iter())
            .map(|p| p[2])
            .fold(f64::INFINITY, f64::min);
        for p in &r.vertices {
            assert!(
                m.margin(*p) >= -1e-3,
                "{name}: {p:?} margin {}",
                m.margin(*p)
            );
            assert!(p[2] >= floor - 1e-4);
        }
        let html = render(&v);
        assert!(html.contains("three.js 0.187.0"));
        assert!(
            !html.contains("{{"),
            "{name}: a template marker left in the page"
        );
    }
}

#[test]
fn scene_view_names_what_it_could_not_compute() {
    // A single point contact: a lower-dimensional GIWC has no polygon to speak of.
    let scene: stance_contact::Scene = serde_json::from_str(
        r#"{"mass": 30, "contacts": [{"name": "tip", "position": [0, 0, 0], "shape": "point", "friction": 0.5}]}"#,
    )
    .unwrap();
    let v = scene_view(&scene, "tip", &SceneViewOptions::default()).unwrap();
    assert_eq!(v.stances[0].contacts.len(), 1);
    let html = render(&v);
    assert!(html.contains("\"tip\""));
    // Whatever was not computed is a note, never a silent gap.
    assert_eq!(
        v.notes.len(),
        usize::from(v.stances[0].polygon.is_none()) + usize::from(v.region.is_none())
    );
}

#[test]
fn motion_view_plays_the_forward_kinematics_of_the_retimed_trajectory() {
    let run = small_sway();
    let model = &run.plan.robot.model;
    let record = MotionRecord::from(&run.result);
    let v = motion_view(&record, model, &Default::default()).unwrap();
    let robot = v.robot.as_ref().unwrap();
    let tr = run.result.trajectory.as_ref().unwrap();
    // Playback: from 0 to the duration, at most 50 frames per second of motion.
    assert_eq!(robot.t[0], 0.0);
    assert_eq!(*robot.t.last().unwrap(), *tr.t.last().unwrap());
    assert!((robot.t.last().unwrap() - run.result.duration.unwrap()).abs() < 1e-9);
    for w in robot.t.windows(2) {
        assert!(w[1] - w[0] >= 0.02 - 1e-9 || w[1] == *tr.t.last().unwrap());
    }
    // Joint origins and CoM: forward kinematics of the sample at that time, to 0.1 mm.
    let mut data = Data::new(model);
    let urdf_text = match &run.plan.robot.urdf {
        Some(path) => std::fs::read_to_string(path).unwrap(),
        None => stance_robot::SMALL_HUMANOID_URDF.to_string(),
    };
    let urdf = urdf_rs::read_from_string(&urdf_text).unwrap();
    let visuals: Vec<(String, stance_robot::Pose)> = urdf
        .links
        .iter()
        .flat_map(|l| {
            l.visual.iter().map(|v| {
                (
                    l.name.clone(),
                    stance_robot::Pose::from_xyz_rpy(v.origin.xyz.0, v.origin.rpy.0),
                )
            })
        })
        .collect();
    assert_eq!(robot.meshes.len(), visuals.len());
    for (f, &t) in robot.t.iter().enumerate() {
        let i = tr.t.iter().position(|&x| x == t).unwrap();
        let com = center_of_mass(model, &mut data, &tr.q[i]).unwrap();
        for k in 0..3 {
            assert!((robot.com[f][k] - com[k]).abs() <= 0.6e-4);
        }
        for j in 1..model.joints.len() {
            let x = data.world_from_joint[j].translation;
            for k in 0..3 {
                assert!((robot.positions[f][3 * (j - 1) + k] - x[k]).abs() <= 0.6e-4);
            }
        }
        assert_eq!(robot.segment[f] + 1, tr.segment[i]);
        // Joint orientations (quaternions rounded to 1e-4) and each drawn mesh where the URDF
        // puts its visual: the link's frame composed with the visual's origin, read here with
        // urdf-rs.
        for j in 1..model.joints.len() {
            let o = &robot.orientations[f][4 * (j - 1)..4 * j];
            let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                o[3], o[0], o[1], o[2],
            ));
            let r = q.to_rotation_matrix();
            assert!((r.matrix() - data.world_from_joint[j].rotation).abs().max() < 1e-3);
        }
        if f % 25 == 0 {
            for (mesh, visual) in robot.meshes.iter().zip(&visuals) {
                let (link, origin) = visual;
                assert_eq!(&mesh.link, link);
                let frame = model.frames.iter().position(|x| &x.name == link).unwrap();
                let want = stance_robot::kinematics::frame_placement(model, &data, frame)
                    .unwrap()
                    .compose(origin);
                let jp = &data.world_from_joint[mesh.joint + 1];
                let o = mesh.origin;
                let local = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                    o[6], o[3], o[4], o[5],
                ));
                let got_r = jp.rotation * local.to_rotation_matrix().matrix();
                let got_t = jp.rotation * nalgebra::Vector3::new(o[0], o[1], o[2]) + jp.translation;
                assert!((got_r - want.rotation).abs().max() < 1e-9);
                assert!((got_t - want.translation).norm() < 1e-9);
            }
        }
    }
    // Every bone joins a joint to its child.
    for b in &robot.bones {
        assert_eq!(model.joints[b[1] + 1].parent, b[0] + 1);
    }
    // The stances are the planned ones: same contacts as the GIWC's of each segment.
    assert_eq!(v.stances.len(), run.rows.len());
    for (s, rows) in v.stances.iter().zip(&run.rows) {
        let planned = rows.stance.contacts();
        assert_eq!(s.contacts.len(), planned.len());
        for (c, p) in s.contacts.iter().zip(planned) {
            assert_eq!(c.vertices.len(), p.vertices_world().len());
            for (a, b) in c.vertices.iter().zip(p.vertices_world()) {
                for k in 0..3 {
                    assert!((a[k] - b[k]).abs() <= 0.6e-4);
                }
            }
        }
        assert!(s.polygon.is_some());
    }
    // The phase plane is the result's, squared.
    let phase = v.phase.as_ref().unwrap();
    let p = run.result.phase.as_ref().unwrap();
    assert_eq!(phase.s, p.s);
    for (x, sd) in phase.x.iter().zip(&p.sd) {
        assert_eq!(*x, sd * sd);
    }
}

#[test]
fn motion_view_from_the_result_json_equals_the_view_of_the_run() {
    let run = small_sway();
    let json = serde_json::to_string(&run.result).unwrap();
    let record: MotionRecord = serde_json::from_str(&json).unwrap();
    let model = record.load_model().unwrap();
    let from_file = motion_view(&record, &model, &Default::default()).unwrap();
    let direct = motion_view(
        &MotionRecord::from(&run.result),
        &run.plan.robot.model,
        &Default::default(),
    )
    .unwrap();
    assert_eq!(from_file, direct);
    // A result whose robot changed since is an error naming what to do.
    let mut changed = record.clone();
    changed.robot.nq += 1;
    let e = changed.load_model().unwrap_err().to_string();
    assert!(e.contains("run `stance motion` again"), "{e}");
}

/// The page's forces hold the motion: at every frame they sum, with their moments about the
/// world origin taken at the page's contact vertices, to minus the gravito-inertial wrench of
/// the frame's sample (so they are in the vertices' order), and each vertex's friction usage is
/// `|f_t| / (mu f_n)` in its contact's frame.
#[test]
fn the_forces_balance_the_gravito_inertial_wrench_at_every_frame() {
    let run = small_sway();
    let model = &run.plan.robot.model;
    let v = motion_view(&MotionRecord::from(&run.result), model, &Default::default()).unwrap();
    let robot = v.robot.as_ref().unwrap();
    let forces = v.forces.as_ref().unwrap();
    let tr = run.result.trajectory.as_ref().unwrap();
    let mut data = Data::new(model);
    assert_eq!(forces.forces.len(), robot.t.len());
    assert!(
        forces.feasible.iter().all(|&f| f),
        "small-sway holds at every frame"
    );
    let weight = model.total_mass() * 9.81;
    assert!((forces.scale - stance_view::WEIGHT_ARROW / weight).abs() < 1e-12);
    for (f, &i) in robot.samples.iter().enumerate() {
        let w = stance_motion::checks::w_gi_of(
            model,
            &mut data,
            &tr.q[i],
            &tr.v[i],
            &tr.a[i],
            run.plan.gravity,
        )
        .unwrap();
        let stance = &v.stances[robot.segment[f]];
        let (mut sum_f, mut sum_m) = ([0.0; 3], [0.0; 3]);
        for (c, fs) in stance.contacts.iter().zip(&forces.forces[f]) {
            assert_eq!(fs.len(), c.vertices.len());
            for (p, x) in c.vertices.iter().zip(fs) {
                let m = [
                    p[1] * x[2] - p[2] * x[1],
                    p[2] * x[0] - p[0] * x[2],
                    p[0] * x[1] - p[1] * x[0],
                ];
                for k in 0..3 {
                    sum_f[k] += x[k];
                    sum_m[k] += m[k];
                }
            }
        }
        for k in 0..3 {
            // rounding to 0.1 N at 8 vertices
            assert!(
                (sum_f[k] + w[k]).abs() < 1.0,
                "frame {f}: force {sum_f:?} vs {w:?}"
            );
            assert!(
                (sum_m[k] + w[3 + k]).abs() < 1.0,
                "frame {f}: moment {sum_m:?} vs {w:?}"
            );
        }
        for ((c, fs), us) in stance
            .contacts
            .iter()
            .zip(&forces.forces[f])
            .zip(&forces.usage[f])
        {
            for (x, u) in fs.iter().zip(us) {
                // in the contact frame: axes are the columns (x, y, normal)
                let local: Vec<f64> = (0..3)
                    .map(|a| (0..3).map(|k| c.axes[k][a] * x[k]).sum())
                    .collect();
                if local[2] > 20.0 {
                    let want = local[0].hypot(local[1]) / (c.friction * local[2]);
                    assert!((u - want).abs() < 0.01, "frame {f}: usage {u} vs {want}");
                }
            }
        }
    }
}

/// The closest approaches the page lists are the collision model's distances, under 2 cm, never
/// closer than the collision check found over all samples; the torque ratios never exceed the
/// limit check's largest.
#[test]
fn clearance_and_torque_layers_agree_with_the_checks() {
    let run = run_full(
        experiments::by_name("box-climbing").unwrap(),
        &RunOptions::default(),
    )
    .unwrap();
    let mut v = motion_view(
        &MotionRecord::from(&run.result),
        &run.plan.robot.model,
        &Default::default(),
    )
    .unwrap();
    stance_view::add_run_layers(&mut v, &run).unwrap();
    let robot = v.robot.as_ref().unwrap();
    let clearance = v.clearance.as_ref().unwrap();
    let checks = run.result.checks.as_ref().unwrap();
    let model = &run.plan.robot.model;
    let mut data = Data::new(model);
    let mut listed = 0;
    for (f, near) in clearance.frames.iter().enumerate() {
        let s = &run.samples[robot.samples[f]];
        stance_robot::forward_kinematics(model, &mut data, &s.q).unwrap();
        for n in near {
            listed += 1;
            assert!(n.distance < stance_view::CLEARANCE_SHOWN);
            let b = run.plan.collision.body(&n.body).unwrap();
            let k = run
                .plan
                .environment
                .iter()
                .position(|e| e.name == n.surface)
                .unwrap();
            let d = run.plan.collision.distance(&data, b, k, 0.1).unwrap();
            assert!((d.distance - n.distance).abs() <= 0.6e-4);
            if let Some(c) = checks.clearances.iter().find(|c| c.body == n.body) {
                assert!(
                    n.distance >= c.distance - 1e-4,
                    "{} closer than the check",
                    n.body
                );
            }
        }
    }
    assert!(
        listed > 0,
        "the hand comes within 2 cm of the ledge before it lands"
    );
    let torque = v.torque.as_ref().unwrap();
    assert!(torque.balanced.iter().all(|&b| b));
    let max = torque.ratio.iter().fold(0.0, |a: f64, &b| a.max(b));
    let checked = checks.max_torque_ratio.unwrap();
    assert!(
        max > 0.1 && max <= checked + 1e-4,
        "{max} vs the check's {checked}"
    );
}

/// A simulation report is drawn beside its plan: its frames are the forward kinematics of the
/// executed configurations, its events numbered in time order, its verdict in the title.
#[test]
fn a_simulation_is_drawn_beside_its_plan() {
    let run = small_sway();
    let model = &run.plan.robot.model;
    // an execution 5 cm ahead of the plan in x, every 20 ms, that "falls" at 1 s
    let mut t = Vec::new();
    let mut q = Vec::new();
    for s in run.samples.iter().step_by(20) {
        let mut x = s.q.clone();
        x[0] += 0.05;
        t.push(s.t);
        q.push(x);
    }
    let record: stance_view::SimRecord = serde_json::from_value(serde_json::json!({
        "held": false, "reason": "fell at t = 1.000 s", "time_scale": 1.0,
        "events": [
            {"kind": "fall", "t": 1.0, "position": [0.0, 0.0, 0.5], "text": "fell"},
            {"kind": "slip", "t": 0.5, "position": [0.0, 0.1, 0.0], "text": "LF slipped"}
        ],
        "trajectory": {"t": t, "q": q, "plan_t0": 0.0},
        "motion": {"motion": "small-sway", "time_scale": 1.0, "segments": null,
                   "no_limits": false, "duration": run.result.duration.unwrap()}
    }))
    .unwrap();
    let v = stance_view::simulation_page(&run, &record, &Default::default()).unwrap();
    assert!(v.title.ends_with("failed in MuJoCo"), "{}", v.title);
    let sim = v.simulation.as_ref().unwrap();
    let numbers: Vec<(usize, &str)> = sim
        .events
        .iter()
        .map(|e| (e.number, e.kind.as_str()))
        .collect();
    assert_eq!(numbers, [(1, "slip"), (2, "fall")]);
    let mut data = Data::new(model);
    for (f, x) in record.trajectory.as_ref().unwrap().q.iter().enumerate() {
        let com = center_of_mass(model, &mut data, x).unwrap();
        for j in 1..model.joints.len() {
            let p = data.world_from_joint[j].translation;
            for k in 0..3 {
                assert!((sim.positions[f][3 * (j - 1) + k] - p[k]).abs() <= 0.6e-4);
            }
        }
        assert!((sim.com[f][0] - com.x).abs() <= 0.6e-4);
    }
    // a report whose trajectory is missing is refused
    let mut bad = record.clone();
    bad.trajectory = None;
    let mut view = v.clone();
    assert!(stance_view::add_simulation(&mut view, &bad, model).is_err());
}
