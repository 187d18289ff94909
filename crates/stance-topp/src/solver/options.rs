//! Options, outcomes and results of the solver.

use serde::Serialize;

use crate::error::ToppError;
use crate::profile::Profile;
use crate::tol::Tolerances;

/// How the continuous constraints are imposed on the grid (Pham and Pham, T-RO 2018, sec. VI).
/// In files: `"collocation"` or `"interpolation"` (the one type of the solver, the facade's
/// specs and the command line).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Discretization {
    /// The rows of grid point `i` constrain `(u_i, x_i)`.
    #[default]
    Collocation,
    /// First-order interpolation: also the rows of grid point `i + 1` evaluated at
    /// `(u_i, x_i + 2 Delta_i u_i)`, so each interval's constant acceleration satisfies the rows
    /// at both of its ends.
    Interpolation,
}

/// Read from a name only, so that anything else (a number, a list) gets a message with the two
/// names (a derived enum reader answers a number in JSON with "expected value").
impl<'de> serde::Deserialize<'de> for Discretization {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Name;
        impl serde::de::Visitor<'_> for Name {
            type Value = Discretization;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("\"collocation\" or \"interpolation\"")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Discretization, E> {
                match v {
                    "collocation" => Ok(Discretization::Collocation),
                    "interpolation" => Ok(Discretization::Interpolation),
                    _ => Err(E::unknown_variant(v, &["collocation", "interpolation"])),
                }
            }
        }
        d.deserialize_str(Name)
    }
}

impl Discretization {
    /// The name used in files: `"collocation"` or `"interpolation"`.
    ///
    /// ```
    /// use stance_topp::Discretization;
    /// assert_eq!(Discretization::Interpolation.name(), "interpolation");
    /// ```
    pub fn name(&self) -> &'static str {
        match self {
            Discretization::Collocation => "collocation",
            Discretization::Interpolation => "interpolation",
        }
    }
}

/// Options of [`crate::solve`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveOptions {
    /// Collocation or first-order interpolation.
    pub discretization: Discretization,
    /// Path speed `s'` at `s_0` (the state is `x_0 = sd_start^2`).
    pub sd_start: f64,
    /// Admissible interval of the path speed `s'` at `s_N` (`[v, v]` for a fixed end speed; the
    /// upper end may be `f64::INFINITY`). Squared like the start: `x_N in [lo^2, hi^2]`.
    pub sd_end: [f64; 2],
    /// Numerical thresholds.
    pub tol: Tolerances,
    /// Add the lines active at the previous stage first in each LP of the backward pass, and
    /// the previous step's limiting row first in each forward step (see [`crate::lp2`]). The
    /// answer does not depend on it; the time does (severalfold faster on the shared instances:
    /// `bench/peers/topp.md`).
    pub warm_start: bool,
}

impl Default for SolveOptions {
    fn default() -> Self {
        Self {
            discretization: Discretization::Collocation,
            sd_start: 0.0,
            sd_end: [0.0, 0.0],
            tol: Tolerances::default(),
            warm_start: true,
        }
    }
}

impl SolveOptions {
    /// Options for a rest-to-rest retiming with the given discretization.
    ///
    /// ```
    /// use stance_topp::{Discretization, SolveOptions};
    /// let o = SolveOptions::new(Discretization::Interpolation).with_start(0.5).with_end(1.0);
    /// assert_eq!(o.sd_end, [1.0, 1.0]);
    /// ```
    pub fn new(discretization: Discretization) -> Self {
        Self {
            discretization,
            ..Self::default()
        }
    }

    /// Sets the start speed `s'(s_0)`.
    ///
    /// ```
    /// use stance_topp::SolveOptions;
    /// assert_eq!(SolveOptions::default().with_start(2.0).sd_start, 2.0);
    /// ```
    pub fn with_start(mut self, sd_start: f64) -> Self {
        self.sd_start = sd_start;
        self
    }

    /// Sets a fixed end speed `s'(s_N)`.
    ///
    /// ```
    /// use stance_topp::SolveOptions;
    /// assert_eq!(SolveOptions::default().with_end(2.0).sd_end, [2.0, 2.0]);
    /// ```
    pub fn with_end(mut self, sd_end: f64) -> Self {
        self.sd_end = [sd_end, sd_end];
        self
    }

