//! Time-optimal retiming of a fixed-base robot's joint path under its actuator limits (joint
//! velocity, acceleration and torque): toppra's home ground, `stance retime-joints`.
//!
//! # Math
//!
//! The path `q(s)` goes through the waypoints ([`stance_topp::path::WaypointPath`]: SciPy's
//! cubic spline with not-a-knot, natural or clamped ends, or a polyline). At every grid point
//! the inverse dynamics along the path give `tau = tau_a u + tau_b x + tau_c`
//! ([`stance_robot::torque_path_terms`]), and the limits become rows in `(u, x) = (s'', s'^2)`
//! ([`stance_topp::limits`]): one velocity row (the tightest joint), two rows per joint with an
//! acceleration or torque limit, each divided by its limit so that a row's value is the ratio to
//! the limit minus one. Reachability analysis then gives the time-optimal profile from
//! `sd_start` to `sd_end`.
//!
//! Between grid points the limits hold only as far as they are checked: the rows are evaluated
//! at `samples_per_interval` points per interval under the profile, and the grid is bisected
//! where a limit is exceeded by more than `max_violation_fraction` of it
//! ([`stance_topp::between::refine_until`]), unless that option is `false` (the grid as given,
//! as toppra solves it).
//!
//! **Checks**, independent of the rows: at every output sample the joint velocity and
//! acceleration come from the path and the profile (`v = q_s s'`, `a = q_s s'' + q_ss s'^2`) and
//! the torque from the RNEA at `(q, v, a)`; the largest ratios to the limits are reported.
//!
//! # Limitations
//!
//! - The root link is fixed to the world (an arm, not a humanoid: whole-body motions with
//!   contacts are [the crate]'s). No joint friction or rotor inertia.
//! - The limits are symmetric. Velocity and effort limits come from the URDF (scaled); a joint
//!   without them has none of that kind.
//! - A polyline path's tangent jumps at interior waypoints, so the retiming must stop there
//!   (the solver's rows require it only at grid points that fall on the waypoints; use a spline
//!   for motions that do not stop).

pub mod spec;

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;
use stance_robot::{torque_path_terms, Data, JointKind, Model, RootJoint, UrdfOptions};
use stance_topp::between::{check_between, refine_until, ContinuousConstraints};
use stance_topp::limits::{JointLimits, LimitKind, LimitTag};
use stance_topp::path::{Interpolation, WaypointPath};
use stance_topp::{CanonicalConstraints, Profile, Row, SolveOptions, Status, Workspace};

use crate::binding::{binds, Binding, RowOrigin};
use crate::limits::JointLimitInfo;
use crate::StanceError;
pub use spec::JointPathSpec;
use spec::{FractionOrOff, JointInterpolation, SplineEnds};

/// The robot, its path and its limits, ready to give rows at any path parameter.
pub struct JointProblem {
    model: Model,
    /// Model joint index of each path coordinate.
    coordinates: Vec<usize>,
    /// The coordinates' names.
    names: Vec<String>,
    path: WaypointPath,
    limits: JointLimits,
    limit_info: Vec<JointLimitInfo>,
    gravity: [f64; 3],
    /// Per row of [`JointLimits::layout`].
    tags: Vec<LimitTag>,
    scratch: RefCell<Scratch>,
}

struct Scratch {
    data: Data,
    q: Vec<f64>,
    c: [Vec<f64>; 3],
    qv: Vec<f64>,
    qs: Vec<f64>,
    qss: Vec<f64>,
    t: [Vec<f64>; 3],
}

/// One output sample: `q`, `v`, `a` of the path coordinates.
struct State {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
}

