//! Acceleration-level inverse kinematics along a path (docs/math.md section 6, the paper's Section
//! V-B): from a CoM path and free end-effector paths, with contact frames held fixed, compute the
//! joint path `q(s)` and its derivatives `q_s`, `q_ss` for [`crate::path_terms`].
//!
//! # Math
//!
//! At a path point with state `(q, q_s)` (`q_s` a velocity-space vector) the joint path
//! acceleration `x = q_ss` solves the quadratic program
//!
//! ```text
//! minimize    w_com |J_com x + Jd_com q_s - pdd_com*|^2 + sum_links w_link |J_l x + Jd_l q_s - pdd_l*|^2
//!             (+ w_link |J_l,ang x + Jd_l,ang q_s - alpha_l*|^2 for links with an orientation task)
//!             + w_posture |x_j - xdd_j*|^2 (joints, with a posture reference)  + eps |x|^2
//! subject to  J_c x = -Jd_c q_s - gamma J_c q_s + k_c e_c             (every contact frame, 6 rows)
//!             J_h x + Jd_h q_s = pdd_h*                            (hard link tasks, 3 or 6 rows)
//!             lo(q, q_s) <= x <= hi(q, q_s)                         (bounded joints)
//! ```
//!
//! where `J` are Jacobians (the CoM Jacobian, `LocalWorldAligned` frame Jacobians), `Jd q_s`
//! their drifts for the velocity `q_s` (classical accelerations), and the desired task
//! accelerations track a reference `(p*, p*_s, p*_ss)` with the paper's gains:
//! `pdd* = p*_ss + K_d (p*_s - J q_s) + K_p (p* - p)`; the posture task tracks a reference
//! configuration the same way, `xdd_j* = -K_d q_s,j + K_p (q*_j - q_j)`. The contact rows keep
//! the contact frames' velocities at zero (`gamma` damps any residual velocity) and, with
//! `k_c > 0` and a target placement, pull the frame back onto it (`e_c` = position error and
//! rotation vector of `R* R^T`, world axes). A link task may also be held as an equality (a
//! "hard" task: a landing foot whose arrival at rest is not traded for the CoM). The joint bounds ([`JointBounds`]) are either
//!
//! - **next step**: keep each bounded joint within its limits over the next path step `ds`,
//!   `2 (lower - q - q_s ds) / ds^2 <= x <= 2 (upper - q - q_s ds) / ds^2` at its end; inside
//!   the step, a joint that turns back peaks below `q + q_s ds / 2` (at `q + q_s^2 / (2 |x|)`,
//!   `|x| > q_s / ds`), so `q + q_s ds / 2` is also kept within the limits at every sample:
//!   `lower - q - 1.5 q_s ds <= x ds^2 <= upper - q - 1.5 q_s ds` for the next one (relaxed to
//!   the end bound where a state breaks it, so that the QP stays feasible); or
//! - **damper** (the paper's form): with the range shrunk about its middle to `range` of its
//!   width, `K_ss (K_s (lower' - q) - q_s) <= x <= K_ss (K_s (upper' - q) - q_s)`, so that a joint
//!   approaches a limit no faster than `q_s = K_s (upper' - q)` allows; it may overshoot the
//!   shrunk range by about `q_s / K_ss`, so the next-step bounds apply too (measured without
//!   them: JVRC-1's waist pitch 0.028 rad past its URDF limit in the box climbing);
//!
//! and the optional rate bound `-r_max <= q_s + x ds <= r_max` ([`IkOptions::max_path_rate`])
//! bounds the joint rates along the path. All of them are bounds on single coordinates of `x`,
//! which the dense solver ([`dense_qp`]) exploits.
//!
//! **Clearances** ([`DistanceBound`]): a point `p` of a body (moving with joint `i`) at signed
//! distance `d` from an obstacle along the unit normal `n` (from the body towards the obstacle)
//! approaches `d_min` no faster than a critically damped system of gain `K`
//! ([`IkOptions::clearance_gain`]) and does not cross `d = 0` over the next step: the distance
//! changes at `d_s = -n^T J_p q_s` and `d_ss = -n^T (J_p x + a_p)` (`J_p` the point's Jacobian,
//! world axes, `a_p` its classical acceleration for `x = 0`), and
//! `d_ss >= -(K^2 (d - d_min) + 2 K d_s)`, `d + d_s ds + d_ss ds^2 / 2 >= 0`, i.e. the row
//!
//! ```text
//! n^T J_p x <= min(K^2 (d - d_min) + 2 K d_s,  2 (d + d_s ds) / ds^2) - n^T a_p
//! ```
//!
//! so that an approach slows down as it nears `d_min` and a body already closer is pushed out.
//! The rows are general inequalities (the dense solver's outer active set); when they make the
//! QP infeasible (a hard task drives the body through the obstacle) the step is solved without
//! them and says so ([`IkStep::clearance_dropped`]): the collision check then reports what
//! happens. Weights `w_com = 1`, `w_link = 0.1`, gains
//! `K_p = K_d = gamma = 10` are the paper's defaults; `eps` is [`crate::tol::IK_REGULARIZATION`].
//!
//! Along a grid `s_0 < s_1 < ...` the path is integrated with constant `q_ss` on each step:
//! `q_{i+1} = q_i (+) (q_s,i ds + q_ss,i ds^2 / 2)`, `q_s,i+1 = q_s,i + q_ss,i ds`.
//!
//! **Solvers.** By default the QP is solved by the dense active-set method of [`dense_qp`]
//! (the KKT conditions verified on its answer), warm-started with the previous step's active
//! bounds; when it cannot certify an answer (an iteration cap, redundant contact rows, an
//! infeasible QP) the step falls back to Clarabel (interior point), which also decides
//! infeasibility. [`IkSolver::Clarabel`] forces the interior-point route (the independent check
//! in the tests). Each result reports its residuals and which solver answered: the largest
//! contact-equation residual and, along a path, the contact frames' drift from their initial
//! placements and the CoM tracking error.

