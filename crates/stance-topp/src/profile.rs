//! The retimed motion: exact piecewise-constant-acceleration `s(t)`.
//!
//! # Math
//!
//! On `[s_i, s_{i+1}]` the path acceleration is the constant `u_i = (x_{i+1} - x_i) / (2 Delta_i)`
//! with `x = s'^2`, so `s'` is affine in time and the interval takes
//! `T_i = 2 Delta_i / (sqrt(x_i) + sqrt(x_{i+1}))` (exact, also when `x_i = 0` and `u_i > 0`).
//! When `x_i = x_{i+1} = 0` the interval is never traversed: `T_i = inf` (status `Stalled`).
//! Inside it, with `tau = t - t_i` and `sd_i = sqrt(x_i)`:
//! `s(t) = s_i + sd_i tau + u_i tau^2 / 2`, `s'(t) = sd_i + u_i tau`, `s''(t) = u_i`.

use crate::constraints::CanonicalConstraints;
use crate::error::ToppError;
use crate::solver::Discretization;

/// A time-parameterized profile on the grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    s: Vec<f64>,
    x: Vec<f64>,
    u: Vec<f64>,
    t: Vec<f64>,
}

/// One sample of the motion along the path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Time.
    pub t: f64,
    /// Path parameter `s(t)`.
    pub s: f64,
    /// Path speed `s'(t)`.
    pub sd: f64,
    /// Path acceleration `s''(t)`.
    pub sdd: f64,
}

