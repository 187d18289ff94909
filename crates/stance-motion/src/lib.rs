//! # stance-motion
//!
//! Whole-body motions across stances (the paper's Section V on a humanoid): a robot moves
//! through a sequence of stances; its whole-body trajectory is made by acceleration-level IK,
//! retimed under contact stability with the angular momentum of the real body, chained across
//! stance changes, and checked at every sample by an independent force check.
//!
//! # The pipeline, one module per stage
//!
//! The stages without a link are private modules (`src/<stage>.rs`): [`run`] and [`run_full`]
//! are their API.
//!
//! 0. [`footholds`]: segments written as stances and landings only get their CoM via-points
//!    and swing paths (the file is made complete; the rest of the pipeline sees no difference).
//! 1. [`plan`]: the motion file ([`spec`]) is validated, names resolved, the robot loaded
//!    ([`robot`]: its contact surfaces are operational frames of the model), the environment
//!    built ([`environment`]) and the initial posture found (`stand`).
//! 2. `ik_stage`: per segment, the contacts are read off the configuration at its start and
//!    checked against their surfaces; the references (`references`) are tracked by the IK,
//!    integrated into `q(s), q_s, q_ss` with the path terms `p, p_s, p_ss, l1, l2` (docs/math.md
//!    section 6: `l1 = A_g,ang q_s`, `l2 = A_g,ang q_ss + (dA_g,ang/ds) q_s`).
//! 3. `rows`: per segment, `U_stance` of its stance (planning friction and area scale) and
//!    the rows of eq. 14 at its grid points.
//! 4. `chain`: the rows laid end to end and retimed as one problem (or rest to rest per
//!    segment), with landing speed bounds (no impacts).
//! 5. [`trajectory`]: `q(t), v(t), a(t)` at the output time step.
//! 6. [`checks`]: supporting forces from the model's centroidal dynamics at every sample,
//!    contact drift, joint limits, the violation between grid points; [`collision`]: the
//!    robot's bodies against the environment's solids at every sample.
//!
//! Every stage is timed; the result ([`result::MotionResult`]) carries the paper's per-segment
//! table. The paper's experiments are built in ([`experiments`]).
//!
//! ```
//! use stance_motion::{experiments, run, RunOptions};
//! let r = run(experiments::by_name("small-sway").unwrap(), &RunOptions::default()).unwrap();
//! assert_eq!(r.status, stance_motion::result::MotionStatus::Optimal);
//! assert_eq!(r.checks.unwrap().samples_without_forces, 0);
//! ```
//!
//! # Also here
//!
//! - [`retime`]: one stance and a CoM path become the rows of eq. (14) through `U_stance`
//!   (computed once), solved by reachability analysis, with the violation of contact stability
//!   between grid points measured (and optionally refined away).
//! - [`joints`]: fixed-base robots' joint paths retimed under joint velocity, acceleration and
//!   torque limits ([`limits`], [`binding`]).
//! - [`input`]: reading scenes and motion files (strict keys, line numbers), shared by the
//!   command line and the Python package.
//!
//! # Limitations
//!
//! - [`retime::retime`] holds one stance for a point-mass CoM path; motions across stances with
//!   the whole body are [`run`]'s. The CoM path is a polyline or a clamped cubic spline through
//!   waypoints (rest to rest: the spline's end tangents are zero); other paths go through
//!   [`stance_topp`] directly. Without `angular_momentum` samples the model is a point mass
//!   (`L' = 0`); with them, `l1` and `l2` are interpolated linearly between samples, so between
//!   samples the retiming is only as good as that interpolation (sample at least at the grid's
//!   resolution where they vary fast, e.g. from [`stance_robot::path_terms_along`]). The
//!   stance's GIWC must be full-dimensional for retiming (a lower-dimensional GIWC, e.g. point
//!   contacts only, is reported as an error naming the equations).
//! - Whole-body motions: the CoM reference passes through its via-points with its corners
//!   rounded over `2 com_blend` path units (it leaves the straight lines between them near each
//!   corner); free links move along straight lines with minimum-jerk timing and stop at every
//!   via-point. The IK is integrated with `q_ss` constant per step: the retiming enforces the
//!   rows on both sides of every grid point, refines the grid at IK samples where they fail and
//!   at points inside IK steps where the model's exact rows there fail (`midpoints`, for the
//!   steps whose ends are within 1e-3 of the weight of a bound: the quarters, then down to 1/32
//!   of a step where one fails), so the rows hold at every IK sample and those points;
//!   elsewhere between IK samples only as the independent force check measures (no sample of
//!   the built-in or gallery motions fails it at 1 ms, nor small-sway's on a 10-interval grid). The
//!   greedy profile is time-optimal as the grid is refined, not exactly on the grid (measured:
//!   0.23 % longer than a one-shot LP's on `small-sway`). Path speeds are unbounded where the
//!   whole body is at rest in path terms (the start, via-points where nothing else moves):
//!   there the profile may reach the solver's box (`s'^2 = 1e8`), which costs no time. Planar
//!   convex environment surfaces only.
//! - The footholds planner ([`footholds`]): each stance switch's CoM maximises a static margin
//!   near the feet, with one margin fraction for the whole motion searched by the retimed
//!   duration; it does not plan CoM velocities. Where two consecutive stances share no static
//!   region it places the switch in the middle of the gap and leaves the crossing to the chained
//!   retiming along the straight CoM path, which does not always find one: a walk with no double
//!   support (small humanoid, 12 cm between the single feet' regions) crosses its switch but
//!   cannot stop the CoM before the next landing, and is not retimable.
//! - Collisions ([`collision`]): the robot is its capsules and contact boxes (not its
//!   meshes), the environment its surfaces' solids; no self-collision. The IK keeps the
//!   clearance of the links it can move freely, linearised per step (a body may overshoot its
//!   clearance, not the surface, by a fraction of a millimetre); a landing link's path is a hard
//!   task that it cannot bend, so a landing through a solid is reported by the check, not
//!   avoided (write a swing that clears it, or leave the landing to the footholds planner).
//! - Actuator limits ([`limits`], `limit_rows`, [`joints`]): symmetric limits only, the
//!   torque's from the URDF's `effort` (a joint without one has none), no friction or motor
//!   model. In a motion the torques are enforced at the grid points and, after the refinement,
//!   at the IK samples (the lifted rows by membership); between IK samples the checks at the
//!   output samples measure them (at most `1 + 3e-15` on the built-in and gallery motions at
//!   1 ms). The contact forces are those of the planning pyramids (planning friction and area),
//!   as the GIWC's: a simulator with more friction or area has more room. `U_stance` + rows +
//!   TOPP with the limits takes 2.5 to 5.3 times as long as without (`bench/peers/limits.md`):
//!   13 to 24 ms for the built-in experiments on the project's slower 2-core machine, over
//!   the issue's 10 ms read literally, under it carried over by that machine's own factor (the
//!   issue's baseline build runs 2.7 to 4 times slower there).
//!   [`joints`] retimes fixed-base robots only (the root fixed to the world); its grid is
//!   refined until no limit is exceeded between grid points by more than
//!   `max_violation_fraction` (default 1e-3).

