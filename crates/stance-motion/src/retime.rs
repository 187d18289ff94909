//! Retiming a CoM motion under contact stability (paper Section V, eq. 13-14).
//!
//! # Math
//!
//! A stance gives, once, the face form `U_stance` of its gravito-inertial wrench cone
//! (`U_stance w_GI <= 0`, wrench at the world origin; [`stance_contact::Stance::u_stance`]). Along
//! a CoM path `p(s)`, `p'' = p_s s'' + p_ss s'^2`, and for a whole-body motion the rate of the
//! angular momentum about the CoM is `L' = l1(s) s'' + l2(s) s'^2` (optional samples,
//! [`AngularSpec`]; `L' = 0` for the point-mass model), so the contact stability condition
//! becomes, with `u = s''` and `x = s'^2`, the rows
//!
//! ```text
//!     a(s) u + b(s) x + c(s) <= 0                                                     (13)
//!     a = -U (m p_s, m p x p_s + l1),  b = -U (m p_ss, m p x p_ss + l2),
//!     c = U (m g, m p x g)                                                            (14)
//! ```
//!
//! produced by [`stance_topp::factored`] and solved by reachability analysis
//! ([`stance_topp::Workspace::solve`]). The rows of unit-norm `U` are in newtons, so the largest row
//! value between grid points ([`stance_topp::between`]) is a violation in newtons, reported also
//! as a fraction of the weight `m |g|`; optionally the grid is refined until it is below a bound.
//!
//! The problem is solved in units where the mass and the gravity are of order one and the
//! answer mapped back (`retime/units.rs`): durations scale with the gravity and do not depend on
//! the mass, as physics says, over the whole range of doubles.
//!
//! The three timings of the paper's Tables I and II are reported: `t_u` (the GIWC face form),
//! `t_abc` (the rows) and `t_topp` (the solve).

use std::time::Instant;

use serde::{Deserialize, Serialize};
use stance_contact::{GiwcOptions, Scene};
use stance_topp::between::{check_between, refine_until, PathRows};
use stance_topp::lp2::{self, Box2, Lp2, Lp2Stats, StageLines};
use stance_topp::path::{AngularTerms, CubicSpline, PathCurve, Polyline, SplineEnds};
use stance_topp::{CanonicalConstraints, Profile, Solution, SolveOptions, Tolerances, Workspace};

use crate::name_or::NameOr;

mod units;
use crate::StanceError;

/// Where the scene of a motion comes from: a built-in example by name
/// (`stance_contact::examples::NAMES`) or a full scene.
///
/// Read from a string (a name) or a map (a scene, whose own error is reported: an untagged
/// enum would only say that the data matched no variant).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum SceneRef {
    /// A built-in example scene, e.g. `"box-climbing"`.
    Named(String),
    /// A scene given in full (the scene-file format).
    Inline(Box<Scene>),
}

impl<'de> Deserialize<'de> for SceneRef {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Ok(
            match NameOr::<Scene>::deserialize(
                d,
                "a built-in example name (string) or a scene (map)",
            )? {
                NameOr::Name(n) => SceneRef::Named(n),
                NameOr::Value(s) => SceneRef::Inline(Box::new(s)),
            },
        )
    }
}

impl SceneRef {
    /// The scene, or an error naming the known examples.
    ///
    /// ```
    /// use stance_motion::retime::SceneRef;
    /// assert!(SceneRef::Named("stairs".into()).scene().is_ok());
    /// assert!(SceneRef::Named("moon".into()).scene().is_err());
    /// ```
    pub fn scene(&self) -> Result<Scene, StanceError> {
        match self {
            SceneRef::Named(n) => stance_contact::examples::by_name(n).ok_or_else(|| {
                StanceError::unknown_name(n, "scene", &stance_contact::examples::NAMES, false)
            }),
            SceneRef::Inline(s) => Ok((**s).clone()),
        }
    }
}

/// How the CoM path interpolates its waypoints.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Interpolation {
    /// Straight segments (the paper's choice; `p_ss = 0` inside segments).
    Polyline,
    /// The C2 cubic spline through the waypoints, with zero end tangents (rest to rest).
    #[default]
    Spline,
}

