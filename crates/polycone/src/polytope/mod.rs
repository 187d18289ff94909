//! Dedicated 2-D and 3-D routines between half-space and vertex descriptions of convex polytopes.
//!
//! # Math
//!
//! A convex polygon (polyhedron) `P = {p in R^d : a_i . p <= b_i, i = 1..n}` (`d = 2, 3`) is
//! described either by its half-spaces (H-form) or by its vertices and faces (V-form):
//!
//! - [`polygon_from_halfplanes`]: half-planes -> vertices in counter-clockwise order, and for
//!   each edge the half-plane it lies on (the *active* half-planes; the others are redundant);
//! - [`polyhedron_from_halfspaces`]: half-spaces -> vertices, faces as vertex loops that are
//!   counter-clockwise seen from outside, and the half-space of each face;
//! - [`hull2`] and [`hull3`]: points -> convex hull, with its irredundant half-spaces, i.e. the
//!   way back.
//!
//! Outcomes are values: [`RegionStatus::Empty`], [`RegionStatus::Unbounded`] (the region
//! reaches farther than `far` from the point of the region it is computed about (the origin,
//! or the region's centroid when that is far from it); the part inside the box of half-size
//! `far` about that point is returned, box faces marked by `None`), and
//! lower-dimensional results (`dim < d`: a segment, a point, a flat polygon in 3-D).
//!
//! # Method and semantics
//!
//! Translating the rows does not change the region, so when the region's centroid `c` is more
//! than 16 units from the origin, the rows are moved to it and the region computed again
//! about it (module `centre`; a region beyond `far` is first located by a coarse pass): a
//! region 3000 km away is found, to the rounding of its own coordinates. The H -> V direction clips the box `[-far, far]^d` by each half-space in turn
//! (Sutherland-Hodgman in 2-D; face-by-face clipping with a cap face in 3-D). Row normals are
//! first normalized, so every predicate is a signed Euclidean distance compared with
//! `dist_tol`: points within `dist_tol` of a plane count as on it. The result is exact for the
//! input up to that tolerance: every returned vertex satisfies every half-space within
//! `dist_tol` (plus rounding), and no point farther than `dist_tol` inside all half-spaces is
//! missed. Vertices closer than `merge_tol` are merged, and vertices that are not corners
//! (collinear or coplanar within `rank_tol`) are dropped. [`hull2`] is Andrew's monotone
//! chain with the same tolerances. [`hull3`] builds the exact hull of the points (quickhull
//! with an exact orientation predicate), merges its triangles into maximal facets coplanar
//! within `dist_tol` with fitted planes, and checks the result (every point within
//! `dist_tol` of every half-space, vertices among the points, convex faces on their planes,
//! every edge on two faces, Euler's formula); on failure it falls back to the polar route
//! (the previous method), checked the same way, and otherwise returns
//! [`PolytopeError::HullCheck`] (see the `hull3d` module).
//!
//! Complexity: `O(n h)` in 2-D and `O(n F)` in 3-D, with `h` (`F`) the size of the running
//! polygon (the number of running face vertices); fine for the hundreds of rows of a stance.
//! [`hull3`]: `O(n log n)` expected for the exact hull (quickhull), `O(n F)` for the fitted
//! planes and the check.
//! In 3-D a second pass from a box just around the first result keeps the rounding at the
//! result's scale (the first pass interpolates along the edges of the far box).
//!
//! # Limitations
//!
//! - Tolerance-based predicates (no exact arithmetic): structure degenerate within `dist_tol`
//!   is merged (a face thinner than `dist_tol` may vanish, near-coplanar faces may stay split).
//! - Regions reaching farther than `far` from their centroid are reported unbounded even when
//!   they are bounded (raise `far` for regions larger than 1e6 units). A region beyond `far`
//!   is located at the rounding of its farthest row: rows 1e290 from the origin hide a region
//!   smaller than 1e274 (it is reported empty).
//! - [`hull3`] answers are exact for the input up to `dist_tol`: structure finer than that
//!   stays. Faces bent by more than `dist_tol` (e.g. vertices computed with a relative error
//!   of 1e-11, 3e5 m from the origin, are 2e-6 m off their face) come back as several
//!   faces: pass tolerances at the accuracy of the data.
//! - [`hull3`]'s direct route can fail its check (the polar fallback then passes or
//!   [`PolytopeError::HullCheck`] is returned); no failure seen in 50 000 random clouds
//!   stretched up to 1e3:1, moved up to 1e4 from the origin and with clusters of nearly
//!   coincident points spaced 1e-13 to 1e-4 (the ignored test `direct_failure_rates`), in
//!   300 000 round trips of random polyhedra, nor on the robust regions of the example
//!   stances. Slabs barely thicker than `dist_tol` make it fail: 8 of 199 random slabs
//!   1.1 `dist_tol` thick, none from 1.5 `dist_tol` (the ignored test `slab_failure_rates`).
//! - Face loops are convex up to the accuracy of the data: a vertex may lie inside the chord
//!   of its two neighbours by up to `dist_tol / sin theta` (`theta` the smallest angle
//!   between the face and another face at that vertex), which clusters of points on nearly
//!   parallel faces produce (4e-8 m seen for `theta` = 6e-4).
//! - [`hull3`] (with its check) costs about as much as the polar route alone on the vertices
//!   of the example stances' robust regions (`hull3_timing`); the exact hull and the facets
//!   take about equal shares of it. On hundreds of points it is slower than Qhull
//!   (`bench/peers/hull3.md` has the figures): the fitted planes and the check are `O(n F)`.
//! - The routines allocate (they are not meant for inner loops; test points against the
//!   returned half-spaces instead).

