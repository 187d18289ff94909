//! One acceleration-level IK step (build + solve) on JVRC-1 (when its URDF is installed) and on
//! the project's small humanoid: the dense active-set solver against Clarabel, on the same QP.
//!
//! `cargo bench -p stance-robot --bench ik_step`

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::Vector3;
use stance_robot::{
    center_of_mass, jvrc1, ContactHold, Data, IkOptions, IkSolver, IkTasks, IkWorkspace,
    JointBounds, LinkTarget, Model, OrientationReference, PointReference, UrdfOptions,
    SMALL_HUMANOID_URDF,
};

/// A model's name, the model, a standing configuration, its two sole frames and a hand frame.
type Setup = (&'static str, Model, Vec<f64>, [usize; 2], usize);

fn setups() -> Vec<Setup> {
    let mut out = Vec::new();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    match jvrc1::locate_urdf(Some(&root)) {
        Ok(urdf) => {
            let m = Model::from_urdf_file(urdf, &jvrc1::urdf_options()).unwrap();
            let mut q = m.neutral();
            q[2] = 0.8;
            for side in ["R", "L"] {
                for (j, x) in [("HIP_P", -0.38), ("KNEE", 0.72), ("ANKLE_P", -0.33)] {
                    q[m.joints[m.joint_id(&format!("{side}_{j}")).unwrap()].idx_q] = x;
                }
            }
            let feet = jvrc1::SOLE_PARENT_FRAMES.map(|f| m.frame_id(f).unwrap());
            let hand = m.frame_id("r_wrist").unwrap();
            out.push(("jvrc1", m, q, feet, hand));
        }
        Err(why) => eprintln!("JVRC-1 skipped: {why}"),
    }
    let m = Model::from_urdf_str(SMALL_HUMANOID_URDF, &UrdfOptions::default()).unwrap();
    let mut q = m.neutral();
    for side in ["l", "r"] {
        for (j, x) in [("hip_p", -0.4), ("knee", 0.8), ("ankle_p", -0.4)] {
            q[m.joints[m.joint_id(&format!("{side}_{j}")).unwrap()].idx_q] = x;
        }
    }
    let feet = [m.frame_id("r_sole").unwrap(), m.frame_id("l_sole").unwrap()];
    let hand = m.frame_id("r_hand").unwrap();
    out.push(("small-humanoid", m, q, feet, hand));
    out
}

fn ik_step(c: &mut Criterion) {
    for (name, m, q, feet, hand) in setups() {
        let mut d = Data::new(&m);
        let c0 = center_of_mass(&m, &mut d, &q).unwrap();
        let holds = feet.map(ContactHold::velocity);
        let link = LinkTarget {
            frame: hand,
            reference: PointReference::hold(Vector3::new(0.3, -0.3, 1.0)),
            orientation: Some(OrientationReference::hold(nalgebra::Matrix3::identity())),
        };
        let tasks = IkTasks {
            contacts: &holds,
            com: PointReference::segment(c0, c0 + Vector3::new(0.0, 0.05, -0.02), 0.3),
            links: &[link],
            hard_links: &[],
            posture: Some(&q),
            distances: &[],
        };
        let q_s: Vec<f64> = (0..m.nv)
            .map(|i| 0.01 * ((i * 7 % 5) as f64 - 2.0))
            .collect();
        for solver in [IkSolver::Dense, IkSolver::Clarabel] {
            let opts = IkOptions {
                joint_bounds: JointBounds::paper(),
                w_posture: 1e-5,
                solver,
                ..Default::default()
            };
            let mut ws = IkWorkspace::new(&m);
            c.bench_function(&format!("ik_step/{name}/{solver:?}"), |b| {
                b.iter(|| ws.step(&m, &mut d, &q, &q_s, &tasks, 0.02, &opts).unwrap())
            });
        }
    }
}

criterion_group!(benches, ik_step);
criterion_main!(benches);
