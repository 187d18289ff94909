//! Thresholds of the simulator's measurements and verdict (each with its unit, default and
//! reason).

/// A planned contact carries load in the simulator when its normal force exceeds this fraction
/// of the weight `m |g|` (dimensionless). Default 0.01: a foot or hand touching without pushing
/// (about 6 N for JVRC-1) is not loaded; its slip is not measured then.
pub const SIM_LOAD: f64 = 0.01;

/// A planned contact is lost in the simulator when it is separated from its surface for longer
/// than this (s). Default 0.01 (ten 1 ms steps): soft contacts chatter for a step or two.
pub const SIM_LOSS_TIME: f64 = 0.01;

/// A planned contact is separated from its surface in the simulator beyond this distance (m).
/// Default 1 mm: soft contacts penetrate by about 1 to 2 mm under load, an unloaded one touches
/// within micrometres; a foot lifted or rocking on an edge is farther.
pub const SIM_SEPARATION: f64 = 1e-3;

/// Window around each stance change where losses and unplanned contacts are not counted (s).
/// Default 0.02: a landing foot may touch a few milliseconds early or late under tracking error.
pub const SIM_TRANSITION: f64 = 0.02;

/// Largest slip of a loaded planned contact for a motion to hold in the simulator (m). Default
/// 5 mm (the bound).
pub const SIM_MAX_SLIP: f64 = 5e-3;

/// The simulated robot fell when its base is this much below the reference's (m). Default
/// 0.25.
pub const SIM_FALL_HEIGHT: f64 = 0.25;

/// The simulated robot fell when its trunk is tilted this much from the reference's (rad).
/// Default 0.5 (about 29 degrees).
pub const SIM_FALL_TILT: f64 = 0.5;

/// Time simulated after the end of the reference, holding its last configuration (s). Default
/// 0.3: a motion that ends at rest but is about to fall falls within it.
pub const SIM_SETTLE: f64 = 0.3;

/// Longest motion the simulator is asked to play (s, after the time scale). Reason: bounded
/// work; MuJoCo runs JVRC-1 at about ten times real time here, so this is about ten seconds
/// of wall time, and a motion stretched past it (`--time-scale 1e-9` ran without end) is
/// refused with the time scale that fits.
pub const SIM_MAX_DURATION: f64 = 120.0;

/// Interval of the executed trajectory the report carries for the viewer (s of simulated time).
/// Default 0.02: the viewer's 50 frames per second (`stance_view::MAX_FRAME_RATE`).
pub const SIM_FRAME_DT: f64 = 0.02;

/// A simulation longer than this (s of simulated time, settling included) says so on the
/// progress channel before it starts (`SimOptions::progress`). Default 5 s: about half a second
/// of wall time for JVRC-1.
pub const SIM_PROGRESS_AFTER: f64 = 5.0;
