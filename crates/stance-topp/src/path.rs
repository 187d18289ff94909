//! Geometric paths `p(s)` with their derivatives `p_s = dp/ds`, `p_ss = d^2p/ds^2`: in 3-D for
//! the CoM path of paper eq. 14, in `n` dimensions for joint paths ([`WaypointPath`]).
//!
//! # Math
//!
//! - [`Polyline`]: straight segments between waypoints `P_k` at knots `s_k` (the paper's
//!   interpolation): `p_s = (P_{k+1} - P_k) / h_k` on segment `k`, `p_ss = 0` (the kinks at the
//!   knots are not differentiable: retime each segment apart, or use a spline).
//! - [`CubicSpline`]: the C2 cubic spline through the waypoints, with second derivatives `M_k`
//!   solving the tridiagonal system
//!   `h_{k-1} M_{k-1} + 2 (h_{k-1} + h_k) M_k + h_k M_{k+1} = 6 (d_k - d_{k-1})`,
//!   `d_k = (P_{k+1} - P_k) / h_k`, closed by natural ends (`M = 0`) or clamped ends (given
//!   tangents, for example zero to start or stop with the path tangent vanishing); joint paths
//!   also take not-a-knot ends (the third derivative continuous at the second and the last but
//!   one knot: SciPy's `CubicSpline` default, which toppra's `SplineInterpolator` uses).
//! - [`AngularTerms`]: the angular-momentum terms `l1(s)`, `l2(s)` of a whole-body motion
//!   (`L' = l1 s'' + l2 s'^2`, `L` about the CoM; docs/math.md section 6), sampled at knots and
//!   linear in between (zero for a point-mass model).

use crate::error::ToppError;

/// Position and derivatives at one path parameter.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PathPoint {
    /// `p(s)`.
    pub p: [f64; 3],
    /// `dp/ds`.
    pub ps: [f64; 3],
    /// `d^2 p / ds^2`.
    pub pss: [f64; 3],
}

/// A path `s -> p(s)` with derivatives, on the domain `[s_0, s_N]`.
pub trait PathCurve {
    /// Domain `[s_start, s_end]`.
    fn domain(&self) -> [f64; 2];
    /// Position and derivatives at `s` (clamped to the domain).
    fn eval(&self, s: f64) -> PathPoint;
}

fn check_waypoints(knots: &[f64], points: &[[f64; 3]]) -> Result<(), ToppError> {
    if knots.len() < 2 {
        return Err(ToppError::GridTooShort { got: knots.len() });
    }
    if points.len() != knots.len() {
        return Err(ToppError::Shape {
            what: "waypoints (one per knot)".into(),
            expected: knots.len(),
            got: points.len(),
        });
    }
    for (i, w) in knots.windows(2).enumerate() {
        if !(w[0].is_finite() && w[1].is_finite() && w[1] > w[0]) {
            return Err(ToppError::GridNotIncreasing {
                index: i + 1,
                value: w[1],
                prev_index: i,
                prev: w[0],
            });
        }
    }
    for (i, p) in points.iter().enumerate() {
        if let Some(v) = p.iter().find(|v| !v.is_finite()) {
            return Err(ToppError::NotFinite {
                what: "waypoint",
                point: i,
                row: 0,
                value: *v,
            });
        }
    }
    Ok(())
}

fn segment(knots: &[f64], s: f64) -> usize {
    knots
        .partition_point(|&k| k <= s)
        .saturating_sub(1)
        .min(knots.len() - 2)
}

/// Straight segments through waypoints.
#[derive(Debug, Clone, PartialEq)]
pub struct Polyline {
    knots: Vec<f64>,
    points: Vec<[f64; 3]>,
}

impl Polyline {
    /// The polyline through `points[k]` at `knots[k]` (strictly increasing).
    ///
    /// ```
    /// use stance_topp::path::{PathCurve, Polyline};
    /// let l = Polyline::new(vec![0.0, 1.0], vec![[0.0; 3], [2.0, 0.0, 0.0]]).unwrap();
    /// let q = l.eval(0.25);
    /// assert_eq!(q.p, [0.5, 0.0, 0.0]);
    /// assert_eq!(q.ps, [2.0, 0.0, 0.0]);
    /// assert!(Polyline::new(vec![0.0], vec![[0.0; 3]]).is_err());
    /// ```
    pub fn new(knots: Vec<f64>, points: Vec<[f64; 3]>) -> Result<Self, ToppError> {
        check_waypoints(&knots, &points)?;
        Ok(Self { knots, points })
    }
}

