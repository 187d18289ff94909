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
//!
//! `a` jumps where `s''` or `q_ss` does: at the grid points and at the IK samples. Sampled at a
//! fixed `dt` across such a jump, two consecutive samples' positions disagree with the trapezoid
//! of their velocities by about `dt^2 |Delta a| / 8` (4.4 mrad at 10 ms on the box climbing). The
//! output ([`output`]) adds, between two samples that disagree by more than
//! [`crate::tol::TRAJECTORY_TRAPEZOID`], the switching instants between them (the times of the
//! IK samples, by [`Profile::time_at`]), then midpoints, so that every two consecutive samples
//! agree; the checks sample at their own fixed step ([`uniform`]).

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

/// The trajectory at time `t` (global profile time).
fn at_time(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    retimed: &Retimed,
    profile: &Profile,
    t: f64,
) -> Result<TrajectorySample, StanceError> {
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
}

/// The trajectory at every multiple of `dt` up to the end, and at the end.
pub fn uniform(
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
        .map(|t| at_time(plan, paths, retimed, profile, t))
        .collect()
}

/// The largest `|q_b - q_a - (v_a + v_b) (t_b - t_a) / 2|` over the one-coordinate joints: how
/// far two samples' positions are from the trapezoid of their velocities.
pub fn trapezoid_error(
    model: &stance_robot::Model,
    a: &TrajectorySample,
    b: &TrajectorySample,
) -> f64 {
    let dt = b.t - a.t;
    model.joints[2..]
        .iter()
        .filter(|j| j.dims() == (1, 1))
        .map(|j| (b.q[j.idx_q] - a.q[j.idx_q] - 0.5 * (a.v[j.idx_v] + b.v[j.idx_v]) * dt).abs())
        .fold(0.0, f64::max)
}

/// The output trajectory (module doc): the samples of [`uniform`], and between two of them whose
/// positions and velocities disagree by more than [`crate::tol::TRAJECTORY_TRAPEZOID`]
/// ([`trapezoid_error`]), the instants where the path acceleration switches (the IK samples,
/// where `q_ss` changes, and the grid points, where `s''` does), then midpoints where that is
/// not enough, so that every two consecutive samples agree.
pub fn output(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    retimed: &Retimed,
    profile: &Profile,
    dt: f64,
) -> Result<Vec<TrajectorySample>, StanceError> {
    let coarse = uniform(plan, paths, retimed, profile, dt)?;
    let m = &plan.robot.model;
    let mut switches: Option<Vec<f64>> = None;
    let mut out = Vec::with_capacity(coarse.len());
    for w in coarse.windows(2) {
        out.push(w[0].clone());
        if trapezoid_error(m, &w[0], &w[1]) <= crate::tol::TRAJECTORY_TRAPEZOID {
            continue;
        }
        let switches = switches.get_or_insert_with(|| {
            // every IK sample's time (the grid points are IK samples)
            let mut t: Vec<f64> = paths
                .iter()
                .zip(&retimed.s_offset)
                .flat_map(|(p, o)| p.samples.iter().map(move |x| profile.time_at(o + x.s)))
                .filter(|t| t.is_finite())
                .collect();
            t.sort_by(f64::total_cmp);
            // a segment's last sample and the next one's first are one instant
            t.dedup_by(|b, a| *b - *a <= 1e-12 * a.abs().max(1.0));
            t
        });
        refine(
            plan,
            paths,
            retimed,
            profile,
            switches,
            &w[0],
            &w[1],
            crate::tol::TRAJECTORY_REFINE_DEPTH,
            &mut out,
        )?;
    }
    if let Some(last) = coarse.last() {
        out.push(last.clone());
    }
    Ok(out)
}

/// Pushes the samples strictly between `a` and `b` that make every consecutive pair agree
/// ([`output`]): the switching instants inside, else the midpoint, `depth` times at most.
#[allow(clippy::too_many_arguments)]
fn refine(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    retimed: &Retimed,
    profile: &Profile,
    switches: &[f64],
    a: &TrajectorySample,
    b: &TrajectorySample,
    depth: usize,
    out: &mut Vec<TrajectorySample>,
) -> Result<(), StanceError> {
    let m = &plan.robot.model;
    if depth == 0 || trapezoid_error(m, a, b) <= crate::tol::TRAJECTORY_TRAPEZOID {
        return Ok(());
    }
    let gap = 1e-9 * b.t.max(1.0);
    let lo = switches.partition_point(|&t| t <= a.t + gap);
    let hi = switches.partition_point(|&t| t < b.t - gap);
    let mut times: Vec<f64> = switches[lo..hi].to_vec();
    if times.is_empty() {
        times.push(0.5 * (a.t + b.t));
    }
    let mut prev = a.clone();
    for t in times {
        let x = at_time(plan, paths, retimed, profile, t)?;
        refine(
            plan,
            paths,
            retimed,
            profile,
            switches,
            &prev,
            &x,
            depth - 1,
            out,
        )?;
        out.push(x.clone());
        prev = x;
    }
    refine(
        plan,
        paths,
        retimed,
        profile,
        switches,
        &prev,
        b,
        depth - 1,
        out,
    )
}
