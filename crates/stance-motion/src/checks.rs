//! Stage 6, independent checks of the retimed motion, at every output sample and between grid
//! points.
//!
//! # Math
//!
//! **Force check.** At a trajectory sample `(q, v, a)` the centroidal momentum `h_G = A_g(q) v`
//! changes at `h_G' = A_g a + (dA_g/dt) v` (from the robot model, not from the retiming rows),
//! so `m p'' = h_G',lin`, `L' = h_G',ang`, and the gravito-inertial wrench at the world origin
//! is `f_GI = m g - m p''`, `tau_GI = p x f_GI - L'` (paper eq. 6-7). The contacts can hold the
//! motion iff forces at the vertices of the planned contact polygons, inside the planned
//! friction pyramids, sum to `-w_GI`: the supporting-forces QP of
//! [`stance_contact::supporting_forces`] (face-form pyramids, Clarabel) decides it, independently
//! of the double description and of eq. 14. Of its forces, per contact, the resultant `F` in the
//! contact frame gives the friction usage `|F_t| / (mu F_n)` (Euclidean: up to `sqrt 2` inside
//! the outer pyramid) and the normal force `F_n`. The QP is first solved in the pyramids' span
//! form by the dense active-set solver, warm-started from the previous sample
//! (`fast_forces`); a sample it cannot certify goes to the Clarabel solve above.
//!
//! **Between grid points.** At every IK sample (grid points included), with the profile's
//! constant `u_i` on the grid interval `[s_i, s_i+1]` that contains it and `x = x_i + 2 u_i (s -
//! s_i)`, the rows of its segment `U (w_c + w_a u + w_b x)` are evaluated with the sample's
//! own path terms (no margin): the largest value is the violation in newtons, also as a fraction
//! of `m |g|`.
//!
//! Also at every sample: the drift of each contact frame from its planned placement, and the
//! joints against their limits.

use rayon::prelude::*;
use stance_contact::{supporting_forces, ForcesOutcome};
use stance_robot::{centroidal_map_dot_v, forward_kinematics, frame_placement, Data};

use super::chain::Retimed;
use super::fast_forces::FastForces;
use super::ik_stage::SegmentPath;
use super::plan::MotionPlan;
use super::rows::SegmentRows;
use super::trajectory::TrajectorySample;
use crate::StanceError;

/// What the force check found at one sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleCheck {
    /// Forces exist (the QP's outcome is feasible).
    pub forces: bool,
    /// The slow path (Clarabel) decided it: the fast path could not certify forces.
    pub slow: bool,
    /// Largest `|F_t| / (mu F_n)` over the contacts.
    pub friction_usage: f64,
    /// Smallest normal force over the contacts (N).
    pub min_normal_force: f64,
    /// Largest contact-frame displacement from the planned placement (m).
    pub contact_drift: f64,
    /// Largest joint-limit violation (0 within limits).
    pub joint_violation: f64,
}

/// The gravito-inertial wrench at the world origin of a sample `(q, v, a)`, from the model.
///
/// ```
/// use stance_motion::checks::w_gi_of;
/// use stance_robot::{Data, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let z = vec![0.0; m.nv];
/// let w = w_gi_of(&m, &mut d, &m.neutral(), &z, &z, [0.0, 0.0, -9.81]).unwrap();
/// assert!((w[2] + 43.2 * 9.81).abs() < 1e-9); // at rest: the weight
/// ```
pub fn w_gi_of(
    model: &stance_robot::Model,
    data: &mut Data,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    gravity: [f64; 3],
) -> Result<[f64; 6], StanceError> {
    centroidal_map_dot_v(model, data, q, v).map_err(StanceError::Robot)?;
    let mut hd = data.centroidal_map_dot_v;
    for (k, ak) in a.iter().enumerate() {
        hd += data.centroidal_map.column(k) * *ak;
    }
    let m = data.mass;
    let f = [
        m * gravity[0] - hd[0],
        m * gravity[1] - hd[1],
        m * gravity[2] - hd[2],
    ];
    let c = data.com;
    let t = [
        c[1] * f[2] - c[2] * f[1] - hd[3],
        c[2] * f[0] - c[0] * f[2] - hd[4],
        c[0] * f[1] - c[1] * f[0] - hd[5],
    ];
    Ok([f[0], f[1], f[2], t[0], t[1], t[2]])
}

