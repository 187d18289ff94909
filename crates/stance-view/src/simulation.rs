//! The simulation beside the plan: a report of `stance simulate` (its executed trajectory, its
//! events, its verdict) drawn as the solid robot, with the plan as a translucent ghost on one
//! time line.
//!
//! The page's time is the simulation's (`simulation.t`, from the start of the reference); the
//! plan is shown at its own time `plan_t0 + t`, held at its end while the simulation settles.

use std::path::Path;

use serde::{Deserialize, Serialize};
use stance_motion::StanceError;
use stance_robot::Model;

use super::{round, ViewData};
use crate::motion::fk_frames;

/// What the view needs of a simulation report (`stance simulate`'s JSON; other keys ignored).
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct SimRecord {
    /// The verdict.
    pub held: bool,
    /// Its reason.
    pub reason: String,
    /// The time scale played.
    pub time_scale: f64,
    /// The events.
    #[serde(default)]
    pub events: Vec<SimEventRecord>,
    /// The executed trajectory.
    pub trajectory: Option<SimTrajectoryRecord>,
    /// What was simulated.
    pub motion: Option<SimSourceRecord>,
}

/// An event of the report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimEventRecord {
    /// `slip`, `contact_loss`, `unplanned_contact`, `early_touch`, `late_lift` or `fall`.
    pub kind: String,
    /// Simulated time (s).
    pub t: f64,
    /// Where (m).
    pub position: [f64; 3],
    /// What.
    pub text: String,
}

/// The executed trajectory of the report.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct SimTrajectoryRecord {
    /// Simulated times (s).
    pub t: Vec<f64>,
    /// Configurations (the model's coordinates).
    pub q: Vec<Vec<f64>>,
    /// The plan's time at simulated time 0 (s).
    pub plan_t0: f64,
}

/// What was simulated.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct SimSourceRecord {
    /// The motion file (absolute path) or built-in name.
    pub motion: String,
    /// Time scale.
    pub time_scale: f64,
    /// Simulated segments, from 1.
    pub segments: Option<[usize; 2]>,
    /// Retimed without actuator limits.
    pub no_limits: bool,
    /// The retimed duration (s).
    pub duration: f64,
}

/// One event as the page marks it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EventView {
    /// Its number, from 1, in time order (on the time line, in 3-D and in the list).
    pub number: usize,
    /// What kind (as the report says).
    pub kind: String,
    /// Simulated time (s).
    pub t: f64,
    /// Where (m).
    pub position: [f64; 3],
    /// What.
    pub text: String,
}

/// The verdict.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VerdictView {
    /// The contacts held.
    pub held: bool,
    /// Why (the report's reason).
    pub reason: String,
}

/// The simulation as the page plays it (`simulation` in the page data).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SimulationView {
    /// Frame times (simulated s).
    pub t: Vec<f64>,
    /// Per frame, the configuration (rounded to 1e-4).
    pub q: Vec<Vec<f64>>,
    /// Per frame, the joint origins (as `robot.positions`).
    pub positions: Vec<Vec<f64>>,
    /// Per frame, the joint orientations (as `robot.orientations`).
    pub orientations: Vec<Vec<f64>>,
    /// Per frame, the CoM.
    pub com: Vec<[f64; 3]>,
    /// The events, in time order.
    pub events: Vec<EventView>,
    /// The verdict.
    pub verdict: VerdictView,
    /// The plan's time at simulated time 0 (s).
    pub plan_t0: f64,
    /// The time scale played.
    pub time_scale: f64,
}

/// Reads a simulation report.
///
/// # Errors
///
/// A file that is not one, or a report without an executed trajectory or its source (written
/// before `stance simulate` recorded them).
pub fn read_sim_record(path: &Path) -> Result<SimRecord, StanceError> {
    let record: SimRecord = stance_motion::input::read_file(path)?;
    if record.trajectory.is_none() || record.motion.is_none() {
        return Err(StanceError::BadMotion(format!(
            "{}: the report has no executed trajectory or no `motion` it simulated: simulate \
             again with this version of `stance simulate`",
            path.display()
        )));
    }
    Ok(record)
}

/// Adds the simulation of `record` to the view of its plan (title and subtitle say the verdict).
///
/// # Errors
///
/// A report without a trajectory, or configurations that do not fit the model.
pub fn add_simulation(
    view: &mut ViewData,
    record: &SimRecord,
    model: &Model,
) -> Result<(), StanceError> {
    let tr = record.trajectory.as_ref().ok_or_else(|| {
        StanceError::BadMotion("the simulation report has no executed trajectory".into())
    })?;
    if tr.q.len() != tr.t.len() || tr.t.is_empty() {
        return Err(StanceError::BadMotion(format!(
            "the simulation report has {} times and {} configurations",
            tr.t.len(),
            tr.q.len()
        )));
    }
    let meshes = view.robot.as_ref().is_some_and(|r| !r.meshes.is_empty());
    let frames = fk_frames(model, &tr.q, meshes)?;
    let mut events: Vec<&SimEventRecord> = record.events.iter().collect();
    events.sort_by(|a, b| a.t.total_cmp(&b.t));
    let held = if record.held { "held" } else { "failed" };
    let scale = if record.time_scale == 1.0 {
        String::new()
    } else {
        format!(" at x{}", record.time_scale)
    };
    view.title = format!("{}{scale}: {held} in MuJoCo", view.title);
    view.subtitle = format!("{} (plan: {})", record.reason, view.subtitle);
    view.simulation = Some(SimulationView {
        t: tr.t.clone(),
        q: tr
            .q
            .iter()
            .map(|q| q.iter().map(|x| (x * 1e4).round() / 1e4).collect())
            .collect(),
        positions: frames.positions,
        orientations: frames.orientations,
        com: frames.com,
        events: events
            .iter()
            .enumerate()
            .map(|(k, e)| EventView {
                number: k + 1,
                kind: e.kind.clone(),
                t: e.t,
                position: e.position.map(round),
                text: e.text.clone(),
            })
            .collect(),
        verdict: VerdictView {
            held: record.held,
            reason: record.reason.clone(),
        },
        plan_t0: tr.plan_t0,
        time_scale: record.time_scale,
    });
    Ok(())
}
