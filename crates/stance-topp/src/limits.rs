//! Actuator limits as canonical rows: joint velocity, acceleration and torque (toppra's
//! `JointVelocityConstraint`, `JointAccelerationConstraint` and `JointTorqueConstraint`).
//!
//! # Math
//!
//! Along a joint path `q(s)` retimed as `s(t)`, with `u = s''` and `x = s'^2`, joint `j` moves at
//! `v_j = q_s,j s'` and accelerates at `a_j = q_s,j u + q_ss,j x`; its generalized force is
//! `tau_j = tau_a,j u + tau_b,j x + tau_c,j` with the inverse-dynamics coefficients along the
//! path (`tau_a = M q_s`, `tau_b = M q_ss + C(q, q_s) q_s`, `tau_c = g(q)`; the robot crate's
//! `torque_path_terms`). The limits `|v_j| <= V_j`, `|a_j| <= A_j`, `|tau_j| <= T_j` are then
//!
//! ```text
//!     x (q_s,j / V_j)^2 - 1 <= 0                             (a bound on x: only the tightest
//!                                                             joint gives a row)
//!     +-(q_s,j u + q_ss,j x) / A_j - 1 <= 0                  (two rows per joint)
//!     +-(tau_a,j u + tau_b,j x + tau_c,j) / T_j - 1 <= 0     (two rows per joint)
//! ```
//!
//! Each row is divided by its limit, so that its value is the ratio to the limit minus one
//! (the velocity row: the squared ratio minus one), unitless and `0` on the limit: a violation
//! between grid points reads the same whatever the path parameter's unit. Every point has the same rows ([`JointLimits::layout`]): a
//! joint whose path does not move it (`q_s,j = q_ss,j = 0`) gives the constant row `-1 <= 0`;
//! a torque row with `tau_a,j = tau_b,j = 0` is constant too, and violated when gravity alone
//! exceeds the limit (the grid point is then infeasible whatever the timing, and the solver
//! reports that point).
//!
//! A robot with a floating base has no actuator on its base: its base rows are not limited
//! here; they are balanced by contact forces (the caller's business: the contact-stability
//! rows, or the torque limits with the contact forces as unknowns).
//!
//! Every row carries a [`LimitTag`] (which kind, which coordinate, which side), so that a caller
//! can name the constraint that binds at a grid point, or that empties it.

use crate::constraints::Row;
use crate::error::ToppError;

/// Kind of an actuator limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LimitKind {
    /// Joint velocity.
    Velocity,
    /// Joint acceleration.
    Acceleration,
    /// Joint torque (or force, for a prismatic joint).
    Torque,
}

impl LimitKind {
    /// Machine-readable name.
    ///
    /// ```
    /// assert_eq!(stance_topp::limits::LimitKind::Torque.name(), "torque");
    /// ```
    pub fn name(&self) -> &'static str {
        match self {
            LimitKind::Velocity => "velocity",
            LimitKind::Acceleration => "acceleration",
            LimitKind::Torque => "torque",
        }
    }
}

/// Which limit a row enforces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct LimitTag {
    /// Velocity, acceleration or torque.
    pub kind: LimitKind,
    /// The coordinate (velocity index of the path's coordinates).
    pub coordinate: usize,
    /// The upper limit (`+V`, `+A`, `+T`) rather than the lower one.
    pub upper: bool,
}

/// Symmetric limits per coordinate: `|v_j| <= velocity[j]`, `|a_j| <= acceleration[j]`,
/// `|tau_j| <= torque[j]`; `f64::INFINITY` where a coordinate has no limit of that kind.
#[derive(Debug, Clone, PartialEq)]
pub struct JointLimits {
    /// Velocity limits (rad/s or m/s).
    pub velocity: Vec<f64>,
    /// Acceleration limits (rad/s^2 or m/s^2).
    pub acceleration: Vec<f64>,
    /// Torque limits (N m or N).
    pub torque: Vec<f64>,
}