    /// Sets an interval of admissible end speeds `s'(s_N) in [lo, hi]`.
    ///
    /// ```
    /// use stance_topp::SolveOptions;
    /// let o = SolveOptions::default().with_end_interval(0.0, f64::INFINITY);
    /// assert_eq!(o.sd_end, [0.0, f64::INFINITY]);
    /// ```
    pub fn with_end_interval(mut self, lo: f64, hi: f64) -> Self {
        self.sd_end = [lo, hi];
        self
    }

    pub(crate) fn validate(&self) -> Result<(), ToppError> {
        if !self.sd_start.is_finite() || self.sd_start < 0.0 {
            return Err(ToppError::InvalidValue {
                what: "sd_start",
                detail: format!(
                    "{} is not a finite non-negative path speed; give s'(s_0) >= 0",
                    self.sd_start
                ),
            });
        }
        let [lo, hi] = self.sd_end;
        if !lo.is_finite() || lo < 0.0 || hi.is_nan() || hi < lo {
            return Err(ToppError::InvalidValue {
                what: "sd_end",
                detail: format!(
                    "[{lo}, {hi}] is not an interval of path speeds; give 0 <= lo <= hi (hi may be infinite)"
                ),
            });
        }
        let t = &self.tol;
        for (name, v) in [
            ("tol.zero_row", t.zero_row),
            ("tol.feasibility", t.feasibility),
            ("tol.parallel", t.parallel),
            ("tol.state", t.state),
            ("tol.max_u", t.max_u),
            ("tol.max_x", t.max_x),
        ] {
            if !v.is_finite() || v < 0.0 {
                return Err(ToppError::InvalidValue {
                    what: "tolerances",
                    detail: format!("{name} = {v}; every tolerance must be finite and >= 0"),
                });
            }
        }
        for (name, v) in [("tol.max_u", t.max_u), ("tol.max_x", t.max_x)] {
            if v > crate::tol::MAX_BOX {
                return Err(ToppError::InvalidValue {
                    what: "tolerances",
                    detail: format!(
                        "{name} = {v:e} exceeds {:e}; give a smaller bounding box",
                        crate::tol::MAX_BOX
                    ),
                });
            }
        }
        Ok(())
    }
}

/// Outcome of a retiming: success or the reason there is no profile. A value, never an error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Status {
    /// A time-optimal profile was found (finite duration).
    Optimal,
    /// No `(u, x)` satisfies the rows at grid point `index` (the smallest such index).
    FeasibleSetEmpty {
        /// Grid point.
        index: usize,
    },
    /// Every grid point has feasible states, but from grid point `index` no feasible sequence
    /// reaches the end interval: the backward pass found `K_index` empty.
    ControllableSetEmpty {
        /// Grid point.
        index: usize,
    },
    /// The start state `x_0 = sd_start^2` lies outside `K_0 = [lo, hi]`.
    StartOutsideControllable {
        /// The start state.
        x_start: f64,
        /// Lower end of `K_0`.
        lo: f64,
        /// Upper end of `K_0`.
        hi: f64,
    },
    /// The forward pass found no admissible acceleration at grid point `index` (only possible
    /// through round-off beyond `tol.state`; reported rather than hidden).
    ForwardPassFailed {
        /// Grid point.
        index: usize,
    },
    /// The profile stops on the interval `[s_index, s_index+1]` (`x = 0` at both ends): the path
    /// cannot be traversed in finite time (the duration is infinite).
    Stalled {
        /// First interval where it happens.
        index: usize,
    },
}

