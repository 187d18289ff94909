//! Property tests (proptest) on the small humanoid, each against an independent slow check:
//!
//! - `A_g v` equals the sum over the bodies of their momenta about the CoM, each body's velocity
//!   taken from finite differences of its placement;
//! - central finite differences of the CoM and of frame placements along random directions match
//!   the CoM Jacobian and the frame Jacobians (all three reference frames);
//! - `(dA_g/dt) v` matches a finite difference of `A_g v` along the motion `q (+) t v`;
//! - frame classical accelerations match finite differences of `J v` along the motion;
//! - the path terms `p_s, p_ss, l1, l2` match finite differences along `q(s) = q0 (+) (s a + s^2 b / 2)`;
//! - locking any subset of joints at their values in `q` leaves mass, CoM, frame placements and
//!   the remaining columns of `A_g` unchanged.
//!
//! Finite-difference step `H = 1e-5` (central differences: truncation `~H^2 = 1e-10`, round-off
//! `~1e-16 / H = 1e-11`), second differences with `H2 = 1e-4`; tolerances are set from these
//! error sizes, relative to the size of the compared quantity.

use nalgebra::{Matrix3, Matrix6xX, Vector3, Vector6};
use proptest::prelude::*;
use stance_robot::*;

const H: f64 = 1e-5;
const H2: f64 = 1e-4;
const FD_TOL: f64 = 1e-6;
const FD2_TOL: f64 = 1e-5;

fn model() -> Model {
    Model::from_urdf_str(SMALL_HUMANOID_URDF, &UrdfOptions::default()).unwrap()
}

/// Configuration from uniform samples in [0, 1): base in a 2 m cube, orientation from 4
/// (shifted) samples, joints within limits (continuous joints: any angle).
fn config_from(model: &Model, u: &[f64]) -> Vec<f64> {
    let mut q = model.neutral();
    let mut k = 0;
    let mut next = || {
        k += 1;
        u[k - 1]
    };
    for j in &model.joints {
        let i = j.idx_q;
        match j.kind {
            JointKind::Universe => {}
            JointKind::FreeFlyer => {
                for x in q.iter_mut().skip(i).take(3) {
                    *x = 2.0 * next() - 1.0;
                }
                let quat: Vec<f64> = (0..4).map(|_| next() - 0.5 + 1e-3).collect();
                let n = quat.iter().map(|x| x * x).sum::<f64>().sqrt();
                for (a, b) in quat.iter().enumerate() {
                    q[i + 3 + a] = b / n;
                }
            }
            JointKind::Continuous { .. } => {
                let a = (2.0 * next() - 1.0) * std::f64::consts::PI;
                q[i] = a.cos();
                q[i + 1] = a.sin();
            }
            _ => q[i] = j.lower + (j.upper - j.lower) * next(),
        }
    }
    q
}

fn sample() -> impl Strategy<Value = (Vec<f64>, Vec<f64>, Vec<f64>)> {
    let m = model();
    (
        prop::collection::vec(0.0..1.0f64, m.nq + 4),
        prop::collection::vec(-1.0..1.0f64, m.nv),
        prop::collection::vec(-1.0..1.0f64, m.nv),
    )
}

fn scaled(v: &[f64], t: f64) -> Vec<f64> {
    v.iter().map(|x| x * t).collect()
}

fn vee_rate(
    r_plus: &Matrix3<f64>,
    r_minus: &Matrix3<f64>,
    r: &Matrix3<f64>,
    h: f64,
) -> Vector3<f64> {
    // angular velocity in world axes: [w] = R_dot R^T
    let w = (r_plus - r_minus) / (2.0 * h) * r.transpose();
    Vector3::new(
        w[(2, 1)] - w[(1, 2)],
        w[(0, 2)] - w[(2, 0)],
        w[(1, 0)] - w[(0, 1)],
    ) / 2.0
}

