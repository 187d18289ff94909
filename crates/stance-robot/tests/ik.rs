//! The acceleration-level IK (docs/math.md section 6) on the small humanoid: the QP solution agrees
//! with an independent dense KKT solve when no bound is active; tracked paths keep the feet in
//! place, follow the CoM and stay within joint limits; negative outcomes are values.

use nalgebra::{DMatrix, DVector, Vector3};
use stance_robot::*;

fn model() -> Model {
    Model::from_urdf_str(SMALL_HUMANOID_URDF, &UrdfOptions::default()).unwrap()
}

/// A standing configuration with bent knees (hips and ankles compensate), feet flat, elbows
/// bent off their limit.
fn standing(m: &Model) -> Vec<f64> {
    let mut q = m.neutral();
    for side in ["l", "r"] {
        let set =
            |q: &mut Vec<f64>, name: &str, x: f64| q[m.joints[m.joint_id(name).unwrap()].idx_q] = x;
        set(&mut q, &format!("{side}_hip_p"), -0.4);
        set(&mut q, &format!("{side}_knee"), 0.8);
        set(&mut q, &format!("{side}_ankle_p"), -0.4);
        set(&mut q, &format!("{side}_elbow"), -0.3);
    }
    q
}

/// Uniform numbers in [-1, 1) from a xorshift generator (reproducible random states).
fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// A random configuration near the standing one (base and joints moved by up to 0.2), its joints
/// within 98 % of their ranges: a state the IK can be asked to step from.
fn reachable(m: &Model, rnd: &mut impl FnMut() -> f64) -> Vec<f64> {
    let dq: Vec<f64> = (0..m.nv).map(|_| 0.2 * rnd()).collect();
    let mut q = integrate(m, &standing(m), &dq).unwrap();
    for j in &m.joints[2..] {
        if j.dims() == (1, 1) {
            let (mid, half) = (0.5 * (j.upper + j.lower), 0.49 * (j.upper - j.lower));
            q[j.idx_q] = q[j.idx_q].clamp(mid - half, mid + half);
        }
    }
    q
}

fn feet(m: &Model) -> [usize; 2] {
    [m.frame_id("r_sole").unwrap(), m.frame_id("l_sole").unwrap()]
}

/// The QP's minimizer under its equality constraints only, by a dense KKT solve:
/// `[P A^T; A 0] [x; y] = [-c; b]`.
fn kkt_solution(qp: &IkQp) -> DVector<f64> {
    let (n, me) = (qp.p.nrows(), qp.a_eq.nrows());
    let mut kkt = DMatrix::zeros(n + me, n + me);
    kkt.view_mut((0, 0), (n, n)).copy_from(&qp.p);
    kkt.view_mut((0, n), (n, me))
        .copy_from(&qp.a_eq.transpose());
    kkt.view_mut((n, 0), (me, n)).copy_from(&qp.a_eq);
    let mut rhs = DVector::zeros(n + me);
    rhs.rows_mut(0, n).copy_from(&(-&qp.c));
    rhs.rows_mut(n, me).copy_from(&qp.b_eq);
    let sol = kkt.lu().solve(&rhs).expect("KKT matrix is regular");
    sol.rows(0, n).into_owned()
}

fn objective(qp: &IkQp, x: &DVector<f64>) -> f64 {
    0.5 * x.dot(&(&qp.p * x)) + qp.c.dot(x)
}

/// Checks Clarabel's answer against the KKT solution when no bound is active: the contact
/// equations hold to 1e-7 (relative to their right-hand side) and the objective matches to
/// 1e-7 relative. Clarabel stops when its duality gap and residuals are below 1e-8 (absolute and
/// relative, on its internally scaled problem): the objective is what that guarantees, not x
/// itself, since the regularization (1e-6) leaves directions along which the objective is
/// nearly flat; 10x margin for the scaling.
fn assert_matches_kkt(qp: &IkQp, step: &IkStep) -> Result<(), String> {
    let x = DVector::from_column_slice(&step.q_ss);
    let x_kkt = kkt_solution(qp);
    let (f, f_kkt) = (objective(qp, &x), objective(qp, &x_kkt));
    let gap = (f - f_kkt).abs() / f_kkt.abs().max(1.0);
    let residual = step.contact_residual / qp.b_eq.amax().max(1.0);
    let dx = (&x - &x_kkt).amax() / x_kkt.amax().max(1.0);
    if gap < 1e-7 && residual < 1e-7 {
        Ok(())
    } else {
        Err(format!(
            "objective gap {gap:.2e}, contact residual {residual:.2e} (x differs by {dx:.2e})"
        ))
    }
}

