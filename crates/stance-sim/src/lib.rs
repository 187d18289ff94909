//! # stance-sim
//!
//! Physics validation in MuJoCo: the retimed motion executed by a simulated robot under
//! joint-space PD control with inverse-dynamics feedforward, and measured.
//!
//! # What runs where
//!
//! The project writes the MuJoCo model from its own data ([`mjcf`]) and the reference
//! trajectory at the simulation's time step (the motion retimed by [`stance_motion`], sampled at
//! 1 ms), then runs the harness (`stance_mujoco.py`, embedded in the binary and written beside
//! its input at each run) with the Python of stance's virtualenv
//! ([`stance_motion::venv`]), where `stance setup` installs MuJoCo from PyPI (`mujoco`). MuJoCo is
//! driven through its official Python bindings rather than a Rust crate linked against the
//! shared library inside a wheel: the bindings come with every wheel and version, while a
//! Rust binding must match the library's exact version and ABI (a mismatch crashes, where a
//! Python import fails with a message).
//!
//! # Control (in the harness)
//!
//! At every step (1 kHz), with the reference `(q*, v*, a*)` in MuJoCo's coordinates and the
//! planned contact forces `f_j` at the vertices `x_j` of the planned contact polygons (from
//! [`stance_motion::checks::supporting_forces_at`]: forces that hold the reference's
//! centroidal dynamics), the feedforward is the inverse dynamics of the reference,
//! `tau_ff = M(q*) a* + c(q*, v*) - sum_j J_j(q*)^T f_j` (its six free-flyer rows are the
//! residual of the plan, reported), and every actuated joint gets
//! `tau = tau_ff + kp (q* - q) + kv (v* - qdot)` (the PD part integrated implicitly).
//!
//! # Measurements
//!
//! For each planned contact while it carries load (normal force above
//! [`crate::tol::SIM_LOAD`] of the weight): the slip (horizontal displacement in the surface
//! plane of its site since it was loaded), the largest `|f_t| / f_n` of MuJoCo's contact
//! forces against `mu`; contact losses (a planned contact separated from its surface by more
//! than [`crate::tol::SIM_SEPARATION`] for longer than [`crate::tol::SIM_LOSS_TIME`], outside
//! [`crate::tol::SIM_TRANSITION`] of a stance change; an unloaded contact that still touches is
//! not lost, since with several contacts the simulator may share the load otherwise than the
//! plan's minimum-norm forces); unplanned contacts (a robot geom touching an environment geom
//! outside the stance, same window: when, how hard, and how long it carried load; a landing
//! that touches early, or a lift-off late, while the reference has the pair within
//! [`crate::tol::SIM_SEPARATION`] is in contact by the tolerance of a loss, and reported apart
//! as an early or late touch); base position and orientation error and CoM error against the
//! reference; a fall
//! (base more than [`crate::tol::SIM_FALL_HEIGHT`] below its reference, or the trunk tilted
//! more than [`crate::tol::SIM_FALL_TILT`] from it). Verdict: held iff no fall, no contact
//! loss, no unplanned contact carrying load (above [`crate::tol::SIM_LOAD`]) for longer than
//! [`crate::tol::SIM_LOSS_TIME`] (the robot leaning on something the plan did not give it:
//! brief touches of a landing foot a few milliseconds early are timing noise, not support), and
//! the largest slip below [`crate::tol::SIM_MAX_SLIP`].

pub mod execution;
pub mod mjcf;
pub mod tol;

pub use execution::{SimEvent, SimEventKind, SimSource, SimTrajectory};

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use stance_robot::JointKind;

use stance_motion::trajectory::TrajectorySample;
use stance_motion::StanceError;
use stance_motion::{run_full, spec::MotionSpec, MotionRun, RunOptions};

/// Options of a simulation.
#[derive(Debug, Clone, Default)]
pub struct SimOptions {
    /// The model's options.
    pub mjcf: mjcf::MjcfOptions,
    /// Play the retimed motion `k` times faster (`None`: as retimed).
    pub time_scale: Option<f64>,
    /// Simulate only the segments `[first, last]` (0-based; `None`: all).
    pub segments: Option<[usize; 2]>,
    /// Folder of the motion file (relative URDF paths).
    pub base_dir: Option<PathBuf>,
    /// Keep the harness's input files in this folder (default: a temporary folder, removed).
    pub keep: Option<PathBuf>,
    /// A force pushing a robot surface's body during the simulation (for tests of the
    /// measurements).
    pub disturbance: Option<Disturbance>,
    /// Retime under contact stability alone (`--no-limits`).
    pub no_limits: bool,
    /// Where long work says what it is doing (the footholds planner's evaluations, and a
    /// simulation of more than [`crate::tol::SIM_PROGRESS_AFTER`] seconds before it starts);
    /// `None`: silent.
    pub progress: Option<fn(&str)>,
}