mod clarabel_qp;
pub mod dense_qp;
mod problem;
mod track;

pub use clarabel_qp::solve_ik_qp;
pub use dense_qp::{DenseQpOptions, DenseQpReport, DenseQpStatus, DenseQpWorkspace};
pub use problem::{ik_qp, ik_step, ContactHold, DistanceBound, IkTasks, IkWorkspace};
pub use track::{track_path, IkPath, PathSample};

use nalgebra::{DMatrix, DVector, Vector3};

use crate::error::RobotError;

/// How the joint position limits enter the QP (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointBounds {
    /// Stay within the limits over the next path step.
    NextStep,
    /// The paper's damper: `K_ss (K_s (upper' - q) - q_s)` with the range shrunk to `range`.
    Damper {
        /// `K_s` (1 per unit of path; the paper's 10).
        k_s: f64,
        /// `K_ss` (1 per unit of path; the paper's 10).
        k_ss: f64,
        /// Fraction of each joint's range kept, about its middle (the paper's 0.95).
        range: f64,
    },
}

impl JointBounds {
    /// The paper's damper: `K_s = K_ss = 10`, ranges shrunk to 95 %.
    ///
    /// ```
    /// let b = stance_robot::JointBounds::paper();
    /// assert!(matches!(b, stance_robot::JointBounds::Damper { range, .. } if range == 0.95));
    /// ```
    pub fn paper() -> Self {
        JointBounds::Damper {
            k_s: 10.0,
            k_ss: 10.0,
            range: 0.95,
        }
    }
}

/// Which QP solver an IK step uses (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IkSolver {
    /// The dense active-set solver, falling back to Clarabel when it cannot certify an answer.
    #[default]
    Dense,
    /// Clarabel only (interior point).
    Clarabel,
}

