//! Geometric paths `p(s)` in 3-D with their derivatives `p_s = dp/ds`, `p_ss = d^2p/ds^2`
//! (for the CoM path of paper eq. 14).
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
//!   tangents, for example zero to start or stop with the path tangent vanishing).
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
            let slope: Vec<f64> = (0..n - 1)
                .map(|k| (points[k + 1][d] - points[k][d]) / h[k])
                .collect();
            // Tridiagonal system: sub[k] M_{k-1} + diag[k] M_k + sup[k] M_{k+1} = rhs[k].
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
            if let SplineEnds::Clamped { start, end } = ends {
                diag[0] = 2.0 * h[0];
                sup[0] = h[0];
                rhs[0] = 6.0 * (slope[0] - start[d]);
                sub[n - 1] = h[n - 2];
                diag[n - 1] = 2.0 * h[n - 2];
                rhs[n - 1] = 6.0 * (end[d] - slope[n - 2]);
            }
            // Thomas algorithm (the system is diagonally dominant).
            for k in 1..n {
                let w = sub[k] / diag[k - 1];
                diag[k] -= w * sup[k - 1];
                rhs[k] -= w * rhs[k - 1];
            }
            m[n - 1][d] = rhs[n - 1] / diag[n - 1];
            for k in (0..n - 1).rev() {
                m[k][d] = (rhs[k] - sup[k] * m[k + 1][d]) / diag[k];
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