#![warn(unnameable_types)]

pub mod binding;
pub mod error;
pub mod input;
pub mod joints;
pub mod limits;
mod name_or;
pub mod paper;
pub mod retime;
mod strict;
pub mod tol;
pub mod venv;

pub use error::StanceError;

// The stages of the pipeline (private: `run` and `run_full` are their API).
mod chain;
mod fast_forces;
mod ik_stage;
mod limit_rows;
mod midpoints;
mod references;
mod rows;
mod separation;
mod stand;
mod via_points;

// What a motion is, what it gives, and the checks and geometry the simulator and the viewer
// share.
pub mod checks;
pub mod collision;
pub mod environment;
pub mod experiments;
pub mod footholds;
pub mod limit_checks;
pub mod plan;
pub mod result;
pub mod robot;
pub mod spec;
pub mod trajectory;

#[cfg(test)]
mod internal_tests;

/// What the private stages produce, as [`MotionRun`] and [`plan::MotionPlan`] carry it: the
/// whole-body path of each segment (IK samples and their path terms, the placed contacts), the
/// references it tracked, the rows of eq. 14 and of the actuator limits, and the retiming. The
/// stages themselves are private; these types are read-only views for callers that need more
/// than [`result::MotionResult`] (the simulator, the viewer, tests).
pub mod intermediate {
    pub use crate::chain::{
        FailureStatus, LandingBound, Refinement, RetimeFailure, Retimed, RetimingMode, SegmentSolve,
    };
    pub use crate::ik_stage::{IkSample, PlacedContact, SegmentPath};
    pub use crate::limit_rows::{LimitsPlan, SegmentContacts};
    pub use crate::references::{ComReference, CornerKernel, LinkLeg, LinkPlan, SegmentReferences};
    pub use crate::rows::{LiftedSide, PointRows, SegmentRows, SideRows};
}

