//! Constraint violation between grid points, and grid refinement until it is small.
//!
//! # Math
//!
//! The solver enforces `a(s) u + b(s) x + c(s) <= 0` at the grid points only. On
//! `[s_i, s_{i+1}]` the profile has constant `u_i` and `x(s) = x_i + 2 (s - s_i) u_i` (exact),
//! so the continuous constraint can be evaluated at any `s` from functions `a(s)`, `b(s)`,
//! `c(s)` that the caller provides ([`ContinuousConstraints`]). [`check_between`] samples each
//! interval at `k` evenly spaced points (both ends included, each with the interval's own `u_i`,
//! so the left-side acceleration at a grid point is checked too) and reports the largest value,
//! in the rows' unit, and as a fraction of a scale the caller gives (for contact stability with
//! unit-norm GIWC rows: newtons, and the fraction of the weight `m |g|`).
//!
//! [`refine_until`] repeats: solve, check, bisect every interval whose violation exceeds the
//! bound, rebuild the rows on the new grid, until the bound holds or a point budget is spent.

use std::time::{Duration, Instant};

use crate::constraints::{CanonicalConstraints, Row};
use crate::error::ToppError;
use crate::factored::{eq14_vectors, FactoredRows};
use crate::path::{AngularTerms, PathCurve, PathPoint};
use crate::profile::Profile;
use crate::solver::{Solution, SolveOptions, Status, Workspace};

/// Constraints given as functions of the path parameter.
pub trait ContinuousConstraints {
    /// Number of rows (the same at every `s`).
    fn num_rows(&self) -> usize;
    /// Writes the rows at `s` into `out` (`num_rows()` entries).
    fn eval(&self, s: f64, out: &mut [Row]);
}

/// Eq. 14 rows `U w(s)` from a face matrix `U`, a CoM path, a mass and gravity (point-mass
/// model unless angular-momentum terms are given with [`PathRows::with_angular`]): a
/// [`ContinuousConstraints`] for contact stability. Rows are in newtons when `U` has unit-norm
/// rows.
#[derive(Debug, Clone)]
pub struct PathRows<P> {
    u: Vec<[f64; 6]>,
    path: P,
    mass: f64,
    gravity: [f64; 3],
    angular: Option<AngularTerms>,
}

impl<P: PathCurve> PathRows<P> {
    /// Checks and stores the data.
    ///
    /// ```
    /// use stance_topp::between::{ContinuousConstraints, PathRows};
    /// use stance_topp::path::Polyline;
    /// let path = Polyline::new(vec![0.0, 1.0], vec![[0.0; 3], [0.0, 0.0, 1.0]]).unwrap();
    /// let r = PathRows::new(vec![[0.0, 0.0, 1.0, 0.0, 0.0, 0.0]], path, 1.0, [0.0, 0.0, -9.81]).unwrap();
    /// let mut out = [stance_topp::Row::default()];
    /// r.eval(0.5, &mut out);
    /// assert_eq!((out[0].a, out[0].c), (-1.0, -9.81));
    /// ```
    pub fn new(u: Vec<[f64; 6]>, path: P, mass: f64, gravity: [f64; 3]) -> Result<Self, ToppError> {
        // Reuse the validation of the factored form on a 2-point grid.
        FactoredRows::from_path(&u, path.domain().to_vec(), &path, mass, gravity)?;
        Ok(Self {
            u,
            path,
            mass,
            gravity,
            angular: None,
        })
    }