impl JointProblem {
    /// Loads the robot and checks the file against it.
    ///
    /// # Errors
    ///
    /// [`StanceError`] naming what to fix: the URDF, joints that are neither listed nor locked,
    /// unknown or repeated joint names, waypoints of the wrong length, knots, limits.
    pub fn new(spec: &JointPathSpec, base_dir: Option<&Path>) -> Result<Self, StanceError> {
        validate(spec)?;
        let urdf = resolve(base_dir, &spec.urdf);
        let options = UrdfOptions {
            root: RootJoint::Fixed,
            locked: spec.locked.iter().map(|(k, v)| (k.clone(), *v)).collect(),
            ..Default::default()
        };
        let model = Model::from_urdf_file(&urdf, &options).map_err(|e| match e {
            // a file that cannot be read names itself already
            stance_robot::RobotError::Io { .. } => StanceError::Robot(e),
            e => StanceError::BadMotion(format!("the URDF {}: {e}", urdf.display())),
        })?;
        let movable: Vec<usize> = (1..model.joints.len())
            .filter(|&k| model.joints[k].dims().1 > 0)
            .collect();
        let coordinates: Vec<usize> = match &spec.joints {
            None => movable.clone(),
            Some(names) => {
                let mut out = Vec::with_capacity(names.len());
                for n in names {
                    let Some(k) = model.joints.iter().position(|j| &j.name == n) else {
                        let hint = crate::limits::closest_name(&model, n)
                            .map(|c| format!(" (did you mean {c:?}?)"))
                            .unwrap_or_default();
                        return Err(StanceError::BadMotion(if spec.locked.contains_key(n) {
                            format!("joints lists {n:?}, which is locked: list it or lock it")
                        } else {
                            format!("joints lists {n:?}, which is not a joint of the URDF{hint}")
                        }));
                    };
                    if out.contains(&k) {
                        return Err(StanceError::BadMotion(format!(
                            "joints lists {n:?} twice: list every joint once"
                        )));
                    }
                    out.push(k);
                }
                let missing: Vec<&str> = movable
                    .iter()
                    .filter(|k| !out.contains(k))
                    .map(|&k| model.joints[k].name.as_str())
                    .collect();
                if !missing.is_empty() {
                    return Err(StanceError::BadMotion(format!(
                        "the movable joints {missing:?} are neither in joints nor locked: add \
                         them to joints (with their columns in the waypoints) or to locked"
                    )));
                }
                out
            }
        };
        if coordinates.is_empty() {
            return Err(StanceError::BadMotion(
                "the robot has no movable joint (all fixed or locked): nothing to retime".into(),
            ));
        }
        let names: Vec<String> = coordinates
            .iter()
            .map(|&k| model.joints[k].name.clone())
            .collect();
        let n = coordinates.len();
        for (i, w) in spec.waypoints.iter().enumerate() {
            if w.len() != n {
                return Err(StanceError::BadMotion(format!(
                    "waypoint {i} has {} value(s) but the path has {n} joint(s) ({}): give one \
                     value per joint, in the order of joints",
                    w.len(),
                    names.join(", ")
                )));
            }
        }
        if let Some(k) = &spec.knots {
            for i in 0..k.len() {
                let bad = !k[i].is_finite() || (i > 0 && k[i] <= k[i - 1]);
                if bad {
                    let after = if i > 0 {
                        format!(" after knots[{}] = {}", i - 1, k[i - 1])
                    } else {
                        String::new()
                    };
                    return Err(StanceError::BadMotion(format!(
                        "knots[{i}] = {}{after}: the knots must be finite and strictly \
                         increasing, one per waypoint",
                        k[i]
                    )));
                }
            }
        }
        let knots = spec.knots.clone().unwrap_or_else(|| {
            let m = spec.waypoints.len();
            (0..m).map(|i| i as f64 / (m.max(2) - 1) as f64).collect()
        });
        let interpolation = match (spec.interpolation, spec.spline) {
            (JointInterpolation::Polyline, _) => Interpolation::Polyline,
            (JointInterpolation::Spline, SplineEnds::NotAKnot) => Interpolation::NotAKnot,
            (JointInterpolation::Spline, SplineEnds::Natural) => Interpolation::Natural,
            (JointInterpolation::Spline, SplineEnds::Clamped) => Interpolation::Clamped {
                start: vec![0.0; n],
                end: vec![0.0; n],
            },
        };
        let path = WaypointPath::new(knots, spec.waypoints.clone(), interpolation)?;
        let resolved = spec.limits.resolve(&model, &coordinates)?;
        if !resolved.any() {
            return Err(StanceError::BadMotion(
                "no limit applies: the URDF gives no positive velocity or effort limits and \
                 [limits] adds none, so nothing bounds the speed; give limits.acceleration, or \
                 velocity and effort limits in the URDF"
                    .into(),
            ));
        }
        let nv = model.nv;
        let scratch = Scratch {
            data: Data::new(&model),
            q: model.neutral(),
            c: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            qv: vec![0.0; nv],
            qs: vec![0.0; nv],
            qss: vec![0.0; nv],
            t: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
        };
        let tags = resolved.limits.layout();
        Ok(Self {
            coordinates,
            names,
            path,
            limits: resolved.limits,
            limit_info: resolved.joints,
            gravity: spec.gravity,
            tags,
            scratch: RefCell::new(scratch),
            model,
        })
    }

