//! Numerical thresholds of the 2-D/3-D polytope routines (`polycone::polytope`).
//!
//! Every threshold is an absolute length in the units of the input coordinates (metres in the
//! robotics crates), because the routines work on points and planes, not on cones. Callers
//! whose data live at another scale pass their own [`PolytopeOptions`].

/// Default distance tolerance (input length unit; default `1e-9`): a point whose signed
/// distance to a line or plane is at most this counts as on it (inside). Reason: 1e-9 m is far
/// below any contact geometry and about 1e6 ulps above double rounding at the metre scale, so
/// rounding never flips an inside/outside decision that matters.
pub const DEFAULT_DIST_TOL: f64 = 1e-9;

/// Default vertex merge distance (input length unit; default `1e-9`): vertices closer than this
/// are one vertex. Same reason as [`DEFAULT_DIST_TOL`].
pub const DEFAULT_MERGE_TOL: f64 = 1e-9;

/// Default "far" bound (input length unit; default `1e6`): the computation starts from the box
/// `[-far, far]^d`; a result that still touches this box is reported as unbounded, with the box
/// faces marked. Reason: a million metres is beyond any robot workspace, and intersections on a
/// box this size keep about 1e-10 absolute accuracy in double precision.
pub const DEFAULT_FAR: f64 = 1e6;

/// Rounding of clipped points relative to the size of the box being clipped (dimensionless;
/// `1e-15`, about 4.5 units in the last place): the 2-D and 3-D clippings decide inside/outside with
/// `max(dist_tol, BOX_ROUNDING * box half-size)`. At the default box (`1e6`) that is
/// [`DEFAULT_DIST_TOL`] itself; the far larger boxes of the search for a region the default
/// box misses (up to `1e300`) would otherwise decide on rounding noise. A numerical floor, not
/// an option. Constant rows (`0 <= b`, a zero normal) keep `dist_tol`: their offset is not a
/// rounded point.
pub const BOX_ROUNDING: f64 = 1e-15;

/// Default threshold on the norm of a normal vector (dimensionless; default `1e-12`): a row
/// `a . p <= b` with `|a|` below this is treated as the constant constraint `0 <= b`.
/// Reason: such rows carry no direction and dividing by their norm would amplify noise 1e12x.
pub const DEFAULT_ZERO_NORMAL: f64 = 1e-12;

/// Default rank threshold (dimensionless; default `1e-9`): unit normals whose mixed product
/// (3-D) or cross product (2-D) is below this are treated as linearly dependent when deciding
/// whether a vertex is a true corner. Reason: matches [`DEFAULT_DIST_TOL`] at unit scale.
pub const DEFAULT_RANK_TOL: f64 = 1e-9;

/// Largest coordinate (input length unit; default 16) of a region's centroid under which the
/// region computed about the origin is the answer; farther, it is computed again about the
/// centroid (module `centre`). Reason: within it, rounding at the coordinates' scale costs at
/// most 4 bits of a unit-sized region, and answers near the origin stay bit for bit what they
/// were. A numerical-method switch, not a tolerance on input: not an option.
pub const NEAR_ORIGIN: f64 = 16.0;

/// Options of the polytope routines; see the constants of this module for meaning and reasons.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PolytopeOptions {
    /// Distance under which a point is on a line/plane ([`DEFAULT_DIST_TOL`]).
    pub dist_tol: f64,
    /// Vertex merge distance ([`DEFAULT_MERGE_TOL`]).
    pub merge_tol: f64,
    /// Half-size of the initial box ([`DEFAULT_FAR`]).
    pub far: f64,
    /// Norm under which a normal is zero ([`DEFAULT_ZERO_NORMAL`]).
    pub zero_normal: f64,
    /// Rank threshold for unit normals ([`DEFAULT_RANK_TOL`]).
    pub rank_tol: f64,
}

impl Default for PolytopeOptions {
    fn default() -> Self {
        Self {
            dist_tol: DEFAULT_DIST_TOL,
            merge_tol: DEFAULT_MERGE_TOL,
            far: DEFAULT_FAR,
            zero_normal: DEFAULT_ZERO_NORMAL,
            rank_tol: DEFAULT_RANK_TOL,
        }
    }
}