/// An external force on the body of a robot surface, in world axes, over a time window.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Disturbance {
    /// The robot surface whose body is pushed.
    #[serde(rename = "geom", serialize_with = "surface_geom_name")]
    pub surface: String,
    /// The force (N, world axes).
    pub force: [f64; 3],
    /// Start of the window (s, motion time).
    pub t_start: f64,
    /// End of the window (s).
    pub t_end: f64,
}

fn surface_geom_name<S: serde::Serializer>(name: &str, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&mjcf::surface_geom(name))
}

/// One planned contact's measurements.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContactReport {
    /// Segment number, from 1.
    pub segment: usize,
    /// Robot surface.
    pub surface: String,
    /// Environment surface.
    pub environment: String,
    /// Largest slip while loaded (m).
    pub max_slip_m: f64,
    /// Largest `|f_t| / f_n` of its contact forces.
    pub max_friction_usage: f64,
    /// The simulator's friction coefficient of this contact (its environment surface's, or the
    /// one given for every surface).
    #[serde(default)]
    pub friction: f64,
    /// The friction coefficient its plan used (`[planning] friction`, else the surface's).
    #[serde(default)]
    pub planned_friction: f64,
    /// Smallest normal force while in its segment (N).
    pub min_normal_force: f64,
    /// Longest time without contact outside the transition windows (s).
    pub longest_loss_s: f64,
}

/// The report of a simulation (written by the harness).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimReport {
    /// The motion held: no fall, no contact loss, slip below the bound.
    pub held: bool,
    /// Why (the first failed criterion, or what held).
    pub reason: String,
    /// Largest slip of a loaded planned contact (m).
    pub max_slip_m: f64,
    /// Planned contacts lost.
    pub contact_losses: usize,
    /// Unplanned contacts: robot and environment geoms, when, the largest normal force.
    pub unplanned_contacts: Vec<String>,
    /// Landings made early and lift-offs made late: a robot surface touching the environment
    /// surface it is planned on in the segment after (or before) while the reference has it
    /// within [`crate::tol::SIM_SEPARATION`] of it (in contact, by the tolerance of a planned
    /// contact's loss; not an unplanned contact): geoms, when, the largest normal force.
    #[serde(default)]
    pub early_or_late_touches: Vec<String>,
    /// The robot fell.
    pub fell: bool,
    /// Largest base position error (m).
    pub max_base_error_m: f64,
    /// Largest base orientation error (rad).
    pub max_base_angle_rad: f64,
    /// Largest CoM error (m).
    pub max_com_error_m: f64,
    /// Largest `|f_t| / f_n` of a planned contact.
    pub max_friction_usage: f64,
    /// The friction coefficient given for every surface, or `null`: each environment surface's
    /// own (per contact in `contacts`).
    #[serde(default)]
    pub friction: Option<f64>,
    /// Largest free-flyer residual of the feedforward (N or N m): how far the planned forces
    /// are from holding the reference's dynamics.
    pub max_feedforward_residual: f64,
    /// Per planned contact.
    pub contacts: Vec<ContactReport>,
    /// Simulated time (s).
    pub sim_time_s: f64,
    /// Wall time of the simulation loop (s).
    pub wall_s: f64,
    /// Wall time per simulated second.
    pub wall_per_sim_s: f64,
    /// Time scale applied to the motion.
    pub time_scale: f64,
    /// MuJoCo's version.
    pub mujoco_version: String,
    /// While the robot stands still before a motion that starts at rest: the weight its contacts
    /// carry, over `m |g|` (mean over the last 100 ms of the hold; 1 when the contacts carry the
    /// robot's weight).
    pub standing_load_ratio: Option<f64>,
    /// What happened, in time order ([`execution`]).
    #[serde(default)]
    pub events: Vec<SimEvent>,
    /// The executed trajectory ([`execution`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub trajectory: Option<SimTrajectory>,
    /// What was simulated (set by `stance simulate`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motion: Option<SimSource>,
}