fn assert_rel(what: &str, got: &[f64], want: &[f64], tol: f64) {
    let scale = want.iter().fold(1.0f64, |a, x| a.max(x.abs()));
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (g - w).abs() <= tol * scale,
            "{what}[{i}]: {g} vs independent {w} (scale {scale})"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn momentum_is_the_sum_of_body_momenta_about_the_com((u, v, _b) in sample()) {
        let m = model();
        let q = config_from(&m, &u);
        let mut d = Data::new(&m);
        centroidal_map(&m, &mut d, &q).unwrap();
        let h = &d.centroidal_map * nalgebra::DVector::from_column_slice(&v);
        let com = d.com;
        // body placements at q (+) -H v, q, q (+) H v
        let mut dp = Data::new(&m);
        let mut dm = Data::new(&m);
        forward_kinematics(&m, &mut dp, &integrate(&m, &q, &scaled(&v, H)).unwrap()).unwrap();
        forward_kinematics(&m, &mut dm, &integrate(&m, &q, &scaled(&v, -H)).unwrap()).unwrap();
        let mut lin = Vector3::zeros();
        let mut ang = Vector3::zeros();
        for i in 1..m.joints.len() {
            let y = &m.inertias[i];
            let c = |x: &Pose| x.transform_point(&y.lever);
            let (p0, pp, pm) = (d.world_from_joint[i], dp.world_from_joint[i], dm.world_from_joint[i]);
            let c_dot = (c(&pp) - c(&pm)) / (2.0 * H);
            let w = vee_rate(&pp.rotation, &pm.rotation, &p0.rotation, H);
            let i_world = p0.rotation * y.inertia_com * p0.rotation.transpose();
            lin += c_dot * y.mass;
            ang += i_world * w + (c(&p0) - com).cross(&(c_dot * y.mass));
        }
        let want = [lin.as_slice(), ang.as_slice()].concat();
        assert_rel("A_g v", h.as_slice(), &want, FD_TOL);
    }

    #[test]
    fn com_and_frame_jacobians_match_finite_differences((u, v, _b) in sample()) {
        let m = model();
        let q = config_from(&m, &u);
        let (qp, qm) = (integrate(&m, &q, &scaled(&v, H)).unwrap(), integrate(&m, &q, &scaled(&v, -H)).unwrap());
        let mut d = Data::new(&m);
        let cp = center_of_mass(&m, &mut d, &qp).unwrap();
        let cm = center_of_mass(&m, &mut d, &qm).unwrap();
        com_jacobian(&m, &mut d, &q).unwrap();
        let jv = &d.com_jacobian * nalgebra::DVector::from_column_slice(&v);
        assert_rel("J_com v", jv.as_slice(), ((cp - cm) / (2.0 * H)).as_slice(), FD_TOL);
        let mut jac = Matrix6xX::zeros(m.nv);
        for name in ["r_sole", "l_hand", "imu", "head", "torso_lift"] {
            let f = m.frame_id(name).unwrap();
            let mut dp = Data::new(&m);
            let mut dm = Data::new(&m);
            forward_kinematics(&m, &mut dp, &qp).unwrap();
            forward_kinematics(&m, &mut dm, &qm).unwrap();
            forward_kinematics(&m, &mut d, &q).unwrap();
            let (p0, pp, pm) = (
                frame_placement(&m, &d, f).unwrap(),
                frame_placement(&m, &dp, f).unwrap(),
                frame_placement(&m, &dm, f).unwrap(),
            );
            let p_dot = (pp.translation - pm.translation) / (2.0 * H);
            let w = vee_rate(&pp.rotation, &pm.rotation, &p0.rotation, H);
            let rt = p0.rotation.transpose();
            let expected = [
                (ReferenceFrame::LocalWorldAligned, p_dot, w),
                (ReferenceFrame::Local, rt * p_dot, rt * w),
                (ReferenceFrame::World, p_dot - w.cross(&p0.translation), w),
            ];
            for (rf, lin, ang) in expected {
                frame_jacobian(&m, &d, f, rf, &mut jac).unwrap();
                let got = &jac * nalgebra::DVector::from_column_slice(&v);
                let want = [lin.as_slice(), ang.as_slice()].concat();
                assert_rel(&format!("{name} J v {rf:?}"), got.as_slice(), &want, FD_TOL);
            }
        }
    }

    #[test]
    fn drifts_match_finite_differences_along_the_motion((u, v, _b) in sample()) {
        let m = model();
        let q = config_from(&m, &u);
        let (qp, qm) = (integrate(&m, &q, &scaled(&v, H)).unwrap(), integrate(&m, &q, &scaled(&v, -H)).unwrap());
        let vv = nalgebra::DVector::from_column_slice(&v);
        let mut d = Data::new(&m);
        centroidal_map(&m, &mut d, &qp).unwrap();
        let hp = &d.centroidal_map * &vv;
        centroidal_map(&m, &mut d, &qm).unwrap();
        let hm = &d.centroidal_map * &vv;
        let dh = centroidal_map_dot_v(&m, &mut d, &q, &v).unwrap();
        assert_rel("dA_g/dt v", dh.as_slice(), ((hp - hm) / (2.0 * H)).as_slice(), FD_TOL);
        let mut jac = Matrix6xX::zeros(m.nv);
        for name in ["l_sole", "r_hand", "head"] {
            let f = m.frame_id(name).unwrap();
            let mut velocity_at = |qx: &[f64]| -> Vector6<f64> {
                let mut dx = Data::new(&m);
                forward_kinematics(&m, &mut dx, qx).unwrap();
                frame_jacobian(&m, &dx, f, ReferenceFrame::LocalWorldAligned, &mut jac).unwrap();
                let x = &jac * &vv;
                Vector6::from_column_slice(x.as_slice())
            };
            let fd = (velocity_at(&qp) - velocity_at(&qm)) / (2.0 * H);
            forward_kinematics_velocity(&m, &mut d, &q, &v).unwrap();
            let (lin, ang) = frame_classical_acceleration(&m, &d, f, ReferenceFrame::LocalWorldAligned).unwrap();
            let got = [lin.as_slice(), ang.as_slice()].concat();
            assert_rel(&format!("{name} classical acceleration"), &got, fd.as_slice(), FD_TOL);
        }
    }

    #[test]
    fn path_terms_match_finite_differences_along_a_path((u, a, b) in sample()) {
        let m = model();
        let q0 = config_from(&m, &u);
        let q_at = |s: f64| {
            let xi: Vec<f64> = a.iter().zip(&b).map(|(x, y)| s * x + 0.5 * s * s * y).collect();
            integrate(&m, &q0, &xi).unwrap()
        };
        let mut d = Data::new(&m);
        let t = path_terms(&m, &mut d, &q0, &a, &b).unwrap();
        let (p_p, p_0, p_m) = (
            center_of_mass(&m, &mut d, &q_at(H2)).unwrap(),
            center_of_mass(&m, &mut d, &q_at(0.0)).unwrap(),
            center_of_mass(&m, &mut d, &q_at(-H2)).unwrap(),
        );
        assert_rel("p", t.p.as_slice(), p_0.as_slice(), 1e-14);
        assert_rel("p_s", t.p_s.as_slice(), ((p_p - p_m) / (2.0 * H2)).as_slice(), FD2_TOL);
        assert_rel("p_ss", t.p_ss.as_slice(), ((p_p - 2.0 * p_0 + p_m) / (H2 * H2)).as_slice(), FD2_TOL);
        // L(s) for s' = 1: A_ang(q(s)) q_s(s), with the path's body twist q_s(s) = a + s b + O(s^2)
        let mut l_at = |s: f64| -> Vector3<f64> {
            centroidal_map(&m, &mut d, &q_at(s)).unwrap();
            let qs: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x + s * y).collect();
            let h = &d.centroidal_map * nalgebra::DVector::from_column_slice(&qs);
            Vector3::new(h[3], h[4], h[5])
        };
        let l1_want = l_at(0.0);
        let l2_want = (l_at(H2) - l_at(-H2)) / (2.0 * H2);
        assert_rel("l1", t.l1.as_slice(), l1_want.as_slice(), 1e-12);
        assert_rel("l2", t.l2.as_slice(), l2_want.as_slice(), FD2_TOL);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// Locking joints at their values in `q` changes nothing but the variables: same mass, CoM,
    /// frame placements, and A_g restricted to the remaining velocity entries.
    #[test]
    fn locking_joints_at_their_values_is_invisible((u, _v, _b) in sample(), mask in prop::collection::vec(any::<bool>(), 26)) {
        let full = model();
        let q = config_from(&full, &u);
        let mut locked = Vec::new();
        let mut keep_q = Vec::new();
        let mut keep_v = Vec::new();
        for (i, j) in full.joints.iter().enumerate().skip(2) {
            let (nq, nv) = j.dims();
            if mask[i - 2] {
                let value = match j.kind {
                    JointKind::Continuous { .. } => q[j.idx_q + 1].atan2(q[j.idx_q]),
                    _ => q[j.idx_q],
                };
                locked.push((j.name.clone(), value));
            } else {
                keep_q.extend(j.idx_q..j.idx_q + nq);
                keep_v.extend(j.idx_v..j.idx_v + nv);
            }
        }
        let reduced = Model::from_urdf_str(SMALL_HUMANOID_URDF, &UrdfOptions { locked, ..Default::default() }).unwrap();
        let q_red: Vec<f64> = (0..7).chain(keep_q).map(|k| q[k]).collect();
        let v_idx: Vec<usize> = (0..6).chain(keep_v).collect();
        prop_assert_eq!(reduced.nq, q_red.len());
        let (mut df, mut dr) = (Data::new(&full), Data::new(&reduced));
        centroidal_map(&full, &mut df, &q).unwrap();
        centroidal_map(&reduced, &mut dr, &q_red).unwrap();
        prop_assert!((df.mass - dr.mass).abs() < 1e-12);
        prop_assert!((df.com - dr.com).norm() < 1e-12);
        for (kr, &kf) in v_idx.iter().enumerate() {
            prop_assert!((df.centroidal_map.column(kf) - dr.centroidal_map.column(kr)).norm() < 1e-11);
        }
        for name in ["r_sole", "l_hand", "imu", "head", "neck", "torso"] {
            let a = frame_placement(&full, &df, full.frame_id(name).unwrap()).unwrap();
            let b = frame_placement(&reduced, &dr, reduced.frame_id(name).unwrap()).unwrap();
            prop_assert!((a.translation - b.translation).norm() < 1e-12);
            prop_assert!((a.rotation - b.rotation).norm() < 1e-12);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Moving the world origin (the robot's base translated by `d`, from 1 m to 1e155 m) leaves
    /// `A_g`, `J_com` and `(dA_g/dt) v` unchanged and moves the CoM by `d` (they were 6e-3 off
    /// at 1e6 m and NaN at 1e155 m when computed about the origin).
    #[test]
    fn centroidal_quantities_do_not_depend_on_the_world_origin(
        (u, v, _b) in sample(),
        exponent in 0i32..=155,
        dir in prop::collection::vec(-1.0..1.0f64, 3),
    ) {
        let m = model();
        let q = config_from(&m, &u);
        let norm = dir.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-3);
        let d: Vec<f64> = dir.iter().map(|x| x / norm * 10f64.powi(exponent)).collect();
        let mut moved = q.clone();
        for k in 0..3 {
            moved[k] += d[k];
        }
        let mut a = Data::new(&m);
        let mut b = Data::new(&m);
        let dh_a = centroidal_map_dot_v(&m, &mut a, &q, &v).unwrap();
        let dh_b = centroidal_map_dot_v(&m, &mut b, &moved, &v).unwrap();
        assert_rel("A_g", b.centroidal_map.as_slice(), a.centroidal_map.as_slice(), 1e-12);
        assert_rel("J_com", b.com_jacobian.as_slice(), a.com_jacobian.as_slice(), 1e-12);
        assert_rel("dA_g v", dh_b.as_slice(), dh_a.as_slice(), 1e-12);
        let mut c = Data::new(&m);
        centroidal_map(&m, &mut c, &moved).unwrap();
        assert_rel("A_g (without v)", c.centroidal_map.as_slice(), a.centroidal_map.as_slice(), 1e-12);
        for (k, dk) in d.iter().enumerate() {
            let want = a.com[k] + dk;
            let tol = 8.0 * f64::EPSILON * want.abs().max(1.0);
            prop_assert!((b.com[k] - want).abs() <= tol, "com[{k}] {} vs {want}", b.com[k]);
            prop_assert!((c.com[k] - want).abs() <= tol);
        }
        // The world placements are those of the moved configuration.
        let base = b.world_from_joint[1].translation;
        for k in 0..3 {
            prop_assert_eq!(base[k], moved[k]);
        }
    }
}