impl JointLimits {
    /// No limits on `n` coordinates.
    ///
    /// ```
    /// let l = stance_topp::limits::JointLimits::none(3);
    /// assert!(l.velocity.iter().all(|v| v.is_infinite()));
    /// assert!(!l.any());
    /// ```
    pub fn none(n: usize) -> Self {
        Self {
            velocity: vec![f64::INFINITY; n],
            acceleration: vec![f64::INFINITY; n],
            torque: vec![f64::INFINITY; n],
        }
    }

    /// Number of coordinates.
    ///
    /// ```
    /// assert_eq!(stance_topp::limits::JointLimits::none(3).len(), 3);
    /// ```
    pub fn len(&self) -> usize {
        self.velocity.len()
    }

    /// Whether there are no coordinates.
    ///
    /// ```
    /// assert!(stance_topp::limits::JointLimits::none(0).is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether any limit is finite.
    ///
    /// ```
    /// let mut l = stance_topp::limits::JointLimits::none(2);
    /// l.torque[1] = 50.0;
    /// assert!(l.any());
    /// ```
    pub fn any(&self) -> bool {
        self.velocity
            .iter()
            .chain(&self.acceleration)
            .chain(&self.torque)
            .any(|v| v.is_finite())
    }

    /// Whether any torque limit is finite.
    ///
    /// ```
    /// let mut l = stance_topp::limits::JointLimits::none(2);
    /// assert!(!l.any_torque());
    /// l.torque[0] = 1.0;
    /// assert!(l.any_torque());
    /// ```
    pub fn any_torque(&self) -> bool {
        self.torque.iter().any(|v| v.is_finite())
    }

    /// Checks the shapes and values: every limit `> 0` (or infinite), none NaN.
    ///
    /// # Errors
    ///
    /// [`ToppError::Shape`] when the three vectors differ in length,
    /// [`ToppError::InvalidValue`] naming the coordinate of a limit `<= 0` or NaN.
    ///
    /// ```
    /// let mut l = stance_topp::limits::JointLimits::none(2);
    /// assert!(l.validate().is_ok());
    /// l.acceleration[1] = -1.0;
    /// assert!(l.validate().is_err());
    /// ```
    pub fn validate(&self) -> Result<(), ToppError> {
        let n = self.velocity.len();
        for (what, v) in [
            ("acceleration limits", &self.acceleration),
            ("torque limits", &self.torque),
        ] {
            if v.len() != n {
                return Err(ToppError::Shape {
                    what: format!("{what} (one per coordinate, as the velocity limits)"),
                    expected: n,
                    got: v.len(),
                });
            }
        }
        for (what, v) in [
            ("velocity limit", &self.velocity),
            ("acceleration limit", &self.acceleration),
            ("torque limit", &self.torque),
        ] {
            if let Some((j, x)) = v.iter().enumerate().find(|(_, x)| x.is_nan() || **x <= 0.0) {
                return Err(ToppError::InvalidValue {
                    what,
                    detail: format!(
                        "coordinate {j} has limit {x}; give a number > 0 (infinity for none)"
                    ),
                });
            }
        }
        Ok(())
    }
}

impl JointLimits {
    /// The rows' layout: which limit each row of [`JointLimits::fill_rows`] enforces, in order:
    /// the velocity row (when any velocity limit is finite; its coordinate is the tightest
    /// joint's, which [`JointLimits::fill_rows`] returns per point), then for every coordinate
    /// with an acceleration limit its upper and lower rows, then the same for torques.
    ///
    /// ```
    /// use stance_topp::limits::{JointLimits, LimitKind};
    /// let mut l = JointLimits::none(3);
    /// l.velocity[0] = 1.0;
    /// l.torque[2] = 10.0;
    /// let tags = l.layout();
    /// assert_eq!(tags.len(), 3);
    /// assert_eq!((tags[1].kind, tags[1].coordinate, tags[1].upper), (LimitKind::Torque, 2, true));
    /// ```
    pub fn layout(&self) -> Vec<LimitTag> {
        let mut tags = Vec::new();
        if self.velocity.iter().any(|v| v.is_finite()) {
            tags.push(LimitTag {
                kind: LimitKind::Velocity,
                coordinate: 0,
                upper: true,
            });
        }
        for (kind, lim) in [
            (LimitKind::Acceleration, &self.acceleration),
            (LimitKind::Torque, &self.torque),
        ] {
            for (j, l) in lim.iter().enumerate() {
                if l.is_finite() {
                    for upper in [true, false] {
                        tags.push(LimitTag {
                            kind,
                            coordinate: j,
                            upper,
                        });
                    }
                }
            }
        }
        tags
    }