/// The harness's report: the [`SimReport`] and the executed `qpos`.
#[derive(Debug, Clone, Deserialize)]
struct HarnessReport {
    #[serde(flatten)]
    report: SimReport,
    executed: HarnessExecution,
}

#[derive(Debug, Clone, Deserialize)]
struct HarnessExecution {
    t: Vec<f64>,
    qpos: Vec<Vec<f64>>,
}

/// The harness's input (see `crates/stance-sim/stance_mujoco.py`).
#[derive(Debug, Clone, Serialize)]
struct HarnessInput {
    mjcf: String,
    timestep: f64,
    kp: f64,
    kv: f64,
    armature: f64,
    mass: f64,
    gravity: [f64; 3],
    time_scale: f64,
    actuated: Vec<String>,
    surfaces: Vec<String>,
    segments: Vec<HarnessSegment>,
    frame_dt: f64,
    reference: HarnessReference,
    thresholds: Thresholds,
    disturbance: Option<Disturbance>,
}

#[derive(Debug, Clone, Serialize)]
struct HarnessSegment {
    /// The segment's number in the motion, from 1 (the report's numbering).
    number: usize,
    t_start: f64,
    t_end: f64,
    stance: Vec<[String; 3]>,
}

#[derive(Debug, Clone, Serialize)]
struct HarnessReference {
    t: Vec<f64>,
    segment: Vec<usize>,
    qpos: Vec<Vec<f64>>,
    qvel: Vec<Vec<f64>>,
    qacc: Vec<Vec<f64>>,
    com: Vec<[f64; 3]>,
    /// Per sample, per planned contact: the body-frame site name and the world points and
    /// forces.
    forces: Vec<Vec<HarnessForces>>,
}

#[derive(Debug, Clone, Serialize)]
struct HarnessForces {
    geom: String,
    points: Vec<[f64; 3]>,
    forces: Vec<[f64; 3]>,
}

#[derive(Debug, Clone, Serialize)]
struct Thresholds {
    load: f64,
    separation: f64,
    loss_time: f64,
    transition: f64,
    max_slip: f64,
    fall_height: f64,
    fall_tilt: f64,
    settle: f64,
}

impl Thresholds {
    /// The measurements' thresholds of [`crate::tol`], for the harness.
    fn from_tol() -> Self {
        Self {
            load: crate::tol::SIM_LOAD,
            separation: crate::tol::SIM_SEPARATION,
            loss_time: crate::tol::SIM_LOSS_TIME,
            transition: crate::tol::SIM_TRANSITION,
            max_slip: crate::tol::SIM_MAX_SLIP,
            fall_height: crate::tol::SIM_FALL_HEIGHT,
            fall_tilt: crate::tol::SIM_FALL_TILT,
            settle: crate::tol::SIM_SETTLE,
        }
    }
}

/// A fresh folder in the system's temporary folder, created here and nowhere else (one per
/// call: simulations may run in parallel in one process; a folder that exists already, perhaps
/// another user's, is never reused, since the harness is written into it and run).
fn unique_temp_dir(prefix: &str) -> Result<PathBuf, StanceError> {
    static COUNT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let mut last = None;
    for _ in 0..100 {
        let n = COUNT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("{prefix}-{}-{n}", std::process::id()));
        let mut builder = std::fs::DirBuilder::new();
        #[cfg(unix)]
        std::os::unix::fs::DirBuilderExt::mode(&mut builder, 0o700);
        match builder.create(&dir) {
            Ok(()) => return Ok(dir),
            Err(e) => last = Some((dir, e)),
        }
    }
    let (dir, e) = last.expect("tried at least once");
    Err(StanceError::BadMotion(format!(
        "cannot create a temporary folder such as {}: {e}",
        dir.display()
    )))
}

/// The virtualenv's Python in isolated mode (`-I`: the harness's folder is not put on the
/// module path, and no user environment variable or site folder changes what it imports).
fn python_command(python: &Path) -> std::process::Command {
    let mut c = std::process::Command::new(python);
    c.arg("-I");
    c
}

/// The MuJoCo harness, embedded in the binary and written beside its input files at each run
/// (the binary works wherever it is installed).
const HARNESS: &str = include_str!("../stance_mujoco.py");