/// Angular-momentum terms `l1(s)`, `l2(s)` sampled at knots `s_k`, piecewise linear in between
/// and constant beyond the ends (see the module docs). Units: `L` in N m s, so `l1` and `l2`
/// in N m s per unit of `s` and per unit of `s` squared over time.
#[derive(Debug, Clone, PartialEq)]
pub struct AngularTerms {
    l1: Polyline,
    l2: Polyline,
}

impl AngularTerms {
    /// The terms `l1[k]`, `l2[k]` at `knots[k]` (strictly increasing, at least 2, finite).
    ///
    /// ```
    /// use stance_topp::path::AngularTerms;
    /// let l = AngularTerms::new(vec![0.0, 1.0], vec![[0.0; 3], [2.0, 0.0, 0.0]],
    ///     vec![[1.0; 3]; 2]).unwrap();
    /// assert_eq!(l.eval(0.25), [[0.5, 0.0, 0.0], [1.0; 3]]);
    /// assert_eq!(l.domain(), [0.0, 1.0]);
    /// assert!(AngularTerms::new(vec![0.0, 1.0], vec![[0.0; 3]; 2], vec![[0.0; 3]]).is_err());
    /// ```
    pub fn new(knots: Vec<f64>, l1: Vec<[f64; 3]>, l2: Vec<[f64; 3]>) -> Result<Self, ToppError> {
        for (what, got) in [
            ("angular-momentum term l1 (one per knot)", l1.len()),
            ("angular-momentum term l2 (one per knot)", l2.len()),
        ] {
            if got != knots.len() {
                return Err(ToppError::Shape {
                    what: what.into(),
                    expected: knots.len(),
                    got,
                });
            }
        }
        Ok(Self {
            l1: Polyline::new(knots.clone(), l1)?,
            l2: Polyline::new(knots, l2)?,
        })
    }

    /// Knot range `[s_0, s_K]`.
    ///
    /// ```
    /// use stance_topp::path::AngularTerms;
    /// let l = AngularTerms::new(vec![0.5, 2.0], vec![[0.0; 3]; 2], vec![[0.0; 3]; 2]).unwrap();
    /// assert_eq!(l.domain(), [0.5, 2.0]);
    /// ```
    pub fn domain(&self) -> [f64; 2] {
        self.l1.domain()
    }

    /// `[l1(s), l2(s)]`.
    ///
    /// ```
    /// use stance_topp::path::AngularTerms;
    /// let l = AngularTerms::new(vec![0.0, 1.0], vec![[0.0; 3], [0.0, 4.0, 0.0]],
    ///     vec![[0.0; 3]; 2]).unwrap();
    /// assert_eq!(l.eval(0.5)[0], [0.0, 2.0, 0.0]);
    /// assert_eq!(l.eval(7.0)[0], [0.0, 4.0, 0.0]); // constant beyond the ends
    /// ```
    pub fn eval(&self, s: f64) -> [[f64; 3]; 2] {
        [self.l1.eval(s).p, self.l2.eval(s).p]
    }
}

impl PathCurve for Polyline {
    fn domain(&self) -> [f64; 2] {
        [self.knots[0], *self.knots.last().expect("2 knots")]
    }

    fn eval(&self, s: f64) -> PathPoint {
        let [s0, s1] = self.domain();
        let s = s.clamp(s0, s1);
        let k = segment(&self.knots, s);
        let h = self.knots[k + 1] - self.knots[k];
        let t = s - self.knots[k];
        let mut q = PathPoint::default();
        for d in 0..3 {
            let slope = (self.points[k + 1][d] - self.points[k][d]) / h;
            q.p[d] = self.points[k][d] + slope * t;
            q.ps[d] = slope;
        }
        q
    }
}

/// How a [`CubicSpline`] ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SplineEnds {
    /// Zero second derivative at both ends.
    Natural,
    /// Given tangents `dp/ds` at the start and at the end (zero to make the tangent vanish).
    Clamped {
        /// Tangent at `s_0`.
        start: [f64; 3],
        /// Tangent at `s_N`.
        end: [f64; 3],
    },
}

