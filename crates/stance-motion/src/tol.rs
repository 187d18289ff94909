//! Thresholds of the motion pipeline, the retimings and their checks (each with its unit,
//! default and reason).

/// Largest grid (number of points) the refinement between grid points may build before it
/// stops unconverged. Unit: grid points. Default 20 000: a hundred times the paper's grids,
/// still solved in milliseconds; beyond it the violation is not a grid effect.
pub const MAX_REFINED_GRID_POINTS: usize = 20_000;

/// Largest number of samples per grid interval in the check between grid points. Unit:
/// samples. Default 100: the violation of smooth rows converges long before (10 is the
/// default); with [`MAX_REFINED_GRID_POINTS`] points and about 170 rows per point it bounds the
/// check to a few hundred million row evaluations (about a second), where a larger count from a
/// file would hang the command.
pub const MAX_SAMPLES_PER_INTERVAL: usize = 100;

/// Largest distance (m) of a robot surface's vertices from the plane of the environment surface
/// it is in contact with, at the start of a segment. Default 5 mm: the IK lands a link within a
/// fraction of a millimetre of its target (measured on the built-in motions); 5 mm accepts
/// that and rejects a link that did not land (a missing `onto`, a target out of reach).
pub const CONTACT_DISTANCE: f64 = 5e-3;

/// Largest angle (rad) between a contact's robot and environment normals. Default 0.05 rad
/// (about 3 degrees), for the same reason as [`CONTACT_DISTANCE`].
pub const CONTACT_ANGLE: f64 = 0.05;

/// Largest distance (m) of a robot surface's vertex outside its environment surface's polygon.
/// Default 5 mm, for the same reason as [`CONTACT_DISTANCE`].
pub const CONTACT_OUTSIDE: f64 = 5e-3;

/// Largest speed (m/s) of a landing link's frame when its contact is made: "arrives at zero
/// velocity" in practice. Default 1 mm/s: a tracking residual of the IK (the references
/// themselves land at rest), far below any impact that matters for a humanoid.
pub const LANDING_SPEED: f64 = 1e-3;

/// Largest angular speed (rad/s) of a landing link's frame when its contact is made. Default
/// 0.01 rad/s, for the same reason as [`LANDING_SPEED`].
pub const LANDING_ANGULAR_SPEED: f64 = 1e-2;

/// Weight of the base coordinates against the joints' in the standing-posture search
/// (dimensionless). Default 1e-3: the base moves freely to satisfy the contacts while the joints
/// stay close to the nominal posture.
pub const STAND_BASE_WEIGHT: f64 = 1e-3;

/// Damping of the standing-posture steps (dimensionless). Default 1e-10: keeps the step defined
/// at a singular configuration without biasing a regular one.
pub const STAND_DAMPING: f64 = 1e-10;

/// Convergence of the standing-posture search (m or rad). Default 1e-10: contacts exactly on their
/// surfaces to far below the contact tolerances.
pub const STAND_RESIDUAL: f64 = 1e-10;

/// Units in the last place of the largest target coordinate added to [`STAND_RESIDUAL`]: far
/// from the origin a position is only known to its last bits (at 1,000 km one unit is 1.2e-10 m,
/// more than the residual). Default 16.
pub const STAND_ULPS: f64 = 16.0;

/// A standing-posture search that fails with its CoM target farther than this from every
/// contact horizontally (m) says that the CoM is the likely cause. Default 0.5: farther than a
/// humanoid's leg can lean.
pub const STAND_FAR_COM: f64 = 0.5;

/// Residual (m or rad) below which the standing-posture search stops pulling towards the nominal
/// posture and polishes the contacts and the CoM alone. Default 1e-6: the pull is second order
/// in the step and would otherwise stall the residual near 1e-9 (measured on JVRC-1).
pub const STAND_POLISH: f64 = 1e-6;

/// Largest step of the standing-posture search (rad or m per coordinate). Default 0.2.
pub const STAND_MAX_STEP: f64 = 0.2;

/// Iterations of the standing-posture search. Default 200 (it converges in 10 to 30 from the
/// nominal posture on the built-in robots).
pub const STAND_MAX_ITERATIONS: usize = 200;