    /// The joint names of the path coordinates.
    pub fn joint_names(&self) -> &[String] {
        &self.names
    }

    /// `points` evenly spaced grid points over the path's domain (the last exactly its end).
    pub fn uniform_grid(&self, points: usize) -> Vec<f64> {
        let [s0, s1] = self.path.domain();
        let n = points.max(2) - 1;
        (0..=n)
            .map(|i| {
                if i == n {
                    s1
                } else {
                    s0 + (s1 - s0) * i as f64 / n as f64
                }
            })
            .collect()
    }

    /// The rows on `grid` and the time-optimal profile under `opts`: what a retiming costs
    /// without its refinement, trajectory and checks (the peer benchmark's unit of work).
    ///
    /// # Errors
    ///
    /// [`StanceError::Topp`] for a grid that is not strictly increasing.
    pub fn solve_on_grid(
        &self,
        grid: &[f64],
        opts: &SolveOptions,
        ws: &mut Workspace,
    ) -> Result<stance_topp::Solution, StanceError> {
        let (k, _) = constraints_on(self, grid)?;
        Ok(ws.solve(&k, opts)?)
    }

    /// `q` of the model from path coordinates `c` (continuous joints take `(cos, sin)`).
    fn model_q(&self, c: &[f64], q: &mut [f64]) {
        for (&k, &x) in self.coordinates.iter().zip(c) {
            let j = &self.model.joints[k];
            match j.kind {
                JointKind::Continuous { .. } => {
                    q[j.idx_q] = x.cos();
                    q[j.idx_q + 1] = x.sin();
                }
                _ => q[j.idx_q] = x,
            }
        }
    }

    /// Scatters coordinate values into the model's velocity layout.
    fn scatter(&self, c: &[f64], v: &mut [f64]) {
        for (&k, &x) in self.coordinates.iter().zip(c) {
            v[self.model.joints[k].idx_v] = x;
        }
    }

    /// The rows at `s` (layout of [`JointLimits::layout`]) and the velocity row's coordinate.
    fn rows_at(&self, s: f64, out: &mut [Row]) -> Option<usize> {
        let mut guard = self.scratch.borrow_mut();
        let sc = &mut *guard;
        let [c0, c1, c2] = &mut sc.c;
        self.path.eval(s, c0, c1, c2);
        let torque = if self.limits.any_torque() {
            self.model_q(c0, &mut sc.q);
            self.scatter(c1, &mut sc.qs);
            self.scatter(c2, &mut sc.qss);
            // the model was checked when it was built, and q is finite: no error
            torque_path_terms(
                &self.model,
                &mut sc.data,
                &sc.q,
                &sc.qs,
                &sc.qss,
                self.gravity,
            )
            .expect("a valid configuration of the model");
            let tp = &sc.data.torque_path;
            for (i, &k) in self.coordinates.iter().enumerate() {
                let iv = self.model.joints[k].idx_v;
                sc.t[0][i] = tp.tau_a[iv];
                sc.t[1][i] = tp.tau_b[iv];
                sc.t[2][i] = tp.tau_c[iv];
            }
            Some([&sc.t[0][..], &sc.t[1][..], &sc.t[2][..]])
        } else {
            None
        };
        self.limits.fill_rows(c1, c2, torque, out)
    }