    /// Writes the rows of one path point in the order of [`JointLimits::layout`] (module doc):
    /// `q_s`, `q_ss` of the coordinates, and the torque coefficients `[tau_a, tau_b, tau_c]`
    /// of the coordinates (required when a torque limit is finite). Returns the coordinate of
    /// the tightest velocity limit (`None` when no limited joint moves: the velocity row is
    /// then the constant `-1 <= 0`, as is the acceleration row of a joint that does not move).
    ///
    /// See [`JointLimits::fill_rows_on_step`] for a path whose `q_s` is linear between samples.
    ///
    /// ```
    /// use stance_topp::limits::JointLimits;
    /// use stance_topp::Row;
    /// let mut l = JointLimits::none(2);
    /// l.velocity = vec![1.0, 2.0];
    /// l.acceleration[0] = 4.0;
    /// let mut rows = vec![Row::default(); l.layout().len()];
    /// let tight = l.fill_rows(&[0.5, 4.0], &[1.0, 0.0], None, &mut rows);
    /// assert_eq!(tight, Some(1)); // (2 / 4)^2 < (1 / 0.5)^2
    /// // x (4 / 2)^2 - 1 <= 0, that is x <= 0.25
    /// assert_eq!((rows[0].b, rows[0].c), (4.0, -1.0));
    /// // at u = 2, x = 4 joint 0 accelerates at 0.5 * 2 + 1 * 4 = 5 against its limit 4
    /// assert_eq!(rows[1].value(2.0, 4.0), 5.0 / 4.0 - 1.0);
    /// ```
    pub fn fill_rows(
        &self,
        q_s: &[f64],
        q_ss: &[f64],
        torque: Option<[&[f64]; 3]>,
        out: &mut [Row],
    ) -> Option<usize> {
        self.fill_rows_on_step(q_s, None, q_ss, torque, out)
    }