impl PolytopeOptions {
    /// Checks that every threshold is finite and positive and that `far` exceeds the others.
    pub(crate) fn validate(&self) -> Result<(), super::PolytopeError> {
        let ok = |x: f64| x.is_finite() && x > 0.0;
        if !(ok(self.dist_tol)
            && ok(self.merge_tol)
            && ok(self.far)
            && ok(self.zero_normal)
            && ok(self.rank_tol))
            || self.far <= self.dist_tol.max(self.merge_tol)
        {
            return Err(super::PolytopeError::BadOptions);
        }
        Ok(())
    }
}

/// Largest move of a vertex by the polish step (dimensionless, 1e-6), relative to
/// `(1 + |p|_inf) / c`, with `c` the conditioning of the corner (2-D: `|det|` of the two unit
/// normals; 3-D: a lower bound of `sqrt(l_min(N^T N))` over the incident unit normals).
/// Clipping from the far box leaves errors of about `far * 1e-16 / c = 1e-10 / c`, so a larger
/// move means the polish used the wrong lines or planes and is rejected. Structural.
pub const POLISH_MAX_MOVE: f64 = 1e-6;

/// Relative margin of the 3-D refinement box around the first-pass result (dimensionless,
/// 0.05): large against rounding, small enough to keep the box at the result's scale.
/// Structural.
pub const REFINE_MARGIN: f64 = 0.05;

/// How many times the 3-D refinement box may grow (by 4x each) before the first pass is kept.
pub const REFINE_TRIES: usize = 4;

/// Two hull facets whose unit normals differ by less than this (dimensionless, 1e-7) are one
/// facet split by rounding in the polar ([`super::hull3`]). Reason: the polar's vertices carry
/// about 1e-10 relative rounding, and distinct facets of the regions handled here differ by far
/// more than 1e-7 rad. Structural.
pub const HULL_SAME_FACET: f64 = 1e-7;

/// The check of every 3-D hull ([`super::hull3`]) accepts a face normal whose length differs
/// from 1 by at most this (dimensionless, 1e-9). Reason: normalized `f64` vectors are unit to
/// a few ulps; anything farther was not normalized. Structural.
pub const HULL_CHECK_UNIT_NORMAL: f64 = 1e-9;

/// The check of every 3-D hull ([`super::hull3`]) accepts a face loop whose angles swept
/// around its centroid sum to `2 pi` within this (radians, 1e-6). Reason: a convex loop
/// winds exactly once (sum `2 pi` up to rounding, about 1e-15 per vertex); a loop that winds
/// twice or backwards is off by `2 pi`. Structural.
pub const HULL_CHECK_WINDING: f64 = 1e-6;

/// Relative forward error bound of the floating-point filter of the 3-D hull's orientation
/// predicate (dimensionless, `(7 + 56 u) u` with `u = 2^-53` the unit roundoff, Shewchuk 1997):
/// the computed determinant differs from the true one by at most this times the permanent
/// (the same expansion with absolute values), for the evaluation order used (differences,
/// then the 3x3 cofactor expansion). Not a tolerance: a larger value only calls the exact
/// path more often, a smaller one would be wrong.
pub const ORIENT_ERR_BOUND: f64 = (7.0 + 56.0 * f64::EPSILON / 2.0) * f64::EPSILON / 2.0;

/// Magnitude range (`2^-300` to `2^300`) of the non-zero parts of the coordinate differences
/// for which the exact orientation predicate of the 3-D hull works in floating-point
/// expansions: products of three such numbers and their rounding errors are then exact `f64`
/// values (no overflow, no underflow below the subnormal granularity). Not a tolerance:
/// outside the range the big-integer path decides.
pub const ORIENT_RANGE_LO: f64 = 4.909093465297727e-91;
/// Upper end of the range of [`ORIENT_RANGE_LO`].
pub const ORIENT_RANGE_HI: f64 = 2.037035976334486e90;