/// The CoM path: waypoints at knots `s_k` (default `0, 1, .., K-1` scaled to `[0, 1]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PathSpec {
    /// CoM waypoints in world coordinates (m), at least two.
    #[serde(deserialize_with = "stance_contact::scene::strict::points3")]
    pub waypoints: Vec<[f64; 3]>,
    /// Path parameter at each waypoint (strictly increasing); default evenly spaced on `[0, 1]`.
    #[serde(default)]
    pub knots: Option<Vec<f64>>,
    /// Interpolation between waypoints (default: spline).
    #[serde(default)]
    pub interpolation: Interpolation,
}

pub use stance_topp::Discretization;

/// The facade's default discretization: interpolation (tighter between grid points).
pub(crate) fn interpolation() -> Discretization {
    Discretization::Interpolation
}

fn default_grid_points() -> usize {
    101
}
fn default_samples() -> usize {
    10
}

/// A CoM motion to retime in one stance: scene, CoM path, grid and boundary speeds (the `stance
/// retime` file; whole-body motions across stances are [`crate::MotionSpec`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ComMotionSpec {
    /// The stance (held during the whole motion).
    pub scene: SceneRef,
    /// The CoM path.
    pub path: PathSpec,
    /// Number of grid points `N + 1` (default 101).
    #[serde(default = "default_grid_points")]
    pub grid_points: usize,
    /// Path speed `s'` at the start (default 0).
    #[serde(default)]
    pub sd_start: f64,
    /// Path speed `s'` at the end (default 0).
    #[serde(default)]
    pub sd_end: f64,
    /// Discretization (default interpolation). Beware collocation with the default spline
    /// (zero tangent at both ends): the rows at `s_0` do not involve `s''`, so the first
    /// interval's acceleration is bounded only by the next grid point's speed and the profile
    /// bounces (measured on a 10 cm sway in double support at 101 points: `s'` goes 0, 2.2, 0
    /// over the first three points, and the contact wrench is violated by 23 % of the weight
    /// between grid points, as `between` reports; 4e-7 % with interpolation).
    #[serde(default = "interpolation")]
    pub discretization: Discretization,
    /// Refine the grid until the violation between grid points is below this fraction of the
    /// weight `m |g|` (e.g. 0.01); none by default (only measured).
    #[serde(default)]
    pub max_violation_fraction: Option<f64>,
    /// Samples per interval for the check between grid points (default 10).
    #[serde(default = "default_samples")]
    pub samples_per_interval: usize,
    /// Resample the retimed trajectory at this time step (s); none by default.
    #[serde(default)]
    pub dt: Option<f64>,
    /// Angular-momentum terms of a whole-body motion (`L' = l1 s'' + l2 s'^2`); none by default
    /// (point-mass model, `L' = 0`).
    #[serde(default)]
    pub angular_momentum: Option<AngularSpec>,
}

/// Samples of the angular-momentum terms `l1(s)`, `l2(s)` (about the CoM, world axes; docs/math.md
/// section 6: `l1 = A_g,ang q_s`, `l2 = A_g,ang q_ss + (dA_g,ang/ds) q_s`), linear between
/// samples. Units: N m s per unit of `s` (`l1`) and per unit of `s` squared (`l2`), so that
/// `l1 s'' + l2 s'^2` is in N m.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AngularSpec {
    /// Path parameters of the samples (strictly increasing, covering the path); default: the
    /// path's knots (one sample per waypoint).
    #[serde(default)]
    pub s: Option<Vec<f64>>,
    /// `l1` at each sample.
    #[serde(deserialize_with = "stance_contact::scene::strict::points3")]
    pub l1: Vec<[f64; 3]>,
    /// `l2` at each sample.
    #[serde(deserialize_with = "stance_contact::scene::strict::points3")]
    pub l2: Vec<[f64; 3]>,
}

/// A curve built from a [`PathSpec`].
#[derive(Debug, Clone)]
pub enum ComPath {
    /// Straight segments.
    Polyline(Polyline),
    /// Cubic spline.
    Spline(CubicSpline),
}

impl PathCurve for ComPath {
    fn domain(&self) -> [f64; 2] {
        match self {
            ComPath::Polyline(p) => p.domain(),
            ComPath::Spline(p) => p.domain(),
        }
    }
    fn eval(&self, s: f64) -> stance_topp::path::PathPoint {
        match self {
            ComPath::Polyline(p) => p.eval(s),
            ComPath::Spline(p) => p.eval(s),
        }
    }
}