#[test]
fn qp_solution_matches_a_dense_kkt_solve_when_no_bound_is_active() {
    let m = model();
    let mut d = Data::new(&m);
    let q = standing(&m);
    let q_s: Vec<f64> = (0..m.nv).map(|k| 0.01 * ((k as f64) * 0.7).sin()).collect();
    let c0 = center_of_mass(&m, &mut d, &q).unwrap();
    let com = PointReference {
        p: c0 + Vector3::new(0.01, -0.02, 0.0),
        p_s: Vector3::new(0.0, 0.05, -0.01),
        p_ss: Vector3::new(0.0, 0.0, 0.1),
    };
    let hand = LinkTarget {
        frame: m.frame_id("l_hand").unwrap(),
        reference: PointReference {
            p: Vector3::new(0.2, 0.3, 0.1),
            p_s: Vector3::zeros(),
            p_ss: Vector3::zeros(),
        },
        orientation: Some(OrientationReference {
            rotation: nalgebra::Rotation3::from_euler_angles(0.1, -0.2, 0.3).into_inner(),
            w_s: Vector3::new(0.1, 0.0, -0.2),
            w_ss: Vector3::new(0.0, 0.3, 0.0),
        }),
    };
    let opts = IkOptions::default();
    let qp = ik_qp(&m, &mut d, &q, &q_s, &feet(&m), &com, &[hand], 0.01, &opts).unwrap();
    let step = solve_ik_qp(&qp, opts.qp_tol).unwrap();
    assert_eq!(step.status, IkStatus::Solved);
    let x = DVector::from_column_slice(&step.q_ss);
    let slack = &qp.h - &qp.g * &x;
    assert!(slack.min() > 1.0, "a bound is active: this test needs none");
    assert_matches_kkt(&qp, &step).unwrap();
}

#[test]
fn tracking_a_com_shift_keeps_the_feet_and_follows_the_com() {
    let m = model();
    let q0 = standing(&m);
    let c0 = center_of_mass(&m, &mut Data::new(&m), &q0).unwrap();
    let c1 = c0 + Vector3::new(0.02, 0.05, -0.03);
    let grid: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
    let path = track_path(
        &m,
        &q0,
        &vec![0.0; m.nv],
        &feet(&m),
        &grid,
        &|s| (PointReference::segment(c0, c1, s), vec![]),
        &IkOptions::default(),
    )
    .unwrap();
    assert_eq!(path.status, IkStatus::Solved);
    assert_eq!(path.samples.len(), grid.len());
    eprintln!(
        "contact drift {:.2e} m, rotation {:.2e} rad, CoM error {:.2e} m, contact residual {:.2e}",
        path.max_contact_drift,
        path.max_contact_rotation,
        path.max_com_error,
        path.max_contact_residual
    );
    // Slip of a 22 cm sole by less than 0.1 mm over the motion: the integration error of 100
    // steps (the QP holds the contact accelerations to its 1e-9 tolerance).
    assert!(path.max_contact_drift < 1e-4);
    assert!(path.max_contact_rotation < 1e-3);
    // The CoM starts at rest while its reference moves at |c1 - c0| per unit s: with K_p = K_d =
    // 10 the lag is a few mm at most on this 6 cm move.
    assert!(path.max_com_error < 0.01, "{}", path.max_com_error);
    let mut d = Data::new(&m);
    let last = path.samples.last().unwrap();
    let t = path_terms(&m, &mut d, &last.q, &last.q_s, &last.q_ss).unwrap();
    assert!((t.p - c1).norm() < 0.01);
}

#[test]
fn joint_limits_hold_when_the_com_rises() {
    // Raising the CoM by 4 cm with the feet held drives the prismatic torso_lift (range +-5 cm)
    // to its upper limit, which the bounds must hold.
    let m = model();
    let q0 = standing(&m);
    let c0 = center_of_mass(&m, &mut Data::new(&m), &q0).unwrap();
    let c1 = c0 + Vector3::new(0.0, 0.0, 0.04);
    let grid: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
    let path = track_path(
        &m,
        &q0,
        &vec![0.0; m.nv],
        &feet(&m),
        &grid,
        &|s| (PointReference::segment(c0, c1, s), vec![]),
        &IkOptions::default(),
    )
    .unwrap();
    assert_eq!(path.status, IkStatus::Solved);
    let lift = m.joints[m.joint_id("torso_lift").unwrap()].clone();
    let mut saturated = false;
    for s in &path.samples {
        for j in &m.joints[1..] {
            if matches!(
                j.kind,
                JointKind::Revolute { .. } | JointKind::Prismatic { .. }
            ) {
                let x = s.q[j.idx_q];
                // the bound is met by the QP to its tolerance (1e-8) times ds^2 / 2
                assert!(
                    x <= j.upper + 1e-9 && x >= j.lower - 1e-9,
                    "{} = {x} out of [{}, {}]",
                    j.name,
                    j.lower,
                    j.upper
                );
            }
        }
        saturated |= s.q[lift.idx_q] > lift.upper - 1e-6;
    }
    assert!(saturated, "torso_lift should reach its limit");
    assert!(path.max_contact_drift < 1e-4);
}