/// How one coordinate of a cubic spline ends (the shared core of [`CubicSpline`] and
/// [`WaypointPath`]).
#[derive(Debug, Clone, Copy, PartialEq)]
enum End {
    /// Zero second derivative at both ends.
    Natural,
    /// The third derivative continuous at the second and the last but one knot (the first two
    /// and the last two pieces are one cubic each; SciPy's and toppra's default).
    NotAKnot,
    /// Given first derivatives at the start and at the end.
    Tangents(f64, f64),
}

/// `x` solving the tridiagonal system `sub[k] x[k-1] + diag[k] x[k] + sup[k] x[k+1] = rhs[k]`
/// (Thomas algorithm; `sub[0]` and `sup[n-1]` unused). The spline systems are diagonally
/// dominant (natural, clamped) or close to it (not-a-knot after eliminating the end unknowns).
fn tridiagonal(sub: &[f64], mut diag: Vec<f64>, sup: &[f64], mut rhs: Vec<f64>) -> Vec<f64> {
    let n = diag.len();
    for k in 1..n {
        let w = sub[k] / diag[k - 1];
        diag[k] -= w * sup[k - 1];
        rhs[k] -= w * rhs[k - 1];
    }
    let mut x = vec![0.0; n];
    x[n - 1] = rhs[n - 1] / diag[n - 1];
    for k in (0..n - 1).rev() {
        x[k] = (rhs[k] - sup[k] * x[k + 1]) / diag[k];
    }
    x
}

/// Second derivatives `M_k` at the knots of the C2 cubic spline through `values` with knot
/// spacings `h` (module doc), for one coordinate.
///
/// Interior rows: `h_{k-1} M_{k-1} + 2 (h_{k-1} + h_k) M_k + h_k M_{k+1} = 6 (d_k - d_{k-1})`.
/// Ends: natural `M_0 = M_N = 0`; tangents `t_0`, `t_N`: `2 h_0 M_0 + h_0 M_1 = 6 (d_0 - t_0)`
/// and `h_{N-1} M_{N-1} + 2 h_{N-1} M_N = 6 (t_N - d_{N-1})`; not-a-knot:
/// `(M_1 - M_0) / h_0 = (M_2 - M_1) / h_1` (and at the other end alike), solved by eliminating
/// `M_0` and `M_N` from the first and last interior rows. With 2 knots not-a-knot is the
/// straight line, with 3 the parabola through the points.
fn second_derivatives(h: &[f64], values: &[f64], end: End) -> Vec<f64> {
    let n = values.len();
    let slope: Vec<f64> = (0..n - 1)
        .map(|k| (values[k + 1] - values[k]) / h[k])
        .collect();
    if end == End::NotAKnot {
        if n == 2 {
            return vec![0.0; 2];
        }
        if n == 3 {
            let m = 2.0 * (slope[1] - slope[0]) / (h[0] + h[1]);
            return vec![m; 3];
        }
        // unknowns M_1 .. M_{n-2}
        let k = n - 2;
        let mut sub = vec![0.0; k];
        let mut diag = vec![0.0; k];
        let mut sup = vec![0.0; k];
        let mut rhs = vec![0.0; k];
        for r in 0..k {
            let i = r + 1;
            sub[r] = h[i - 1];
            diag[r] = 2.0 * (h[i - 1] + h[i]);
            sup[r] = h[i];
            rhs[r] = 6.0 * (slope[i] - slope[i - 1]);
        }
        // M_0 = ((h_0 + h_1) M_1 - h_0 M_2) / h_1 into the row of M_1
        diag[0] += h[0] * (h[0] + h[1]) / h[1];
        sup[0] -= h[0] * h[0] / h[1];
        // M_{n-1} = ((h_{n-3} + h_{n-2}) M_{n-2} - h_{n-2} M_{n-3}) / h_{n-3} into the last row
        let (a, b) = (h[n - 3], h[n - 2]);
        diag[k - 1] += b * (a + b) / a;
        sub[k - 1] -= b * b / a;
        let inner = tridiagonal(&sub, diag, &sup, rhs);
        let mut m = vec![0.0; n];
        m[1..n - 1].copy_from_slice(&inner);
        m[0] = ((h[0] + h[1]) * m[1] - h[0] * m[2]) / h[1];
        m[n - 1] = ((a + b) * m[n - 2] - b * m[n - 3]) / a;
        return m;
    }
    let mut sub = vec![0.0; n];
    let mut diag = vec![1.0; n];
    let mut sup = vec![0.0; n];
    let mut rhs = vec![0.0; n];
    for k in 1..n - 1 {
        sub[k] = h[k - 1];
        diag[k] = 2.0 * (h[k - 1] + h[k]);
        sup[k] = h[k];
        rhs[k] = 6.0 * (slope[k] - slope[k - 1]);
    }
    if let End::Tangents(start, end) = end {
        diag[0] = 2.0 * h[0];
        sup[0] = h[0];
        rhs[0] = 6.0 * (slope[0] - start);
        sub[n - 1] = h[n - 2];
        diag[n - 1] = 2.0 * h[n - 2];
        rhs[n - 1] = 6.0 * (end - slope[n - 2]);
    }
    tridiagonal(&sub, diag, &sup, rhs)
}