impl PathSpec {
    /// The path curve (validates waypoints and knots).
    ///
    /// ```
    /// use stance_motion::retime::{Interpolation, PathSpec};
    /// use stance_topp::path::PathCurve;
    /// let spec = PathSpec { waypoints: vec![[0.0; 3], [0.1, 0.0, 0.0]], knots: None,
    ///     interpolation: Interpolation::Polyline };
    /// assert_eq!(spec.curve().unwrap().domain(), [0.0, 1.0]);
    /// ```
    pub fn curve(&self) -> Result<ComPath, StanceError> {
        if self.waypoints.len() < 2 {
            return Err(StanceError::BadMotion(format!(
                "path.waypoints has {} point(s); give at least 2 CoM waypoints",
                self.waypoints.len()
            )));
        }
        let knots = self.knots();
        Ok(match self.interpolation {
            Interpolation::Polyline => {
                ComPath::Polyline(Polyline::new(knots, self.waypoints.clone())?)
            }
            Interpolation::Spline => ComPath::Spline(CubicSpline::new(
                knots,
                self.waypoints.clone(),
                SplineEnds::Clamped {
                    start: [0.0; 3],
                    end: [0.0; 3],
                },
            )?),
        })
    }
}

impl PathSpec {
    /// The knots: as given, or evenly spaced on `[0, 1]`.
    ///
    /// ```
    /// use stance_motion::retime::{Interpolation, PathSpec};
    /// let spec = PathSpec { waypoints: vec![[0.0; 3]; 3], knots: None,
    ///     interpolation: Interpolation::Polyline };
    /// assert_eq!(spec.knots(), vec![0.0, 0.5, 1.0]);
    /// ```
    pub fn knots(&self) -> Vec<f64> {
        let n = self.waypoints.len();
        match &self.knots {
            Some(k) => k.clone(),
            None => (0..n).map(|i| i as f64 / (n.max(2) - 1) as f64).collect(),
        }
    }
}

/// The largest violation of the contact-stability rows between grid points.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Between {
    /// Largest row value (N; <= 0 means satisfied) over the finer grid.
    pub max_violation_newtons: f64,
    /// The same as a fraction of the weight `m |g|` (not a number, `null` in JSON, for a
    /// zero gravity).
    pub fraction_of_weight: f64,
    /// Path parameter where it occurs.
    pub at_s: f64,
}

/// What the optional refinement did.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Refinement {
    /// The violation is below the requested bound.
    pub converged: bool,
    /// Rounds of refine-and-resolve.
    pub rounds: usize,
    /// Grid points added.
    pub points_added: usize,
    /// Wall time of the refinement (ms).
    pub elapsed_ms: f64,
}

/// Timings of the three stages (ms), as in the paper's Tables I and II.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Timings {
    /// GIWC face form (`U_stance`).
    pub t_u_ms: f64,
    /// Rows `a, b, c` on the grid.
    pub t_abc_ms: f64,
    /// Reachability analysis.
    pub t_topp_ms: f64,
}

/// The retimed motion.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Retiming {
    /// Optimal, or the reason there is no profile (serialized as its name, `"optimal"`, ...).
    pub status: stance_topp::Status,
    /// The grid point of a failure.
    pub index: Option<usize>,
    /// The discretization that ran.
    pub discretization: Discretization,
    /// Duration (s) when optimal.
    pub duration: Option<f64>,
    /// Grid `s_i`.
    pub s: Vec<f64>,
    /// Path speed `s'` at the grid points (empty without a profile).
    pub sd: Vec<f64>,
    /// Path acceleration `s''` on each interval (empty without a profile).
    pub sdd: Vec<f64>,
    /// Time at the grid points (empty without a profile; one per grid point, infinite (`null`
    /// in JSON) after the interval where a stalled profile stops).
    pub t: Vec<f64>,
    /// CoM at the grid points.
    pub com: Vec<[f64; 3]>,
    /// Controllable sets `[lo, hi]` of `x = s'^2` (null where empty).
    pub controllable_sets: Vec<Option<[f64; 2]>>,
    /// Feasible sets `[lo, hi]` of `x = s'^2` at each grid point (null where empty): the `x` for
    /// which some `s''` satisfies the rows of that point.
    pub feasible_sets: Vec<Option<[f64; 2]>>,
    /// Rows per grid point (facets of `U_stance`).
    pub rows_per_point: usize,
    /// Whether the GIWC conversion certified its face form.
    pub giwc_certified: bool,
    /// Whether the profile reached the solver's speed box (`s'^2` = `tol.max_x`, 1e8): the rows
    /// leave the path speed unbounded there (for example a CoM path that does not move, or knots
    /// spanning a huge range of `s`), so the box, not contact stability, decided the duration.
    /// (The acceleration box is reached routinely where the path tangent vanishes, at the ends
    /// of a rest-to-rest spline, and is not reported.)
    pub speed_at_box: bool,
    /// Violation between grid points (of the final grid).
    pub between: Option<Between>,
    /// What the refinement did, when asked.
    pub refinement: Option<Refinement>,
    /// Resampled trajectory `[t, s, s', s'']` at the requested time step.
    pub samples: Vec<[f64; 4]>,
    /// Stage timings.
    pub timings: Timings,
}

