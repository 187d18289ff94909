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