/// Writes the harness into `dir` and returns its path.
fn write_harness(dir: &Path) -> Result<PathBuf, StanceError> {
    let path = dir.join("stance_mujoco.py");
    std::fs::write(&path, HARNESS).map_err(|e| {
        StanceError::BadMotion(format!(
            "cannot write the MuJoCo harness {}: {e}",
            path.display()
        ))
    })?;
    Ok(path)
}

/// The Python of stance's virtualenv ([`stance_motion::venv`]), or how to install it.
fn venv_python() -> Result<PathBuf, StanceError> {
    let python = stance_motion::venv::python(&stance_motion::venv::dir()?);
    if python.is_file() {
        Ok(python)
    } else {
        Err(StanceError::NotInstalled(format!(
            "no Python virtualenv at {} for MuJoCo: {}",
            python.display(),
            stance_motion::venv::how_to_install()
        )))
    }
}

/// Pinocchio's configuration to MuJoCo's `qpos` (free flyer quaternion `w` first, continuous
/// joints as angles).
fn mujoco_qpos(model: &stance_robot::Model, q: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(model.nq);
    for j in &model.joints[1..] {
        let x = &q[j.idx_q..];
        match j.kind {
            JointKind::FreeFlyer => {
                out.extend_from_slice(&x[..3]);
                out.extend_from_slice(&[x[6], x[3], x[4], x[5]]);
            }
            JointKind::Continuous { .. } => out.push(x[1].atan2(x[0])),
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => out.push(x[0]),
            JointKind::Universe => {}
        }
    }
    out
}

/// Pinocchio's velocity and acceleration to MuJoCo's `qvel`, `qacc`: the free flyer's linear
/// velocity in world axes (`R v`), its linear acceleration `R (a + w x v)`; the rest as is.
fn mujoco_velocities(
    model: &stance_robot::Model,
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let (mut qvel, mut qacc) = (v.to_vec(), a.to_vec());
    if model.has_free_flyer() {
        let quat = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            q[6], q[3], q[4], q[5],
        ));
        let r = quat.to_rotation_matrix();
        let lin = nalgebra::Vector3::new(v[0], v[1], v[2]);
        let ang = nalgebra::Vector3::new(v[3], v[4], v[5]);
        let acc = nalgebra::Vector3::new(a[0], a[1], a[2]);
        let v_world = r * lin;
        let a_world = r * (acc + ang.cross(&lin));
        qvel[..3].copy_from_slice(v_world.as_slice());
        qacc[..3].copy_from_slice(a_world.as_slice());
    }
    (qvel, qacc)
}

/// Retimes a motion, writes the MuJoCo model and the reference at the simulation's time step,
/// runs the harness, and returns its report.
///
/// # Errors
///
/// Bad motion files as [`stance_motion::run`]; a motion that could not be retimed; MuJoCo or the
/// virtualenv missing (the message says how to install them).
pub fn simulate(
    spec: MotionSpec,
    options: &SimOptions,
) -> Result<(MotionRun, SimReport), StanceError> {
    let run = retimed_run(spec, options)?;
    let plan = &run.plan;
    let m = &plan.robot.model;
    let k = options.time_scale.unwrap_or(1.0);
    check_duration(run.result.duration.unwrap_or(0.0), k)?;
    let [first, last] = segment_range(options.segments, run.paths.len())?;
    let xml = mjcf::mjcf(plan, &options.mjcf)?;
    let owned: Vec<TrajectorySample> = run
        .samples
        .iter()
        .filter(|s| s.segment >= first && s.segment <= last)
        .cloned()
        .collect();
    let forces = stance_motion::checks::supporting_forces_at(plan, &run.rows, &owned)?;
    let t0 = owned.first().map_or(0.0, |s| s.t);
    let reference = harness_reference(m, &owned, &forces, t0)?;
    let segments = harness_segments(&run, k, t0, [first, last]);
    let input = HarnessInput {
        mjcf: String::new(),
        timestep: options.mjcf.timestep,
        kp: options.mjcf.kp,
        kv: options.mjcf.kv,
        armature: options.mjcf.armature,
        mass: m.total_mass(),
        gravity: plan.gravity,
        time_scale: k,
        actuated: m.joints[2..].iter().map(|j| j.name.clone()).collect(),
        surfaces: plan
            .robot
            .surfaces
            .iter()
            .map(|s| mjcf::surface_geom(&s.name))
            .collect(),
        segments,
        frame_dt: crate::tol::SIM_FRAME_DT,
        reference,
        thresholds: Thresholds::from_tol(),
        disturbance: options.disturbance.clone(),
    };
    let simulated = input.reference.t.last().copied().unwrap_or(0.0) + crate::tol::SIM_SETTLE;
    if let Some(say) = options.progress {
        if simulated > crate::tol::SIM_PROGRESS_AFTER {
            say(&format!(
                "simulating {simulated:.1} s in MuJoCo (about a tenth of that in wall time for a \
                 humanoid)..."
            ));
        }
    }
    let (mut report, executed) = run_harness(&xml, input, options.keep.as_deref())?;
    let q = executed
        .qpos
        .iter()
        .map(|x| execution::model_q_of_qpos(m, x))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| StanceError::BadMotion(format!("the harness's report is invalid: {e}")))?;
    report.trajectory = Some(SimTrajectory {
        t: executed.t,
        q,
        plan_t0: t0,
    });
    report.friction = options.mjcf.friction;
    set_contact_frictions(&mut report, &run, options.mjcf.friction)?;
    Ok((run, report))
}