/// The feasible set of `x` at one grid point: min and max `x` over `{(u, x) : rows <= 0}`
/// within the solver's bounding box and the point's bounds on `x` (two exact 2-variable LPs).
pub(crate) fn feasible_set(
    k: &CanonicalConstraints,
    i: usize,
    tol: &Tolerances,
) -> Option<[f64; 2]> {
    let lines = StageLines::from_rows(k.rows_at(i));
    let [x_lo, x_hi] = k.x_bounds_at(i);
    let bbox = Box2 {
        u_lo: -tol.max_u,
        u_hi: tol.max_u,
        x_lo: x_lo.max(0.0),
        x_hi: x_hi.min(tol.max_x),
    };
    let mut stats = Lp2Stats::default();
    let mut extreme =
        |dir: f64| match lp2::solve(&lines, bbox, [0.0, dir], [1.0, 0.0], &[], tol, &mut stats) {
            Lp2::Optimal { x, .. } => Some(x),
            Lp2::Infeasible => None,
        };
    Some([extreme(-1.0)?, extreme(1.0)?])
}

/// Retimes a motion: `U_stance` once, the rows of eq. 14 on the grid, reachability analysis,
/// the violation between grid points, and optionally a refinement of the grid.
///
/// ```
/// use stance_motion::retime::{retime, ComMotionSpec};
/// let spec: ComMotionSpec = serde_json::from_str(r#"{"scene": "double-support",
///     "path": {"waypoints": [[0.0, 0.05, 0.8], [0.0, -0.05, 0.8]]}}"#).unwrap();
/// let r = retime(&spec).unwrap();
/// assert_eq!(r.status, "optimal");
/// assert!(r.duration.unwrap() > 0.0);
/// ```
pub fn retime(spec: &ComMotionSpec) -> Result<Retiming, StanceError> {
    validate(spec)?;
    let scene = spec.scene.scene()?;
    let units = units::Units::of(scene.mass, scene.gravity);
    if units.is_identity() {
        return retime_in_units(spec, scene, 1.0);
    }
    let normalized = units.normalize(spec, &scene)?;
    let scene = normalized.scene.scene()?;
    Ok(units.restore(retime_in_units(&normalized, scene, units.time_unit())?))
}