    /// The state of the path coordinates at path parameter `s` with speed `sd` and
    /// acceleration `sdd`.
    fn state(&self, s: f64, sd: f64, sdd: f64) -> State {
        let n = self.names.len();
        let (mut q, mut qs, mut qss) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        self.path.eval(s, &mut q, &mut qs, &mut qss);
        let v = qs.iter().map(|d| d * sd).collect();
        let a = qs
            .iter()
            .zip(&qss)
            .map(|(d, dd)| d * sdd + dd * sd * sd)
            .collect();
        State { q, v, a }
    }

    /// The torques of the path coordinates by the RNEA at a state (the independent check).
    fn torques(&self, st: &State) -> Vec<f64> {
        let mut guard = self.scratch.borrow_mut();
        let sc = &mut *guard;
        self.model_q(&st.q, &mut sc.q);
        self.scatter(&st.v, &mut sc.qv);
        self.scatter(&st.a, &mut sc.qss);
        stance_robot::rnea(
            &self.model,
            &mut sc.data,
            &sc.q,
            &sc.qv,
            &sc.qss,
            self.gravity,
        )
        .expect("a valid configuration of the model");
        self.coordinates
            .iter()
            .map(|&k| sc.data.tau[self.model.joints[k].idx_v])
            .collect()
    }
}

impl ContinuousConstraints for JointProblem {
    fn num_rows(&self) -> usize {
        self.tags.len()
    }
    fn eval(&self, s: f64, out: &mut [Row]) {
        self.rows_at(s, out);
    }
}

fn resolve(base: Option<&Path>, p: &str) -> PathBuf {
    let path = Path::new(p);
    match base {
        Some(b) if path.is_relative() => b.join(path),
        _ => path.to_path_buf(),
    }
}

fn validate(spec: &JointPathSpec) -> Result<(), StanceError> {
    let bad = |m: String| Err(StanceError::BadMotion(m));
    if spec.waypoints.len() < 2 {
        return bad(format!(
            "waypoints has {} row(s); give at least 2 waypoints",
            spec.waypoints.len()
        ));
    }
    if !(2..=crate::tol::MAX_REFINED_GRID_POINTS).contains(&spec.grid_points) {
        return bad(format!(
            "grid_points is {}; give 2 to {}",
            spec.grid_points,
            crate::tol::MAX_REFINED_GRID_POINTS
        ));
    }
    for (what, v) in [("sd_start", spec.sd_start), ("sd_end", spec.sd_end)] {
        if !(v.is_finite() && v >= 0.0) {
            return bad(format!("{what} is {v}; give a finite path speed >= 0"));
        }
    }
    if !(spec.dt.is_finite() && spec.dt > 0.0) {
        return bad(format!("dt is {}; give a finite time step > 0", spec.dt));
    }
    if !(1..=crate::tol::MAX_SAMPLES_PER_INTERVAL).contains(&spec.samples_per_interval) {
        return bad(format!(
            "samples_per_interval is {}; give 1 to {}",
            spec.samples_per_interval,
            crate::tol::MAX_SAMPLES_PER_INTERVAL
        ));
    }
    if let FractionOrOff::Fraction(f) = spec.max_violation_fraction {
        if !(f.is_finite() && f > 0.0) {
            return bad(format!(
                "max_violation_fraction is {f}; give a fraction > 0 (e.g. 0.001) or false"
            ));
        }
    }
    if let Some(g) = spec.gravity.iter().find(|g| !g.is_finite()) {
        return bad(format!("gravity has {g}; give finite numbers (m/s^2)"));
    }
    Ok(())
}

