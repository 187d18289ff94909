//! Stage 6b, the actuator limits checked at every output sample, independently of the retiming
//! rows.
//!
//! # Math
//!
//! At a trajectory sample `(q, v, a)` the joint velocities and accelerations are compared with
//! their limits directly. The joint torques follow from the model's inverse dynamics
//! `tau = M(q) a + C(q, v) v + g(q)` ([`stance_robot::rnea`]) and the contact forces: with the
//! generators `g` of each planned contact's wrench cone (its span form `V_surf`: the vertex
//! forces inside the friction pyramids, in the contact's planned frame) weighted by `z >= 0`,
//! the contacts apply `sum_k J_k^T (sum_g z_g g)` (`J_k` the Jacobian of the robot body in
//! contact at the planned frame, in that frame's axes). The check solves the linear program
//!
//! ```text
//!     minimize t   over z >= 0, t
//!     subject to   tau_base = sum_k J_k,base^T w_k               (6 rows: no base actuator,
//!                                                                  within 1e-6 relative as the
//!                                                                  force check's residual)
//!                  |tau_j - sum_k J_k,j^T w_k| <= t T_j           (every joint with a limit)
//! ```
//!
//! with Clarabel (an interior-point solver; the retiming's rows come from the face form of the
//! same cones, projected by the crate's own simplex): `t` is the smallest largest torque ratio
//! the contacts allow at that sample (`<= 1` when the torque limits hold). A sample where no
//! forces balance the base rows reports no ratio (the force check counts it).
//!
//! **Only the largest ratio is reported**, so the linear program runs where it can matter: at
//! every sample the force check's fast path (`fast_forces`) gives forces that balance
//! the base (the same cones; the base rows are the centroidal Newton-Euler equations), whose
//! ratio bounds `t` from above; the samples are then solved exactly in decreasing order of their
//! bounds until a bound falls below the largest exact ratio found (less
//! [`crate::tol::TORQUE_BOUND_MARGIN`]). A sample whose forces the fast path cannot certify is
//! solved exactly. The other samples keep their bound ([`LimitSample::torque_exact`]).

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::Matrix6xX;
use rayon::prelude::*;
use stance_contact::Stance;
use stance_robot::{frame_jacobian, rnea, Data, Model, Pose, ReferenceFrame};

use super::fast_forces::FastForces;
use super::ik_stage::SegmentPath;
use super::plan::MotionPlan;
use super::trajectory::TrajectorySample;
use crate::limit_rows::{contact_jacobian, LimitsPlan};
use crate::StanceError;

/// What the limit check found at one sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LimitSample {
    /// Largest `|v_j| / V_j` (0 without velocity limits).
    pub velocity_ratio: f64,
    /// Its joint (coordinate).
    pub velocity_joint: usize,
    /// Largest `|a_j| / A_j` (0 without acceleration limits).
    pub acceleration_ratio: f64,
    /// Its joint.
    pub acceleration_joint: usize,
    /// Smallest largest `|tau_j| / T_j` over the contact forces (module doc; 0 without torque
    /// limits, NaN where no forces balance the base).
    pub torque_ratio: f64,
    /// Its joint.
    pub torque_joint: usize,
    /// `torque_ratio` is the linear program's value; `false`: an upper bound of it, below the
    /// largest ratio of the motion (module doc).
    pub torque_exact: bool,
    /// Largest `|a_j|` over the actuated joints (rad/s^2 or m/s^2).
    pub max_abs_acceleration: f64,
}