    /// Adds the angular-momentum terms `L' = l1 s'' + l2 s'^2` (whole-body model); their knots
    /// must cover the path's domain.
    ///
    /// ```
    /// use stance_topp::between::{ContinuousConstraints, PathRows};
    /// use stance_topp::path::{AngularTerms, Polyline};
    /// let path = Polyline::new(vec![0.0, 1.0], vec![[0.0; 3], [0.0, 0.0, 1.0]]).unwrap();
    /// let l = AngularTerms::new(vec![0.0, 1.0], vec![[0.0, 2.0, 0.0]; 2], vec![[0.0; 3]; 2])
    ///     .unwrap();
    /// // Row on the torque about y: a = -U (m p_s, m p x p_s + l1) = -l1_y.
    /// let r = PathRows::new(vec![[0.0, 0.0, 0.0, 0.0, 1.0, 0.0]], path, 1.0, [0.0, 0.0, -9.81])
    ///     .unwrap()
    ///     .with_angular(l)
    ///     .unwrap();
    /// let mut out = [stance_topp::Row::default()];
    /// r.eval(0.5, &mut out);
    /// assert_eq!(out[0].a, -2.0);
    /// ```
    pub fn with_angular(mut self, angular: AngularTerms) -> Result<Self, ToppError> {
        let [p0, p1] = self.path.domain();
        let [l0, l1] = angular.domain();
        if l0 > p0 || l1 < p1 {
            return Err(ToppError::InvalidValue {
                what: "angular-momentum terms",
                detail: format!(
                    "their knots cover [{l0}, {l1}] but the path runs over [{p0}, {p1}]; give \
                     samples from the start to the end of the path"
                ),
            });
        }
        self.angular = Some(angular);
        Ok(self)
    }

    /// `[l1, l2]` at `s` (zero for the point-mass model).
    fn angular_at(&self, s: f64) -> [[f64; 3]; 2] {
        self.angular.as_ref().map_or([[0.0; 3]; 2], |l| l.eval(s))
    }

    /// The path.
    ///
    /// ```
    /// use stance_topp::between::PathRows;
    /// use stance_topp::path::{PathCurve, Polyline};
    /// let path = Polyline::new(vec![0.0, 2.0], vec![[0.0; 3], [1.0; 3]]).unwrap();
    /// let r = PathRows::new(vec![[1.0; 6]], path, 1.0, [0.0, 0.0, -9.81]).unwrap();
    /// assert_eq!(r.path().domain(), [0.0, 2.0]);
    /// ```
    pub fn path(&self) -> &P {
        &self.path
    }

    /// The rows on a grid, in factored form (for the solver).
    ///
    /// ```
    /// use stance_topp::between::PathRows;
    /// use stance_topp::path::Polyline;
    /// let path = Polyline::new(vec![0.0, 1.0], vec![[0.0; 3], [1.0; 3]]).unwrap();
    /// let r = PathRows::new(vec![[1.0; 6]], path, 1.0, [0.0, 0.0, -9.81]).unwrap();
    /// assert_eq!(r.on_grid(vec![0.0, 0.5, 1.0]).unwrap().num_points(), 3);
    /// ```
    pub fn on_grid(&self, s: Vec<f64>) -> Result<CanonicalConstraints, ToppError> {
        Ok(self.factored_on_grid(s)?.to_constraints())
    }

    /// The factored rows on a grid (the path and angular terms sampled at every grid point).
    ///
    /// ```
    /// use stance_topp::between::PathRows;
    /// use stance_topp::path::Polyline;
    /// let path = Polyline::new(vec![0.0, 1.0], vec![[0.0; 3], [1.0; 3]]).unwrap();
    /// let r = PathRows::new(vec![[1.0; 6]], path, 1.0, [0.0, 0.0, -9.81]).unwrap();
    /// assert_eq!(r.factored_on_grid(vec![0.0, 0.5, 1.0]).unwrap().num_rows(), 1);
    /// ```
    pub fn factored_on_grid(&self, s: Vec<f64>) -> Result<FactoredRows, ToppError> {
        let samples: Vec<PathPoint> = s.iter().map(|&si| self.path.eval(si)).collect();
        let angular: Option<Vec<[[f64; 3]; 2]>> = self
            .angular
            .as_ref()
            .map(|l| s.iter().map(|&si| l.eval(si)).collect());
        FactoredRows::from_samples(
            &self.u,
            s,
            &samples,
            self.mass,
            self.gravity,
            angular.as_deref(),
        )
    }
}

impl<P: PathCurve> ContinuousConstraints for PathRows<P> {
    fn num_rows(&self) -> usize {
        self.u.len()
    }