/// The trajectory at the output time step.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointTrajectory {
    /// Times (s).
    pub t: Vec<f64>,
    /// Joint positions, one row per time, in the order of `joint_names` (rad or m).
    pub q: Vec<Vec<f64>>,
    /// Joint velocities.
    pub v: Vec<Vec<f64>>,
    /// Joint accelerations.
    pub a: Vec<Vec<f64>>,
    /// The joints.
    pub joint_names: Vec<String>,
}

/// The largest ratios to the limits over the output samples (independent of the rows; module
/// doc), and where.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LimitChecks {
    /// Samples checked.
    pub samples: usize,
    /// Largest `|v_j| / V_j` (0 without velocity limits).
    pub max_velocity_ratio: f64,
    /// Largest `|a_j| / A_j` (0 without acceleration limits).
    pub max_acceleration_ratio: f64,
    /// Largest `|tau_j| / T_j` (0 without torque limits).
    pub max_torque_ratio: f64,
    /// The joint and time of each largest ratio (`"velocity"`, `"acceleration"`, `"torque"`).
    pub worst: Vec<WorstSample>,
    /// Largest joint acceleration in absolute value (rad/s^2 or m/s^2), whatever the limits.
    pub max_abs_acceleration: f64,
}

/// Where a ratio is largest.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WorstSample {
    /// `velocity`, `acceleration` or `torque`.
    pub kind: &'static str,
    /// The joint.
    pub joint: String,
    /// The time (s).
    pub t: f64,
    /// The ratio.
    pub ratio: f64,
}

/// Why there is no profile, located and named.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointFailure {
    /// The grid point (from 0).
    pub grid_point: usize,
    /// Its path parameter.
    pub s: f64,
    /// The constraints that empty it, or bind next to it.
    pub constraints: Vec<String>,
    /// What it means and what to relax.
    pub reason: String,
}

/// The result of [`retime_joints`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointRetiming {
    /// `optimal`, or why there is no profile.
    pub status: Status,
    /// Duration (s) when optimal.
    pub duration: Option<f64>,
    /// The failure, when there is no profile.
    pub failure: Option<JointFailure>,
    /// The limits used, per joint (`null`: none of that kind).
    pub limits: Vec<JointLimitInfo>,
    /// Grid points (after refinement).
    pub grid_points: usize,
    /// The discretization.
    pub discretization: stance_topp::Discretization,
    /// Grid points bound by each kind of limit.
    pub binding: Binding,
    /// Largest excess over a limit between grid points (ratio to the limit minus one; `<= 0`:
    /// none), and where.
    pub between: Option<BetweenInfo>,
    /// What the refinement did.
    pub refinement: Option<crate::retime::Refinement>,
    /// The independent checks at the output samples.
    pub checks: Option<LimitChecks>,
    /// The phase plane: grid, `s'` and `s''`, times, controllable sets of `x = s'^2`.
    pub phase: JointPhase,
    /// The trajectory at `dt`.
    pub trajectory: Option<JointTrajectory>,
    /// Stage times.
    pub timings: JointTimings,
}

/// The phase plane of [`JointRetiming`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointPhase {
    /// Grid.
    pub s: Vec<f64>,
    /// `s'` at the grid points (empty without a profile).
    pub sd: Vec<f64>,
    /// `s''` per interval.
    pub sdd: Vec<f64>,
    /// Times at the grid points.
    pub t: Vec<f64>,
    /// Controllable sets `[lo, hi]` of `x = s'^2`.
    pub controllable_sets: Vec<Option<[f64; 2]>>,
    /// Feasible sets `[lo, hi]` of `x` at each grid point (the `x` for which some `s''`
    /// satisfies that point's limits).
    pub feasible_sets: Vec<Option<[f64; 2]>>,
}