/// [`retime`] in the units of `scene` (module [`units`]: mass and gravity of order one), whose
/// unit of time is `time_unit` seconds of the caller's (`spec.dt` is in the caller's seconds).
fn retime_in_units(
    spec: &ComMotionSpec,
    scene: Scene,
    time_unit: f64,
) -> Result<Retiming, StanceError> {
    let curve = spec.path.curve()?;
    let grid = uniform_grid(curve.domain(), spec.grid_points - 1);

    let t0 = Instant::now();
    let giwc = scene.stance()?.u_stance(&GiwcOptions::default())?;
    let t_u = t0.elapsed();
    if giwc.equations.nrows() > 0 {
        return Err(StanceError::BadMotion(format!(
            "the stance's GIWC is lower-dimensional ({} equation(s)); retiming needs a \
             full-dimensional GIWC (use surface contacts or more contacts)",
            giwc.equations.nrows()
        )));
    }
    let u = giwc.facet_rows();
    check_finite_path(&curve, &grid)?;
    let rows = path_rows(spec, &u, &curve, &scene)?;
    let t1 = Instant::now();
    let k = rows.factored_on_grid(grid.clone())?.to_constraints();
    let t_abc = t1.elapsed();

    let disc = spec.discretization;
    let opts = SolveOptions::new(disc)
        .with_start(spec.sd_start)
        .with_end(spec.sd_end);
    let mut ws = Workspace::new();
    let t2 = Instant::now();
    let sol = ws.solve(&k, &opts)?;
    let t_topp = t2.elapsed();

    let weight = scene.mass * scene.gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
    if spec.max_violation_fraction.is_some() && weight <= 0.0 {
        return Err(StanceError::BadMotion(format!(
            "max_violation_fraction is a fraction of the weight m |g|, but the scene's gravity \
             is {:?}; drop max_violation_fraction or give a non-zero gravity",
            scene.gravity
        )));
    }
    let (k_final, sol, refinement) = refine(spec, &rows, grid, &opts, weight, k, sol)?;

    let index = sol.status.grid_index();
    let speed_at_box = sol.profile.as_ref().is_some_and(|p| {
        p.x()
            .iter()
            .any(|&x| x >= opts.tol.max_x * (1.0 - stance_topp::tol::BOX_TOUCH))
    });
    let s_final = k_final.grid().to_vec();
    let com = s_final.iter().map(|&s| curve.eval(s).p).collect();
    let feasible_sets = (0..s_final.len())
        .map(|i| feasible_set(&k_final, i, &opts.tol))
        .collect();
    let (between, sd, sdd, t, samples) = match &sol.profile {
        Some(p) => profile_output(p, &rows, spec, weight, time_unit)?,
        None => (None, Vec::new(), Vec::new(), Vec::new(), Vec::new()),
    };
    Ok(Retiming {
        status: sol.status,
        index,
        discretization: disc,
        duration: sol.duration().filter(|d| d.is_finite()),
        s: s_final,
        sd,
        sdd,
        t,
        com,
        controllable_sets: sol.controllable.clone(),
        feasible_sets,
        rows_per_point: u.len(),
        giwc_certified: giwc.certified,
        speed_at_box,
        between,
        refinement,
        samples,
        timings: Timings {
            t_u_ms: t_u.as_secs_f64() * 1e3,
            t_abc_ms: t_abc.as_secs_f64() * 1e3,
            t_topp_ms: t_topp.as_secs_f64() * 1e3,
        },
    })
}

/// Stage 1: the options of a motion file, each in its range.
fn validate(spec: &ComMotionSpec) -> Result<(), StanceError> {
    if spec.grid_points < 2 {
        return Err(StanceError::BadMotion(format!(
            "grid_points is {}; give at least 2",
            spec.grid_points
        )));
    }
    for (what, v) in [("sd_start", spec.sd_start), ("sd_end", spec.sd_end)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(StanceError::BadMotion(format!(
                "{what} is {v}; give a finite path speed >= 0"
            )));
        }
    }
    if spec.grid_points > crate::tol::MAX_REFINED_GRID_POINTS {
        return Err(StanceError::BadMotion(format!(
            "grid_points is {}; give at most {} (or ask for max_violation_fraction to refine \
             only where needed)",
            spec.grid_points,
            crate::tol::MAX_REFINED_GRID_POINTS
        )));
    }
    if !(1..=crate::tol::MAX_SAMPLES_PER_INTERVAL).contains(&spec.samples_per_interval) {
        return Err(StanceError::BadMotion(format!(
            "samples_per_interval is {}; give 1 to {}",
            spec.samples_per_interval,
            crate::tol::MAX_SAMPLES_PER_INTERVAL
        )));
    }
    if let Some(dt) = spec.dt {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(StanceError::BadMotion(format!(
                "dt is {dt}; give a finite time step > 0"
            )));
        }
    }
    if let Some(bound) = spec.max_violation_fraction {
        if !(bound.is_finite() && bound > 0.0) {
            return Err(StanceError::BadMotion(format!(
                "max_violation_fraction is {bound}; give a finite fraction > 0 (e.g. 0.01)"
            )));
        }
    }
    Ok(())
}