    fn eval(&self, s: f64, out: &mut [Row]) {
        let q = self.path.eval(s);
        let [l1, l2] = self.angular_at(s);
        let [wa, wb, wc] = eq14_vectors(&q, self.mass, self.gravity, l1, l2);
        let dot = |r: &[f64; 6], v: &[f64; 6]| r.iter().zip(v).map(|(a, b)| a * b).sum::<f64>();
        for (o, r) in out.iter_mut().zip(&self.u) {
            *o = Row {
                a: dot(r, &wa),
                b: dot(r, &wb),
                c: dot(r, &wc),
            };
        }
    }
}

/// Largest violation of the continuous constraint along a profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BetweenReport {
    /// Largest `a u + b x + c` found (rows' unit; `<= 0` means no violation seen).
    pub max_violation: f64,
    /// `max_violation / scale`.
    pub fraction: f64,
    /// Where: path parameter, interval index and row index.
    pub at_s: f64,
    /// Interval `[s_i, s_{i+1}]` of the worst sample.
    pub interval: usize,
    /// Row of the worst sample.
    pub row: usize,
    /// Number of points evaluated.
    pub samples: usize,
}

/// Largest violation on each interval (`per_interval[i]`) and overall, sampling every interval
/// at `samples_per_interval + 1` points (ends included). `scale` converts to a fraction (for
/// contact stability: `m |g|`).
///
/// ```
/// use stance_topp::between::{check_between, ContinuousConstraints};
/// use stance_topp::{Profile, Row};
/// // x <= 1 + s(1 - s) * 4: the profile x = 1 is feasible everywhere.
/// struct Bump;
/// impl ContinuousConstraints for Bump {
///     fn num_rows(&self) -> usize { 1 }
///     fn eval(&self, s: f64, out: &mut [Row]) { out[0] = Row { a: 0.0, b: 1.0, c: -1.0 - 4.0 * s * (1.0 - s) }; }
/// }
/// let p = Profile::from_states(vec![0.0, 1.0], vec![1.0, 1.0], vec![0.0]).unwrap();
/// let (r, per) = check_between(&p, &Bump, 10, 1.0);
/// assert!(r.max_violation <= 0.0 && per.len() == 1);
/// ```
pub fn check_between(
    profile: &Profile,
    cons: &impl ContinuousConstraints,
    samples_per_interval: usize,
    scale: f64,
) -> (BetweenReport, Vec<f64>) {
    let k = samples_per_interval.max(1);
    let s = profile.grid();
    let x = profile.x();
    let u = profile.u();
    let mut buf = vec![Row::default(); cons.num_rows()];
    let mut rep = BetweenReport {
        max_violation: f64::NEG_INFINITY,
        fraction: f64::NEG_INFINITY,
        at_s: s[0],
        interval: 0,
        row: 0,
        samples: 0,
    };
    let mut per = vec![f64::NEG_INFINITY; s.len() - 1];
    for i in 0..s.len() - 1 {
        for q in 0..=k {
            let si = if q == k {
                s[i + 1]
            } else {
                s[i] + (s[i + 1] - s[i]) * q as f64 / k as f64
            };
            let xi = (x[i] + 2.0 * (si - s[i]) * u[i]).max(0.0);
            cons.eval(si, &mut buf);
            rep.samples += 1;
            for (j, r) in buf.iter().enumerate() {
                let v = r.value(u[i], xi);
                per[i] = per[i].max(v);
                if v > rep.max_violation {
                    rep.max_violation = v;
                    rep.at_s = si;
                    rep.interval = i;
                    rep.row = j;
                }
            }
        }
    }
    rep.fraction = rep.max_violation / scale;
    (rep, per)
}

/// What [`refine_until`] did.
#[derive(Debug, Clone)]
pub struct RefineReport {
    /// The last solution (on the final grid).
    pub solution: Solution,
    /// The final grid.
    pub grid: Vec<f64>,
    /// Violation on the final grid.
    pub between: BetweenReport,
    /// Whether the bound holds at the end.
    pub converged: bool,
    /// Solve-check-bisect rounds run.
    pub rounds: usize,
    /// Grid points added.
    pub points_added: usize,
    /// Wall time of the whole refinement (solves, checks and row rebuilds).
    pub elapsed: Duration,
}