use std::path::PathBuf;
use std::time::Instant;

use chain::{retime_chained, FailureStatus, RetimeFailure, Retimed, RetimingMode};
use ik_stage::{run_segment, IkStageWorkspace, SegmentPath};
use plan::MotionPlan;
use result::{
    ChecksInfo, ContactInfo, EnvironmentInfo, MotionResult, MotionStatus, PhaseInfo, RobotInfo,
    SegmentInfo, Timings, TrajectoryInfo,
};
use rows::SegmentRows;
pub use spec::MotionSpec;
use trajectory::TrajectorySample;

/// Options of [`run`] beyond the motion file.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Folder of the motion file (relative URDF paths).
    pub base_dir: Option<PathBuf>,
    /// Skip the independent checks (they dominate the run time).
    pub skip_checks: bool,
    /// Time-scale the retimed trajectory before the checks (`k > 1` plays it `k` times faster;
    /// for showing that the check has teeth). Default 1.
    pub time_scale: Option<f64>,
    /// Run the force check with other contacts than the planned ones: each contact's full area
    /// and a circular friction cone of this radius, approximated from inside by an 8-sided
    /// pyramid (e.g. a simulator's friction; default: the planned contacts).
    pub check_friction: Option<f64>,
    /// Retime under contact stability alone (`--no-limits`): the file's actuator limits are
    /// still checked and reported, not enforced.
    pub no_limits: bool,
    /// Where long work reports progress (the footholds planner's search), e.g. a function
    /// printing to standard error.
    pub progress: Option<fn(&str)>,
}

/// Everything the pipeline computed, for callers that need more than the result (the tests,
/// the simulator, the viewer).
#[derive(Debug, Clone)]
pub struct MotionRun {
    /// The validated motion.
    pub plan: MotionPlan,
    /// Per segment: the whole-body path.
    pub paths: Vec<SegmentPath>,
    /// Per segment: `U_stance` and the rows.
    pub rows: Vec<SegmentRows>,
    /// The retiming.
    pub retimed: Option<chain::Retimed>,
    /// The trajectory samples.
    pub samples: Vec<trajectory::TrajectorySample>,
    /// The result.
    pub result: MotionResult,
}