impl Profile {
    /// Builds the profile from the grid (strictly increasing, at least 2 points), the states
    /// `x_i` (`N + 1`, finite, `>= 0`) and the controls `u_i` (`N`, finite), computing the times.
    /// `u` should satisfy `x_{i+1} = x_i + 2 Delta_i u_i` (the solver guarantees it; it is not
    /// re-checked here: the times use `x`, the closed form inside an interval uses `u`).
    ///
    /// # Errors
    ///
    /// [`ToppError`] when the shapes do not match or a value is not finite, negative (`x`) or
    /// out of order (`s`).
    ///
    /// ```
    /// use stance_topp::Profile;
    /// // From rest, u = 1 over s in [0, 0.5]: x_1 = 1, time 1.
    /// let p = Profile::from_states(vec![0.0, 0.5], vec![0.0, 1.0], vec![1.0]).unwrap();
    /// assert!((p.duration() - 1.0).abs() < 1e-15);
    /// assert!(Profile::from_states(vec![0.0], vec![0.0], vec![]).is_err());
    /// assert!(Profile::from_states(vec![0.0, 0.5], vec![0.0, -1.0], vec![1.0]).is_err());
    /// ```
    pub fn from_states(s: Vec<f64>, x: Vec<f64>, u: Vec<f64>) -> Result<Self, ToppError> {
        crate::constraints::check_grid(&s)?;
        for (what, got, expected) in [
            ("profile states x (one per grid point)", x.len(), s.len()),
            (
                "profile controls u (one per interval)",
                u.len(),
                s.len() - 1,
            ),
        ] {
            if got != expected {
                return Err(ToppError::Shape {
                    what: what.into(),
                    expected,
                    got,
                });
            }
        }
        for (what, v) in [("x", &x), ("u", &u)] {
            if let Some((i, &bad)) = v.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                return Err(ToppError::NotFinite {
                    what,
                    point: i,
                    row: 0,
                    value: bad,
                });
            }
        }
        if let Some((i, &bad)) = x.iter().enumerate().find(|(_, v)| **v < 0.0) {
            return Err(ToppError::InvalidValue {
                what: "x",
                detail: format!("x[{i}] = {bad} < 0; x = s'^2 is never negative"),
            });
        }
        Ok(Self::from_valid_states(s, x, u))
    }

    /// [`Self::from_states`] on data the solver produced (shapes and signs hold by construction).
    pub(crate) fn from_valid_states(s: Vec<f64>, x: Vec<f64>, u: Vec<f64>) -> Self {
        let mut t = Vec::with_capacity(s.len());
        t.push(0.0);
        for i in 0..s.len() - 1 {
            let den = x[i].max(0.0).sqrt() + x[i + 1].max(0.0).sqrt();
            let dt = if den > 0.0 {
                2.0 * (s[i + 1] - s[i]) / den
            } else {
                f64::INFINITY
            };
            t.push(t[i] + dt);
        }
        Self { s, x, u, t }
    }

    /// Grid `s_i`.
    ///
    /// ```
    /// # use stance_topp::Profile;
    /// let p = Profile::from_states(vec![0.0, 0.5], vec![0.0, 1.0], vec![1.0]).unwrap();
    /// assert_eq!(p.grid(), &[0.0, 0.5]);
    /// ```
    pub fn grid(&self) -> &[f64] {
        &self.s
    }

    /// States `x_i = s'(s_i)^2`.
    ///
    /// ```
    /// # use stance_topp::Profile;
    /// let p = Profile::from_states(vec![0.0, 0.5], vec![0.0, 1.0], vec![1.0]).unwrap();
    /// assert_eq!(p.x(), &[0.0, 1.0]);
    /// ```
    pub fn x(&self) -> &[f64] {
        &self.x
    }

    /// Controls `u_i = s''` on `[s_i, s_{i+1}]` (`N` values).
    ///
    /// ```
    /// # use stance_topp::Profile;
    /// let p = Profile::from_states(vec![0.0, 0.5], vec![0.0, 1.0], vec![1.0]).unwrap();
    /// assert_eq!(p.u(), &[1.0]);
    /// ```
    pub fn u(&self) -> &[f64] {
        &self.u
    }

    /// Times `t_i` at the grid points (`t_0 = 0`).
    ///
    /// ```
    /// # use stance_topp::Profile;
    /// let p = Profile::from_states(vec![0.0, 0.5], vec![0.0, 1.0], vec![1.0]).unwrap();
    /// assert_eq!(p.times()[1], 1.0);
    /// ```
    pub fn times(&self) -> &[f64] {
        &self.t
    }

    /// Path speeds `sqrt(x_i)`.
    ///
    /// ```
    /// # use stance_topp::Profile;
    /// let p = Profile::from_states(vec![0.0, 0.5], vec![0.0, 4.0], vec![4.0]).unwrap();
    /// assert_eq!(p.sd(), vec![0.0, 2.0]);
    /// ```
    pub fn sd(&self) -> Vec<f64> {
        self.x.iter().map(|x| x.max(0.0).sqrt()).collect()
    }

    /// Total duration (infinite when an interval is never traversed).
    ///
    /// ```
    /// # use stance_topp::Profile;
    /// let p = Profile::from_states(vec![0.0, 1.0], vec![0.0, 0.0], vec![0.0]).unwrap();
    /// assert!(p.duration().is_infinite());
    /// ```
    pub fn duration(&self) -> f64 {
        *self.t.last().expect("at least 2 grid points")
    }

    /// First interval with `x_i = x_{i+1} = 0` (infinite time), if any.
    ///
    /// ```
    /// # use stance_topp::Profile;
    /// let p = Profile::from_states(vec![0.0, 1.0, 2.0], vec![0.0, 2.0, 0.0], vec![1.0, -1.0]).unwrap();
    /// assert_eq!(p.first_stall(), None);
    /// ```
    pub fn first_stall(&self) -> Option<usize> {
        (0..self.t.len() - 1).find(|&i| !(self.t[i + 1] - self.t[i]).is_finite())
    }

    /// The exact state at time `t` (clamped to `[0, duration]`), by binary search on the grid
    /// times and the closed form inside the interval.
    ///
    /// ```
    /// # use stance_topp::Profile;
    /// // u = 1 from rest over [0, 0.5]: s(t) = t^2 / 2.
    /// let p = Profile::from_states(vec![0.0, 0.5], vec![0.0, 1.0], vec![1.0]).unwrap();
    /// let q = p.at(0.5);
    /// assert!((q.s - 0.125).abs() < 1e-15 && (q.sd - 0.5).abs() < 1e-15 && q.sdd == 1.0);
    /// ```
    pub fn at(&self, t: f64) -> Sample {
        let n = self.s.len();
        let t_end = self.duration();
        let t = if t_end.is_finite() {
            t.clamp(0.0, t_end)
        } else {
            t.max(0.0)
        };
        // Last i with t_i <= t (and i <= N - 1).
        let i = match self.t.partition_point(|&ti| ti <= t) {
            0 => 0,
            k => (k - 1).min(n - 2),
        };
        let tau = (t - self.t[i]).max(0.0);
        let sd_i = self.x[i].max(0.0).sqrt();
        let ui = self.u[i];
        let s = (self.s[i] + sd_i * tau + 0.5 * ui * tau * tau).min(self.s[i + 1]);
        let sd = (sd_i + ui * tau).max(0.0);
        Sample { t, s, sd, sdd: ui }
    }

    /// The time at which the motion reaches the path parameter `s` (clamped to the grid), the
    /// inverse of [`Self::at`]: inside interval `i`, `s = s_i + s'_i tau + u_i tau^2 / 2`, so
    /// `tau = 2 (s - s_i) / (s'_i + sqrt(s'_i^2 + 2 u_i (s - s_i)))` (no cancellation). Infinite
    /// where the interval is never traversed.
    ///
    /// ```
    /// # use stance_topp::Profile;
    /// // u = 1 from rest over [0, 0.5]: s(t) = t^2 / 2, reached at t = sqrt(2 s).
    /// let p = Profile::from_states(vec![0.0, 0.5], vec![0.0, 1.0], vec![1.0]).unwrap();
    /// assert!((p.time_at(0.125) - 0.5).abs() < 1e-15);
    /// assert!((p.at(p.time_at(0.3)).s - 0.3).abs() < 1e-15);
    /// assert_eq!((p.time_at(-1.0), p.time_at(0.5)), (0.0, 1.0));
    /// ```
    pub fn time_at(&self, s: f64) -> f64 {
        let n = self.s.len();
        let s = s.clamp(self.s[0], self.s[n - 1]);
        let i = match self.s.partition_point(|&si| si <= s) {
            0 => 0,
            k => (k - 1).min(n - 2),
        };
        let d = s - self.s[i];
        if d <= 0.0 {
            return self.t[i];
        }
        if s >= self.s[i + 1] {
            return self.t[i + 1];
        }
        let sd = self.x[i].max(0.0).sqrt();
        let root = (sd * sd + 2.0 * self.u[i] * d).max(0.0).sqrt();
        let tau = 2.0 * d / (sd + root);
        self.t[i] + tau.min(self.t[i + 1] - self.t[i])
    }

    /// Samples the motion every `dt` from 0 to the duration (the end point included).
    ///
    /// # Errors
    ///
    /// [`ToppError::InvalidValue`] when `dt` is not a positive finite number, the duration is
    /// infinite (a stalled profile), or the samples would exceed
    /// [`crate::tol::MAX_RESAMPLE_POINTS`] (give a larger `dt`).
    ///
    /// ```
    /// # use stance_topp::Profile;
    /// let p = Profile::from_states(vec![0.0, 0.5], vec![0.0, 1.0], vec![1.0]).unwrap();
    /// let v = p.resample(0.25).unwrap();
    /// assert_eq!(v.len(), 5);
    /// assert!((v[4].s - 0.5).abs() < 1e-15);
    /// assert!(p.resample(0.0).is_err() && p.resample(1e-300).is_err());
    /// ```
    pub fn resample(&self, dt: f64) -> Result<Vec<Sample>, ToppError> {
        let t_end = self.duration();
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(ToppError::InvalidValue {
                what: "time step",
                detail: format!("dt = {dt}; give a finite time step > 0"),
            });
        }
        if !t_end.is_finite() {
            return Err(ToppError::InvalidValue {
                what: "time step",
                detail: "the profile stalls (infinite duration): there is nothing to resample"
                    .into(),
            });
        }
        let steps = (t_end / dt).floor();
        if steps + 2.0 > crate::tol::MAX_RESAMPLE_POINTS as f64 {
            return Err(ToppError::InvalidValue {
                what: "time step",
                detail: format!(
                    "dt = {dt} s over a duration of {t_end} s gives more than {} samples; give \
                     dt >= {:e}",
                    crate::tol::MAX_RESAMPLE_POINTS,
                    t_end / (crate::tol::MAX_RESAMPLE_POINTS - 2) as f64
                ),
            });
        }
        let steps = steps as usize;
        let mut out: Vec<Sample> = (0..=steps).map(|k| self.at(k as f64 * dt)).collect();
        if out.last().is_some_and(|q| q.t < t_end) {
            out.push(self.at(t_end));
        }
        Ok(out)
    }

    /// Residuals of every row: `a u + b x + c` (in the rows' own unit; `<= 0` means
    /// satisfied). For collocation, row `j` of grid point `i < N` is evaluated at `(u_i, x_i)`
    /// and at `i = N` at `(u_{N-1}, x_N)` (the acceleration actually applied on arrival, which
    /// collocation does not constrain); for interpolation, `left` also holds the rows of grid
    /// point `i + 1` at `(u_i, x_{i+1})`.
    ///
    /// ```
    /// use stance_topp::{solve, CanonicalConstraints, Discretization, Row, SolveOptions};
    /// let rows = vec![Row { a: 1.0, b: 0.0, c: -1.0 }, Row { a: -1.0, b: 0.0, c: -1.0 }];
    /// let s: Vec<f64> = (0..=10).map(|i| i as f64 / 10.0).collect();
    /// let offsets: Vec<usize> = (0..=11).map(|i| 2 * i).collect();
    /// let k = CanonicalConstraints::new(s, offsets, rows.repeat(11)).unwrap();
    /// let sol = solve(&k, &SolveOptions::default()).unwrap();
    /// let r = sol.profile.unwrap().residuals(&k, Discretization::Collocation);
    /// assert!(r.max_normalized() < 1e-9);
    /// ```
    pub fn residuals(&self, k: &CanonicalConstraints, disc: Discretization) -> Residuals {
        let n = self.s.len();
        let mut at = Vec::with_capacity(k.rows().len());
        let mut left = Vec::new();
        for i in 0..n {
            let ui = self.u[i.min(n - 2)];
            at.extend(k.rows_at(i).iter().map(|r| r.value(ui, self.x[i])));
        }
        if disc == Discretization::Interpolation {
            for i in 1..n {
                let ui = self.u[i - 1];
                left.extend(k.rows_at(i).iter().map(|r| r.value(ui, self.x[i])));
            }
        }
        // Scaled to |(a, b)| = 1 (constant rows unscaled).
        let norm = |r: &crate::Row, v: f64| -> f64 {
            let nn = r.a.hypot(r.b);
            if nn > 0.0 {
                v / nn
            } else {
                v
            }
        };
        let mut max_norm = f64::NEG_INFINITY;
        let mut max_norm_collocated = f64::NEG_INFINITY;
        for i in 0..n {
            for (j, r) in k.rows_at(i).iter().enumerate() {
                let v = norm(r, at[k.offsets()[i] + j]);
                max_norm = max_norm.max(v);
                if i + 1 < n {
                    max_norm_collocated = max_norm_collocated.max(v);
                }
            }
        }
        if !left.is_empty() {
            let base = k.offsets()[1];
            for i in 1..n {
                for (j, r) in k.rows_at(i).iter().enumerate() {
                    let v = norm(r, left[k.offsets()[i] - base + j]);
                    max_norm = max_norm.max(v);
                    max_norm_collocated = max_norm_collocated.max(v);
                }
            }
        }
        Residuals {
            at,
            left,
            enforced_max: if disc == Discretization::Interpolation {
                max_norm
            } else {
                max_norm_collocated
            },
            all_max: max_norm,
        }
    }
}

/// Residuals of a profile (see [`Profile::residuals`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Residuals {
    /// `a u + b x + c` of every row, with the offsets of the constraints.
    pub at: Vec<f64>,
    /// Interpolation only: rows of grid point `i + 1` at `(u_i, x_{i+1})`, offsets shifted by
    /// one grid point (empty for collocation).
    pub left: Vec<f64>,
    /// Largest residual of a row scaled to `|(a, b)| = 1` among the rows the discretization
    /// enforces (unit `1/time^2`); `<= 0` up to round-off for a solver profile.
    pub enforced_max: f64,
    /// Largest scaled residual of all rows evaluated (collocation: including the end point).
    pub all_max: f64,
}

impl Residuals {
    /// [`Self::enforced_max`], the figure to compare with the solver tolerance.
    ///
    /// ```
    /// use stance_topp::Residuals;
    /// let r = Residuals { at: vec![], left: vec![], enforced_max: -1.0, all_max: 0.5 };
    /// assert_eq!(r.max_normalized(), -1.0);
    /// ```
    pub fn max_normalized(&self) -> f64 {
        self.enforced_max
    }
}