/// A joint driven onto its limit and back on a coarse grid stays within the limit inside each
/// step too: with `q_ss` constant on a step, a joint that turns back within it peaks between
/// the samples, which the next-step bound at the step's end alone does not see.
#[test]
fn joint_limits_hold_inside_each_step() {
    let m = model();
    let q0 = standing(&m);
    let c0 = center_of_mass(&m, &mut Data::new(&m), &q0).unwrap();
    let lift = m.joints[m.joint_id("torso_lift").unwrap()].clone();
    let (a, pi) = (0.06, std::f64::consts::PI);
    let grid: Vec<f64> = (0..=50).map(|i| i as f64 / 50.0).collect();
    let reference = |s: f64| PointReference {
        p: c0 + Vector3::new(0.0, 0.0, a * (pi * s).sin()),
        p_s: Vector3::new(0.0, 0.0, a * pi * (pi * s).cos()),
        p_ss: Vector3::new(0.0, 0.0, -a * pi * pi * (pi * s).sin()),
    };
    let path = track_path(
        &m,
        &q0,
        &vec![0.0; m.nv],
        &feet(&m),
        &grid,
        &|s| (reference(s), vec![]),
        &IkOptions::default(),
    )
    .unwrap();
    assert_eq!(path.status, IkStatus::Solved);
    let mut peak = f64::NEG_INFINITY;
    for (w, smp) in path.samples.windows(2).zip(&path.samples) {
        let ds = w[1].s - w[0].s;
        let (q, v, x) = (smp.q[lift.idx_q], smp.q_s[lift.idx_v], smp.q_ss[lift.idx_v]);
        for k in 0..=100 {
            let d = ds * f64::from(k) / 100.0;
            peak = peak.max(q + v * d + 0.5 * x * d * d);
        }
    }
    eprintln!(
        "torso_lift peaks at {:.6} m, limit {:.6} m",
        peak, lift.upper
    );
    assert!(peak > lift.upper - 1e-3, "the lift should reach its limit");
    assert!(peak <= lift.upper + 1e-9, "{peak} > {}", lift.upper);
}

#[test]
fn unreachable_target_is_a_negative_outcome_not_an_error() {
    let m = model();
    let q0 = standing(&m);
    let hand = m.frame_id("r_hand").unwrap();
    let c0 = center_of_mass(&m, &mut Data::new(&m), &q0).unwrap();
    let far = PointReference {
        p: Vector3::new(0.0, -2.0, 1.5), // 2 m to the side
        p_s: Vector3::zeros(),
        p_ss: Vector3::zeros(),
    };
    let grid: Vec<f64> = (0..=60).map(|i| i as f64 / 60.0).collect();
    let opts = IkOptions {
        w_link: 1.0,
        ..Default::default()
    };
    let path = track_path(
        &m,
        &q0,
        &vec![0.0; m.nv],
        &feet(&m),
        &grid,
        &|s| {
            (
                PointReference::segment(c0, c0, s),
                vec![LinkTarget {
                    frame: hand,
                    reference: far,
                    orientation: None,
                }],
            )
        },
        &opts,
    )
    .unwrap();
    assert!(
        matches!(path.status, IkStatus::Infeasible | IkStatus::Failed(_)),
        "{:?}",
        path.status
    );
    assert!(path.samples.len() < grid.len());
}

#[test]
fn infeasible_qp_is_a_value() {
    let qp = IkQp {
        p: DMatrix::identity(1, 1),
        c: DVector::zeros(1),
        a_eq: DMatrix::from_row_slice(1, 1, &[1.0]),
        b_eq: DVector::from_vec(vec![1.0]),
        g: DMatrix::from_row_slice(1, 1, &[1.0]),
        h: DVector::from_vec(vec![0.0]),
    };
    let step = solve_ik_qp(&qp, 1e-9).unwrap();
    assert_eq!(step.status, IkStatus::Infeasible);
}

#[test]
fn bad_ik_input_is_an_error() {
    let m = model();
    let mut d = Data::new(&m);
    let q = m.neutral();
    let z = PointReference {
        p: Vector3::zeros(),
        p_s: Vector3::zeros(),
        p_ss: Vector3::zeros(),
    };
    let v = vec![0.0; m.nv];
    let o = IkOptions::default();
    assert!(ik_step(&m, &mut d, &q, &v, &[], &z, &[], 0.0, &o).is_err());
    assert!(ik_step(&m, &mut d, &q, &v, &[99_999], &z, &[], 0.1, &o).is_err());
    let bad = IkOptions { gamma: -1.0, ..o };
    assert!(ik_step(&m, &mut d, &q, &v, &[], &z, &[], 0.1, &bad).is_err());
    let nan = PointReference {
        p: Vector3::new(f64::NAN, 0.0, 0.0),
        ..z
    };
    assert!(ik_step(&m, &mut d, &q, &v, &[], &nan, &[], 0.1, &o).is_err());
    let refs = |_s: f64| (z, vec![]);
    assert!(track_path(&m, &q, &v, &[], &[0.0], &refs, &o).is_err());
    assert!(track_path(&m, &q, &v, &[], &[0.0, 0.5, 0.5], &refs, &o).is_err());
}