/// The supporting forces of every sample (in parallel): the contact forces of the planned
/// stance (vertices of the planned polygons, planned friction) that hold the centroidal
/// dynamics of the model at `(q, v, a)`, or the solver's closest attempt where none exist (its
/// outcome says which).
pub fn supporting_forces_at(
    plan: &MotionPlan,
    rows: &[SegmentRows],
    samples: &[TrajectorySample],
) -> Result<Vec<stance_contact::SupportingForces>, StanceError> {
    let m = &plan.robot.model;
    let tol = stance_contact::tol::ContactTolerances::default();
    samples
        .par_iter()
        .map_init(
            || Data::new(m),
            |data, smp| {
                let w = w_gi_of(m, data, &smp.q, &smp.v, &smp.a, plan.gravity)?;
                Ok(supporting_forces(&rows[smp.segment].stance, &w, &tol)?)
            },
        )
        .collect()
}

/// The force check and the kinematic checks at every sample (in parallel), with the contacts of
/// `stances` (one per segment: the planned ones, or others, e.g. a simulator's friction).
pub fn check_samples(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    stances: &[&stance_contact::Stance],
    samples: &[TrajectorySample],
) -> Result<Vec<SampleCheck>, StanceError> {
    let m = &plan.robot.model;
    let tol = stance_contact::tol::ContactTolerances::default();
    samples
        .par_iter()
        .map_init(
            || (Data::new(m), FastForces::new()),
            |(data, fast), smp| {
                let w = w_gi_of(m, data, &smp.q, &smp.v, &smp.a, plan.gravity)?;
                let stance = stances[smp.segment];
                // the fast path, else the slow one (module doc)
                let (forces, resultants, slow) =
                    match fast.resultants(stance, &w, tol.qp_max_residual) {
                        Some(r) => (true, r, false),
                        None => {
                            let f = supporting_forces(stance, &w, &tol)?;
                            let r = f
                                .contacts
                                .iter()
                                .map(|cf| {
                                    let mut sum = [0.0; 3];
                                    for fl in &cf.forces_local {
                                        for k in 0..3 {
                                            sum[k] += fl[k];
                                        }
                                    }
                                    sum
                                })
                                .collect();
                            (f.outcome == ForcesOutcome::Feasible, r, true)
                        }
                    };
                // below this a contact force is zero (round-off of the QP)
                let zero =
                    crate::tol::ZERO_FORCE * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
                let mut usage = 0.0f64;
                let mut normal = f64::INFINITY;
                for (c, sum) in stance.contacts().iter().zip(&resultants) {
                    normal = normal.min(sum[2]);
                    let mu = c.friction();
                    let ft = sum[0].hypot(sum[1]);
                    usage = usage.max(if ft <= zero {
                        0.0
                    } else if sum[2] > 0.0 && mu > 0.0 {
                        ft / (mu * sum[2])
                    } else {
                        f64::INFINITY
                    });
                }
                forward_kinematics(m, data, &smp.q).map_err(StanceError::Robot)?;
                let mut drift = 0.0f64;
                for c in &paths[smp.segment].contacts {
                    let x = frame_placement(m, data, plan.robot.surfaces[c.surface].frame)
                        .map_err(StanceError::Robot)?;
                    drift = drift.max((x.translation - c.pose.translation).norm());
                }
                let mut joint = 0.0f64;
                for j in &m.joints[2..] {
                    if j.dims() == (1, 1) {
                        let x = smp.q[j.idx_q];
                        joint = joint.max(j.lower - x).max(x - j.upper);
                    }
                }
                Ok(SampleCheck {
                    forces,
                    slow,
                    friction_usage: usage,
                    min_normal_force: normal,
                    contact_drift: drift,
                    joint_violation: joint,
                })
            },
        )
        .collect()
}

/// The largest row value (N, no margin) at the IK samples under the profile, and where (global
/// `s`): the violation between grid points (module doc).
pub fn between_violation(
    paths: &[SegmentPath],
    rows: &[SegmentRows],
    retimed: &Retimed,
) -> (f64, f64) {
    let Some(profile) = &retimed.profile else {
        return (f64::NAN, f64::NAN);
    };
    let values = super::chain::sample_row_values(paths, rows, &retimed.s_offset, profile);
    let mut worst = (f64::NEG_INFINITY, 0.0);
    for (k, (path, v)) in paths.iter().zip(&values).enumerate() {
        for (smp, x) in path.samples.iter().zip(v) {
            if x.contact > worst.0 {
                worst = (x.contact, retimed.s_offset[k] + smp.s);
            }
        }
    }
    worst
}