/// Stage 2: `n` equal intervals of `[s0, s1]`, the last point exactly `s1`.
fn uniform_grid([s0, s1]: [f64; 2], n: usize) -> Vec<f64> {
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

/// Knots too close together (or waypoints too far apart) overflow the path's derivatives: say
/// so rather than report a non-finite row.
fn check_finite_path(curve: &ComPath, grid: &[f64]) -> Result<(), StanceError> {
    let [s0, s1] = curve.domain();
    for &s in [s0, s1].iter().chain(grid) {
        let q = curve.eval(s);
        if q.p
            .iter()
            .chain(&q.ps)
            .chain(&q.pss)
            .any(|v| !v.is_finite())
        {
            return Err(StanceError::BadMotion(format!(
                "the CoM path or its derivatives are not finite at s = {s}: the knots are too \
                 close together for the waypoints' distances; spread the knots (e.g. over [0, 1])"
            )));
        }
    }
    Ok(())
}

/// Stage 3: the rows of eq. 14 along the path (`U_stance` rows `u`, with the angular-momentum
/// terms when given).
fn path_rows(
    spec: &ComMotionSpec,
    u: &[[f64; 6]],
    curve: &ComPath,
    scene: &Scene,
) -> Result<PathRows<ComPath>, StanceError> {
    let mut rows = PathRows::new(u.to_vec(), curve.clone(), scene.mass, scene.gravity)?;
    if let Some(l) = &spec.angular_momentum {
        let knots = l.s.clone().unwrap_or_else(|| spec.path.knots());
        rows = rows.with_angular(AngularTerms::new(knots, l.l1.clone(), l.l2.clone())?)?;
    }
    Ok(rows)
}

/// Stage 5: with `max_violation_fraction` and a profile, the grid refined until the violation
/// between grid points is below that fraction of the weight; otherwise the first solve as it is.
fn refine(
    spec: &ComMotionSpec,
    rows: &PathRows<ComPath>,
    grid: Vec<f64>,
    opts: &SolveOptions,
    weight: f64,
    k: CanonicalConstraints,
    sol: Solution,
) -> Result<(CanonicalConstraints, Solution, Option<Refinement>), StanceError> {
    let (Some(bound), Some(_)) = (spec.max_violation_fraction, &sol.profile) else {
        return Ok((k, sol, None));
    };
    let rep = refine_until(
        rows,
        grid,
        opts,
        bound * weight,
        weight,
        crate::tol::MAX_REFINED_GRID_POINTS,
        spec.samples_per_interval,
    )?;
    let refinement = Refinement {
        converged: rep.converged,
        rounds: rep.rounds,
        points_added: rep.points_added,
        elapsed_ms: rep.elapsed.as_secs_f64() * 1e3,
    };
    Ok((rows.on_grid(rep.grid)?, rep.solution, Some(refinement)))
}

/// The error of a `dt` that gives too many samples over `duration` (both in the caller's
/// seconds).
fn too_many_samples(dt: f64, duration: f64) -> StanceError {
    let n = stance_topp::tol::MAX_RESAMPLE_POINTS;
    StanceError::BadMotion(format!(
        "dt: dt = {dt} s over a duration of {duration} s gives more than {n} samples; give dt >= \
         {:e} s",
        duration / (n as f64 - 2.0)
    ))
}

/// The output of a profile: violation between grid points, `s'`, `s''`, times, and the
/// trajectory resampled at `dt` when asked (a stalled profile, of infinite duration, has none).
#[allow(clippy::type_complexity)]
fn profile_output(
    p: &Profile,
    rows: &PathRows<ComPath>,
    spec: &ComMotionSpec,
    weight: f64,
    time_unit: f64,
) -> Result<(Option<Between>, Vec<f64>, Vec<f64>, Vec<f64>, Vec<[f64; 4]>), StanceError> {
    let (rep, _) = check_between(p, rows, spec.samples_per_interval, weight);
    let samples = match spec.dt {
        // (in the profile's units of time; an error in the caller's)
        Some(dt) if p.duration().is_finite() => p
            .resample(dt / time_unit)
            .map_err(|_| too_many_samples(dt, p.duration() * time_unit))?
            .iter()
            .map(|q| [q.t, q.s, q.sd, q.sdd])
            .collect(),
        _ => Vec::new(),
    };
    Ok((
        Some(Between {
            max_violation_newtons: rep.max_violation,
            fraction_of_weight: rep.fraction,
            at_s: rep.at_s,
        }),
        p.sd(),
        p.u().to_vec(),
        p.times().to_vec(),
        samples,
    ))
}