/// Largest number of retiming grid intervals per segment of a motion. Default 10 000 (the paper
/// uses 100); beyond it the IK's cost, not the answer, grows.
pub const MAX_MOTION_GRID: usize = 10_000;

/// Largest number of IK steps per retiming grid interval. Default 100.
pub const MAX_IK_SUBSTEPS: usize = 100;

/// Smallest output time step of a motion (s). Default 1e-4 (10 kHz; a 20 s motion then has
/// 200 000 samples).
pub const MIN_MOTION_DT: f64 = 1e-4;

/// Shortest move (path units). Default 1e-3: the IK gains are per unit of path (10 by default),
/// so a shorter move asks for accelerations the IK cannot follow.
pub const MIN_MOVE_DURATION: f64 = 1e-3;

/// Longest move (path units). Default 1e4.
pub const MAX_MOVE_DURATION: f64 = 1e4;

/// Range of the gravity's magnitude (m/s^2) of a whole-body motion. Default 0.01 to 1000: a
/// small moon to a hundred times the Earth's. Reason: the whole-body pipeline's thresholds
/// (IK residuals, landing speeds, the solver's speed box) are absolute in seconds, so unlike
/// the CoM retiming (solved in normalized units) it is not claimed across the range of doubles;
/// outside this range a motion is refused with it rather than answered wrongly. Zero gravity
/// is outside too (contact stability then has no weight to hold).
pub const MOTION_GRAVITY_RANGE: [f64; 2] = [1e-2, 1e3];

/// Rounds of the refinement between grid points of a motion's retiming (IK samples where the
/// rows do not hold become grid points, and the motion is solved again). Default 8: each round
/// adds only the violating samples; the built-in motions converge in 2 to 4.
pub const MAX_REFINE_ROUNDS: usize = 8;

/// A contact force below this fraction of the gravito-inertial force `|f_GI|` is zero in the
/// force check's friction usage (dimensionless). Default 1e-6: the supporting-forces QP meets its
/// equations to about 1e-9 relative; an unloaded contact's residual tangential force is
/// round-off, not friction.
pub const ZERO_FORCE: f64 = 1e-6;

/// A row binds at a grid point when its value is within this fraction of the size of its terms
/// (`|a u| + |b x| + |c|`) of zero ([`crate::binding`]). Dimensionless. Default 1e-6: the
/// reachability pass puts the profile on its binding rows to round-off (about 1e-12 relative),
/// while a row that is merely close (a limit not quite reached) is off by far more than 1e-6.
pub const BINDING: f64 = 1e-6;

/// Largest number of output samples of a retimed joint path (its duration over `dt`). Unit:
/// samples. Default 10 000 000: ten hours at 1 ms, or the longest a user could ask for by
/// mistake without hanging the command (each sample costs an inverse dynamics, about a
/// microsecond for an arm).
pub const MAX_OUTPUT_SAMPLES: usize = 10_000_000;

/// Largest distance (m) of an environment surface's polygon vertex from the surface's origin.
/// Default 1e5 m (100 km): far beyond any scene, and the collision queries (GJK and EPA, on
/// the surface's solid against links of centimetres) stay reliable; a floor of 1e20 m made
/// them report a collision that was not there, and one of 1e160 m made them fail (a fuzz
/// finding).
pub const MAX_SURFACE_EXTENT: f64 = 1e5;

/// Largest distance (m) of an environment surface's origin from the world origin. Default 1e6 m
/// (1000 km): the computation is in metres with double precision, which leaves fewer digits
/// below the millimetre the farther the scene is. The gallery's squat moved along x has the
/// duration of the squat at the origin to 1.2e-9 at 1e6 m, 7e-8 at 1e8 m, 2e-6 at 1e9 m and
/// 8e-4 at 1e12 m, and from 1e15 m on its feet are no longer on the floor where they stand.
pub const MAX_SCENE_DISTANCE: f64 = 1e6;

/// Smallest `planning.area_scale`: the contact polygons are scaled by its square root, so 1e-6
/// leaves a thousandth of a sole's length, a fraction of a millimetre. Below about 1e-10 the
/// polygons are nanometres wide and the cones of the footholds planner's regions degenerate
/// (1e-12: 0.9 s for what 1e-8 does in 2 ms; a fuzz input at 2e-16 took over 12 s).
pub const MIN_AREA_SCALE: f64 = 1e-6;

