//! What the page shows of a motion that needs its plan, not only its result: the robot's
//! closest approaches to the environment and its worst joint torque ratio, at every playback
//! frame.
//!
//! - **Clearance**: the collision check's pairs ([`stance_motion::collision::near_pairs`]: the
//!   robot's capsules and contact boxes against the environment's solids, held contacts left
//!   out) whose signed distance is under [`CLEARANCE_SHOWN`], with the witness point on the
//!   robot and the direction to the solid.
//! - **Torque**: where the motion has torque limits, the smallest largest ratio `|tau_j| / T_j`
//!   over the contact forces, and its joint ([`stance_motion::limit_checks::exact_torque_ratio`],
//!   the limit check's linear program, solved at each frame).

use serde::Serialize;
use stance_motion::collision::near_pairs;
use stance_motion::limit_checks::{exact_torque_ratio, planned_contacts};
use stance_motion::{MotionRun, StanceError};
use stance_robot::Data;

use super::ViewData;

/// Closest approaches shown (m): 2 cm.
pub const CLEARANCE_SHOWN: f64 = 0.02;

/// A robot body near an environment solid at one frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NearView {
    /// The body (`link:<joint>:<child>` or `surface:<name>`).
    pub body: String,
    /// The environment surface.
    pub surface: String,
    /// Signed distance (m; negative: penetration), rounded to 0.1 mm.
    pub distance: f64,
    /// The closest point on the body (m).
    pub point: [f64; 3],
    /// Unit direction from the body towards the solid.
    pub normal: [f64; 3],
}

/// The closest approaches of the playback (`clearance` in the page data).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClearanceView {
    /// The distance under which a pair is listed (m).
    pub threshold: f64,
    /// Per frame, the pairs under it.
    pub frames: Vec<Vec<NearView>>,
}

/// The worst joint torque ratio of the playback (`torque` in the page data).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TorqueView {
    /// Per frame, whether contact forces balance the base (else no ratio: 0 and no joint).
    pub balanced: Vec<bool>,
    /// Per frame, the ratio.
    pub ratio: Vec<f64>,
    /// Per frame, its joint.
    pub joint: Vec<String>,
}

/// Adds the clearance and torque layers of `run` to its view (made from its result).
///
/// # Errors
///
/// A view whose frames are not the run's samples, or a sample that does not fit the model.
pub fn add_run_layers(view: &mut ViewData, run: &MotionRun) -> Result<(), StanceError> {
    let Some(robot) = view.robot.as_ref() else {
        return Ok(());
    };
    if robot.samples.iter().any(|&i| i >= run.samples.len()) {
        return Err(StanceError::BadMotion(
            "the view's frames are not the run's samples".into(),
        ));
    }
    let plan = &run.plan;
    let mut data = Data::new(&plan.robot.model);
    let mut frames = Vec::with_capacity(robot.samples.len());
    for &i in &robot.samples {
        let s = &run.samples[i];
        let near = near_pairs(
            plan,
            &run.paths,
            s.segment,
            &s.q,
            CLEARANCE_SHOWN,
            &mut data,
        )?;
        frames.push(
            near.into_iter()
                .map(|(b, k, d)| NearView {
                    body: plan.collision.bodies[b].name.clone(),
                    surface: plan.environment[plan.collision.solids[k].surface]
                        .name
                        .clone(),
                    distance: (d.distance * 1e4).round() / 1e4,
                    point: super::round3(d.point.into()),
                    normal: d.normal.into(),
                })
                .collect(),
        );
    }
    view.clearance = Some(ClearanceView {
        threshold: CLEARANCE_SHOWN,
        frames,
    });
    let Some(lp) = plan
        .limits
        .as_ref()
        .filter(|lp| lp.torque.iter().any(|t| t.is_finite()))
    else {
        return Ok(());
    };
    let contacts = planned_contacts(plan, &run.paths);
    let mut torque = TorqueView {
        balanced: Vec::new(),
        ratio: Vec::new(),
        joint: Vec::new(),
    };
    for &i in &robot.samples {
        let s = &run.samples[i];
        let stance = &run.rows[s.segment].stance;
        match exact_torque_ratio(plan, lp, stance, &contacts[s.segment], s)? {
            Some((r, j)) => {
                torque.balanced.push(true);
                torque.ratio.push((r * 1e4).round() / 1e4);
                torque.joint.push(lp.names[j].clone());
            }
            None => {
                torque.balanced.push(false);
                torque.ratio.push(0.0);
                torque.joint.push(String::new());
            }
        }
    }
    view.torque = Some(torque);
    Ok(())
}