/// Largest relative errors of central differences of the CoM over the samples of a tracked path
/// against the path terms p_s and p_ss at the samples, for `n` steps.
fn path_consistency(n: usize) -> (f64, f64) {
    let m = model();
    let q0 = standing(&m);
    let c0 = center_of_mass(&m, &mut Data::new(&m), &q0).unwrap();
    let c1 = c0 + Vector3::new(0.02, 0.05, -0.03);
    let grid: Vec<f64> = (0..=n).map(|i| i as f64 / n as f64).collect();
    let path = track_path(
        &m,
        &q0,
        &vec![0.0; m.nv],
        &feet(&m),
        &grid,
        &|s| (PointReference::segment(c0, c1, s), vec![]),
        &IkOptions::default(),
    )
    .unwrap();
    let mut d = Data::new(&m);
    let terms: Vec<PathTerms> = path
        .samples
        .iter()
        .map(|x| path_terms(&m, &mut d, &x.q, &x.q_s, &x.q_ss).unwrap())
        .collect();
    let ds = 1.0 / n as f64;
    let s1 = terms.iter().fold(0.0f64, |a, t| a.max(t.p_s.norm()));
    let s2 = terms.iter().fold(0.0f64, |a, t| a.max(t.p_ss.norm()));
    let (mut e1, mut e2) = (0.0f64, 0.0f64);
    for i in 1..terms.len() - 1 {
        let fd1 = (terms[i + 1].p - terms[i - 1].p) / (2.0 * ds);
        let fd2 = (terms[i + 1].p - 2.0 * terms[i].p + terms[i - 1].p) / (ds * ds);
        e1 = e1.max((fd1 - terms[i].p_s).norm() / s1);
        e2 = e2.max((fd2 - terms[i].p_ss).norm() / s2);
    }
    (e1, e2)
}

/// The samples of a tracked path are a consistent path: central differences of the CoM over the
/// samples converge to the path terms p_s and p_ss as the grid is refined. With q_ss constant on
/// each step, the second difference straddles two steps, so its error is first order in ds:
/// halving ds must roughly halve it (ratio above 1.6); the first difference is second order
/// (ratio above 3).
#[test]
fn tracked_samples_converge_to_their_path_terms() {
    let (a1, a2) = path_consistency(100);
    let (b1, b2) = path_consistency(200);
    eprintln!("p_s: {a1:.2e} -> {b1:.2e}, p_ss: {a2:.2e} -> {b2:.2e}");
    assert!(a1 / b1 > 3.0 && a2 / b2 > 1.6);
    assert!(b1 < 1e-3 && b2 < 0.05);
}