/// Weights and gains of the IK (the paper's defaults, docs/math.md section 6). The paper gives
/// one task gain of 10; the tracking law needs two, named here by role, `k_p` on the position
/// error and `k_d` on the rate error, both 10 by default. (`K_s`, `K_ss` are the joint-limit
/// damper's gains: see the module docs.)
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IkOptions {
    /// Weight of the CoM task (default 1).
    pub w_com: f64,
    /// Weight of each free link task (default 0.1).
    pub w_link: f64,
    /// Weight of the posture task, when a posture reference is given (default 0: none).
    pub w_posture: f64,
    /// Position gain `K_p` of the task references (1/s^2 per unit path; default 10).
    pub k_p: f64,
    /// Velocity gain `K_d` (default 10).
    pub k_d: f64,
    /// Damping `gamma` of the contact velocities (default 10).
    pub gamma: f64,
    /// Position gain `k_c` pulling a contact frame back onto its target placement (default 0:
    /// velocities only, as in docs/math.md).
    pub contact_k_p: f64,
    /// Regularization weight (default [`crate::tol::IK_REGULARIZATION`]).
    pub regularization: f64,
    /// QP solver tolerance of the Clarabel route (default [`crate::tol::IK_QP_TOL`]).
    pub qp_tol: f64,
    /// Largest joint rate along the path, `|dq_j/ds|` for every revolute and prismatic joint
    /// (rad or m per unit of `s`; default `+inf`, no bound). Enforced at the end of each step:
    /// `|q_s + q_ss ds| <= max_path_rate`.
    pub max_path_rate: f64,
    /// The joint-limit bounds (default [`JointBounds::NextStep`]).
    pub joint_bounds: JointBounds,
    /// Gain `K` of the clearance damper (per unit of path; default 10, the joint damper's).
    pub clearance_gain: f64,
    /// The QP solver (default [`IkSolver::Dense`]).
    pub solver: IkSolver,
}

impl Default for IkOptions {
    /// The paper's weights and gains.
    ///
    /// ```
    /// let o = stance_robot::IkOptions::default();
    /// assert_eq!((o.w_com, o.w_link, o.k_p, o.k_d, o.gamma), (1.0, 0.1, 10.0, 10.0, 10.0));
    /// ```
    fn default() -> Self {
        Self {
            w_com: 1.0,
            w_link: 0.1,
            w_posture: 0.0,
            k_p: 10.0,
            k_d: 10.0,
            gamma: 10.0,
            contact_k_p: 0.0,
            regularization: crate::tol::IK_REGULARIZATION,
            qp_tol: crate::tol::IK_QP_TOL,
            max_path_rate: f64::INFINITY,
            joint_bounds: JointBounds::NextStep,
            clearance_gain: 10.0,
            solver: IkSolver::Dense,
        }
    }
}

/// A reference point path at one value of `s`: position, first and second derivative in `s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointReference {
    /// `p*(s)` (m).
    pub p: Vector3<f64>,
    /// `dp*/ds`.
    pub p_s: Vector3<f64>,
    /// `d^2p*/ds^2`.
    pub p_ss: Vector3<f64>,
}

impl PointReference {
    /// The straight segment from `a` (at `s = 0`) to `b` (at `s = 1`), evaluated at `s`.
    ///
    /// ```
    /// use nalgebra::Vector3;
    /// let r = stance_robot::PointReference::segment(Vector3::zeros(), Vector3::x(), 0.25);
    /// assert_eq!(r.p.x, 0.25);
    /// assert_eq!(r.p_s, Vector3::x());
    /// ```
    pub fn segment(a: Vector3<f64>, b: Vector3<f64>, s: f64) -> Self {
        Self {
            p: a + (b - a) * s,
            p_s: b - a,
            p_ss: Vector3::zeros(),
        }
    }

    /// Hold the point `p` (zero rates).
    ///
    /// ```
    /// let r = stance_robot::PointReference::hold(nalgebra::Vector3::x());
    /// assert_eq!(r.p_s.norm(), 0.0);
    /// ```
    pub fn hold(p: Vector3<f64>) -> Self {
        Self {
            p,
            p_s: Vector3::zeros(),
            p_ss: Vector3::zeros(),
        }
    }
}

/// A free link's position task: the origin of `frame` follows `reference`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkTarget {
    /// Frame index (see [`crate::Model::frame_id`]).
    pub frame: usize,
    /// Its reference at the current `s`.
    pub reference: PointReference,
    /// Optional orientation task for the same frame (same weight).
    pub orientation: Option<OrientationReference>,
}

/// A reference orientation path at one value of `s`: `world_from_frame*` and its angular rates
/// in world axes (`[w_s] = dR*/ds R*^T`, `w_ss = dw_s/ds`). Tracked with the same gains as
/// positions: `alpha* = w_ss + K_d (w_s - w) + K_p log(R* R^T)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrientationReference {
    /// `world_from_frame*` (a rotation matrix).
    pub rotation: nalgebra::Matrix3<f64>,
    /// Angular rate along the path (world axes, rad per unit s).
    pub w_s: Vector3<f64>,
    /// Its derivative along the path.
    pub w_ss: Vector3<f64>,
}