/// The motion retimed at the simulation's time step (the checks skipped: the simulation is
/// the check), or why there is no trajectory to simulate.
fn retimed_run(spec: MotionSpec, options: &SimOptions) -> Result<MotionRun, StanceError> {
    let mut spec = spec;
    spec.retiming.dt = options.mjcf.timestep;
    let run = run_full(
        spec,
        &RunOptions {
            base_dir: options.base_dir.clone(),
            skip_checks: true,
            time_scale: options.time_scale,
            check_friction: None,
            no_limits: options.no_limits,
            progress: options.progress,
        },
    )?;
    if run.samples.is_empty() {
        let why = run
            .result
            .failure
            .as_ref()
            .map_or_else(|| "no trajectory".to_string(), |f| f.reason.clone());
        return Err(StanceError::BadMotion(format!(
            "the motion could not be retimed ({why}); nothing to simulate"
        )));
    }
    Ok(run)
}

/// Checks that the motion, lasting `total` seconds played at time scale `k`, fits in
/// [`crate::tol::SIM_MAX_DURATION`]; if not, the message gives the least time scale that fits
/// (`k total / max`, rounded up to the thousandth).
fn check_duration(total: f64, k: f64) -> Result<(), StanceError> {
    // (1e-300 in Rust's plain notation has 300 digits)
    let num = |x: f64| {
        if x != 0.0 && !(1e-3..1e6).contains(&x.abs()) {
            format!("{x:e}")
        } else {
            format!("{x}")
        }
    };
    if total > crate::tol::SIM_MAX_DURATION {
        return Err(StanceError::BadMotion(format!(
            "the motion played at time scale {} lasts {} s; the simulator plays at most \
             {} s: give a time scale of at least {:.3}",
            num(k),
            num((total * 10.0).round() / 10.0),
            crate::tol::SIM_MAX_DURATION,
            // rounded up, so that the scale given back fits
            (k * total / crate::tol::SIM_MAX_DURATION * 1e3).ceil() / 1e3
        )));
    }
    Ok(())
}

/// The segments to simulate, `[first, last]` (0-based): those of [`SimOptions::segments`],
/// checked against the motion's `count`, or all.
fn segment_range(segments: Option<[usize; 2]>, count: usize) -> Result<[usize; 2], StanceError> {
    let [first, last] = segments.unwrap_or([0, count - 1]);
    if first > last || last >= count {
        return Err(StanceError::BadMotion(format!(
            "segments {}..{}: the motion has {} segments (give FIRST..LAST from 1)",
            first + 1,
            last + 1,
            count
        )));
    }
    Ok([first, last])
}