/// The violation between grid points.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BetweenInfo {
    /// Largest row value: the largest ratio to a limit minus one.
    pub max_excess: f64,
    /// Where (path parameter).
    pub at_s: f64,
    /// Which limit.
    pub constraint: String,
}

/// Stage times (ms).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct JointTimings {
    /// Model, path and limits.
    pub t_setup_ms: f64,
    /// Rows on the grid (the inverse dynamics along the path).
    pub t_rows_ms: f64,
    /// Reachability analysis on the grid.
    pub t_topp_ms: f64,
    /// Refinement between grid points (solves and rows included).
    pub t_refine_ms: f64,
    /// Trajectory and checks.
    pub t_checks_ms: f64,
}

fn ms(d: std::time::Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// Retimes a joint path (module doc).
///
/// # Errors
///
/// [`StanceError`] for bad input (see [`JointProblem::new`]); an infeasible path is a result
/// whose status says so, with [`JointRetiming::failure`].
pub fn retime_joints(
    spec: &JointPathSpec,
    base_dir: Option<&Path>,
) -> Result<JointRetiming, StanceError> {
    let t0 = Instant::now();
    let problem = JointProblem::new(spec, base_dir)?;
    retime_problem(&problem, spec, t0)
}

/// [`retime_joints`] on a loaded problem (`t0`: when its setup started, for the timings).
pub fn retime_problem(
    problem: &JointProblem,
    spec: &JointPathSpec,
    t0: Instant,
) -> Result<JointRetiming, StanceError> {
    let t_setup = t0.elapsed();
    let grid = problem.uniform_grid(spec.grid_points);
    let opts = SolveOptions::new(spec.discretization)
        .with_start(spec.sd_start)
        .with_end(spec.sd_end);
    let t1 = Instant::now();
    let (mut k, mut velocity_joint) = constraints_on(problem, &grid)?;
    let t_rows = t1.elapsed();
    let t2 = Instant::now();
    let mut sol = Workspace::new().solve(&k, &opts)?;
    let t_topp = t2.elapsed();
    let mut refinement = None;
    let t3 = Instant::now();
    if let (FractionOrOff::Fraction(bound), Some(p)) = (
        spec.max_violation_fraction,
        sol.profile
            .as_ref()
            .filter(|_| sol.status == Status::Optimal),
    ) {
        let (rep, _) = check_between(p, problem, spec.samples_per_interval, 1.0);
        if rep.max_violation > bound {
            let rep = refine_until(
                problem,
                grid,
                &opts,
                bound,
                1.0,
                crate::tol::MAX_REFINED_GRID_POINTS,
                spec.samples_per_interval,
            )?;
            refinement = Some(crate::retime::Refinement {
                converged: rep.converged,
                rounds: rep.rounds,
                points_added: rep.points_added,
                elapsed_ms: ms(rep.elapsed),
            });
            (k, velocity_joint) = constraints_on(problem, &rep.grid)?;
            sol = rep.solution;
        }
    }
    let t_refine = t3.elapsed();
    let t4 = Instant::now();
    let profile = sol
        .profile
        .as_ref()
        .filter(|_| sol.status == Status::Optimal);
    let names = problem.joint_names();
    let origin = |i: usize, r: usize| {
        let mut tag = problem.tags[r];
        if tag.kind == LimitKind::Velocity {
            tag.coordinate = velocity_joint[i].unwrap_or(0);
        }
        RowOrigin::Limit(tag)
    };
    let mut binding = Binding::default();
    let (mut between, mut trajectory, mut checks) = (None, None, None);
    if let Some(p) = profile {
        for i in 0..k.num_points() {
            let u = p.u()[i.min(p.u().len() - 1)];
            let x = p.x()[i];
            binding.add_point(
                k.rows_at(i)
                    .iter()
                    .enumerate()
                    .filter(|(_, r)| binds(r, u, x))
                    .map(|(r, _)| origin(i, r)),
                names,
            );
        }
        let (rep, _) = check_between(p, problem, spec.samples_per_interval, 1.0);
        let mut tag_row = vec![Row::default(); problem.tags.len()];
        let vj = problem.rows_at(rep.at_s, &mut tag_row);
        let mut tag = problem.tags.get(rep.row).copied();
        if let Some(t) = tag.as_mut().filter(|t| t.kind == LimitKind::Velocity) {
            t.coordinate = vj.unwrap_or(0);
        }
        between = Some(BetweenInfo {
            max_excess: rep.max_violation,
            at_s: rep.at_s,
            constraint: tag.map_or(String::new(), |t| RowOrigin::Limit(t).describe(names)),
        });
        let (tr, ch) = trajectory_and_checks(problem, p, spec.dt)?;
        trajectory = Some(tr);
        checks = Some(ch);
    }
    let failure = match (sol.status, profile) {
        (Status::Optimal, Some(_)) => None,
        (status, _) => Some(explain(
            problem,
            &k,
            &velocity_joint,
            status,
            &sol.controllable,
            &opts,
        )),
    };
    let t_checks = t4.elapsed();
    Ok(JointRetiming {
        status: sol.status,
        duration: profile.map(Profile::duration),
        failure,
        limits: problem.limit_info.clone(),
        grid_points: k.num_points(),
        discretization: spec.discretization,
        binding,
        between,
        refinement,
        checks,
        phase: JointPhase {
            s: k.grid().to_vec(),
            sd: profile.map_or(Vec::new(), Profile::sd),
            sdd: profile.map_or(Vec::new(), |p| p.u().to_vec()),
            t: profile.map_or(Vec::new(), |p| p.times().to_vec()),
            controllable_sets: sol.controllable.clone(),
            feasible_sets: (0..k.num_points())
                .map(|i| crate::retime::feasible_set(&k, i, &opts.tol))
                .collect(),
        },
        trajectory,
        timings: JointTimings {
            t_setup_ms: ms(t_setup),
            t_rows_ms: ms(t_rows),
            t_topp_ms: ms(t_topp),
            t_refine_ms: ms(t_refine),
            t_checks_ms: ms(t_checks),
        },
    })
}

/// The rows on a grid, and the velocity row's joint at every point.
fn constraints_on(
    problem: &JointProblem,
    grid: &[f64],
) -> Result<(CanonicalConstraints, Vec<Option<usize>>), StanceError> {
    let m = problem.tags.len();
    let mut rows = vec![Row::default(); grid.len() * m];
    let velocity_joint: Vec<Option<usize>> = grid
        .iter()
        .zip(rows.chunks_mut(m.max(1)))
        .map(|(&s, out)| problem.rows_at(s, out))
        .collect();
    let offsets = (0..=grid.len()).map(|i| i * m).collect();
    Ok((
        CanonicalConstraints::new(grid.to_vec(), offsets, rows)?,
        velocity_joint,
    ))
}

/// The trajectory at `dt` and the independent checks (module doc).
fn trajectory_and_checks(
    problem: &JointProblem,
    p: &Profile,
    dt: f64,
) -> Result<(JointTrajectory, LimitChecks), StanceError> {
    let total = p.duration();
    let steps = (total / dt).floor();
    if steps > crate::tol::MAX_OUTPUT_SAMPLES as f64 {
        return Err(StanceError::BadMotion(format!(
            "dt {dt} s gives {steps} samples of the {total} s trajectory; give a dt of at least \
             {:.3e} s",
            total / crate::tol::MAX_OUTPUT_SAMPLES as f64
        )));
    }
    let mut times: Vec<f64> = (0..=steps as usize).map(|i| i as f64 * dt).collect();
    if total - times[times.len() - 1] > 1e-12 * total.max(1.0) {
        times.push(total);
    }
    let l = &problem.limits;
    let names = problem.joint_names();
    let mut tr = JointTrajectory {
        t: Vec::with_capacity(times.len()),
        q: Vec::with_capacity(times.len()),
        v: Vec::with_capacity(times.len()),
        a: Vec::with_capacity(times.len()),
        joint_names: names.to_vec(),
    };
    let mut worst: [(f64, usize, f64); 3] = [(0.0, 0, 0.0); 3];
    let mut max_abs_a = 0.0f64;
    for &t in &times {
        let smp = p.at(t);
        let st = problem.state(smp.s, smp.sd, smp.sdd);
        let tau = if l.any_torque() {
            problem.torques(&st)
        } else {
            Vec::new()
        };
        for j in 0..names.len() {
            max_abs_a = max_abs_a.max(st.a[j].abs());
            let ratios = [
                st.v[j].abs() / l.velocity[j],
                st.a[j].abs() / l.acceleration[j],
                tau.get(j).map_or(0.0, |x| x.abs() / l.torque[j]),
            ];
            for (w, r) in worst.iter_mut().zip(ratios) {
                if r > w.0 {
                    *w = (r, j, t);
                }
            }
        }
        tr.t.push(t);
        tr.q.push(st.q);
        tr.v.push(st.v);
        tr.a.push(st.a);
    }
    let kinds = ["velocity", "acceleration", "torque"];
    let checks = LimitChecks {
        samples: times.len(),
        max_velocity_ratio: worst[0].0,
        max_acceleration_ratio: worst[1].0,
        max_torque_ratio: worst[2].0,
        worst: worst
            .iter()
            .zip(kinds)
            .filter(|(w, _)| w.0 > 0.0)
            .map(|(w, kind)| WorstSample {
                kind,
                joint: names[w.1].clone(),
                t: w.2,
                ratio: w.0,
            })
            .collect(),
        max_abs_acceleration: max_abs_a,
    };
    Ok((tr, checks))
}

/// Names the constraints of a failure ([`crate::binding::explain`]).
fn explain(
    problem: &JointProblem,
    k: &CanonicalConstraints,
    velocity_joint: &[Option<usize>],
    status: Status,
    controllable: &[Option<[f64; 2]>],
    opts: &SolveOptions,
) -> JointFailure {
    let names = problem.joint_names();
    let mut origins = Vec::with_capacity(k.offsets()[k.num_points()]);
    for vj in velocity_joint {
        for t in &problem.tags {
            let mut t = *t;
            if t.kind == LimitKind::Velocity {
                t.coordinate = vj.unwrap_or(0);
            }
            origins.push(RowOrigin::Limit(t));
        }
    }
    let (i, constraints) = crate::binding::explain(
        k,
        &origins,
        names,
        status,
        controllable,
        opts.sd_end,
        &opts.tol,
        0,
    );
    let list = constraints.join(", ");
    let reason = match status {
        Status::FeasibleSetEmpty { .. } => format!(
            "no path acceleration keeps every limit at this point of the path, even at rest: \
             {list} cannot be met there; raise that limit or change the path"
        ),
        Status::ControllableSetEmpty { .. } => format!(
            "from grid point {i} no admissible speed profile reaches the end: {list} cannot all \
             hold there; raise that limit, lower sd_end, or slow the path down before it"
        ),
        Status::StartOutsideControllable { .. } => "the start speed sd_start is not reachable \
            under the limits: lower sd_start (or raise the limits)"
            .into(),
        other => format!("the solver stopped ({}): report it", other.name()),
    };
    JointFailure {
        grid_point: i,
        s: k.grid()[i],
        constraints,
        reason,
    }
}
