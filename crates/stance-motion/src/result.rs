//! What `stance motion` returns (serialized as its JSON output).

use serde::{Deserialize, Serialize};
use stance_contact::FrictionModel;

use super::chain::{LandingBound, Refinement, RetimeFailure, RetimingMode};
use super::environment::OnSurface;
/// The per-move report of the via-points (computed by the private via-points check).
pub use super::via_points::{LinkReached, MoveInfo, ViaPointMiss};

/// The outcome of a motion: a value, never an error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MotionStatus {
    /// Retimed: a time-optimal profile exists.
    Optimal,
    /// The IK could not follow the references (a joint limit, an unreachable via-point).
    IkFailed,
    /// The whole-body path exists but no timing keeps the contacts stable (see `failure`).
    NotRetimable,
}

/// The robot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RobotInfo {
    /// Built-in name or URDF file name.
    pub name: String,
    /// Path of the URDF (`null` for the embedded small humanoid).
    pub urdf: Option<String>,
    /// Locked joints and their values.
    pub locked: Vec<(String, f64)>,
    /// Total mass (kg).
    pub mass: f64,
    /// Configuration and velocity sizes.
    pub nq: usize,
    /// Velocity size.
    pub nv: usize,
    /// Elements of the URDF the model does not use, as `<name> (line N)`.
    #[serde(default)]
    pub unknown_urdf_elements: Vec<String>,
}

/// An environment surface of the motion (what the viewer draws; the contacts say which one
/// they lie on).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EnvironmentInfo {
    /// Its name.
    pub name: String,
    /// Its convex polygon in world coordinates (m).
    pub vertices: Vec<[f64; 3]>,
    /// Friction coefficient.
    pub friction: f64,
}

/// A contact of a segment as planned.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContactInfo {
    /// Robot surface name.
    pub name: String,
    /// Its link.
    pub link: String,
    /// The environment surface.
    pub environment: String,
    /// Contact frame origin (m, world).
    pub position: [f64; 3],
    /// Contact frame -> world (row-major).
    pub rotation: [[f64; 3]; 3],
    /// Half sizes as planned (after the area scale; 0 for a point; a polygon's bounding box).
    pub half_length: f64,
    /// Half width as planned.
    pub half_width: f64,
    /// Friction as planned.
    pub friction: f64,
    /// The contact polygon as planned (contact frame, m): the GIWC's vertices.
    pub vertices: Vec<[f64; 2]>,
    /// How well the robot surface lies on the environment surface.
    pub on_surface: OnSurface,
}

/// One segment of the result, with the paper's table columns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SegmentInfo {
    /// Name.
    pub name: String,
    /// Start and end time (s) in the retimed motion (`null` without a profile).
    pub t_start: Option<f64>,
    /// End time.
    pub t_end: Option<f64>,
    /// Duration (s).
    pub duration: Option<f64>,
    /// Path speed `s'` at its start and end.
    pub sd_boundaries: Option<[f64; 2]>,
    /// Contacts.
    pub contacts: Vec<ContactInfo>,
    /// Rows of `U_stance`.
    pub u_stance_rows: usize,
    /// Whether `U_stance` is certified.
    pub giwc_certified: bool,
    /// Retiming grid points of the segment.
    pub grid_points: usize,
    /// IK steps.
    pub ik_steps: usize,
    /// Steps the dense IK solver gave to Clarabel.
    pub ik_fallbacks: usize,
    /// IK steps whose clearance rows could not all be kept (a landing link's path through a
    /// solid), solved without them: the collision check reports what happens.
    #[serde(default)]
    pub ik_clearance_dropped: usize,
    /// `T_IK` (ms).
    pub t_ik_ms: f64,
    /// `T_U` (ms).
    pub t_u_ms: f64,
    /// `T_abc` (ms).
    pub t_abc_ms: f64,
    /// `T_TOPP` (ms): the segment's own solve (rest to rest) or its re-solve with the chained
    /// boundary speeds.
    pub t_topp_ms: Option<f64>,
    /// Largest CoM tracking error of the IK (m), against its reference (which passes through
    /// the file's via-points: `moves` measures against them).
    pub max_com_error: f64,
    /// Each move's end: its CoM and link via-points and where the IK's path was.
    #[serde(default)]
    pub moves: Vec<super::via_points::MoveInfo>,
    /// Largest contact-frame drift during the IK (m).
    pub max_contact_drift: f64,
    /// Grid points of this segment bound by each kind of constraint under the profile
    /// (`null` without a profile); the grid point a segment shares with the next counts in the
    /// next.
    pub binding: Option<crate::binding::Binding>,
    /// Cuts of the torque rows with the contact forces as unknowns that the retiming needed
    /// (rows in `(u, x)` valid at their grid point's side; none without two contacts or more).
    #[serde(default)]
    pub torque_cuts: usize,
}