fn ms(d: std::time::Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// Runs a motion and returns its result (see [`run_full`]).
pub fn run(spec: MotionSpec, options: &RunOptions) -> Result<MotionResult, StanceError> {
    run_full(spec, options).map(|r| r.result)
}

/// Runs the whole pipeline of the module doc.
///
/// # Errors
///
/// Bad input ([`StanceError`]): an invalid motion file, a contact that is not on its surface at
/// the start of its segment. A motion whose IK fails or that cannot be retimed is a result with
/// that status, not an error.
pub fn run_full(spec: MotionSpec, options: &RunOptions) -> Result<MotionRun, StanceError> {
    let t_start = Instant::now();
    check_friction_option(options)?;
    let (spec, planning) = if footholds::needs_planning(&spec) {
        let planned = footholds::plan(&spec, options)?;
        (planned.spec, Some(planned.info))
    } else {
        (spec, None)
    };
    let mut plan = MotionPlan::new(spec, options.base_dir.as_deref())?;
    if options.no_limits {
        // the file's limits stay in plan.actuator_limits: checked, not enforced
        plan.limits = None;
    }
    let t_plan = t_start.elapsed();
    let m = &plan.robot.model;
    let mode = if plan.spec.retiming.rest_to_rest {
        RetimingMode::RestToRest
    } else {
        RetimingMode::Chained
    };
    let mut ik_ws = IkStageWorkspace::new(&plan);
    let (paths, mut failure) = ik_paths(&plan, &mut ik_ws)?;
    let mut rows = Vec::new();
    let mut retimed = None;
    if failure.is_none() {
        let r;
        (rows, r) = retime_chained(&plan, &paths, mode, &mut ik_ws)?;
        failure = r.failure.clone();
        retimed = Some(r);
    }
    let t_pipeline = t_start.elapsed();

    // trajectory and checks
    let mut samples = Vec::new();
    let mut checks = None;
    let moves = via_points::moves_reached(&plan, &paths)?;
    let profile = retimed.as_ref().and_then(|r| r.profile.clone());
    if let (Some(r), Some(p)) = (&retimed, &profile) {
        (samples, checks) = trajectory_and_checks(&plan, &paths, &rows, r, p, &moves, options)?;
    }

    // the result
    let status = match (&failure, &profile) {
        (None, Some(_)) => MotionStatus::Optimal,
        (Some(f), _) if f.status == FailureStatus::IkFailed => MotionStatus::IkFailed,
        _ => MotionStatus::NotRetimable,
    };
    let times = profile.as_ref().map(|p| p.times().to_vec());
    let segments = segment_infos(
        &plan,
        &paths,
        &rows,
        retimed.as_ref(),
        times.as_deref(),
        moves,
    );
    let result = MotionResult {
        name: plan.name.clone(),
        status,
        mode,
        duration: profile
            .as_ref()
            .map(|p| p.duration() / options.time_scale.unwrap_or(1.0)),
        robot: robot_info(&plan),
        limits: plan.limits.as_ref().map(|l| l.info.clone()),
        gravity: plan.gravity,
        environment: environment_info(&plan),
        friction_cone: plan.spec.planning.friction_cone,
        segments,
        failure,
        landings: retimed.as_ref().map_or(Vec::new(), |r| r.landings.clone()),
        refinement: retimed.as_ref().map(|r| r.refinement),
        phase: retimed.as_ref().map(|r| phase_info(r, profile.as_ref())),
        checks,
        trajectory: (!samples.is_empty()).then(|| trajectory_info(m, &samples)),
        timings: timings(&paths, &rows, retimed.as_ref(), [t_plan, t_pipeline]),
        planning,
    };
    Ok(MotionRun {
        plan,
        paths,
        rows,
        retimed,
        samples,
        result,
    })
}

/// Checks [`RunOptions::check_friction`]: a finite friction coefficient `> 0` when given.
fn check_friction_option(options: &RunOptions) -> Result<(), StanceError> {
    if let Some(mu) = options.check_friction {
        if !(mu.is_finite() && mu > 0.0) {
            return Err(StanceError::BadMotion(format!(
                "check friction (--check-friction) {mu}: give the friction coefficient of the \
                 force check, > 0 (the simulator's: 0.9)"
            )));
        }
    }
    Ok(())
}

/// Stages 5 and 6: the trajectory at the output step and, unless skipped, the checks at their
/// own step (module doc of `trajectory`), both played `k = time_scale` times faster
/// (`t / k`, `v k`, `a k^2`), with the via-points' errors from `moves`.
fn trajectory_and_checks(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    rows: &[SegmentRows],
    r: &Retimed,
    p: &stance_topp::Profile,
    moves: &[Vec<via_points::MoveInfo>],
    options: &RunOptions,
) -> Result<(Vec<TrajectorySample>, Option<ChecksInfo>), StanceError> {
    let k = options.time_scale.unwrap_or(1.0);
    if !(k.is_finite() && k > 0.0) {
        return Err(StanceError::BadMotion(format!(
            "time scale {k}; give a finite factor > 0"
        )));
    }
    // played k times faster
    let scale = |samples: &mut Vec<TrajectorySample>| {
        if k != 1.0 {
            for smp in samples {
                smp.t /= k;
                smp.v.iter_mut().for_each(|x| *x *= k);
                smp.a.iter_mut().for_each(|x| *x *= k * k);
            }
        }
    };
    let mut samples = trajectory::output(plan, paths, r, p, plan.spec.retiming.dt)?;
    scale(&mut samples);
    let mut checks = None;
    if !options.skip_checks {
        // the checks at their own step, every check_dt (module doc of `trajectory`)
        let mut at = trajectory::uniform(plan, paths, r, p, plan.spec.retiming.check_dt)?;
        scale(&mut at);
        checks = Some(checks_info(
            plan,
            paths,
            rows,
            r,
            &at,
            options,
            plan.actuator_limits.as_ref(),
        )?);
        if let Some(c) = checks.as_mut() {
            [c.max_via_point_error, c.max_via_point_rotation_deg] =
                via_points::largest_errors(moves);
            c.via_points_missed = via_points::missed(plan, moves);
        }
    }
    Ok((samples, checks))
}

/// The result's phase plane: the global grid, the segments' starts on it, the profile's
/// `s'`, `s''` and times (empty without a profile), and the controllable and feasible sets.
fn phase_info(r: &Retimed, profile: Option<&stance_topp::Profile>) -> PhaseInfo {
    PhaseInfo {
        s: r.constraints.grid().to_vec(),
        segment_starts: r.seg_start.clone(),
        sd: profile.map_or(Vec::new(), |p| p.sd()),
        sdd: profile.map_or(Vec::new(), |p| p.u().to_vec()),
        t: profile.map_or(Vec::new(), |p| p.times().to_vec()),
        controllable_sets: r.controllable.clone(),
        feasible_sets: r.feasible.clone(),
    }
}

/// The result's trajectory: the samples' times, segments (from 1), `q`, `v`, `a`, and the
/// joints' names (the universe left out).
fn trajectory_info(m: &stance_robot::Model, samples: &[TrajectorySample]) -> TrajectoryInfo {
    TrajectoryInfo {
        t: samples.iter().map(|s| s.t).collect(),
        segment: samples.iter().map(|s| s.segment + 1).collect(),
        q: samples.iter().map(|s| s.q.clone()).collect(),
        v: samples.iter().map(|s| s.v.clone()).collect(),
        a: samples.iter().map(|s| s.a.clone()).collect(),
        joint_names: m.joint_names()[1..].to_vec(),
    }
}

/// The result's timings (ms): the stages' own times summed over the segments, the retiming's,
/// and the wall times `[t_plan, t_pipeline]` that [`run_full`] measured (planning; everything
/// up to the retiming's end). `t_u_abc_topp_ms` is the wall time from the rows' start to the
/// first solve's end ([`Retimed::t_rows_first`]).
fn timings(
    paths: &[SegmentPath],
    rows: &[SegmentRows],
    retimed: Option<&Retimed>,
    [t_plan, t_pipeline]: [std::time::Duration; 2],
) -> Timings {
    let t_ik: f64 = paths.iter().map(|p| ms(p.elapsed)).sum();
    let t_u: f64 = rows.iter().map(|r| ms(r.t_u)).sum();
    let t_abc: f64 =
        rows.iter().map(|r| ms(r.t_abc)).sum::<f64>() + retimed.map_or(0.0, |r| ms(r.t_assemble));
    let t_topp = retimed.map_or(0.0, |r| ms(r.t_topp));
    let t_lifted = retimed.map_or(0.0, |r| ms(r.t_lifted));
    Timings {
        t_plan_ms: ms(t_plan),
        t_ik_ms: t_ik,
        t_u_ms: t_u,
        t_abc_ms: t_abc,
        t_topp_ms: t_topp,
        t_refine_ms: retimed.map_or(0.0, |r| ms(r.refinement.elapsed)),
        t_lifted_ms: t_lifted,
        t_u_abc_topp_ms: retimed.map_or(0.0, |r| ms(r.t_rows_first)),
        t_pipeline_ms: ms(t_pipeline),
    }
}

/// Stage 1: the IK along every segment, chained (each starts where the previous one ended),
/// until the end or the first segment whose IK stops (its path kept, with the failure).
fn ik_paths(
    plan: &MotionPlan,
    ik_ws: &mut IkStageWorkspace,
) -> Result<(Vec<SegmentPath>, Option<RetimeFailure>), StanceError> {
    let m = &plan.robot.model;
    let grid = plan.spec.retiming.grid;
    let substeps = plan.spec.ik.substeps;
    let mut paths: Vec<SegmentPath> = Vec::new();
    let mut failure = None;
    let (mut q, mut q_s) = (plan.q0.clone(), vec![0.0; m.nv]);
    let mut previous: Vec<ik_stage::PlacedContact> = Vec::new();
    let com = ik_stage::com_reference(plan)?;
    let mut s_offset = 0.0;
    for k in 0..plan.segments.len() {
        let path = run_segment(
            plan,
            k,
            &com,
            s_offset,
            &q,
            &q_s,
            &previous,
            grid * substeps,
            ik_ws,
        )?;
        s_offset += path.references.length();
        previous = path.contacts.clone();
        if let Some((i, status)) = &path.failure {
            failure = Some(RetimeFailure {
                status: FailureStatus::IkFailed,
                segment: k + 1,
                segment_name: plan.segments[k].name.clone(),
                grid_point: i / substeps,
                s: path.references.length() * *i as f64 / (grid * substeps) as f64,
                constraints: Vec::new(),
                reason: format!(
                    "in {}, grid point {}: the IK stopped at step {i} of {}: \
                     {status:?} (a joint limit, or a via-point out of reach)",
                    plan::segment_label(k, &plan.segments[k].name),
                    i / substeps,
                    grid * substeps
                ),
            });
            paths.push(path);
            break;
        }
        let last = &path.samples[path.samples.len() - 1];
        q = last.q.clone();
        q_s = last.q_s.clone();
        paths.push(path);
    }
    Ok((paths, failure))
}

/// Stage 4: the independent checks of the sampled trajectory (supporting forces at every sample,
/// friction, drift, joint limits) and the rows between grid points.
fn checks_info(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    rows: &[SegmentRows],
    r: &Retimed,
    samples: &[TrajectorySample],
    options: &RunOptions,
    limits: Option<&limit_rows::LimitsPlan>,
) -> Result<ChecksInfo, StanceError> {
    let m = &plan.robot.model;
    let t0 = Instant::now();
    let stances: Vec<stance_contact::Stance> = match options.check_friction {
        None => rows.iter().map(|r| r.stance.clone()).collect(),
        Some(mu) => paths
            .iter()
            .map(|p| {
                rows::stance_of(
                    plan,
                    p,
                    1.0,
                    Some(mu),
                    stance_contact::FrictionModel {
                        sides: 8,
                        approximation: stance_contact::Approximation::Inner,
                    },
                )
            })
            .collect::<Result<_, _>>()?,
    };
    let refs: Vec<&stance_contact::Stance> = stances.iter().collect();
    let c = checks::check_samples(plan, paths, &refs, samples)?;
    let (between, _at) = checks::between_violation(paths, rows, r);
    let actuators = match limits {
        Some(lp) => {
            let planned: Vec<&stance_contact::Stance> = rows.iter().map(|r| &r.stance).collect();
            let contacts = limit_checks::planned_contacts(plan, paths);
            let l = limit_checks::check_limits(plan, lp, &planned, &contacts, samples)?;
            Some(result::LimitChecksInfo::from_samples(&l, samples, lp))
        }
        None => None,
    };
    let t_collisions = Instant::now();
    let collisions = collision::check_collisions(plan, &plan.collision, paths, samples)?;
    let t_collisions = t_collisions.elapsed();
    let t = t0.elapsed();
    let weight = m.total_mass() * plan.gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
    Ok(ChecksInfo {
        samples: c.len(),
        samples_without_forces: c.iter().filter(|x| !x.forces).count(),
        slow_force_samples: c.iter().filter(|x| x.slow).count(),
        first_without_forces: c
            .iter()
            .zip(samples)
            .filter(|(x, _)| !x.forces)
            .map(|(_, s)| s.t)
            .take(20)
            .collect(),
        max_friction_usage: c.iter().map(|x| x.friction_usage).fold(0.0, f64::max),
        min_normal_force: c
            .iter()
            .map(|x| x.min_normal_force)
            .fold(f64::INFINITY, f64::min),
        max_contact_drift: c.iter().map(|x| x.contact_drift).fold(0.0, f64::max),
        max_joint_violation: c.iter().map(|x| x.joint_violation).fold(0.0, f64::max),
        max_com_error: paths.iter().map(|p| p.max_com_error).fold(0.0, f64::max),
        // set from the moves by the caller
        max_via_point_error: 0.0,
        via_points_missed: Vec::new(),
        max_via_point_rotation_deg: 0.0,
        max_between_violation: between,
        max_between_violation_fraction: between / weight,
        max_velocity_ratio: actuators.as_ref().map(|a| a.max_velocity_ratio),
        max_acceleration_ratio: actuators.as_ref().map(|a| a.max_acceleration_ratio),
        max_torque_ratio: actuators.as_ref().map(|a| a.max_torque_ratio),
        max_joint_acceleration: samples
            .iter()
            .flat_map(|s| s.a.iter().skip(6).map(|x| x.abs()))
            .fold(0.0, f64::max),
        limits: actuators,
        max_penetration: collisions.max_penetration,
        collisions: collisions.collisions,
        clearances: collisions.clearances,
        unplanned_touches: collisions.touches,
        t_collisions_ms: ms(t_collisions),
        t_checks_ms: ms(t),
        t_per_sample_us: ms(t) * 1e3 / c.len().max(1) as f64,
    })
}

/// One line per segment of the result: its times, contacts, rows, IK and timings.
fn segment_infos(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    rows: &[SegmentRows],
    retimed: Option<&Retimed>,
    times: Option<&[f64]>,
    moves: Vec<Vec<via_points::MoveInfo>>,
) -> Vec<SegmentInfo> {
    paths
        .iter()
        .zip(moves)
        .enumerate()
        .map(|(k, (path, moves))| {
            let r = rows.get(k);
            let span = retimed
                .zip(times)
                .map(|(rt, t)| (t[rt.seg_start[k]], t[rt.seg_start[k + 1]]));
            let solve = retimed.and_then(|rt| rt.segments.get(k));
            SegmentInfo {
                name: plan.segments[k].name.clone(),
                t_start: span.map(|s| s.0),
                t_end: span.map(|s| s.1),
                duration: span.map(|s| s.1 - s.0),
                sd_boundaries: solve.map(|s| s.sd),
                contacts: contact_infos(plan, path, r),
                u_stance_rows: r.map_or(0, |r| r.u.len()),
                giwc_certified: r.is_some_and(|r| r.certified),
                grid_points: r.map_or(0, |r| r.grid.len()),
                ik_steps: path.samples.len(),
                ik_fallbacks: path.fallbacks,
                ik_clearance_dropped: path.clearance_dropped,
                t_ik_ms: ms(path.elapsed),
                t_u_ms: r.map_or(0.0, |r| ms(r.t_u)),
                t_abc_ms: r.map_or(0.0, |r| ms(r.t_abc)),
                t_topp_ms: solve.map(|s| ms(s.t_topp)),
                max_com_error: path.max_com_error,
                moves,
                max_contact_drift: path.max_contact_drift,
                binding: retimed.and_then(|rt| segment_binding(plan, rt, k)),
                torque_cuts: r.map_or(0, |r| r.cuts),
            }
        })
        .collect()
}

/// The grid points of segment `k` bound by each kind of constraint under the profile
/// ([`crate::binding`]); its last point counts in the next segment (but the last segment's).
fn segment_binding(plan: &MotionPlan, rt: &Retimed, k: usize) -> Option<crate::binding::Binding> {
    let p = rt.profile.as_ref()?;
    let joints: &[String] = plan.limits.as_ref().map_or(&[], |lp| &lp.names);
    let c = &rt.constraints;
    let (a, mut b) = (rt.seg_start[k], rt.seg_start[k + 1]);
    if k + 2 == rt.seg_start.len() {
        b += 1;
    }
    let mut out = crate::binding::Binding::default();
    let (u, x) = (p.u(), p.x());
    for i in a..b {
        let ui = u[i.min(u.len() - 1)];
        let (o0, o1) = (c.offsets()[i], c.offsets()[i + 1]);
        out.add_point(
            c.rows_at(i)
                .iter()
                .zip(&rt.origins[o0..o1])
                .filter(|(r, _)| crate::binding::binds(r, ui, x[i]))
                .map(|(_, o)| *o),
            joints,
        );
    }
    Some(out)
}

/// The robot as the result describes it.
fn robot_info(plan: &MotionPlan) -> RobotInfo {
    let m = &plan.robot.model;
    RobotInfo {
        name: plan.robot.name.clone(),
        urdf: plan.robot.urdf.as_ref().map(|p| p.display().to_string()),
        locked: plan.robot.locked.clone(),
        mass: m.total_mass(),
        nq: m.nq,
        nv: m.nv,
        unknown_urdf_elements: m
            .unknown_elements
            .iter()
            .map(|(name, line)| format!("<{name}> (line {line})"))
            .collect(),
    }
}

/// The environment's surfaces as the result describes them (polygons in world coordinates).
fn environment_info(plan: &MotionPlan) -> Vec<EnvironmentInfo> {
    plan.environment
        .iter()
        .map(|e| EnvironmentInfo {
            name: e.name.clone(),
            vertices: e
                .polygon
                .iter()
                .map(|p| {
                    (e.pose.rotation * nalgebra::Vector3::new(p[0], p[1], 0.0) + e.pose.translation)
                        .into()
                })
                .collect(),
            friction: e.friction,
        })
        .collect()
}

fn contact_infos(
    plan: &MotionPlan,
    path: &SegmentPath,
    rows: Option<&SegmentRows>,
) -> Vec<ContactInfo> {
    path.contacts
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let surf = &plan.robot.surfaces[c.surface];
            let r = &c.pose.rotation;
            let planned = rows.map(|r| &r.stance.contacts()[i]);
            let (half_length, half_width) = planned.map_or((0.0, 0.0), |p| {
                let v = p.vertices_local();
                (
                    v.iter().map(|x| x[0].abs()).fold(0.0, f64::max),
                    v.iter().map(|x| x[1].abs()).fold(0.0, f64::max),
                )
            });
            ContactInfo {
                name: surf.name.clone(),
                link: surf.link.clone(),
                environment: plan.environment[c.environment].name.clone(),
                position: c.pose.translation.into(),
                rotation: [
                    [r[(0, 0)], r[(0, 1)], r[(0, 2)]],
                    [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
                    [r[(2, 0)], r[(2, 1)], r[(2, 2)]],
                ],
                half_length,
                half_width,
                friction: planned
                    .map_or(plan.environment[c.environment].friction, |p| p.friction()),
                vertices: planned.map_or(Vec::new(), |p| p.vertices_local().to_vec()),
                on_surface: c.on_surface,
            }
        })
        .collect()
}
