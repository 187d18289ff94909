//! Numerical thresholds of `stance-contact`, each with its unit, default and reason. They are
//! collected in [`ContactTolerances`] and passed through the options of each computation.

/// Rotation check (dimensionless, default `1e-9`): a `rotation` is accepted when
/// `|R^T R - I|_max` and `|det R - 1|` are below this. Reason: rotations written with 12-16
/// significant digits pass, a matrix that is not a rotation (a typo, a scale) fails.
pub const DEFAULT_ROTATION_TOL: f64 = 1e-9;

/// Smallest accepted polygon area (m^2, default `1e-12`, a 1 um square): below it a contact
/// polygon is degenerate (use a point contact instead).
pub const DEFAULT_MIN_AREA: f64 = 1e-12;

/// Convexity check (m, default `1e-9`): a vertex may lie at most this far on the wrong side of
/// the line through its neighbours. Reason: coordinates written with nm precision pass.
pub const DEFAULT_CONVEXITY_TOL: f64 = 1e-9;

/// Face-form membership band (dimensionless, relative, default `1e-9`): `U w <= tol |w|` counts
/// as inside (unit rows `U`). Reason: the DD output's rows are accurate to about 1e-12 after
/// normalization; 1e-9 keeps boundary points on the stable side without blurring the answer.
pub const DEFAULT_FACE_TOL: f64 = 1e-9;

/// Membership band of the CoM regions (m, default `1e-9`): a CoM this close outside a
/// static-equilibrium half-space still counts as stable. Same reason as [`DEFAULT_FACE_TOL`].
pub const DEFAULT_REGION_TOL: f64 = 1e-9;

/// Zero half-space normal (dimensionless, relative to `|g|`, default `1e-12`): a CoM half-space
/// `a . p <= d` with `|a| <= tol |g|` does not depend on the CoM and is checked as `0 <= d`.
pub const DEFAULT_ZERO_NORMAL: f64 = 1e-12;

/// Supporting-forces QP: feasibility tolerance of the solver (relative, default `1e-9`), and the
/// largest accepted residual `|sum of contact wrenches - target| / |target|` (default `1e-6`)
/// before a solution is called feasible. Reason: interior-point solutions meet the equality to
/// about 1e-9 relative; 1e-6 leaves room while rejecting a wrong "solved".
pub const DEFAULT_QP_FEAS_TOL: f64 = 1e-9;
/// See [`DEFAULT_QP_FEAS_TOL`].
pub const DEFAULT_QP_MAX_RESIDUAL: f64 = 1e-6;

/// Direct polygon LPs: optimality threshold on reduced costs (dimensionless, default `1e-12`).
/// The LP columns are normalized to unit length and lengths are scaled by the stance's extent,
/// so every coefficient is of order 1; a reduced cost below this counts as zero. The answer does
/// not rely on it: every edge's dual bound is verified from the data, positive reduced costs
/// included (module doc of `equilibrium::direct`).
pub const DEFAULT_LP_OPT: f64 = 1e-12;

/// Direct polygon LPs: smallest pivot (dimensionless, default `1e-11`): smaller tableau entries
/// never pivot, and a basis whose elimination meets a smaller pivot is singular. Reason: the
/// 4 x 4 bases have unit columns; 1e-11 keeps their condition number below about 1e11, so basic
/// solutions keep at least 5 correct digits before the residual check.
pub const DEFAULT_LP_PIVOT: f64 = 1e-11;

/// Direct polygon LPs: largest accepted residual of force and moment balance (relative to `|g|`,
/// default `1e-9`) of a vertex's contact forces, and the phase-1 infeasibility above which the
/// direct route gives way to `U_stance`. Same reason as [`DEFAULT_FACE_TOL`].
pub const DEFAULT_LP_FEAS: f64 = 1e-9;

/// Largest accepted friction coefficient (dimensionless, `1e6`). Reason: the pyramid's edges
/// `(+-mu, +-mu, 1)` carry the normal force in a component `1 / mu` of their length; from
/// about `mu = 1e9` the cone conversion's relative rank decisions drop it (a flat foot then
/// gets a segment, or an empty static-equilibrium polygon, reported as certified). `1e6`
/// keeps three orders of magnitude from that, and any physical contact is far below it.
pub const MAX_FRICTION: f64 = 1e6;

/// Largest accepted number of vertices of a polygon contact (64). Reason: the contact wrench
/// cone has four generators per vertex and the double description's work grows steeply with
/// them (`bench/peers/contact.md` has measured times); a contact surface is described well
/// by far fewer vertices.
pub const MAX_POLYGON_VERTICES: usize = 64;

/// The thresholds of this crate; see the constants of this module for units and reasons.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactTolerances {
    /// [`DEFAULT_ROTATION_TOL`].
    pub rotation: f64,
    /// [`DEFAULT_MIN_AREA`].
    pub min_area: f64,
    /// [`DEFAULT_CONVEXITY_TOL`].
    pub convexity: f64,
    /// [`DEFAULT_FACE_TOL`].
    pub face: f64,
    /// [`DEFAULT_REGION_TOL`].
    pub region: f64,
    /// [`DEFAULT_ZERO_NORMAL`].
    pub zero_normal: f64,
    /// [`DEFAULT_QP_FEAS_TOL`].
    pub qp_feas: f64,
    /// [`DEFAULT_QP_MAX_RESIDUAL`].
    pub qp_max_residual: f64,
    /// [`DEFAULT_LP_OPT`].
    pub lp_opt: f64,
    /// [`DEFAULT_LP_PIVOT`].
    pub lp_pivot: f64,
    /// [`DEFAULT_LP_FEAS`].
    pub lp_feas: f64,
}

impl Default for ContactTolerances {
    fn default() -> Self {
        Self {
            rotation: DEFAULT_ROTATION_TOL,
            min_area: DEFAULT_MIN_AREA,
            convexity: DEFAULT_CONVEXITY_TOL,
            face: DEFAULT_FACE_TOL,
            region: DEFAULT_REGION_TOL,
            zero_normal: DEFAULT_ZERO_NORMAL,
            qp_feas: DEFAULT_QP_FEAS_TOL,
            qp_max_residual: DEFAULT_QP_MAX_RESIDUAL,
            lp_opt: DEFAULT_LP_OPT,
            lp_pivot: DEFAULT_LP_PIVOT,
            lp_feas: DEFAULT_LP_FEAS,
        }
    }
}

/// Winding check of contact polygons (rad, default `1e-6`): the total turn of a simple convex
/// polygon is `2 pi`; a self-intersecting order turns by a multiple of `2 pi` at least `4 pi`,
/// so any value below `pi` separates them. Structural, not an option.
pub const WINDING_TOL: f64 = 1e-6;