/// JVRC-1 (38 degrees of freedom, fingers locked): shifting the CoM over the feet keeps the
/// soles in place and the joints within limits. Needs the URDF from the virtualenv; skips
/// without it.
#[test]
fn jvrc1_com_shift_over_the_feet() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let urdf = match jvrc1::locate_urdf(Some(&root)) {
        Ok(p) => p,
        Err(why) => {
            eprintln!("SKIPPED jvrc1_com_shift_over_the_feet: {why}");
            return;
        }
    };
    let m = Model::from_urdf_file(urdf, &jvrc1::urdf_options()).unwrap();
    let mut q0 = m.neutral();
    q0[2] = 0.8;
    for side in ["R", "L"] {
        for (joint, x) in [("HIP_P", -0.3), ("KNEE", 0.6), ("ANKLE_P", -0.3)] {
            q0[m.joints[m.joint_id(&format!("{side}_{joint}")).unwrap()].idx_q] = x;
        }
    }
    let feet = jvrc1::SOLE_PARENT_FRAMES.map(|f| m.frame_id(f).unwrap());
    let c0 = center_of_mass(&m, &mut Data::new(&m), &q0).unwrap();
    let c1 = c0 + Vector3::new(0.0, 0.05, -0.03);
    // the right hand holds its placement (position and orientation) meanwhile
    let hand = m.frame_id("r_wrist").unwrap();
    let mut d0 = Data::new(&m);
    forward_kinematics(&m, &mut d0, &q0).unwrap();
    let x0 = frame_placement(&m, &d0, hand).unwrap();
    let hold = LinkTarget {
        frame: hand,
        reference: PointReference::segment(x0.translation, x0.translation, 0.0),
        orientation: Some(OrientationReference::hold(x0.rotation)),
    };
    let grid: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
    let path = track_path(
        &m,
        &q0,
        &vec![0.0; m.nv],
        &feet,
        &grid,
        &|s| (PointReference::segment(c0, c1, s), vec![hold]),
        &IkOptions::default(),
    )
    .unwrap();
    eprintln!(
        "JVRC-1: contact drift {:.2e} m, rotation {:.2e} rad, CoM error {:.2e} m",
        path.max_contact_drift, path.max_contact_rotation, path.max_com_error
    );
    assert_eq!(path.status, IkStatus::Solved);
    assert!(path.max_contact_drift < 1e-4 && path.max_contact_rotation < 1e-3);
    let last = path.samples.last().unwrap();
    let c_end = center_of_mass(&m, &mut Data::new(&m), &last.q).unwrap();
    assert!((c_end - c1).norm() < 0.01);
    let (mut dp, mut dr) = (0.0f64, 0.0f64);
    let mut d = Data::new(&m);
    for s in &path.samples {
        for j in &m.joints[2..] {
            let x = s.q[j.idx_q];
            assert!(
                x <= j.upper + 1e-9 && x >= j.lower - 1e-9,
                "{} = {x}",
                j.name
            );
        }
        forward_kinematics(&m, &mut d, &s.q).unwrap();
        let x = frame_placement(&m, &d, hand).unwrap();
        dp = dp.max((x.translation - x0.translation).norm());
        let r = x0.rotation.transpose() * x.rotation;
        dr = dr.max(((r.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos());
    }
    eprintln!("JVRC-1 hand drift: {dp:.2e} m, {dr:.2e} rad");
    // the 7-joint arm absorbs the torso motion: the hand stays within 1 mm and 1 mrad (measured:
    // about 1e-5) of its placement while the CoM moves by 6 cm
    assert!(dp < 1e-3 && dr < 1e-3);
}

/// The optional joint-rate bound holds at every sample and slows the tracking down.
#[test]
fn joint_rate_bound_holds() {
    let m = model();
    let q0 = standing(&m);
    let c0 = center_of_mass(&m, &mut Data::new(&m), &q0).unwrap();
    let c1 = c0 + Vector3::new(0.02, 0.05, -0.03);
    let grid: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
    let run = |max_path_rate: f64| {
        track_path(
            &m,
            &q0,
            &vec![0.0; m.nv],
            &feet(&m),
            &grid,
            &|s| (PointReference::segment(c0, c1, s), vec![]),
            &IkOptions {
                max_path_rate,
                ..Default::default()
            },
        )
        .unwrap()
    };
    let free = run(f64::INFINITY);
    let rate_of = |p: &IkPath| {
        p.samples
            .iter()
            .flat_map(|s| m.joints[2..].iter().map(move |j| s.q_s[j.idx_v].abs()))
            .fold(0.0f64, f64::max)
    };
    let free_rate = rate_of(&free);
    let bound = 0.5 * free_rate;
    let slow = run(bound);
    assert_eq!(slow.status, IkStatus::Solved);
    // the bound is met by the QP to its tolerance (1e-8) times ds
    assert!(
        rate_of(&slow) <= bound + 1e-9,
        "{} > {bound}",
        rate_of(&slow)
    );
    // The bound slows the tracking down: the CoM lags further behind its reference at the end of
    // the path (measured: 3.0 mm against 2.4 mm). (The largest error over the path is the same
    // for both: it is reached at the first steps, where the reference already moves and the
    // robot starts from rest; comparing it passed only by 3e-12 of round-off with Clarabel.)
    let end_error = |p: &IkPath| {
        let q = &p.samples.last().unwrap().q;
        (center_of_mass(&m, &mut Data::new(&m), q).unwrap() - c1).norm()
    };
    assert!(end_error(&slow) > end_error(&free) + 1e-4);
    assert!(slow.max_contact_drift < 1e-4);
    let bad = IkOptions {
        max_path_rate: 0.0,
        ..Default::default()
    };
    let mut d = Data::new(&m);
    let z = PointReference::segment(c0, c0, 0.0);
    assert!(ik_step(&m, &mut d, &q0, &vec![0.0; m.nv], &[], &z, &[], 0.1, &bad).is_err());
}

/// The orientation task holds a hand's orientation while the CoM moves. (The small humanoid's
/// hand hangs on two joints, shoulder pitch and elbow, behind the chest pitch: it cannot hold its
/// full placement while the torso moves, so the weighted tasks trade a few cm of hand position
/// for the orientation; the JVRC-1 test below holds the whole placement with a 7-joint arm.)
#[test]
fn hand_pose_task_holds_the_hand() {
    let m = model();
    let q0 = standing(&m);
    let mut d = Data::new(&m);
    let c0 = center_of_mass(&m, &mut d, &q0).unwrap();
    let c1 = c0 + Vector3::new(0.02, 0.05, -0.03);
    let hand = m.frame_id("l_hand").unwrap();
    forward_kinematics(&m, &mut d, &q0).unwrap();
    let x0 = frame_placement(&m, &d, hand).unwrap();
    let grid: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
    let run = |orientation: Option<OrientationReference>| {
        let target = LinkTarget {
            frame: hand,
            reference: PointReference::segment(x0.translation, x0.translation, 0.0),
            orientation,
        };
        let path = track_path(
            &m,
            &q0,
            &vec![0.0; m.nv],
            &feet(&m),
            &grid,
            &|s| (PointReference::segment(c0, c1, s), vec![target]),
            &IkOptions::default(),
        )
        .unwrap();
        assert_eq!(path.status, IkStatus::Solved);
        let mut d = Data::new(&m);
        let (mut dp, mut dr) = (0.0f64, 0.0f64);
        for s in &path.samples {
            forward_kinematics(&m, &mut d, &s.q).unwrap();
            let x = frame_placement(&m, &d, hand).unwrap();
            dp = dp.max((x.translation - x0.translation).norm());
            let r = x0.rotation.transpose() * x.rotation;
            dr = dr.max(((r.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos());
        }
        (dp, dr)
    };
    let (p_free, r_free) = run(None);
    let (p_held, r_held) = run(Some(OrientationReference::hold(x0.rotation)));
    eprintln!("hand drift: position {p_free:.2e} -> {p_held:.2e} m, rotation {r_free:.2e} -> {r_held:.2e} rad");
    assert!(
        r_held < 0.05 * r_free,
        "the orientation task should hold the hand's orientation"
    );
    assert!(r_held < 0.01);
    assert!(p_free < 1e-3);
}

mod property {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        // About a quarter of the random states have no joint bound active (the others are
        // rejected): room for the rejects of a long run (`PROPTEST_CASES=500` hit the default
        // limit of 1024 after 311 cases).
        #![proptest_config(ProptestConfig {
            cases: 24,
            max_global_rejects: 1 << 16,
            ..ProptestConfig::default()
        })]

        /// At random path states and references near the standing configuration, whenever no
        /// joint bound is active, Clarabel's answer is the dense KKT solution.
        #[test]
        fn qp_matches_kkt_at_random_states(
            dq in prop::collection::vec(-0.2..0.2f64, 27),
            q_s in prop::collection::vec(-0.05..0.05f64, 27),
            dc in prop::collection::vec(-0.05..0.05f64, 9),
        ) {
            let m = model();
            let mut q = standing(&m);
            q = integrate(&m, &q, &dq).unwrap();
            let mut d = Data::new(&m);
            let c0 = center_of_mass(&m, &mut d, &q).unwrap();
            let com = PointReference {
                p: c0 + Vector3::new(dc[0], dc[1], dc[2]),
                p_s: Vector3::new(dc[3], dc[4], dc[5]),
                p_ss: Vector3::new(dc[6], dc[7], dc[8]),
            };
            let opts = IkOptions::default();
            let qp = ik_qp(&m, &mut d, &q, &q_s, &feet(&m), &com, &[], 0.01, &opts).unwrap();
            let step = solve_ik_qp(&qp, opts.qp_tol).unwrap();
            prop_assert_eq!(&step.status, &IkStatus::Solved);
            let x = DVector::from_column_slice(&step.q_ss);
            prop_assume!((&qp.h - &qp.g * &x).min() > 1.0); // no bound active
            let check = assert_matches_kkt(&qp, &step);
            prop_assert!(check.is_ok(), "{}", check.unwrap_err());
        }
    }
}

