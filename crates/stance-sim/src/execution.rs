//! What the simulator executed, for the viewer: the robot's configuration every
//! [`crate::tol::SIM_FRAME_DT`] of simulated time, and the events the measurements found, each
//! with its time and place; and what was simulated (to draw the plan beside it).
//!
//! Times are simulated seconds from the start of the reference (the preroll that lets the
//! contacts settle before a motion that starts at rest is not included; the settling time after
//! its end is). The reference's own time at simulated time `t` is `plan_t0 + t` (the simulated
//! segments' start in the retimed motion, already played at the time scale).

use serde::{Deserialize, Serialize};
use stance_robot::{JointKind, Model};

/// What an event is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SimEventKind {
    /// A loaded planned contact slipped more than [`crate::tol::SIM_MAX_SLIP`] (when it first
    /// does, where its site is).
    Slip,
    /// A planned contact separated from its surface for longer than
    /// [`crate::tol::SIM_LOSS_TIME`] (when it separated).
    ContactLoss,
    /// A robot geom touched an environment geom outside the stance (its first touch, where).
    UnplannedContact,
    /// A landing touched before its stance (within the separation threshold in the plan).
    EarlyTouch,
    /// A lift-off still touched after its stance.
    LateLift,
    /// The robot fell (where its base was).
    Fall,
}

/// One event of a simulation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimEvent {
    /// What happened.
    pub kind: SimEventKind,
    /// When (simulated s).
    pub t: f64,
    /// Where (world, m).
    pub position: [f64; 3],
    /// What, in words.
    pub text: String,
}

/// The executed trajectory.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimTrajectory {
    /// Simulated times (s).
    pub t: Vec<f64>,
    /// The robot's configuration at each (the model's coordinates, as `stance motion`'s
    /// trajectory).
    pub q: Vec<Vec<f64>>,
    /// The reference's time at simulated time 0 (s).
    pub plan_t0: f64,
}

/// What was simulated, so that a viewer can draw the plan again (set by `stance simulate`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimSource {
    /// The motion: a file (its absolute path) or a built-in name.
    pub motion: String,
    /// The time scale it was played at.
    pub time_scale: f64,
    /// The simulated segments `[first, last]`, from 1.
    pub segments: Option<[usize; 2]>,
    /// Retimed without actuator limits.
    pub no_limits: bool,
    /// The retimed duration of the whole motion at that time scale (s): a check that the motion
    /// is still the one simulated.
    pub duration: f64,
}

/// MuJoCo's `qpos` to the model's configuration: the inverse of the harness input's
/// conversion (free flyer quaternion `w` last, continuous joints as `(cos, sin)`).
///
/// ```
/// use stance_robot::Model;
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let q = m.neutral();
/// let mut qpos = vec![0.0; m.nq - 1]; // one continuous joint: one angle instead of two numbers
/// qpos[3] = 1.0; // w of the base quaternion
/// assert_eq!(stance_sim::execution::model_q_of_qpos(&m, &qpos).unwrap(), q);
/// ```
///
/// # Errors
///
/// A `qpos` whose length is not the model's.
pub fn model_q_of_qpos(model: &Model, qpos: &[f64]) -> Result<Vec<f64>, String> {
    let mut q = Vec::with_capacity(model.nq);
    let mut at = 0;
    let mut take = |n: usize| -> Result<&[f64], String> {
        let x = qpos.get(at..at + n).ok_or_else(|| {
            format!(
                "the simulator's qpos has {} numbers, fewer than the model needs",
                qpos.len()
            )
        })?;
        at += n;
        Ok(x)
    };
    for j in &model.joints[1..] {
        match j.kind {
            JointKind::FreeFlyer => {
                let x = take(7)?;
                q.extend_from_slice(&x[..3]);
                q.extend_from_slice(&[x[4], x[5], x[6], x[3]]);
            }
            JointKind::Continuous { .. } => {
                let a = take(1)?[0];
                q.extend_from_slice(&[a.cos(), a.sin()]);
            }
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => q.push(take(1)?[0]),
            JointKind::Universe => {}
        }
    }
    if at != qpos.len() {
        return Err(format!(
            "the simulator's qpos has {} numbers, the model {}",
            qpos.len(),
            at
        ));
    }
    Ok(q)
}

#[cfg(test)]
mod tests {
    use super::model_q_of_qpos;

    /// The harness input's conversion and this one are inverses, on every joint kind of the
    /// small humanoid (free flyer, revolute, prismatic, continuous).
    #[test]
    fn qpos_to_q_inverts_q_to_qpos() {
        let m = stance_robot::Model::from_urdf_str(
            stance_robot::SMALL_HUMANOID_URDF,
            &Default::default(),
        )
        .unwrap();
        let mut q = m.neutral();
        for (k, x) in q.iter_mut().enumerate() {
            *x += 0.01 * k as f64;
        }
        // a unit quaternion and a unit (cos, sin) pair again
        let n = (3..7).map(|k| q[k] * q[k]).sum::<f64>().sqrt();
        q[3..7].iter_mut().for_each(|x| *x /= n);
        for j in &m.joints {
            if let stance_robot::JointKind::Continuous { .. } = j.kind {
                let (c, s) = (q[j.idx_q], q[j.idx_q + 1]);
                let r = c.hypot(s);
                q[j.idx_q] = c / r;
                q[j.idx_q + 1] = s / r;
            }
        }
        let back = model_q_of_qpos(&m, &crate::mujoco_qpos(&m, &q)).unwrap();
        for (a, b) in back.iter().zip(&q) {
            assert!((a - b).abs() < 1e-12);
        }
        assert!(model_q_of_qpos(&m, &[0.0; 3]).is_err());
        assert!(model_q_of_qpos(&m, &vec![0.0; m.nq + 5]).is_err());
    }
}
