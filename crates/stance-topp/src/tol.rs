//! Every numerical threshold of the crate, with its unit, default and reason.
//!
//! Units: the path parameter `s` is dimensionless here (any unit works as long as it is used
//! consistently); `u = s''` and `x = s'^2` are then both in `1/time^2`, so after a constraint row
//! `a u + b x + c <= 0` is scaled to `|(a, b)| = 1`, its value is a distance in the `(u, x)` plane
//! measured in `1/time^2`. The thresholds below that compare such values are in that unit, and
//! that unit is the problem's own: the solver works on a path parameter of unit range
//! (`CanonicalConstraints::on_unit_grid`) and, when the rows' typical distance from the origin
//! of the `(u, x)` plane is more than 256 times off 1, in a time unit `4^m` near it
//! (`CanonicalConstraints::on_unit_time`; not with a separation oracle, whose cuts are in the
//! caller's units), so that a path crossed in days and one crossed in microseconds get the same
//! decisions.

/// Numerical thresholds of the solver, passed through [`crate::SolveOptions`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// A row `a u + b x + c <= 0` whose coefficient norm `|(a, b)|` is at most
    /// `zero_row * |c|` is treated as the constant constraint `c <= 0` (relative within the
    /// row: multiplying a row by a positive factor changes no decision). Unit: dimensionless
    /// (relative). Default `1e-12`: coefficients below that are round-off of exact zeros (for
    /// example a row of a cone that is orthogonal to the path tangent).
    pub zero_row: f64,
    /// Slack allowed on a row when a point `(u, x)` is tested against it in the 2-variable LP:
    /// the row value may exceed 0 by `feasibility * |(a, b)| * max(1, |(u, x)|)`, i.e. a
    /// distance of `feasibility` in the `(u, x)` plane, relative to the size of the point (and
    /// independent of the row's scale).
    /// Unit: dimensionless (relative). Default `1e-10`: well above the round-off of the
    /// products involved (about 1e-16 relative per operation, with speeds up to `max_x` where
    /// rows leave them unbounded) and far below any physically meaningful margin.
    pub feasibility: f64,
    /// Two constraint lines whose normalized normals have a cross product at most this are
    /// treated as parallel in the 1-D sub-problems of the LP kernel. Unit: dimensionless (sine of
    /// the angle). Default `1e-13`: intersections of nearly parallel lines are ill-conditioned
    /// beyond that point.
    pub parallel: f64,
    /// Amount by which a state may lie outside a controllable set, or a row may be violated in
    /// the forward pass, and still be accepted as round-off. Relative to `max(1, |x|)` for
    /// states; unit `1/time^2` for normalized rows. Default `1e-8`: the backward pass solves each
    /// LP to about `1e-12` relative; `1e-8` leaves room for the accumulation over thousands of
    /// grid points while still catching any real infeasibility.
    pub state: f64,
    /// Bounding box of the LPs: `|u| <= max_u`. Unit: `1/time^2`. Default `1e8`: only bounds the
    /// LP when the constraints leave `u` free; a result that touches it is reported through
    /// [`crate::Solution::hit_box`].
    pub max_u: f64,
    /// Bounding box of the LPs: `x <= max_x`. Unit: `1/time^2`. Default `1e8` (path speed `1e4`
    /// per unit time): only matters when no constraint bounds the speed.
    pub max_x: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Self {
            zero_row: 1e-12,
            feasibility: 1e-10,
            parallel: 1e-13,
            state: 1e-8,
            max_u: 1e8,
            max_x: 1e8,
        }
    }
}

/// Default bound on the constraint violation between grid points asked of
/// [`crate::between::refine_until`], as a fraction of the scale the caller gives (for contact stability,
/// `m |g|`). Unit: dimensionless. Default `0.01` (1 % of the robot's weight), the figure.
pub const DEFAULT_BETWEEN_GRID_FRACTION: f64 = 0.01;

/// Largest number of samples [`crate::Profile::resample`] produces before it refuses the time
/// step. Unit: samples. Default `1_000_000` (32 MB of samples): a thousand times a typical
/// resampling (a few seconds at 1 ms); beyond it a tiny `dt` is a mistake that would exhaust
/// memory rather than a request.
pub const MAX_RESAMPLE_POINTS: usize = 1_000_000;

/// An LP optimum counts as lying on a side of the bounding box ([`Tolerances::max_u`],
/// [`Tolerances::max_x`]), and [`crate::Solution::hit_box`] is set, when it is within this
/// fraction of the side. Unit: dimensionless (relative). Default `1e-12`: the optimum on a box
/// side is computed from that side to round-off (about 1e-16 relative); any real constraint
/// stops it much farther away.
pub const BOX_TOUCH: f64 = 1e-12;

/// Largest absolute value of a row coefficient `a`, `b`, `c` (and of the products of eq. 14's
/// factored form) that the crate accepts. Unit: that of the rows. Default `1e100`: the LP
/// kernel squares coefficients and multiplies them by squared points of the box (up to
/// [`MAX_BOX`]), which must stay below the largest double (about 1.8e308); rows beyond it
/// overflowed and were then accepted everywhere. Scaling a row by a positive factor does not
/// change its feasible set, so rescale rows that exceed it.
pub const MAX_ABS_COEFFICIENT: f64 = 1e100;

/// Largest bounding box [`Tolerances::max_u`], [`Tolerances::max_x`] accepted. Unit:
/// `1/time^2`. Default `1e30`: with coefficients up to [`MAX_ABS_COEFFICIENT`], the kernel's
/// squared products stay below about 1e260.
pub const MAX_BOX: f64 = 1e30;

/// Largest number of cuts a separation oracle may add to one LP of the reachability passes
/// before the solve stops with an error ([`crate::Separation`]). Unit: cuts. Default 64: a
/// guard against an oracle whose cuts do not converge (on the random lifted polytopes of
/// `tests/lifted.rs` the cutting-plane loop of [`crate::lifted::Membership::separate`] needs
/// at most 8).
pub const MAX_CUTS_PER_LP: usize = 64;