impl OrientationReference {
    /// Hold the orientation `rotation` (zero rates).
    ///
    /// ```
    /// let o = stance_robot::OrientationReference::hold(nalgebra::Matrix3::identity());
    /// assert_eq!(o.w_s.norm(), 0.0);
    /// ```
    pub fn hold(rotation: nalgebra::Matrix3<f64>) -> Self {
        Self {
            rotation,
            w_s: Vector3::zeros(),
            w_ss: Vector3::zeros(),
        }
    }
}

/// The outcome of an IK QP (a value, not an error).
#[derive(Debug, Clone, PartialEq)]
pub enum IkStatus {
    /// Solved to the requested tolerance.
    Solved,
    /// The contacts and joint bounds admit no acceleration (a joint limit is reached, or the
    /// contacts ask for incompatible motions).
    Infeasible,
    /// The solver stopped without an answer (its status, for diagnosis).
    Failed(String),
}

/// Which solver gave an [`IkStep`]'s answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IkAnswerFrom {
    /// The dense active-set solver, certified by its KKT check.
    Dense,
    /// Clarabel (asked for, or the fallback).
    Clarabel,
}

/// The QP of one IK step in dense form: minimize `x^T P x / 2 + c^T x` subject to
/// `A_eq x = b_eq` and `G x <= h`.
#[derive(Debug, Clone, PartialEq)]
pub struct IkQp {
    /// Hessian (nv x nv, symmetric positive definite).
    pub p: DMatrix<f64>,
    /// Linear term.
    pub c: DVector<f64>,
    /// Contact equations (6 per contact).
    pub a_eq: DMatrix<f64>,
    /// Their right-hand side.
    pub b_eq: DVector<f64>,
    /// Joint bounds (one row per finite bound of a coordinate: `x_k <= hi` or `-x_k <= -lo`),
    /// then the clearance rows.
    pub g: DMatrix<f64>,
    /// Their right-hand side.
    pub h: DVector<f64>,
}

/// One IK step's answer.
#[derive(Debug, Clone, PartialEq)]
pub struct IkStep {
    /// Outcome.
    pub status: IkStatus,
    /// `q_ss` (zeros unless solved).
    pub q_ss: Vec<f64>,
    /// Largest absolute residual of the contact equations `|A_eq x - b_eq|_inf`.
    pub contact_residual: f64,
    /// Largest violation of the joint bounds `max(G x - h, 0)`.
    pub bound_violation: f64,
    /// The clearance rows made the step infeasible and it was solved without them.
    pub clearance_dropped: bool,
    /// Which solver answered.
    pub answer_from: IkAnswerFrom,
}

pub(crate) fn check_options(o: &IkOptions) -> Result<(), RobotError> {
    let fields = [
        ("w_com", o.w_com),
        ("w_link", o.w_link),
        ("w_posture", o.w_posture),
        ("k_p", o.k_p),
        ("k_d", o.k_d),
        ("gamma", o.gamma),
        ("contact_k_p", o.contact_k_p),
        ("regularization", o.regularization),
        ("qp_tol", o.qp_tol),
        ("clearance_gain", o.clearance_gain),
    ];
    for (name, x) in fields {
        if !(x.is_finite() && x >= 0.0) {
            return Err(RobotError::InvalidOption {
                name,
                reason: format!("{x} must be finite and >= 0"),
            });
        }
    }
    if o.max_path_rate.is_nan() || o.max_path_rate <= 0.0 {
        return Err(RobotError::InvalidOption {
            name: "max_path_rate",
            reason: format!("{} must be > 0 (+inf for no bound)", o.max_path_rate),
        });
    }
    if o.regularization <= 0.0 || o.qp_tol <= 0.0 {
        return Err(RobotError::InvalidOption {
            name: "regularization / qp_tol",
            reason: "must be > 0".into(),
        });
    }
    if let JointBounds::Damper { k_s, k_ss, range } = o.joint_bounds {
        if !(k_s.is_finite() && k_s > 0.0 && k_ss.is_finite() && k_ss > 0.0) {
            return Err(RobotError::InvalidOption {
                name: "joint_bounds",
                reason: format!(
                    "the damper gains K_s = {k_s}, K_ss = {k_ss} must be finite and > 0"
                ),
            });
        }
        if !(range > 0.0 && range <= 1.0) {
            return Err(RobotError::InvalidOption {
                name: "joint_bounds",
                reason: format!("the kept range fraction {range} must be in (0, 1]"),
            });
        }
    }
    Ok(())
}