/// Joint torques `tau - sum_k J_k^T w_k` for contact wrenches `w_k` (each in its contact
/// frame `frames[k]`, force then moment about the frame's origin), by the model's inverse
/// dynamics at `(q, v, a)`: what the actuators apply (the base entries are what the contacts
/// leave unbalanced, zero for wrenches that hold the motion).
///
/// # Errors
///
/// [`StanceError::Robot`] for vectors of the wrong size.
///
/// ```
/// use stance_motion::limit_checks::joint_torques;
/// use stance_robot::{Data, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let z = vec![0.0; m.nv];
/// // no contact: the base must be held up by its own "actuator"
/// let tau = joint_torques(&m, &mut d, &m.neutral(), &z, &z, [0.0, 0.0, -9.81], &[]).unwrap();
/// assert!((tau[2] - m.total_mass() * 9.81).abs() < 1e-9);
/// ```
pub fn joint_torques(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    gravity: [f64; 3],
    contacts: &[(usize, [f64; 6])],
) -> Result<Vec<f64>, StanceError> {
    rnea(model, data, q, v, a, gravity).map_err(StanceError::Robot)?;
    let mut tau = data.tau.clone();
    let mut jac = Matrix6xX::zeros(model.nv);
    for (frame, w) in contacts {
        frame_jacobian(model, data, *frame, ReferenceFrame::Local, &mut jac)
            .map_err(StanceError::Robot)?;
        for (k, t) in tau.iter_mut().enumerate() {
            *t -= (0..6).map(|r| jac[(r, k)] * w[r]).sum::<f64>();
        }
    }
    Ok(tau)
}

/// The smallest largest torque ratio at one sample (module doc) and its joint; `None` where no
/// contact forces balance the base.
#[allow(clippy::too_many_arguments)]
fn torque_ratio(
    model: &Model,
    data: &mut Data,
    sample: &TrajectorySample,
    gravity: [f64; 3],
    stance: &Stance,
    contacts: &[(usize, Pose)],
    lp: &LimitsPlan,
) -> Result<Option<(f64, usize)>, StanceError> {
    rnea(model, data, &sample.q, &sample.v, &sample.a, gravity).map_err(StanceError::Robot)?;
    let tau = data.tau.clone();
    let mut jac = Matrix6xX::zeros(model.nv);
    // columns: the generalized force of every generator of every contact (in its planned
    // frame, on the robot body in contact)
    let mut cols: Vec<Vec<f64>> = Vec::new();
    for (c, (f, pose)) in stance.contacts().iter().zip(contacts) {
        contact_jacobian(model, data, *f, pose, &mut jac)?;
        let g = c.v_surf(stance.friction_model());
        for r in g.row_iter() {
            cols.push(
                (0..model.nv)
                    .map(|k| (0..6).map(|i| jac[(i, k)] * r[i]).sum())
                    .collect(),
            );
        }
    }
    let limited: Vec<usize> = (0..lp.torque.len())
        .filter(|&c| lp.torque[c].is_finite())
        .collect();
    let nz = cols.len();
    let n = nz + 1; // z, t
                    // rows: the 6 base rows as two inequalities each (within the force check's residual,
                    // relative to the base's generalized force), 2 per limited joint, z >= 0, t >= 0
    let m = 12 + 2 * limited.len() + n;
    let mut a = vec![0.0; m * n];
    let mut b = vec![0.0; m];
    let slack = stance_contact::tol::DEFAULT_QP_MAX_RESIDUAL
        * tau[..6].iter().map(|x| x * x).sum::<f64>().sqrt().max(1.0);
    for r in 0..6 {
        for (g, col) in cols.iter().enumerate() {
            a[2 * r * n + g] = col[r];
            a[(2 * r + 1) * n + g] = -col[r];
        }
        b[2 * r] = tau[r] + slack;
        b[2 * r + 1] = -tau[r] + slack;
    }
    for (q, &c) in limited.iter().enumerate() {
        let iv = lp.velocity_index[c];
        let t = lp.torque[c];
        let (r1, r2) = (12 + 2 * q, 13 + 2 * q);
        // tau_j - sum c z <= t T  ->  -sum c z - T t <= -tau_j
        // sum c z - tau_j <= t T  ->   sum c z - T t <= tau_j
        for (g, col) in cols.iter().enumerate() {
            a[r1 * n + g] = -col[iv];
            a[r2 * n + g] = col[iv];
        }
        a[r1 * n + nz] = -t;
        a[r2 * n + nz] = -t;
        b[r1] = -tau[iv];
        b[r2] = tau[iv];
    }
    for k in 0..n {
        a[(12 + 2 * limited.len() + k) * n + k] = -1.0;
    }
    let mut q = vec![0.0; n];
    q[nz] = 1.0;
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_feas(1e-9)
        .tol_gap_abs(1e-10)
        .tol_gap_rel(1e-10)
        .build()
        .map_err(|e| StanceError::BadMotion(format!("torque check settings: {e:?}")))?;
    let cones = [SupportedConeT::NonnegativeConeT(m)];
    let mut solver = DefaultSolver::new(
        &CscMatrix::zeros((n, n)),
        &q,
        &csc(m, n, &a),
        &b,
        &cones,
        settings,
    )
    .map_err(|e| StanceError::BadMotion(format!("torque check setup: {e:?}")))?;
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {
            let x = &solver.solution.x;
            // the ratio and its joint from the forces found (the LP's t, recomputed)
            let mut worst = (0.0f64, 0usize);
            for &c in &limited {
                let iv = lp.velocity_index[c];
                let applied: f64 = cols.iter().zip(x).map(|(col, z)| col[iv] * z).sum();
                let r = (tau[iv] - applied).abs() / lp.torque[c];
                if r > worst.0 {
                    worst = (r, c);
                }
            }
            Ok(Some(worst))
        }
        _ => Ok(None),
    }
}