/// The independent checks (module `checks`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChecksInfo {
    /// Samples checked.
    pub samples: usize,
    /// Samples where the force QP finds no supporting forces.
    pub samples_without_forces: usize,
    /// Samples the force check's fast path could not certify, decided by the slow path
    /// (Clarabel): the infeasible ones, and any the fast path failed on.
    #[serde(default)]
    pub slow_force_samples: usize,
    /// Times of the first samples without supporting forces (at most 20).
    pub first_without_forces: Vec<f64>,
    /// Largest `|F_t| / (mu F_n)` of a contact's resultant.
    pub max_friction_usage: f64,
    /// Smallest normal force of a contact (N).
    pub min_normal_force: f64,
    /// Largest contact-frame drift at the samples (m).
    pub max_contact_drift: f64,
    /// Largest joint-limit violation at the samples (rad or m).
    pub max_joint_violation: f64,
    /// Largest CoM tracking error of the IK (m), against its reference (which passes through
    /// the file's via-points, module `references`).
    pub max_com_error: f64,
    /// Largest distance of the IK's path from a via-point at its move's end, CoM or link (m).
    pub max_via_point_error: f64,
    /// The via-points missed by more than [`crate::tol::VIA_POINT_DISTANCE`] or
    /// [`crate::tol::VIA_POINT_ANGLE_DEG`], in order (empty: every via-point reached).
    #[serde(default)]
    pub via_points_missed: Vec<super::via_points::ViaPointMiss>,
    /// Largest angle of a link from its via-point's orientation at its move's end (degrees).
    pub max_via_point_rotation_deg: f64,
    /// Largest row value at the IK samples under the profile (N), i.e. between grid points.
    pub max_between_violation: f64,
    /// The same as a fraction of the weight.
    pub max_between_violation_fraction: f64,
    /// Largest joint velocity over its limit at the samples (`null` without limits).
    pub max_velocity_ratio: Option<f64>,
    /// Largest joint acceleration over its limit at the samples (`null` without limits).
    pub max_acceleration_ratio: Option<f64>,
    /// Largest joint torque over its limit at the samples, with the contact forces that make it
    /// smallest (`null` without limits).
    pub max_torque_ratio: Option<f64>,
    /// Largest joint acceleration at the samples, whatever the limits (rad/s^2 or m/s^2).
    #[serde(default)]
    pub max_joint_acceleration: f64,
    /// Where each largest ratio occurs.
    pub limits: Option<LimitChecksInfo>,
    /// Deepest penetration of a robot body into an environment solid (m; 0 without one): a
    /// collision beyond [`crate::tol::COLLISION_PENETRATION`] (module
    /// [`super::collision`]).
    #[serde(default)]
    pub max_penetration: f64,
    /// The collisions, per robot body and environment surface, deepest first (empty: none).
    #[serde(default)]
    pub collisions: Vec<super::collision::CollisionInfo>,
    /// The smallest clearance of every robot body that comes within
    /// [`crate::tol::CLEARANCE_RANGE`] of a surface, smallest first.
    #[serde(default)]
    pub clearances: Vec<super::collision::ClearanceInfo>,
    /// Unplanned touches that last ([`crate::tol::UNPLANNED_TOUCH_TIME`]), longest first.
    #[serde(default)]
    pub unplanned_touches: Vec<super::collision::TouchInfo>,
    /// Time of the collision check (ms; part of `t_checks_ms`).
    #[serde(default)]
    pub t_collisions_ms: f64,
    /// Time of the checks (ms), and per sample (us).
    pub t_checks_ms: f64,
    /// Time per sample (us).
    pub t_per_sample_us: f64,
}

/// The retimed trajectory in Pinocchio's conventions.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrajectoryInfo {
    /// Times (s).
    pub t: Vec<f64>,
    /// Segment of each sample (its number, from 1).
    pub segment: Vec<usize>,
    /// Configurations.
    pub q: Vec<Vec<f64>>,
    /// Velocities.
    pub v: Vec<Vec<f64>>,
    /// Accelerations.
    pub a: Vec<Vec<f64>>,
    /// Joint names (after the free flyer), in `q` order.
    pub joint_names: Vec<String>,
}

/// The retiming in the phase plane, on the global grid of the path parameter.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PhaseInfo {
    /// Grid `s_i` (global path parameter).
    pub s: Vec<f64>,
    /// Index of each segment's first grid point, and of the last point.
    pub segment_starts: Vec<usize>,
    /// Path speed `s'` at the grid points (empty without a profile).
    pub sd: Vec<f64>,
    /// Path acceleration `s''` on each interval (empty without a profile).
    pub sdd: Vec<f64>,
    /// Time at the grid points (empty without a profile).
    pub t: Vec<f64>,
    /// Controllable sets `[lo, hi]` of `x = s'^2` (null where empty or not computed).
    pub controllable_sets: Vec<Option<[f64; 2]>>,
    /// Feasible sets of `x` (null where empty).
    pub feasible_sets: Vec<Option<[f64; 2]>>,
}