/// C2 cubic spline through waypoints.
#[derive(Debug, Clone, PartialEq)]
pub struct CubicSpline {
    knots: Vec<f64>,
    points: Vec<[f64; 3]>,
    /// Second derivatives at the knots.
    m: Vec<[f64; 3]>,
}

impl CubicSpline {
    /// The cubic spline through `points[k]` at `knots[k]` with the given ends.
    ///
    /// ```
    /// use stance_topp::path::{CubicSpline, PathCurve, SplineEnds};
    /// // Through 3 points of the parabola y = s^2 with its exact end tangents: reproduced.
    /// let sp = CubicSpline::new(
    ///     vec![0.0, 1.0, 2.0],
    ///     vec![[0.0; 3], [0.0, 1.0, 0.0], [0.0, 4.0, 0.0]],
    ///     SplineEnds::Clamped { start: [0.0; 3], end: [0.0, 4.0, 0.0] },
    /// )
    /// .unwrap();
    /// let q = sp.eval(1.5);
    /// assert!((q.p[1] - 2.25).abs() < 1e-12 && (q.ps[1] - 3.0).abs() < 1e-12);
    /// assert!((q.pss[1] - 2.0).abs() < 1e-12);
    /// ```
    pub fn new(
        knots: Vec<f64>,
        points: Vec<[f64; 3]>,
        ends: SplineEnds,
    ) -> Result<Self, ToppError> {
        check_waypoints(&knots, &points)?;
        if let SplineEnds::Clamped { start, end } = ends {
            if start.iter().chain(end.iter()).any(|v| !v.is_finite()) {
                return Err(ToppError::InvalidValue {
                    what: "spline end tangents",
                    detail: "end tangents must be finite".into(),
                });
            }
        }
        let n = knots.len();
        let h: Vec<f64> = knots.windows(2).map(|w| w[1] - w[0]).collect();
        let mut m = vec![[0.0; 3]; n];
        for d in 0..3 {
            let values: Vec<f64> = points.iter().map(|p| p[d]).collect();
            let end = match ends {
                SplineEnds::Natural => End::Natural,
                SplineEnds::Clamped { start, end } => End::Tangents(start[d], end[d]),
            };
            for (k, mk) in second_derivatives(&h, &values, end).into_iter().enumerate() {
                m[k][d] = mk;
            }
        }
        Ok(Self { knots, points, m })
    }
}

impl PathCurve for CubicSpline {
    fn domain(&self) -> [f64; 2] {
        [self.knots[0], *self.knots.last().expect("2 knots")]
    }

    fn eval(&self, s: f64) -> PathPoint {
        let [s0, s1] = self.domain();
        let s = s.clamp(s0, s1);
        let k = segment(&self.knots, s);
        let h = self.knots[k + 1] - self.knots[k];
        let (l, r) = (self.knots[k + 1] - s, s - self.knots[k]);
        let mut q = PathPoint::default();
        for d in 0..3 {
            let (m0, m1) = (self.m[k][d], self.m[k + 1][d]);
            let c0 = self.points[k][d] / h - m0 * h / 6.0;
            let c1 = self.points[k + 1][d] / h - m1 * h / 6.0;
            q.p[d] = (m0 * l * l * l + m1 * r * r * r) / (6.0 * h) + c0 * l + c1 * r;
            q.ps[d] = (-m0 * l * l + m1 * r * r) / (2.0 * h) - c0 + c1;
            q.pss[d] = (m0 * l + m1 * r) / h;
        }
        q
    }
}

