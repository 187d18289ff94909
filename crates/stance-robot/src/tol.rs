//! Every numerical threshold of the crate, with its unit, default and reason.
//!
//! They are gathered in [`Tolerances`], which the model builder and the kinematics take as an
//! option; [`Tolerances::default`] gives the values below.

/// Largest accepted deviation of a free-flyer quaternion's norm from 1 (dimensionless).
///
/// Default `1e-6`: configuration vectors written with 7 to 9 significant digits (JSON files,
/// command lines) stay accepted, while a vector whose 4 quaternion entries are plainly not a unit
/// quaternion (a typo, joint angles shifted by one slot) is rejected instead of silently
/// normalized. Accepted quaternions are normalized before use.
pub const QUATERNION_NORM_TOL: f64 = 1e-6;

/// Largest accepted deviation of `cos^2 + sin^2` of a continuous joint's `(cos, sin)` pair from 1
/// (dimensionless). Same reason and default as [`QUATERNION_NORM_TOL`].
pub const UNIT_COMPLEX_NORM_TOL: f64 = 1e-6;

/// Smallest total mass for which the centre of mass is defined (kg).
///
/// Default `1e-9` kg: a URDF without any `<inertial>` mass (or whose only masses are on locked or
/// removed parts) has no CoM; below a microgram the CoM is round-off.
pub const MIN_TOTAL_MASS: f64 = 1e-9;

/// Smallest accepted norm of a joint axis in a URDF (dimensionless; axes are normalized).
///
/// Default `1e-12`: a zero axis (`xyz="0 0 0"`) is a modelling error, while any non-zero axis is
/// a direction that can be normalized exactly enough.
pub const MIN_AXIS_NORM: f64 = 1e-12;

/// Tolerance on the symmetric positive semi-definiteness of a link's rotational inertia (kg m^2),
/// relative to the largest diagonal entry: eigenvalues down to `-tol * max|I_ii|` and triangle
/// inequalities violated by that much are accepted as round-off of the URDF's decimal digits.
///
/// Default `1e-9`.
pub const INERTIA_PSD_REL_TOL: f64 = 1e-9;

/// Angle (rad) below which the SE(3) exponential used by [`crate::integrate`] switches to the
/// Taylor series (to `t^4`) of `sin t / t`, `(1 - cos t) / t^2` and `(t - sin t) / t^3`.
///
/// Default `1e-2`: there the series' truncation error is below `t^6 / 5040 < 1e-15` relative,
/// while above it the closed form of `(t - sin t) / t^3` loses at most `1e-11` relatively to
/// cancellation (multiplied by `t^2` in the exponential). A numerical-method switch, not a
/// tolerance on input: not an option.
pub const EXP_SERIES_ANGLE: f64 = 1e-2;

/// Base translations (m, largest coordinate) beyond which `A_g`, `J_com` and `(dA_g/dt) v` are
/// computed with the free-flyer base moved to the world origin and the CoM moved back.
///
/// Default 16 m. These quantities do not depend on where the world origin is, but computed
/// about it they lose `|p| / size` digits to cancellation (`L_G = L_O - c x h`: 6e-3 wrong at
/// 1e6 m, meaningless at 1e9 m, NaN at 1e155 m). Within 16 m the loss is at most 4 bits of a
/// humanoid's metre-sized quantities, and the answers stay bit for bit what they were. A
/// numerical-method switch, not a tolerance on input: not an option.
pub const FAR_BASE: f64 = 16.0;

/// The thresholds above, passed as options to [`crate::Model::from_urdf_str`] and to the
/// configuration checks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// See [`QUATERNION_NORM_TOL`].
    pub quaternion_norm: f64,
    /// See [`UNIT_COMPLEX_NORM_TOL`].
    pub unit_complex_norm: f64,
    /// See [`MIN_TOTAL_MASS`].
    pub min_total_mass: f64,
    /// See [`MIN_AXIS_NORM`].
    pub min_axis_norm: f64,
    /// See [`INERTIA_PSD_REL_TOL`].
    pub inertia_psd_rel: f64,
    /// See [`IK_REGULARIZATION`].
    pub ik_regularization: f64,
    /// See [`IK_QP_TOL`].
    pub ik_qp: f64,
}

