//! Golden tests against Pinocchio 4.1.0 (fixtures made by `testdata/robot/make_fixtures.py`):
//! joint order, nq/nv, mass, CoM, CoM Jacobian, A_g, dA_g/dt v, the path terms p_s, p_ss, l1,
//! l2, `integrate`, inverse dynamics (`rnea`, generalized gravity, and the coefficients along a
//! path), frame placements, frame Jacobians (WORLD, LOCAL, LOCAL_WORLD_ALIGNED) and classical
//! accelerations, at random configurations and velocities.
//!
//! Tolerance: every entry within `1e-9 * max(1, max |reference entry|)` of the same quantity.
//! The JVRC-1 test needs the URDF from PyPI `jvrc-description` (see
//! `stance_robot::jvrc1::locate_urdf`); without it, it prints why and skips.

use std::path::{Path, PathBuf};

use nalgebra::Matrix6xX;
use serde_json::Value;
use stance_robot::*;

const REL_TOL: f64 = 1e-9;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn load(name: &str) -> Value {
    let path = root().join("testdata/robot").join(name);
    serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap()
}

fn vecf(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn mat(v: &Value) -> Vec<Vec<f64>> {
    v.as_array().unwrap().iter().map(vecf).collect()
}

/// Asserts that `got(i, j)` matches the reference rows within the relative tolerance.
fn check(what: &str, got: impl Fn(usize, usize) -> f64, reference: &[Vec<f64>]) -> f64 {
    let scale = reference
        .iter()
        .flatten()
        .fold(1.0f64, |a, x| a.max(x.abs()));
    let mut worst = 0.0f64;
    for (i, row) in reference.iter().enumerate() {
        for (j, r) in row.iter().enumerate() {
            let e = (got(i, j) - r).abs() / scale;
            assert!(
                e <= REL_TOL,
                "{what}[{i}][{j}]: got {}, Pinocchio {r} (relative error {e:.2e})",
                got(i, j)
            );
            worst = worst.max(e);
        }
    }
    worst
}

fn check_vec(what: &str, got: &[f64], reference: &[f64]) -> f64 {
    assert_eq!(got.len(), reference.len(), "{what}: length");
    check(what, |_, j| got[j], &[reference.to_vec()])
}

fn run_fixture(model: &Model, fx: &Value) {
    assert_eq!(model.nq as u64, fx["nq"].as_u64().unwrap(), "nq");
    assert_eq!(model.nv as u64, fx["nv"].as_u64().unwrap(), "nv");
    let names: Vec<String> = fx["joint_names"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_str().unwrap().to_string())
        .collect();
    assert_eq!(
        model.joint_names(),
        names,
        "joint order differs from Pinocchio's"
    );
    let mut data = Data::new(model);
    let mut jac = Matrix6xX::zeros(model.nv);
    let mut worst = 0.0f64;
    for (c, case) in fx["cases"].as_array().unwrap().iter().enumerate() {
        let q = vecf(&case["q"]);
        let v = vecf(&case["v"]);
        let dh = centroidal_map_dot_v(model, &mut data, &q, &v).unwrap();
        let tag = |s: &str| format!("case {c}: {s}");
        worst = worst.max(check_vec(
            &tag("mass"),
            &[data.mass],
            &[case["mass"].as_f64().unwrap()],
        ));
        worst = worst.max(check_vec(
            &tag("com"),
            data.com.as_slice(),
            &vecf(&case["com"]),
        ));
        let jc = &data.com_jacobian;
        worst = worst.max(check(
            &tag("com_jacobian"),
            |i, j| jc[(i, j)],
            &mat(&case["com_jacobian"]),
        ));
        let ag = &data.centroidal_map;
        worst = worst.max(check(
            &tag("centroidal_map"),
            |i, j| ag[(i, j)],
            &mat(&case["centroidal_map"]),
        ));
        worst = worst.max(check_vec(
            &tag("centroidal_map_dot_v"),
            dh.as_slice(),
            &vecf(&case["centroidal_map_dot_v"]),
        ));
        let pt = &case["path_terms"];
        let q_ss = vecf(&pt["q_ss"]);
        let t = path_terms(model, &mut data, &q, &v, &q_ss).unwrap();
        for (key, got) in [("p_s", t.p_s), ("p_ss", t.p_ss), ("l1", t.l1), ("l2", t.l2)] {
            worst = worst.max(check_vec(&tag(key), got.as_slice(), &vecf(&pt[key])));
        }
        let v3: Vec<f64> = v.iter().map(|x| 0.3 * x).collect();
        let q_next = integrate(model, &q, &v3).unwrap();
        worst = worst.max(check_vec(
            &tag("integrate(q, 0.3 v)"),
            &q_next,
            &vecf(&case["integrate_0_3_v"]),
        ));
        // path_terms recomputed the kinematics at the same (q, v): the frame checks below hold
        for (fname, fref) in case["frames"].as_object().unwrap() {
            let fid = model.frame_id(fname).unwrap();
            let pose = frame_placement(model, &data, fid).unwrap();
            worst = worst.max(check(
                &tag(&format!("{fname} rotation")),
                |i, j| pose.rotation[(i, j)],
                &mat(&fref["rotation"]),
            ));
            worst = worst.max(check_vec(
                &tag(&format!("{fname} translation")),
                pose.translation.as_slice(),
                &vecf(&fref["translation"]),
            ));
            for (key, rf) in [
                ("world", ReferenceFrame::World),
                ("local", ReferenceFrame::Local),
                ("local_world_aligned", ReferenceFrame::LocalWorldAligned),
            ] {
                frame_jacobian(model, &data, fid, rf, &mut jac).unwrap();
                let what = tag(&format!("{fname} jacobian {key}"));
                worst = worst.max(check(
                    &what,
                    |i, j| jac[(i, j)],
                    &mat(&fref[format!("jacobian_{key}")]),
                ));
                let (lin, ang) = frame_classical_acceleration(model, &data, fid, rf).unwrap();
                let got = [lin.as_slice(), ang.as_slice()].concat();
                let what = tag(&format!("{fname} classical acceleration {key}"));
                worst = worst.max(check_vec(
                    &what,
                    &got,
                    &vecf(&fref[format!("classical_acceleration_{key}")]),
                ));
            }
        }
        // inverse dynamics at (q, v, a = q_ss) with Pinocchio's default gravity, and the
        // coefficients along a path: tau_b + tau_c is the RNEA at (q, q_s, q_ss) (u = 0, x = 1)
        let g = [0.0, 0.0, -9.81];
        rnea(model, &mut data, &q, &v, &q_ss, g).unwrap();
        worst = worst.max(check_vec(&tag("rnea"), &data.tau, &vecf(&case["rnea"])));
        torque_path_terms(model, &mut data, &q, &v, &q_ss, g).unwrap();
        let tp = data.torque_path.clone();
        let at = |u: f64, x: f64| (0..model.nv).map(|k| tp.at(k, u, x)).collect::<Vec<_>>();
        worst = worst.max(check_vec(
            &tag("tau_b + tau_c"),
            &at(0.0, 1.0),
            &vecf(&case["rnea"]),
        ));
        worst = worst.max(check_vec(
            &tag("tau_c (generalized gravity)"),
            &tp.tau_c,
            &vecf(&case["generalized_gravity"]),
        ));
        // at another (u, x): v = q_s sqrt(x), a = q_s u + q_ss x, against the RNEA just checked
        let (u, x): (f64, f64) = (1.3, 0.4);
        let vx: Vec<f64> = v.iter().map(|y| y * x.sqrt()).collect();
        let ax: Vec<f64> = v.iter().zip(&q_ss).map(|(y, z)| y * u + z * x).collect();
        rnea(model, &mut data, &q, &vx, &ax, g).unwrap();
        let tau = data.tau.clone();
        worst = worst.max(check_vec(
            &tag("tau_a u + tau_b x + tau_c"),
            &at(u, x),
            &tau,
        ));
    }
    eprintln!("worst relative error against Pinocchio: {worst:.2e}");
}

fn small_options(fx: &Value) -> UrdfOptions {
    let locked = fx["locked"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p[0].as_str().unwrap().to_string(), p[1].as_f64().unwrap()))
        .collect();
    UrdfOptions {
        locked,
        ..Default::default()
    }
}