/// Largest thickness (m) of an environment surface's solid. Default 100 m: far beyond any
/// scene; a larger value is a unit mistake.
pub const MAX_SOLID_THICKNESS: f64 = 100.0;

/// Deepest penetration (m) of a robot body into an environment solid that the collision check
/// accepts. Default 1 mm: a landing link touches its surface within micrometres (measured on the
/// built-in motions) and a link lifting off starts on it; deeper is a collision (MuJoCo, whose
/// soft contacts push back from the first micrometre, reports it as an unplanned contact).
pub const COLLISION_PENETRATION: f64 = 1e-3;

/// Range (m) within which the collision check measures a robot body's clearance exactly (the
/// bounding boxes of farther pairs are not refined). Default 0.2 m: a body farther than this
/// from every surface is reported as clear without a number.
pub const CLEARANCE_RANGE: f64 = 0.2;

/// Distance (m) beyond the clearance at which the IK starts to watch a pair (robot body,
/// environment solid): closer pairs get a distance row. Default 5 cm: the clearance damper
/// decays an approach over about a tenth of a unit of path, and a link moving at the
/// references' rates covers less than this in one IK step.
pub const CLEARANCE_WATCH: f64 = 0.05;

/// Largest `ik.clearance` (m). Default 0.5 m: beyond it no leg could step; a larger value is a
/// unit mistake.
pub const MAX_CLEARANCE: f64 = 0.5;

/// Regularization `eps` of the force check's fast path (dimensionless, against the squared
/// norm of unit-height pyramid edges). Default 1e-6: makes the Hessian of the edge weights
/// definite (an 8-sided pyramid's edges span three directions) while moving the forces from
/// the minimum-norm ones by about that fraction, far below what the friction usage reports.
pub const FAST_FORCES_REGULARIZATION: f64 = 1e-6;

/// Largest number of KKT solves of the force check's fast path before it hands the sample to
/// the slow path. Default 50: a warm-started sample takes one to three; an infeasible sample
/// cycles, and the slow path certifies it.
pub const FAST_FORCES_MAX_ITERATIONS: usize = 50;

/// Signed distance (m) at or below which a robot body touches an environment solid. Default
/// 1 um: a foot placed on its surface sits there to the standing search's and the IK's
/// residuals (1e-10 m), not exactly at 0.
pub const TOUCH_DISTANCE: f64 = 1e-6;

/// Shortest unplanned touch (s) the collision check reports: a robot body within
/// [`TOUCH_DISTANCE`] of a solid it is not held on, for this long. Default 0.05 s: a lift-off or a
/// landing touches for at most 16 ms in the built-in and gallery motions that hold in MuJoCo
/// (measured at 1 ms), while a swing foot that the plan leaves on the floor for 0.86 s (the
/// gallery's Talos step up) is what the simulator reports as leaning on an unplanned contact.
pub const UNPLANNED_TOUCH_TIME: f64 = 0.05;

/// Margin of the torque check's pruning (a ratio): a sample whose upper bound is below the
/// largest exact ratio by more than this is not solved exactly. Default 1e-6: the bound's forces
/// balance the base within the force check's residual (relative 1e-6), which the exact program
/// also allows; a sample within the margin is solved.
pub const TORQUE_BOUND_MARGIN: f64 = 1e-6;

/// A via-point (CoM or link position) is reached when the IK's path ends its move within this
/// distance of it (m). Default 1 mm: the IK tracks its references to a few hundredths of this,
/// so a larger distance is a target out of reach or traded for another task.
pub const VIA_POINT_DISTANCE: f64 = 1e-3;

/// A link via-point's orientation is reached within this angle (degrees). Default 0.5, for the
/// same reason as [`VIA_POINT_DISTANCE`].
pub const VIA_POINT_ANGLE_DEG: f64 = 0.5;

/// Two consecutive samples of an output trajectory agree when, for every one-coordinate joint,
/// the position changes by the trapezoid of the two velocities within this (rad or m). Default
/// 1e-4: what a user integrating the velocities, or a controller interpolating the positions,
/// can ignore (the bound).
pub const TRAJECTORY_TRAPEZOID: f64 = 1e-4;