impl Default for Tolerances {
    /// The documented defaults.
    ///
    /// ```
    /// let t = stance_robot::Tolerances::default();
    /// assert_eq!(t.quaternion_norm, stance_robot::tol::QUATERNION_NORM_TOL);
    /// ```
    fn default() -> Self {
        Self {
            quaternion_norm: QUATERNION_NORM_TOL,
            unit_complex_norm: UNIT_COMPLEX_NORM_TOL,
            min_total_mass: MIN_TOTAL_MASS,
            min_axis_norm: MIN_AXIS_NORM,
            inertia_psd_rel: INERTIA_PSD_REL_TOL,
            ik_regularization: IK_REGULARIZATION,
            ik_qp: IK_QP_TOL,
        }
    }
}

/// Weight of the regularization `|q_ss|^2` in the acceleration-level IK objective, relative to
/// the task weights (dimensionless).
///
/// Default `1e-6`: the tasks and contacts do not determine every joint acceleration (an arm not
/// in any task), so the QP needs a strictly convex term to pick one answer (the least-norm
/// acceleration); at `1e-6` it biases the tracked task accelerations by about `1e-6` relative.
pub const IK_REGULARIZATION: f64 = 1e-6;

/// Feasibility and optimality tolerance asked of the QP solver in the IK (its own units: the
/// residuals of the acceleration equations, 1/s^2 per unit of path).
///
/// Default `1e-8` (Clarabel's own default): the contact equations are then met to far below what
/// the integration error of one path step adds to the contact drift, while tighter values make
/// the interior-point solver stall ("insufficient progress") on badly scaled steps.
pub const IK_QP_TOL: f64 = 1e-8;

/// Largest number of KKT solves of the IK's dense active-set QP solver before it gives way to
/// Clarabel ([`crate::ik::dense_qp`]).
///
/// Default `50`: a step changes its working set by a few joint bounds at most (warm-started from
/// the previous step's), so a problem that needs more is cycling or infeasible, which the
/// interior-point fallback then settles.
pub const IK_DENSE_MAX_ITERATIONS: usize = 50;

/// Primal tolerance of the dense IK solver (dimensionless, relative to `max(1, |bound|)` for a
/// joint bound and to `max(1, |b|_inf, |A|_max |x|_inf)` for the contact equations).
///
/// Default `1e-9`: the range-space solve meets the equations to round-off (about `1e-13`
/// relative on JVRC-1); `1e-9` accepts that and rejects an answer that is wrong.
pub const IK_DENSE_PRIMAL_TOL: f64 = 1e-9;

/// Multiplier-sign tolerance of the dense IK solver (dimensionless, relative to
/// `max(1, |P|_max |x|_inf, |c|_inf)`, the scale of the gradient).
///
/// Default `1e-9`, for the same reason as [`IK_DENSE_PRIMAL_TOL`]: a multiplier of a held bound
/// that is wrong by less than this is round-off of a bound that is just active.
pub const IK_DENSE_DUAL_TOL: f64 = 1e-9;

/// Smallest accepted squared pivot of the Cholesky factorization of `Y^T Y` in the dense IK
/// solver, relative to its largest diagonal entry (dimensionless).
///
/// Default `1e-12`: below it the contact rows are numerically dependent (two contact frames on
/// one rigid body, or more held joints than the equations allow), the multipliers are not
/// determined to better than `1e-6` relative, and the step goes to the interior-point solver.
pub const IK_DENSE_PIVOT: f64 = 1e-12;

/// Deepest nesting of XML elements a URDF may have. Unit: levels. Value `64`: a URDF needs about
/// six (`robot`, `link`, `visual`, `geometry`, `mesh`; xacro output is no deeper), and the XML
/// parsers recurse once per level: a file nested tens of thousands deep overflowed the stack.
pub const MAX_URDF_DEPTH: usize = 64;