mod centre;
mod hull;
mod hull3d;
mod polygon;
mod polyhedron;
pub mod tol;

pub use hull::hull2;
pub use hull3d::hull3;
pub use polygon::{polygon_from_halfplanes, Polygon};
pub use polyhedron::{polyhedron_from_halfspaces, Polyhedron};
pub use tol::PolytopeOptions;

/// What kind of region a half-space intersection is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RegionStatus {
    /// No point satisfies all half-spaces (within the distance tolerance).
    Empty,
    /// A bounded region (possibly lower-dimensional: see the `dim` field of the result).
    Bounded,
    /// The region reaches farther than `far` from the origin; the part inside the box
    /// `[-far, far]^d` is returned and box faces are marked with `None`.
    Unbounded,
}

impl RegionStatus {
    /// Machine-readable name: `"empty"`, `"bounded"` or `"unbounded"`.
    ///
    /// ```
    /// assert_eq!(polycone::polytope::RegionStatus::Bounded.name(), "bounded");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            RegionStatus::Empty => "empty",
            RegionStatus::Bounded => "bounded",
            RegionStatus::Unbounded => "unbounded",
        }
    }
}

impl std::fmt::Display for RegionStatus {
    /// The machine-readable [`RegionStatus::name`].
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Errors of the polytope routines: bad input, with what to fix.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PolytopeError {
    /// A coordinate or offset is NaN or infinite.
    #[error(
        "row {row} of the input has a non-finite value (NaN or infinity): give finite numbers"
    )]
    NonFinite {
        /// Index of the offending row.
        row: usize,
    },
    /// Normal rows and offsets have different lengths.
    #[error("{normals} normal rows but {offsets} offsets: give one offset per half-space")]
    LengthMismatch {
        /// Number of normal rows.
        normals: usize,
        /// Number of offsets.
        offsets: usize,
    },
    /// The hull of an empty point set was asked for.
    #[error("no points given: the convex hull needs at least one point")]
    NoPoints,
    /// The 3-D hull failed its check by both routes (the points are degenerate at the scale
    /// of the tolerances, e.g. a slab a few `dist_tol` thick).
    #[error(
        "the 3-D convex hull failed its check (direct route: {direct}; polar route: {polar}): \
         the points are degenerate at the scale of dist_tol; raise dist_tol and merge_tol to \
         the accuracy of the data"
    )]
    HullCheck {
        /// The first failed check of the direct route.
        direct: &'static str,
        /// The first failed check of the polar route.
        polar: &'static str,
    },
    /// Options out of range.
    #[error("polytope options must be finite and positive, with `far` larger than the tolerances")]
    BadOptions,
}

pub(crate) fn check_rows<const D: usize>(
    normals: &[[f64; D]],
    offsets: &[f64],
) -> Result<(), PolytopeError> {
    if normals.len() != offsets.len() {
        return Err(PolytopeError::LengthMismatch {
            normals: normals.len(),
            offsets: offsets.len(),
        });
    }
    for (row, (a, b)) in normals.iter().zip(offsets).enumerate() {
        if !b.is_finite() || a.iter().any(|x| !x.is_finite()) {
            return Err(PolytopeError::NonFinite { row });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