/// The dense active-set solver against Clarabel at 300 random path states of the small humanoid
/// (joints within 98 % of their ranges, large random joint rates) with both feet held, the
/// paper's joint-limit damper, a hand task and a posture task: both give the same outcome; where
/// solvable (about two thirds; the rest are joints rushing at a limit they cannot stop before,
/// infeasible for both), the objectives agree to 1e-7 (relative), the dense answer meets the
/// contact equations to 1e-9 and its bounds exactly. About two fifths of the solvable states
/// have joint bounds active (asserted: at least a fifth), so the working-set updates are
/// exercised, not only the first KKT solve.
#[test]
fn dense_solver_agrees_with_clarabel_at_random_states() {
    let m = model();
    let mut rnd = uniform(0x2545_f491_4f6c_dd1d);
    let hand = m.frame_id("r_hand").unwrap();
    let holds: Vec<ContactHold> = feet(&m).iter().map(|&f| ContactHold::velocity(f)).collect();
    let (mut with_active, mut from_dense, mut solved) = (0, 0, 0);
    let cases = 300;
    for case in 0..cases {
        let q = reachable(&m, &mut rnd);
        let q_s: Vec<f64> = (0..m.nv).map(|_| 0.8 * rnd()).collect();
        let mut d = Data::new(&m);
        let c0 = center_of_mass(&m, &mut d, &q).unwrap();
        let com = PointReference {
            p: c0 + Vector3::new(0.05 * rnd(), 0.05 * rnd(), 0.05 * rnd()),
            p_s: Vector3::new(0.1 * rnd(), 0.1 * rnd(), 0.1 * rnd()),
            p_ss: Vector3::zeros(),
        };
        let link = LinkTarget {
            frame: hand,
            reference: PointReference::hold(Vector3::new(0.3, -0.2, 0.2 * rnd())),
            orientation: None,
        };
        let opts = IkOptions {
            joint_bounds: JointBounds::paper(),
            w_posture: 1e-3,
            ..Default::default()
        };
        let tasks = IkTasks {
            contacts: &holds,
            com,
            links: &[link],
            hard_links: &[],
            posture: Some(&standing(&m)),
            distances: &[],
        };
        let mut ws = IkWorkspace::new(&m);
        ws.build(&m, &mut d, &q, &q_s, &tasks, 0.02, &opts).unwrap();
        let qp = ws.qp();
        let dense = ws.solve(&opts).unwrap();
        let reference = solve_ik_qp(&qp, opts.qp_tol).unwrap();
        assert_eq!(dense.status, reference.status, "case {case}");
        if dense.status != IkStatus::Solved {
            continue;
        }
        solved += 1;
        if dense.answer_from == IkAnswerFrom::Dense {
            from_dense += 1;
        }
        let (x, x_ref) = (
            DVector::from_column_slice(&dense.q_ss),
            DVector::from_column_slice(&reference.q_ss),
        );
        let slack = &qp.h - &qp.g * &x;
        assert!(slack.min() >= -1e-9 * qp.h.amax().max(1.0), "case {case}");
        if slack.min() < 1e-9 * qp.h.amax().max(1.0) {
            with_active += 1;
        }
        let (f, f_ref) = (objective(&qp, &x), objective(&qp, &x_ref));
        assert!(
            (f - f_ref) <= 1e-7 * f_ref.abs().max(1.0),
            "case {case}: dense objective {f} above Clarabel's {f_ref}"
        );
        assert!(
            (f - f_ref).abs() <= 1e-7 * f_ref.abs().max(1.0),
            "case {case}: objectives {f} and {f_ref}"
        );
        assert!(dense.contact_residual <= 1e-9 * qp.b_eq.amax().max(1.0));
    }
    eprintln!(
        "{solved} of {cases} states solvable, {with_active} of them with active bounds, \
         {from_dense} answered by the dense solver"
    );
    assert!(solved >= cases / 2, "only {solved} solvable states");
    assert!(
        with_active >= solved / 5,
        "only {with_active} states with active bounds"
    );
    assert!(from_dense >= solved * 9 / 10);
}

