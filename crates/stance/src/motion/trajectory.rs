//! Stage 5, the retimed trajectory `q(t), v(t), a(t)` at a time step.
//!
//! # Math
//!
//! The profile gives `s(t), s'(t), s''(t)` exactly (piecewise-constant `s''`). The joint path
//! between IK samples is the one the IK integrated: on `[s_j, s_j+1]`, with `d = s - s_j`,
//! `q(s) = q_j (+) (q_s,j d + q_ss,j d^2 / 2)` and `q_s(s) = q_s,j + q_ss,j d`, `q_ss = q_ss,j`.
//! Then, in Pinocchio's conventions (base twist in the base frame),
//!
//! ```text
//! v = q_s(s) s',        a = q_ss(s) s'^2 + q_s(s) s''.
//! ```

use stance_robot::integrate;
use stance_topp::Profile;

use super::chain::Retimed;
use super::ik_stage::SegmentPath;
use super::plan::MotionPlan;
use crate::StanceError;

/// One trajectory sample.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectorySample {
    /// Time (s).
    pub t: f64,
    /// Global path parameter.
    pub s: f64,
    /// Path speed `s'` and acceleration `s''`.
    pub sd: [f64; 2],
    /// Segment index.
    pub segment: usize,
    /// Configuration.
    pub q: Vec<f64>,
    /// Velocity.
    pub v: Vec<f64>,
    /// Acceleration.
    pub a: Vec<f64>,
}

/// The joint path at one value of the path parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct JointPathPoint {
    /// Segment index.
    pub segment: usize,
    /// Configuration.
    pub q: Vec<f64>,
    /// `dq/ds`.
    pub q_s: Vec<f64>,
    /// `d^2q/ds^2`.
    pub q_ss: Vec<f64>,
}

/// `(q, q_s, q_ss)` at the global path parameter `s` (module doc).
pub fn joint_path_at(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    retimed: &Retimed,
    s: f64,
) -> Result<JointPathPoint, StanceError> {
    let nseg = paths.len();
    let k = (0..nseg)
        .rev()
        .find(|&k| retimed.s_offset[k] <= s)
        .unwrap_or(0);
    let local = (s - retimed.s_offset[k]).max(0.0);
    let samples = &paths[k].samples;
    let ds = samples[1].s - samples[0].s;
    let j = ((local / ds).floor() as usize).min(samples.len() - 2);
    let sm = &samples[j];
    let d = (local - sm.s).clamp(0.0, ds);
    let delta: Vec<f64> = sm
        .q_s
        .iter()
        .zip(&sm.q_ss)
        .map(|(v, a)| v * d + 0.5 * a * d * d)
        .collect();
    let q = integrate(&plan.robot.model, &sm.q, &delta).map_err(StanceError::Robot)?;
    let q_s = sm
        .q_s
        .iter()
        .zip(&sm.q_ss)
        .map(|(v, a)| v + a * d)
        .collect();
    Ok(JointPathPoint {
        segment: k,
        q,
        q_s,
        q_ss: sm.q_ss.clone(),
    })
}

/// The trajectory at every multiple of `dt` up to the end, and at the end.
pub fn sample(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    retimed: &Retimed,
    profile: &Profile,
    dt: f64,
) -> Result<Vec<TrajectorySample>, StanceError> {
    let total = profile.duration();
    let n = (total / dt).floor() as usize;
    let mut times: Vec<f64> = (0..=n).map(|i| i as f64 * dt).collect();
    if total - times[times.len() - 1] > 1e-12 * total.max(1.0) {
        times.push(total);
    }
    times
        .into_iter()
        .map(|t| {
            let p = profile.at(t);
            let JointPathPoint {
                segment,
                q,
                q_s,
                q_ss,
            } = joint_path_at(plan, paths, retimed, p.s)?;
            let v = q_s.iter().map(|x| x * p.sd).collect();
            let a = q_ss
                .iter()
                .zip(&q_s)
                .map(|(x, y)| x * p.sd * p.sd + y * p.sdd)
                .collect();
            Ok(TrajectorySample {
                t,
                s: p.s,
                sd: [p.sd, p.sdd],
                segment,
                q,
                v,
                a,
            })
        })
        .collect()
}