/// How the coordinates of a [`WaypointPath`] are interpolated between its waypoints.
#[derive(Debug, Clone, PartialEq)]
pub enum Interpolation {
    /// Straight segments (`q_ss = 0`; the tangent jumps at interior waypoints, so a retiming
    /// must come to rest there for finite accelerations).
    Polyline,
    /// The C2 cubic spline with natural ends (zero second derivative).
    Natural,
    /// The C2 cubic spline with not-a-knot ends (SciPy's and toppra's `SplineInterpolator`
    /// default).
    NotAKnot,
    /// The C2 cubic spline with given tangents `dq/ds` at the start and the end (SciPy's and
    /// toppra's `"clamped"` is both zero).
    Clamped {
        /// Tangent at `s_0` (one entry per coordinate).
        start: Vec<f64>,
        /// Tangent at `s_N`.
        end: Vec<f64>,
    },
}

/// A path `s -> q(s)` in `n` dimensions through waypoints (a joint path): polyline or C2 cubic
/// spline per coordinate, with `q_s` and `q_ss` (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct WaypointPath {
    knots: Vec<f64>,
    /// Waypoints, one row per knot.
    points: Vec<Vec<f64>>,
    /// Second derivatives at the knots (spline), one row per knot; `None` for a polyline.
    m: Option<Vec<Vec<f64>>>,
}

impl WaypointPath {
    /// The path through `points[k]` at `knots[k]` (strictly increasing, at least 2; every point
    /// of the same length, finite).
    ///
    /// ```
    /// use stance_topp::path::{Interpolation, WaypointPath};
    /// // not-a-knot reproduces a cubic through 4 points
    /// let f = |s: f64| s * s * s - 2.0 * s;
    /// let knots = vec![0.0, 0.5, 1.5, 2.0];
    /// let pts = knots.iter().map(|&s| vec![f(s)]).collect();
    /// let p = WaypointPath::new(knots, pts, Interpolation::NotAKnot).unwrap();
    /// let (mut q, mut qs, mut qss) = ([0.0], [0.0], [0.0]);
    /// p.eval(1.2, &mut q, &mut qs, &mut qss);
    /// assert!((q[0] - f(1.2)).abs() < 1e-12 && (qss[0] - 6.0 * 1.2).abs() < 1e-12);
    /// ```
    pub fn new(
        knots: Vec<f64>,
        points: Vec<Vec<f64>>,
        interpolation: Interpolation,
    ) -> Result<Self, ToppError> {
        let dim = points.first().map_or(0, Vec::len);
        let flat: Vec<[f64; 3]> = points.iter().map(|_| [0.0; 3]).collect();
        check_waypoints(&knots, &flat)?;
        if dim == 0 {
            return Err(ToppError::InvalidValue {
                what: "waypoints",
                detail: "a waypoint has no coordinates; give one value per joint".into(),
            });
        }
        for (i, p) in points.iter().enumerate() {
            if p.len() != dim {
                return Err(ToppError::Shape {
                    what: format!("waypoint {i} (as many values as the first waypoint)"),
                    expected: dim,
                    got: p.len(),
                });
            }
            if let Some(v) = p.iter().find(|v| !v.is_finite()) {
                return Err(ToppError::NotFinite {
                    what: "waypoint",
                    point: i,
                    row: 0,
                    value: *v,
                });
            }
        }
        let h: Vec<f64> = knots.windows(2).map(|w| w[1] - w[0]).collect();
        let end = |d: usize| -> Result<Option<End>, ToppError> {
            Ok(match &interpolation {
                Interpolation::Polyline => None,
                Interpolation::Natural => Some(End::Natural),
                Interpolation::NotAKnot => Some(End::NotAKnot),
                Interpolation::Clamped { start, end } => {
                    if start.len() != dim || end.len() != dim {
                        return Err(ToppError::Shape {
                            what: "spline end tangents (one per coordinate)".into(),
                            expected: dim,
                            got: if start.len() != dim {
                                start.len()
                            } else {
                                end.len()
                            },
                        });
                    }
                    if !(start[d].is_finite() && end[d].is_finite()) {
                        return Err(ToppError::InvalidValue {
                            what: "spline end tangents",
                            detail: "end tangents must be finite".into(),
                        });
                    }
                    Some(End::Tangents(start[d], end[d]))
                }
            })
        };
        let m = if interpolation == Interpolation::Polyline {
            None
        } else {
            let mut m = vec![vec![0.0; dim]; knots.len()];
            for d in 0..dim {
                let values: Vec<f64> = points.iter().map(|p| p[d]).collect();
                let e = end(d)?.expect("a spline");
                for (k, mk) in second_derivatives(&h, &values, e).into_iter().enumerate() {
                    m[k][d] = mk;
                }
            }
            Some(m)
        };
        Ok(Self { knots, points, m })
    }