/// The clearance rows (module doc of `ik`) have teeth: a hand pulled 25 cm down towards a
/// horizontal plane 8 cm below it goes through the plane without a clearance row, and stops at
/// its clearance (1 cm) with one: the row is rebuilt at every step from the hand's own distance,
/// as the motion pipeline does from its collision model.
#[test]
fn a_clearance_row_stops_a_hand_at_a_plane() {
    let m = model();
    let q0 = standing(&m);
    let hand = m.frame_id("r_hand").unwrap();
    let joint = m.frames[hand].parent_joint;
    let mut d = Data::new(&m);
    forward_kinematics(&m, &mut d, &q0).unwrap();
    let x0 = frame_placement(&m, &d, hand).unwrap().translation;
    let c0 = center_of_mass(&m, &mut d, &q0).unwrap();
    let plane = x0.z - 0.08;
    let holds: Vec<ContactHold> = feet(&m).iter().map(|&f| ContactHold::velocity(f)).collect();
    let run = |keep: bool| {
        let mut ws = IkWorkspace::new(&m);
        let mut d = Data::new(&m);
        let (mut q, mut q_s) = (q0.clone(), vec![0.0; m.nv]);
        let n = 400;
        let ds = 1.0 / n as f64;
        let mut lowest = f64::INFINITY;
        for i in 0..=n {
            let s = i as f64 * ds;
            forward_kinematics(&m, &mut d, &q).unwrap();
            let p = frame_placement(&m, &d, hand).unwrap().translation;
            lowest = lowest.min(p.z - plane);
            let bound = DistanceBound {
                joint,
                point: p,
                normal: -Vector3::z(),
                distance: p.z - plane,
                min_distance: 0.01,
            };
            let bounds = [bound];
            let link = LinkTarget {
                frame: hand,
                reference: PointReference::segment(x0, x0 - Vector3::new(0.0, 0.0, 0.25), s),
                orientation: None,
            };
            let links = [link];
            let tasks = IkTasks {
                contacts: &holds,
                com: PointReference::hold(c0),
                links: &links,
                hard_links: &[],
                posture: None,
                distances: if keep { &bounds } else { &[] },
            };
            let step = ws
                .step(&m, &mut d, &q, &q_s, &tasks, ds, &IkOptions::default())
                .unwrap();
            assert_eq!(step.status, IkStatus::Solved, "step {i}");
            assert!(!step.clearance_dropped);
            let delta: Vec<f64> = q_s
                .iter()
                .zip(&step.q_ss)
                .map(|(v, a)| v * ds + 0.5 * a * ds * ds)
                .collect();
            q = integrate(&m, &q, &delta).unwrap();
            for (v, a) in q_s.iter_mut().zip(&step.q_ss) {
                *v += a * ds;
            }
        }
        forward_kinematics(&m, &mut d, &q).unwrap();
        let end = frame_placement(&m, &d, hand).unwrap().translation.z - plane;
        (lowest, end)
    };
    let (free_lowest, free_end) = run(false);
    let (kept_lowest, kept_end) = run(true);
    eprintln!(
        "hand above the plane: without the row lowest {free_lowest:.4} m (end {free_end:.4}), \
         with it lowest {kept_lowest:.4} m (end {kept_end:.4})"
    );
    assert!(free_end < -0.05, "the task alone must cross the plane");
    assert!(
        kept_lowest > 0.0,
        "the row must keep the hand above the plane"
    );
    assert!((kept_end - 0.01).abs() < 2e-3, "it rests at its clearance");
}