/// The reference for the harness at every sample: time from `t0`, segment, MuJoCo's
/// `qpos`, `qvel`, `qacc` ([`mujoco_qpos`], [`mujoco_velocities`]), the CoM, and the planned
/// contacts' supporting forces at their points (world axes).
fn harness_reference(
    m: &stance_robot::Model,
    samples: &[TrajectorySample],
    forces: &[stance_contact::SupportingForces],
    t0: f64,
) -> Result<HarnessReference, StanceError> {
    let mut reference = HarnessReference {
        t: Vec::new(),
        segment: Vec::new(),
        qpos: Vec::new(),
        qvel: Vec::new(),
        qacc: Vec::new(),
        com: Vec::new(),
        forces: Vec::new(),
    };
    let mut data = stance_robot::Data::new(m);
    for (smp, f) in samples.iter().zip(forces) {
        let (qvel, qacc) = mujoco_velocities(m, &smp.q, &smp.v, &smp.a);
        reference.t.push(smp.t - t0);
        reference.segment.push(smp.segment);
        reference.qpos.push(mujoco_qpos(m, &smp.q));
        reference.qvel.push(qvel);
        reference.qacc.push(qacc);
        let c = stance_robot::center_of_mass(m, &mut data, &smp.q).map_err(StanceError::Robot)?;
        reference.com.push([c.x, c.y, c.z]);
        reference.forces.push(
            f.contacts
                .iter()
                .map(|cf| HarnessForces {
                    geom: mjcf::surface_geom(&cf.contact),
                    points: cf.points.clone(),
                    forces: cf.forces_world.clone(),
                })
                .collect(),
        );
    }
    Ok(reference)
}

/// The simulated segments `[first, last]` for the harness: their numbers, their times played
/// at time scale `k` from `t0`, and their stances as (robot surface, its geom, the environment
/// surface's geom).
fn harness_segments(
    run: &MotionRun,
    k: f64,
    t0: f64,
    [first, last]: [usize; 2],
) -> Vec<HarnessSegment> {
    let plan = &run.plan;
    let times = run.result.segments.iter().map(|s| {
        (
            s.t_start.unwrap_or(0.0) / k - t0,
            s.t_end.unwrap_or(0.0) / k - t0,
        )
    });
    times
        .zip(&run.paths)
        .enumerate()
        .filter(|(i, _)| *i >= first && *i <= last)
        .map(|(i, ((a, b), p))| HarnessSegment {
            number: i + 1,
            t_start: a,
            t_end: b,
            stance: p
                .contacts
                .iter()
                .map(|c| {
                    let s = &plan.robot.surfaces[c.surface].name;
                    [
                        s.clone(),
                        mjcf::surface_geom(s),
                        mjcf::environment_geom(&plan.environment[c.environment].name),
                    ]
                })
                .collect(),
        })
        .collect()
}

/// Sets each reported contact's friction coefficients: the one its plan used (its segment's
/// planned stance) and the simulator's (`friction` given for every surface, else its
/// environment surface's). A contact the plan does not have is an error.
fn set_contact_frictions(
    report: &mut SimReport,
    run: &MotionRun,
    friction: Option<f64>,
) -> Result<(), StanceError> {
    for c in &mut report.contacts {
        let planned = run.rows.get(c.segment.wrapping_sub(1)).and_then(|r| {
            r.stance
                .contacts()
                .iter()
                .find(|x| x.name() == c.surface)
                .map(|x| x.friction())
        });
        let surface = run
            .plan
            .environment
            .iter()
            .find(|e| e.name == c.environment);
        let (Some(planned), Some(surface)) = (planned, surface) else {
            return Err(StanceError::BadMotion(format!(
                "the simulator reported a contact the plan does not have: {} on {} in \
                 segment {}",
                c.surface, c.environment, c.segment
            )));
        };
        c.planned_friction = planned;
        c.friction = friction.unwrap_or(surface.friction);
    }
    Ok(())
}

/// What MuJoCo compiled from a model: body masses and principal inertias, joint ranges, and the
/// world corners of the box geoms' faces `z = -size_z` at a configuration (the harness's
/// `--describe` mode), for comparing the model with the project's.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct ModelDescription {
    /// Bodies but the world.
    pub bodies: Vec<BodyDescription>,
    /// Joints.
    pub joints: Vec<JointDescription>,
    /// Box geoms.
    pub geoms: Vec<GeomDescription>,
    /// Total mass (kg).
    pub total_mass: f64,
}

/// A body as MuJoCo compiled it.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct BodyDescription {
    /// Name.
    pub name: String,
    /// Mass (kg).
    pub mass: f64,
    /// Principal moments of inertia, increasing (kg m^2).
    pub inertia: Vec<f64>,
}

/// A joint as MuJoCo compiled it.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct JointDescription {
    /// Name.
    pub name: String,
    /// Range.
    pub range: [f64; 2],
    /// Whether the range is enforced.
    pub limited: bool,
}