/// Stage timings of the pipeline (ms).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Timings {
    /// Validation and the standing posture.
    pub t_plan_ms: f64,
    /// IK of every segment.
    pub t_ik_ms: f64,
    /// `U_stance` of every segment.
    pub t_u_ms: f64,
    /// Rows of every segment and their layout on the global grid.
    pub t_abc_ms: f64,
    /// The retiming solve (the last one, after refinement).
    pub t_topp_ms: f64,
    /// The separation oracle of the lifted torque rows (torque limits with the contact forces)
    /// during the first solve, part of that solve's time (ms).
    #[serde(default)]
    pub t_lifted_ms: f64,
    /// The refinement between grid points (its row updates and solves).
    pub t_refine_ms: f64,
    /// `U_stance` + rows + TOPP (the paper's three columns), as the user waits for them: the
    /// wall time of the segments' `U_stance` and rows (computed in parallel), their layout,
    /// the solve and the lifted torque rows' work (ms).
    pub t_u_abc_topp_ms: f64,
    /// The whole pipeline without the checks.
    pub t_pipeline_ms: f64,
}

/// The result of `stance motion`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MotionResult {
    /// Name of the motion.
    pub name: String,
    /// Outcome.
    pub status: MotionStatus,
    /// Chained or rest to rest.
    pub mode: RetimingMode,
    /// Duration (s) when optimal.
    pub duration: Option<f64>,
    /// The robot.
    pub robot: RobotInfo,
    /// The actuator limits the retiming enforced, per joint (`null` without: `--no-limits`, or
    /// none finite); the checks use the file's (`checks.limits`).
    pub limits: Option<Vec<crate::limits::JointLimitInfo>>,
    /// Gravity (m/s^2, world).
    pub gravity: [f64; 3],
    /// The environment surfaces.
    pub environment: Vec<EnvironmentInfo>,
    /// The friction pyramid of every contact's GIWC (`[planning] friction_cone`).
    pub friction_cone: FrictionModel,
    /// The segments.
    pub segments: Vec<SegmentInfo>,
    /// Where and why the IK or the retiming failed.
    pub failure: Option<RetimeFailure>,
    /// Speed bounds at landings.
    pub landings: Vec<LandingBound>,
    /// What the refinement between grid points did.
    pub refinement: Option<Refinement>,
    /// The retiming in the phase plane (when the IK succeeded).
    pub phase: Option<PhaseInfo>,
    /// The checks (when run and a profile exists).
    pub checks: Option<ChecksInfo>,
    /// The trajectory (when a profile exists).
    pub trajectory: Option<TrajectoryInfo>,
    /// Stage timings.
    pub timings: Timings,
    /// What the footholds planner chose (`null` when every segment is written by hand).
    #[serde(default)]
    pub planning: Option<crate::footholds::PlanningInfo>,
}

/// The actuator limits checked at every sample ([`super::limit_checks`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LimitChecksInfo {
    /// Largest `|v_j| / V_j` (0 without velocity limits).
    pub max_velocity_ratio: f64,
    /// Largest `|a_j| / A_j` (0 without acceleration limits).
    pub max_acceleration_ratio: f64,
    /// Largest of the samples' smallest largest torque ratios (0 without torque limits).
    pub max_torque_ratio: f64,
    /// Samples where no contact forces balance the base (no torque ratio).
    pub samples_without_torque_ratio: usize,
    /// The joint and time of each largest ratio.
    pub worst: Vec<WorstLimit>,
}

/// Where a largest ratio occurs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WorstLimit {
    /// `velocity`, `acceleration` or `torque`.
    pub kind: String,
    /// The joint.
    pub joint: String,
    /// The time (s).
    pub t: f64,
    /// The ratio.
    pub ratio: f64,
}

impl LimitChecksInfo {
    /// The largest ratios over the samples.
    pub fn from_samples(
        l: &[super::limit_checks::LimitSample],
        samples: &[super::trajectory::TrajectorySample],
        lp: &crate::limit_rows::LimitsPlan,
    ) -> Self {
        let mut worst = [(0.0f64, 0usize, 0.0f64); 3];
        let mut without = 0;
        for (x, s) in l.iter().zip(samples) {
            if x.torque_ratio.is_nan() {
                without += 1;
            }
            for (w, (r, j)) in worst.iter_mut().zip([
                (x.velocity_ratio, x.velocity_joint),
                (x.acceleration_ratio, x.acceleration_joint),
                (x.torque_ratio, x.torque_joint),
            ]) {
                if r > w.0 {
                    *w = (r, j, s.t);
                }
            }
        }
        Self {
            max_velocity_ratio: worst[0].0,
            max_acceleration_ratio: worst[1].0,
            max_torque_ratio: worst[2].0,
            samples_without_torque_ratio: without,
            worst: worst
                .iter()
                .zip(["velocity", "acceleration", "torque"])
                .filter(|(w, _)| w.0 > 0.0)
                .map(|(w, kind)| WorstLimit {
                    kind: kind.to_string(),
                    joint: lp.names[w.1].clone(),
                    t: w.2,
                    ratio: w.0,
                })
                .collect(),
        }
    }
}