/// Most halvings of an output interval that still disagrees once its switching instants are in
/// ([`TRAJECTORY_TRAPEZOID`]). Default 12: a 10 ms step halved down to 2.4 us.
pub const TRAJECTORY_REFINE_DEPTH: usize = 12;

/// Sampling step (m) of the footholds planner's swing traverse when it measures the clearance
/// of the link's contact box (module `footholds::swing`). Default 1 cm.
pub const SWING_SAMPLE: f64 = 0.01;

/// How much less than the swing clearance a traverse may keep (m): the start and end of the
/// traverse are exactly the clearance away from their surfaces. Default 0.1 mm.
pub const SWING_CLEARANCE_SLACK: f64 = 1e-4;

/// The least raise (m) of a swing traverse per trial. Default 5 mm.
pub const SWING_RAISE_STEP: f64 = 5e-3;

/// The highest raise (m) of a swing traverse before the planner gives up. Default 1 m.
pub const MAX_SWING_HEIGHT: f64 = 1.0;

/// A surface normal within this distance of the world's `z` axis is vertical for the swing
/// planner (legs along it merge). Default 1e-9.
pub const SWING_VERTICAL: f64 = 1e-9;

/// The widest gap (m) between the static-equilibrium regions of two consecutive stances that
/// the footholds planner hands to the chained retiming to cross with momentum; wider gaps are
/// refused before any computation. Default 0.3 m (the box climbing's is 0.04 m).
pub const MAX_CROSSING_GAP: f64 = 0.3;

/// The smallest `planning.swing.clearance` (m): a swing must leave its surface. Default 1 mm.
pub const MIN_SWING_CLEARANCE: f64 = 1e-3;

/// The margin fractions the footholds planner tries at the stance switches: each switch's CoM
/// is the point closest to the feet with at least this fraction of the largest static margin
/// the two stances share (module `footholds`). The search starts from the middle one.
pub const SWITCH_MARGIN_FRACTIONS: [f64; 5] = [0.25, 0.4, 0.55, 0.7, 0.85];

/// Grid intervals per segment of the footholds planner's search (the file's grid when
/// coarser). Default 40: half the pipeline's time of the default 100, the same ranking on the
/// motions tried.
pub const PLANNER_GRID: usize = 40;

/// The footholds planner reports its evaluations (`RunOptions::progress`) once it has run for
/// this long (s). Default 1 s.
pub const PLANNER_PROGRESS_AFTER: f64 = 1.0;

/// The refinement evaluates the contact rows inside an IK step when a contact row
/// at either end of the step is within this fraction of the weight `m |g|` of its bound
/// (module `midpoints`). Default 1e-3: a step farther from its bounds cannot reach them within
/// the step (the rows between samples differ from the samples' by 1e-5 of the weight where
/// measured).
pub const MIDPOINT_WATCH: f64 = 1e-3;

/// The finest interior points of an IK step where the refinement evaluates the model's exact
/// contact rows (module `midpoints`), as the number of parts the step is cut into: the
/// quarters first, then halving where a point failed. Default 32: where the retiming holds a
/// concave row of curvature `k` at points `h` apart, it can exceed its bound between them by
/// `k h^2 / 8`, so at 1/32 of a step by 1/1024 of what a step's ends alone allow (the small
/// humanoid's weight shift on a 10-interval grid: a curvature measured from the 1 ms samples of
/// 5.5e-4 of the weight per step squared, so 6.9e-5 over a whole step and 7e-8 at 1/32, against
/// the force check's residual tolerance of 1e-6). A power of two, at least 4.
pub const STEP_INTERIOR_SPACING: usize = 32;

/// Most friction-cone edges in one stance (contact vertices times the cone's sides): the contact
/// wrench cone's generators. Default 256: two rectangular feet with 32-sided cones, computed in
/// about 3 s (debug build; 48 sides took 13 s, 64 sides 40 s and 7 GB). Reason: bounded work.
pub const MAX_STANCE_EDGES: usize = 256;

/// IK samples per parallel task when the rows are built (`rows::SegmentRows::compute`): small
/// enough that both threads share every segment's work, large enough that each task's setup
/// (its buffers, the contact rows' factorization) stays small beside it.
pub const ROWS_CHUNK: usize = 16;