/// A box geom's face `z = -size_z` in world coordinates.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct GeomDescription {
    /// Name.
    pub name: String,
    /// Its four corners (world).
    pub corners: Vec<[f64; 3]>,
}

/// Compiles `xml` with MuJoCo (the harness's `--describe` mode) and describes it at the
/// configuration `q` (Pinocchio's conventions, of `model`).
///
/// # Errors
///
/// The virtualenv or MuJoCo missing, or MuJoCo rejecting the model.
pub fn describe(
    xml: &str,
    model: &stance_robot::Model,
    q: &[f64],
) -> Result<ModelDescription, StanceError> {
    let python = venv_python()?;
    let dir = unique_temp_dir("stance-describe")?;
    let io = |e: std::io::Error| StanceError::BadMotion(format!("{}: {e}", dir.display()));
    let (xml_path, q_path, out_path) = (
        dir.join("model.xml"),
        dir.join("qpos.json"),
        dir.join("out.json"),
    );
    std::fs::write(&xml_path, xml).map_err(io)?;
    let harness = write_harness(&dir)?;
    std::fs::write(
        &q_path,
        serde_json::to_string(&mujoco_qpos(model, q))
            .map_err(|e| StanceError::BadMotion(e.to_string()))?,
    )
    .map_err(io)?;
    let out = python_command(&python)
        .arg(&harness)
        .arg("--describe")
        .args([&xml_path, &q_path, &out_path])
        .output()
        .map_err(|e| StanceError::BadMotion(format!("cannot run {}: {e}", python.display())))?;
    if !out.status.success() {
        return Err(StanceError::BadMotion(format!(
            "MuJoCo could not describe the model: {}",
            String::from_utf8_lossy(&out.stderr)
                .lines()
                .last()
                .unwrap_or("")
        )));
    }
    let text = std::fs::read_to_string(&out_path).map_err(io)?;
    let _ = std::fs::remove_dir_all(&dir);
    serde_json::from_str(&text).map_err(|e| StanceError::BadMotion(e.to_string()))
}

fn run_harness(
    xml: &str,
    mut input: HarnessInput,
    keep: Option<&Path>,
) -> Result<(SimReport, HarnessExecution), StanceError> {
    let python = venv_python()?;
    let io = |e: std::io::Error, what: &str| StanceError::BadMotion(format!("{what}: {e}"));
    let dir = match keep {
        Some(d) => {
            std::fs::create_dir_all(d)
                .map_err(|e| io(e, &format!("cannot create {}", d.display())))?;
            d.to_path_buf()
        }
        None => unique_temp_dir("stance-sim")?,
    };
    let model = dir.join("model.xml");
    std::fs::write(&model, xml).map_err(|e| io(e, &format!("cannot write {}", model.display())))?;
    input.mjcf = model.display().to_string();
    let harness = write_harness(&dir)?;
    let input_path = dir.join("input.json");
    let report_path = dir.join("report.json");
    let text = serde_json::to_string(&input)
        .map_err(|e| StanceError::BadMotion(format!("cannot serialize the harness input: {e}")))?;
    std::fs::write(&input_path, text)
        .map_err(|e| io(e, &format!("cannot write {}", input_path.display())))?;
    let out = python_command(&python)
        .arg(&harness)
        .arg(&input_path)
        .arg(&report_path)
        .output()
        .map_err(|e| io(e, &format!("cannot run {}", python.display())))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let last = err.lines().last().unwrap_or("").trim().to_string();
        if last.contains("No module named 'mujoco'") {
            return Err(StanceError::NotInstalled(format!(
                "MuJoCo is not installed in the virtualenv of {}: {}",
                python.display(),
                stance_motion::venv::how_to_install()
            )));
        }
        return Err(StanceError::BadMotion(format!(
            "the MuJoCo harness failed ({}): {last}",
            out.status
        )));
    }
    let text = std::fs::read_to_string(&report_path)
        .map_err(|e| io(e, &format!("cannot read {}", report_path.display())))?;
    let report: HarnessReport = serde_json::from_str(&text)
        .map_err(|e| StanceError::BadMotion(format!("the harness's report is invalid: {e}")))?;
    if keep.is_none() {
        let _ = std::fs::remove_dir_all(&dir);
    }
    Ok((report.report, report.executed))
}