impl Status {
    /// Short machine-readable name (`"optimal"`, `"feasible_set_empty"`, ...).
    ///
    /// ```
    /// use stance_topp::Status;
    /// assert_eq!(Status::Optimal.name(), "optimal");
    /// assert_eq!(Status::Stalled { index: 3 }.name(), "stalled");
    /// ```
    pub fn name(&self) -> &'static str {
        match self {
            Status::Optimal => "optimal",
            Status::FeasibleSetEmpty { .. } => "feasible_set_empty",
            Status::ControllableSetEmpty { .. } => "controllable_set_empty",
            Status::StartOutsideControllable { .. } => "start_outside_controllable_set",
            Status::ForwardPassFailed { .. } => "forward_pass_failed",
            Status::Stalled { .. } => "stalled",
        }
    }

    /// The grid point where the failure was found (0 for a start state outside `K_0`), or
    /// `None` when optimal.
    ///
    /// ```
    /// use stance_topp::Status;
    /// assert_eq!(Status::Optimal.grid_index(), None);
    /// assert_eq!(Status::ControllableSetEmpty { index: 7 }.grid_index(), Some(7));
    /// assert_eq!(Status::StartOutsideControllable { x_start: 1.0, lo: 0.0, hi: 0.5 }.grid_index(), Some(0));
    /// ```
    pub fn grid_index(&self) -> Option<usize> {
        match *self {
            Status::FeasibleSetEmpty { index }
            | Status::ControllableSetEmpty { index }
            | Status::ForwardPassFailed { index }
            | Status::Stalled { index } => Some(index),
            Status::StartOutsideControllable { .. } => Some(0),
            Status::Optimal => None,
        }
    }
}

impl std::fmt::Display for Status {
    /// The machine-readable [`Status::name`].
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A status equals its machine-readable [`Status::name`]:
///
/// ```
/// use stance_topp::Status;
/// assert_eq!(Status::Optimal, "optimal");
/// assert_ne!(Status::Stalled { index: 3 }, "optimal");
/// ```
impl PartialEq<&str> for Status {
    fn eq(&self, name: &&str) -> bool {
        self.name() == *name
    }
}

/// Serialized as its [`Status::name`] (the grid point is a separate field of the results that
/// carry a status).
impl Serialize for Status {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// Work counters of a solve (to measure the warm start honestly).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SolveStats {
    /// Number of 2-variable LPs solved.
    pub lps: usize,
    /// Lines that moved the LP optimum (each costs a 1-D sub-problem).
    pub moves: usize,
    /// Line evaluations inside the 1-D sub-problems.
    pub inner_steps: usize,
    /// Rows a [`crate::Separation`] oracle added (cutting planes).
    pub cuts: usize,
}

/// Result of [`crate::solve`].
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// Success or the reason for failure.
    pub status: Status,
    /// The discretization that ran.
    pub discretization: Discretization,
    /// Controllable sets `K_i = [lo_i, hi_i]` of `x = s'^2` (`None` where the backward pass
    /// found the set empty or did not reach).
    pub controllable: Vec<Option<[f64; 2]>>,
    /// The profile, present when the forward pass ran to the end (statuses `Optimal` and
    /// `Stalled`).
    pub profile: Option<Profile>,
    /// Whether an LP optimum touched the bounding box `tol.max_x` / `tol.max_u` (the constraints
    /// then leave the speed or acceleration unbounded there).
    pub hit_box: bool,
    /// Work counters.
    pub stats: SolveStats,
    /// The cuts a separation oracle added, per grid point, in the caller's units (empty
    /// without an oracle; [`super::separation`]).
    pub cuts: super::separation::Cuts,
}

impl Solution {
    /// Duration of the profile (`None` without a profile, infinite when stalled).
    ///
    /// ```
    /// use stance_topp::{solve, CanonicalConstraints, Row, SolveOptions};
    /// // |u| <= 1 on s in [0, 1], rest to rest: accelerate then brake, duration 2.
    /// let rows = vec![Row { a: 1.0, b: 0.0, c: -1.0 }, Row { a: -1.0, b: 0.0, c: -1.0 }];
    /// let s: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
    /// let offsets: Vec<usize> = (0..=101).map(|i| 2 * i).collect();
    /// let k = CanonicalConstraints::new(s, offsets, rows.repeat(101)).unwrap();
    /// let sol = solve(&k, &SolveOptions::default()).unwrap();
    /// assert!((sol.duration().unwrap() - 2.0).abs() < 1e-9);
    /// ```
    pub fn duration(&self) -> Option<f64> {
        self.profile.as_ref().map(Profile::duration)
    }
}
