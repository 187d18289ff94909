//! Joint-path files (JSON or TOML) for `stance retime-joints`: a fixed-base robot, a path
//! through joint waypoints, its limits and the solver's options. Strict like the other input
//! files: unknown keys and arrays of the wrong length are errors.
//!
//! ```text
//! urdf = "ur5.urdf"                  # path (relative to the file's folder); root fixed to the world
//! locked = { J = 0.0 }               # joints held at a value (rad or m; optional)
//! joints = ["J1", "J2", ...]         # the waypoints' columns (default: every movable joint, in
//!                                    #   the model's order); every movable joint is listed or locked
//! waypoints = [[q...], ...]          # at least 2 (rad or m; continuous joints: the angle)
//! knots = [s...]                     # path parameter of each waypoint (default evenly on [0, 1])
//! interpolation = "spline"           # or "polyline" (default "spline")
//! spline = "not-a-knot"              # or "natural", "clamped" (zero end tangents); SciPy's and
//!                                    #   toppra's SplineInterpolator's bc_type (default "not-a-knot")
//! gravity = [0, 0, -9.81]
//! grid_points = 101                  # N + 1
//! sd_start = 0.0                     # path speeds s' at the ends
//! sd_end = 0.0
//! discretization = "interpolation"   # or "collocation"
//! max_violation_fraction = 0.001     # refine the grid until no limit is exceeded by more than
//!                                    #   this fraction between grid points; false: solve on the
//!                                    #   grid as given (toppra's way)
//! samples_per_interval = 10          # for that check
//! dt = 0.01                          # output time step (s)
//! [limits]                           # see stance_motion::limits (velocity 1.0, torque 1.0 by default)
//! ```

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use stance_topp::Discretization;

use crate::limits::LimitsSpec;

/// How the waypoints are joined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum JointInterpolation {
    /// A C2 cubic spline per joint ([`SplineEnds`] at the ends).
    #[default]
    Spline,
    /// Straight segments (the path must stop at every interior waypoint: its tangent jumps).
    Polyline,
}

/// The ends of the spline (SciPy's `CubicSpline` `bc_type`, as toppra's `SplineInterpolator`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SplineEnds {
    /// Third derivative continuous at the second and the last but one waypoint.
    #[default]
    NotAKnot,
    /// Zero second derivative at the ends.
    Natural,
    /// Zero first derivative at the ends (the path starts and ends at rest in path terms).
    Clamped,
}

/// A fraction, or `false` for "off".
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(untagged)]
pub enum FractionOrOff {
    /// Off.
    Off,
    /// The fraction.
    Fraction(f64),
}

impl<'de> Deserialize<'de> for FractionOrOff {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Ok(match crate::limits::Scale::deserialize(d)? {
            crate::limits::Scale::Off => FractionOrOff::Off,
            crate::limits::Scale::Fraction(f) => FractionOrOff::Fraction(f),
        })
    }
}

fn default_refine() -> FractionOrOff {
    FractionOrOff::Fraction(1e-3)
}
fn default_grid_points() -> usize {
    101
}
fn default_samples() -> usize {
    10
}
fn default_dt() -> f64 {
    0.01
}
fn gravity() -> [f64; 3] {
    stance_contact::scene::STANDARD_GRAVITY
}

/// A joint-path file (module doc).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointPathSpec {
    /// The robot's URDF (relative paths: from the file's folder). Its root link is fixed to the
    /// world.
    pub urdf: String,
    /// Joints held at a value.
    #[serde(default)]
    pub locked: BTreeMap<String, f64>,
    /// The joints of the waypoints' columns (default: every movable joint in the model's order).
    #[serde(default)]
    pub joints: Option<Vec<String>>,
    /// The waypoints (one row per waypoint, one column per joint).
    pub waypoints: Vec<Vec<f64>>,
    /// Path parameter of each waypoint (default evenly spaced on `[0, 1]`).
    #[serde(default)]
    pub knots: Option<Vec<f64>>,
    /// Spline or polyline (default spline).
    #[serde(default)]
    pub interpolation: JointInterpolation,
    /// The spline's ends (default not-a-knot).
    #[serde(default)]
    pub spline: SplineEnds,
    /// Gravity (m/s^2; default `[0, 0, -9.81]`).
    #[serde(
        default = "gravity",
        deserialize_with = "stance_contact::scene::strict::vec3"
    )]
    pub gravity: [f64; 3],
    /// Grid points `N + 1` (default 101).
    #[serde(default = "default_grid_points")]
    pub grid_points: usize,
    /// Path speed at the start (default 0).
    #[serde(default)]
    pub sd_start: f64,
    /// Path speed at the end (default 0).
    #[serde(default)]
    pub sd_end: f64,
    /// Discretization (default interpolation).
    #[serde(default = "crate::retime::interpolation")]
    pub discretization: Discretization,
    /// Refinement between grid points: the largest excess over a limit, as a fraction of it
    /// (default 0.001), or `false` to solve on the grid as given.
    #[serde(default = "default_refine")]
    pub max_violation_fraction: FractionOrOff,
    /// Samples per interval of the check between grid points (default 10).
    #[serde(default = "default_samples")]
    pub samples_per_interval: usize,
    /// Output time step (s; default 0.01).
    #[serde(default = "default_dt")]
    pub dt: f64,
    /// Actuator limits (default: the URDF's velocity and effort limits).
    #[serde(default)]
    pub limits: LimitsSpec,
}