/// Solves on `grid`, then bisects the intervals whose sampled violation exceeds `bound` (rows'
/// unit; for contact stability, e.g. `0.01 m |g|`, see
/// [`crate::tol::DEFAULT_BETWEEN_GRID_FRACTION`]) and solves again, until the bound holds, the
/// retiming fails, or the grid would exceed `max_points`.
///
/// ```
/// use stance_topp::between::{refine_until, ContinuousConstraints};
/// use stance_topp::{Row, SolveOptions};
/// // u <= 2 - s: tighter along the path; collocation checks only the left end of each interval.
/// struct Ramp;
/// impl ContinuousConstraints for Ramp {
///     fn num_rows(&self) -> usize { 2 }
///     fn eval(&self, s: f64, out: &mut [Row]) {
///         out[0] = Row { a: 1.0, b: 0.0, c: -(2.0 - s) };
///         out[1] = Row { a: -1.0, b: 0.0, c: -2.0 };
///     }
/// }
/// let grid: Vec<f64> = (0..=4).map(|i| i as f64 / 4.0).collect();
/// let r = refine_until(&Ramp, grid, &SolveOptions::default(), 1e-3, 1.0, 1000, 8).unwrap();
/// assert!(r.converged && r.between.max_violation <= 1e-3 && r.points_added > 0);
/// ```
pub fn refine_until(
    cons: &impl ContinuousConstraints,
    grid: Vec<f64>,
    opts: &SolveOptions,
    bound: f64,
    scale: f64,
    max_points: usize,
    samples_per_interval: usize,
) -> Result<RefineReport, ToppError> {
    if !(bound.is_finite() && bound >= 0.0 && scale.is_finite() && scale > 0.0) {
        return Err(ToppError::InvalidValue {
            what: "refinement bound",
            detail: format!(
                "bound {bound} and scale {scale}: give a finite bound >= 0 and a finite scale > 0"
            ),
        });
    }
    let start = Instant::now();
    let n0 = grid.len();
    let mut grid = grid;
    let mut ws = Workspace::new();
    let m = cons.num_rows();
    let mut rounds = 0;
    loop {
        rounds += 1;
        let mut rows = Vec::with_capacity(grid.len() * m);
        let mut buf = vec![Row::default(); m];
        for &s in &grid {
            cons.eval(s, &mut buf);
            rows.extend_from_slice(&buf);
        }
        let offsets = (0..=grid.len()).map(|i| i * m).collect();
        let k = CanonicalConstraints::new(grid.clone(), offsets, rows)?;
        let solution = ws.solve(&k, opts)?;
        let done = |solution: Solution, between, converged, grid: Vec<f64>| RefineReport {
            points_added: grid.len() - n0,
            solution,
            grid,
            between,
            converged,
            rounds,
            elapsed: start.elapsed(),
        };
        let Some(profile) = solution
            .profile
            .as_ref()
            .filter(|_| solution.status == Status::Optimal)
        else {
            let nan = BetweenReport {
                max_violation: f64::NAN,
                fraction: f64::NAN,
                at_s: f64::NAN,
                interval: 0,
                row: 0,
                samples: 0,
            };
            return Ok(done(solution, nan, false, grid));
        };
        let (rep, per) = check_between(profile, cons, samples_per_interval, scale);
        let bad: Vec<usize> = (0..per.len()).filter(|&i| per[i] > bound).collect();
        if bad.is_empty() {
            return Ok(done(solution, rep, true, grid));
        }
        if grid.len() + bad.len() > max_points {
            return Ok(done(solution, rep, false, grid));
        }
        let mut next = Vec::with_capacity(grid.len() + bad.len());
        let mut bi = 0;
        for i in 0..grid.len() {
            next.push(grid[i]);
            if bi < bad.len() && bad[bi] == i {
                next.push(0.5 * (grid[i] + grid[i + 1]));
                bi += 1;
            }
        }
        grid = next;
    }
}