fn csc(m: usize, n: usize, a: &[f64]) -> CscMatrix<f64> {
    let mut colptr = vec![0];
    let (mut rowval, mut nzval) = (Vec::new(), Vec::new());
    for j in 0..n {
        for i in 0..m {
            let v = a[i * n + j];
            if v != 0.0 {
                rowval.push(i);
                nzval.push(v);
            }
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(m, n, colptr, rowval, nzval)
}

/// The limit check at every sample (in parallel), with the planned stances (one per segment)
/// and each segment's contacts: the robot surface's frame and the contact's planned frame.
pub fn check_limits(
    plan: &MotionPlan,
    lp: &LimitsPlan,
    stances: &[&Stance],
    contacts: &[Vec<(usize, Pose)>],
    samples: &[TrajectorySample],
) -> Result<Vec<LimitSample>, StanceError> {
    let m = &plan.robot.model;
    let tol = stance_contact::tol::ContactTolerances::default();
    let mut out: Vec<LimitSample> = samples
        .par_iter()
        .map_init(
            || (Data::new(m), FastForces::new(), Matrix6xX::zeros(m.nv)),
            |(data, fast, jac), smp| {
                let mut out = LimitSample {
                    velocity_ratio: 0.0,
                    velocity_joint: 0,
                    acceleration_ratio: 0.0,
                    acceleration_joint: 0,
                    torque_ratio: 0.0,
                    torque_joint: 0,
                    torque_exact: true,
                    max_abs_acceleration: 0.0,
                };
                for (c, &iv) in lp.velocity_index.iter().enumerate() {
                    let rv = smp.v[iv].abs() / lp.kinematic.velocity[c];
                    if rv > out.velocity_ratio {
                        (out.velocity_ratio, out.velocity_joint) = (rv, c);
                    }
                    let ra = smp.a[iv].abs() / lp.kinematic.acceleration[c];
                    if ra > out.acceleration_ratio {
                        (out.acceleration_ratio, out.acceleration_joint) = (ra, c);
                    }
                    out.max_abs_acceleration = out.max_abs_acceleration.max(smp.a[iv].abs());
                }
                if lp.any_torque() {
                    let stance = stances[smp.segment];
                    let w = super::checks::w_gi_of(m, data, &smp.q, &smp.v, &smp.a, plan.gravity)?;
                    let bound = match fast.wrenches(stance, &w, tol.qp_max_residual) {
                        Some(wrenches) => torque_bound(
                            m,
                            data,
                            smp,
                            plan.gravity,
                            &contacts[smp.segment],
                            &wrenches,
                            lp,
                            jac,
                        )?,
                        None => None,
                    };
                    match bound {
                        Some((r, j)) => {
                            (out.torque_ratio, out.torque_joint) = (r, j);
                            out.torque_exact = false;
                        }
                        None => match torque_ratio(
                            m,
                            data,
                            smp,
                            plan.gravity,
                            stance,
                            &contacts[smp.segment],
                            lp,
                        )? {
                            Some((r, j)) => (out.torque_ratio, out.torque_joint) = (r, j),
                            None => out.torque_ratio = f64::NAN,
                        },
                    }
                }
                Ok(out)
            },
        )
        .collect::<Result<_, StanceError>>()?;
    if lp.any_torque() {
        // the exact ratio where a bound may exceed the largest one found (module doc)
        let mut best = out
            .iter()
            .filter(|x| x.torque_exact && !x.torque_ratio.is_nan())
            .map(|x| x.torque_ratio)
            .fold(0.0f64, f64::max);
        let mut order: Vec<usize> = (0..out.len()).filter(|&i| !out[i].torque_exact).collect();
        order.sort_by(|&a, &b| out[b].torque_ratio.total_cmp(&out[a].torque_ratio));
        let mut data = Data::new(m);
        for i in order {
            if out[i].torque_ratio < best - crate::tol::TORQUE_BOUND_MARGIN {
                break;
            }
            let smp = &samples[i];
            match torque_ratio(
                m,
                &mut data,
                smp,
                plan.gravity,
                stances[smp.segment],
                &contacts[smp.segment],
                lp,
            )? {
                Some((r, j)) => {
                    (out[i].torque_ratio, out[i].torque_joint) = (r, j);
                    best = best.max(r);
                }
                None => out[i].torque_ratio = f64::NAN,
            }
            out[i].torque_exact = true;
        }
    }
    Ok(out)
}

/// Each segment's contacts as `(frame, planned placement)`: what the torque check applies its
/// contact wrenches to.
pub fn planned_contacts(plan: &MotionPlan, paths: &[SegmentPath]) -> Vec<Vec<(usize, Pose)>> {
    paths
        .iter()
        .map(|p| {
            p.contacts
                .iter()
                .map(|c| (plan.robot.surfaces[c.surface].frame, c.pose))
                .collect()
        })
        .collect()
}

/// The linear program of the module doc at one sample: the smallest largest torque ratio over
/// the contact forces of `stance` (contacts `(frame, planned placement)`) and its joint (an index
/// of `lp`), or `None` when no forces balance the base. [`check_limits`] solves it where it can
/// matter; this solves it anywhere (the tests' exhaustive check).
pub fn exact_torque_ratio(
    plan: &MotionPlan,
    lp: &LimitsPlan,
    stance: &Stance,
    contacts: &[(usize, Pose)],
    sample: &TrajectorySample,
) -> Result<Option<(f64, usize)>, StanceError> {
    let m = &plan.robot.model;
    torque_ratio(
        m,
        &mut Data::new(m),
        sample,
        plan.gravity,
        stance,
        contacts,
        lp,
    )
}

/// The largest torque ratio, and its joint, of the contact wrenches `wrenches` (each in its
/// planned contact frame, force then moment about the frame's origin) at a sample: an upper
/// bound of [`torque_ratio`]'s value when the wrenches balance the base.
#[allow(clippy::too_many_arguments)]
fn torque_bound(
    model: &Model,
    data: &mut Data,
    sample: &TrajectorySample,
    gravity: [f64; 3],
    contacts: &[(usize, Pose)],
    wrenches: &[[f64; 6]],
    lp: &LimitsPlan,
    jac: &mut Matrix6xX<f64>,
) -> Result<Option<(f64, usize)>, StanceError> {
    rnea(model, data, &sample.q, &sample.v, &sample.a, gravity).map_err(StanceError::Robot)?;
    let mut tau = data.tau.clone();
    for ((f, pose), w) in contacts.iter().zip(wrenches) {
        contact_jacobian(model, data, *f, pose, jac)?;
        for (k, t) in tau.iter_mut().enumerate() {
            *t -= (0..6).map(|i| jac[(i, k)] * w[i]).sum::<f64>();
        }
    }
    let mut worst = (0.0f64, 0usize);
    for (c, &limit) in lp.torque.iter().enumerate() {
        if limit.is_finite() {
            let r = tau[lp.velocity_index[c]].abs() / limit;
            if r > worst.0 {
                worst = (r, c);
            }
        }
    }
    Ok(Some(worst))
}