/// The dense solver's rows (its outer active set, `dense_qp`) against Clarabel at 300 random
/// states of the small humanoid: both feet held, a hand task, the paper's joint damper, and one
/// to three random clearance rows on the hand, forearm or shin. Both agree on the outcome (a step
/// whose rows make the QP infeasible is solved without them and says so, where Clarabel finds
/// the QP with them infeasible); where solved, the objectives agree to 1e-7 (relative) and the
/// dense answer meets every row. At least a fifth of the solved states hold a row active, so
/// the outer active set is exercised.
#[test]
fn dense_solver_with_clearance_rows_agrees_with_clarabel() {
    let m = model();
    let mut rnd = uniform(0x9e37_79b9_7f4a_7c15);
    let hand = m.frame_id("r_hand").unwrap();
    let bodies = [
        m.frames[hand].parent_joint,
        m.joint_id("r_elbow").unwrap(),
        m.joint_id("l_knee").unwrap(),
    ];
    let holds: Vec<ContactHold> = feet(&m).iter().map(|&f| ContactHold::velocity(f)).collect();
    let (mut with_rows_active, mut solved, mut dropped) = (0, 0, 0);
    let cases = 300;
    for case in 0..cases {
        let q = reachable(&m, &mut rnd);
        let q_s: Vec<f64> = (0..m.nv).map(|_| 0.4 * rnd()).collect();
        let mut d = Data::new(&m);
        let c0 = center_of_mass(&m, &mut d, &q).unwrap();
        forward_kinematics(&m, &mut d, &q).unwrap();
        let rows = 1 + ((rnd() + 1.0) * 1.5) as usize % 3;
        let bounds: Vec<DistanceBound> = (0..rows)
            .map(|_| {
                let joint = bodies[((rnd() + 1.0) * 1.5) as usize % 3];
                let point = d.world_from_joint[joint].translation
                    + Vector3::new(0.05 * rnd(), 0.05 * rnd(), 0.05 * rnd());
                let normal = Vector3::new(rnd(), rnd(), -1.0).normalize();
                DistanceBound {
                    joint,
                    point,
                    normal,
                    distance: 0.03 * rnd(),
                    min_distance: 0.01,
                }
            })
            .collect();
        let link = LinkTarget {
            frame: hand,
            reference: PointReference::hold(Vector3::new(0.3, -0.2, 0.2 * rnd())),
            orientation: None,
        };
        let opts = IkOptions {
            joint_bounds: JointBounds::paper(),
            w_posture: 1e-3,
            ..Default::default()
        };
        let tasks = IkTasks {
            contacts: &holds,
            com: PointReference {
                p: c0 + Vector3::new(0.03 * rnd(), 0.03 * rnd(), 0.03 * rnd()),
                p_s: Vector3::zeros(),
                p_ss: Vector3::zeros(),
            },
            links: &[link],
            hard_links: &[],
            posture: Some(&standing(&m)),
            distances: &bounds,
        };
        let mut ws = IkWorkspace::new(&m);
        ws.build(&m, &mut d, &q, &q_s, &tasks, 0.02, &opts).unwrap();
        let qp = ws.qp();
        let dense = ws.solve(&opts).unwrap();
        let reference = solve_ik_qp(&qp, opts.qp_tol).unwrap();
        if dense.clearance_dropped {
            dropped += 1;
            assert_ne!(reference.status, IkStatus::Solved, "case {case}");
            continue;
        }
        assert_eq!(dense.status, reference.status, "case {case}");
        if dense.status != IkStatus::Solved {
            continue;
        }
        solved += 1;
        let (x, x_ref) = (
            DVector::from_column_slice(&dense.q_ss),
            DVector::from_column_slice(&reference.q_ss),
        );
        let slack = &qp.h - &qp.g * &x;
        assert!(slack.min() >= -1e-9 * qp.h.amax().max(1.0), "case {case}");
        let n_rows = qp.g.nrows();
        let row_slack = slack.rows(n_rows - rows, rows);
        if row_slack.min() < 1e-9 * qp.h.amax().max(1.0) {
            with_rows_active += 1;
        }
        let (f, f_ref) = (objective(&qp, &x), objective(&qp, &x_ref));
        assert!(
            (f - f_ref).abs() <= 1e-7 * f_ref.abs().max(1.0),
            "case {case}: objectives {f} and {f_ref}"
        );
    }
    eprintln!(
        "{solved} of {cases} states solved, {with_rows_active} with a clearance row active, \
         {dropped} solved without their rows"
    );
    assert!(solved >= cases / 3, "only {solved} solved states");
    assert!(
        with_rows_active >= solved / 5,
        "only {with_rows_active} states with an active row"
    );
}