#[test]
fn small_humanoid_matches_pinocchio() {
    let fx = load("small_humanoid.json");
    let model = Model::from_urdf_str(SMALL_HUMANOID_URDF, &small_options(&fx)).unwrap();
    run_fixture(&model, &fx);
}

#[test]
fn small_humanoid_with_a_fixed_root_matches_pinocchio() {
    let fx = load("small_humanoid_fixed.json");
    assert_eq!(fx["root_joint"], "fixed");
    let options = UrdfOptions {
        root: RootJoint::Fixed,
        ..small_options(&fx)
    };
    let model = Model::from_urdf_str(SMALL_HUMANOID_URDF, &options).unwrap();
    run_fixture(&model, &fx);
}

#[test]
fn small_humanoid_with_locked_joints_matches_pinocchio_reduced_model() {
    let fx = load("small_humanoid_locked.json");
    let model = Model::from_urdf_str(SMALL_HUMANOID_URDF, &small_options(&fx)).unwrap();
    run_fixture(&model, &fx);
}

#[test]
fn jvrc1_matches_pinocchio() {
    let path = match jvrc1::locate_urdf(Some(&root())) {
        Ok(p) => p,
        Err(why) => {
            eprintln!("SKIPPED jvrc1_matches_pinocchio: {why}");
            return;
        }
    };
    let fx = load("jvrc1.json");
    let model = Model::from_urdf_file(path, &jvrc1::urdf_options()).unwrap();
    run_fixture(&model, &fx);
}