    /// [`JointLimits::fill_rows`] for one side of a sample of a path whose `q_s` is linear
    /// between samples (and `q_ss` constant, as the IK integrates a whole-body path): the
    /// velocity row takes the larger `|q_s,j|` of the step's two ends (`q_s_other` is the other
    /// end's), so that with `x` bounded at both ends of the step, `|q_s,j(s)| s'(s) <= V_j` holds
    /// all along it (`|q_s,j|` and `x` are linear there, each at most its larger end value). The
    /// acceleration `q_s u + q_ss x` is linear along the step within a grid interval, so its
    /// rows at the ends bound it everywhere.
    ///
    /// ```
    /// use stance_topp::limits::JointLimits;
    /// use stance_topp::Row;
    /// let mut l = JointLimits::none(1);
    /// l.velocity = vec![1.0];
    /// let mut rows = vec![Row::default(); 1];
    /// l.fill_rows_on_step(&[0.5], Some(&[1.0]), &[0.0], None, &mut rows);
    /// assert_eq!(rows[0].b, 1.0); // (max(0.5, 1.0) / 1)^2
    /// ```
    pub fn fill_rows_on_step(
        &self,
        q_s: &[f64],
        q_s_other: Option<&[f64]>,
        q_ss: &[f64],
        torque: Option<[&[f64]; 3]>,
        out: &mut [Row],
    ) -> Option<usize> {
        let mut k = 0;
        let mut tight = None;
        if self.velocity.iter().any(|v| v.is_finite()) {
            // The tightest joint has the largest |q_s,j| / V_j.
            let mut worst = 0.0;
            for (j, (&d0, &v)) in q_s.iter().zip(&self.velocity).enumerate() {
                let d = q_s_other.map_or(d0.abs(), |o| d0.abs().max(o[j].abs()));
                if d == 0.0 || v.is_infinite() {
                    continue;
                }
                let r = d / v;
                if r > worst {
                    worst = r;
                    tight = Some(j);
                }
            }
            out[k] = match tight {
                None => CONSTANT,
                // x (q_s,j / V_j)^2 - 1 <= 0: unitless, like the other rows, so that its value
                // does not depend on the path parameter's unit
                Some(_) if (worst * worst).is_finite() => Row {
                    a: 0.0,
                    b: worst * worst,
                    c: -1.0,
                },
                // a ratio whose square overflows: the bound on x itself (0 or subnormal)
                Some(_) => Row {
                    a: 0.0,
                    b: 1.0,
                    c: -(1.0 / worst) * (1.0 / worst),
                },
            };
            k += 1;
        }
        let mut abs_rows = |coef: [f64; 3], lim: f64, k: &mut usize| {
            let (a, b, c) = (coef[0] / lim, coef[1] / lim, coef[2] / lim);
            out[*k] = Row { a, b, c: c - 1.0 };
            out[*k + 1] = Row {
                a: -a,
                b: -b,
                c: -c - 1.0,
            };
            *k += 2;
        };
        for (j, &lim) in self.acceleration.iter().enumerate() {
            if lim.is_finite() {
                abs_rows([q_s[j], q_ss[j], 0.0], lim, &mut k);
            }
        }
        if self.any_torque() {
            let [ta, tb, tc] = torque.expect("torque coefficients with a finite torque limit");
            for (j, &lim) in self.torque.iter().enumerate() {
                if lim.is_finite() {
                    abs_rows([ta[j], tb[j], tc[j]], lim, &mut k);
                }
            }
        }
        tight
    }
}

/// The row `0 u + 0 x - 1 <= 0`: always satisfied (the placeholder of a limit that does not
/// constrain a point, so that every point has the same layout).
const CONSTANT: Row = Row {
    a: 0.0,
    b: 0.0,
    c: -1.0,
};

#[cfg(test)]
mod tests {
    use super::*;

    /// Every row's value is the ratio to the limit minus one, for random states.
    #[test]
    fn row_values_are_ratios_minus_one() {
        let q_s = [0.3, -1.2, 0.0, 2.0];
        let q_ss = [1.5, 0.2, -0.7, 0.0];
        let ta = [1.0, -2.0, 0.5, 3.0];
        let tb = [0.2, 0.1, -0.4, 1.0];
        let tc = [5.0, -3.0, 0.0, 2.0];
        let mut l = JointLimits::none(4);
        l.acceleration = vec![2.0, 5.0, 1.0, f64::INFINITY];
        l.torque = vec![f64::INFINITY, 10.0, 4.0, 8.0];
        let tags = l.layout();
        assert_eq!(tags.len(), 12);
        let mut rows = vec![Row::default(); tags.len()];
        l.fill_rows(&q_s, &q_ss, Some([&ta, &tb, &tc]), &mut rows);
        for (u, x) in [(0.3, 1.7), (-2.0, 0.1), (0.0, 4.0)] {
            for (r, t) in rows.iter().zip(&tags) {
                let j = t.coordinate;
                let (v, lim) = match t.kind {
                    LimitKind::Acceleration => (q_s[j] * u + q_ss[j] * x, l.acceleration[j]),
                    LimitKind::Torque => (ta[j] * u + tb[j] * x + tc[j], l.torque[j]),
                    LimitKind::Velocity => unreachable!(),
                };
                let ratio = if t.upper { v } else { -v } / lim;
                assert!((r.value(u, x) - (ratio - 1.0)).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn validate_names_the_coordinate() {
        let mut l = JointLimits::none(3);
        l.torque[2] = f64::NAN;
        let e = l.validate().unwrap_err().to_string();
        assert!(
            e.contains("torque limit") && e.contains("coordinate 2"),
            "{e}"
        );
        l.torque.pop();
        assert!(l.validate().is_err());
    }
}