    /// Number of coordinates.
    ///
    /// ```
    /// use stance_topp::path::{Interpolation, WaypointPath};
    /// let p = WaypointPath::new(vec![0.0, 1.0], vec![vec![0.0; 6], vec![1.0; 6]],
    ///     Interpolation::Polyline).unwrap();
    /// assert_eq!(p.dim(), 6);
    /// ```
    pub fn dim(&self) -> usize {
        self.points[0].len()
    }

    /// Knot range `[s_0, s_N]`.
    ///
    /// ```
    /// use stance_topp::path::{Interpolation, WaypointPath};
    /// let p = WaypointPath::new(vec![0.5, 2.0], vec![vec![0.0], vec![1.0]],
    ///     Interpolation::Natural).unwrap();
    /// assert_eq!(p.domain(), [0.5, 2.0]);
    /// ```
    pub fn domain(&self) -> [f64; 2] {
        [self.knots[0], *self.knots.last().expect("2 knots")]
    }

    /// The knots.
    ///
    /// ```
    /// use stance_topp::path::{Interpolation, WaypointPath};
    /// let p = WaypointPath::new(vec![0.0, 1.0], vec![vec![0.0], vec![1.0]],
    ///     Interpolation::Polyline).unwrap();
    /// assert_eq!(p.knots(), &[0.0, 1.0]);
    /// ```
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// `q(s)`, `q_s(s)`, `q_ss(s)` into the three slices (length [`Self::dim`]); `s` is clamped
    /// to the domain. On a polyline, at an interior knot, the tangent of the segment that
    /// starts there.
    ///
    /// ```
    /// use stance_topp::path::{Interpolation, WaypointPath};
    /// let p = WaypointPath::new(vec![0.0, 2.0], vec![vec![0.0], vec![1.0]],
    ///     Interpolation::Polyline).unwrap();
    /// let (mut q, mut qs, mut qss) = ([0.0], [0.0], [0.0]);
    /// p.eval(1.0, &mut q, &mut qs, &mut qss);
    /// assert_eq!((q[0], qs[0], qss[0]), (0.5, 0.5, 0.0));
    /// ```
    pub fn eval(&self, s: f64, q: &mut [f64], q_s: &mut [f64], q_ss: &mut [f64]) {
        let [s0, s1] = self.domain();
        let s = s.clamp(s0, s1);
        let k = segment(&self.knots, s);
        let h = self.knots[k + 1] - self.knots[k];
        let (p0, p1) = (&self.points[k], &self.points[k + 1]);
        match &self.m {
            None => {
                let t = s - self.knots[k];
                for d in 0..self.dim() {
                    let slope = (p1[d] - p0[d]) / h;
                    q[d] = p0[d] + slope * t;
                    q_s[d] = slope;
                    q_ss[d] = 0.0;
                }
            }
            Some(m) => {
                let (l, r) = (self.knots[k + 1] - s, s - self.knots[k]);
                for d in 0..self.dim() {
                    let (m0, m1) = (m[k][d], m[k + 1][d]);
                    let c0 = p0[d] / h - m0 * h / 6.0;
                    let c1 = p1[d] / h - m1 * h / 6.0;
                    q[d] = (m0 * l * l * l + m1 * r * r * r) / (6.0 * h) + c0 * l + c1 * r;
                    q_s[d] = (-m0 * l * l + m1 * r * r) / (2.0 * h) - c0 + c1;
                    q_ss[d] = (m0 * l + m1 * r) / h;
                }
            }
        }
    }
}
