//! Points -> 3-D convex hull with its irredundant half-spaces (the way back from vertices).
//!
//! # Math
//!
//! For points `P = {p_i}` in `R^3` the hull `conv(P)` is the polytope whose facets are the
//! planes `n . p = d` that support `P` (`n . p_i <= d` for all `i`) and contain three points of
//! `P` that are not collinear; its vertices are the points of `P` lying on three or more
//! facets. With the tolerance `dist_tol`, facets are *slabs*: a facet is a set of points lying
//! within `dist_tol` below its plane, every point is at most `dist_tol` above every plane, and
//! points within `dist_tol` of the hull of the others are not vertices.
//!
//! # Method
//!
//! 1. The exact hull as triangles ([`incremental`]): quickhull with conflict lists and an exact
//!    orientation predicate ([`predicates`]); points at most `dist_tol` above the current hull
//!    are not added (and are swept again against the final triangles).
//! 2. Facets ([`facets`]): coplanar triangles (within `dist_tol`) merged into maximal facets
//!    with a fitted plane; slivers with fewer than three corners dissolved; the corners and
//!    face loops of the polytope.
//! 3. The check ([`check`]): soundness, vertices among the points, convex faces on their
//!    planes, every edge on two faces, Euler's formula. On failure the polar route
//!    ([`polar`], the previous method) is tried and checked the same way; if it fails too,
//!    [`PolytopeError::HullCheck`] is returned: never an unchecked polytope.

mod check;
mod facets;
mod incremental;
mod polar;
mod predicates;

use super::hull::check_points;
use super::polyhedron::{affine_dim, dedup_points, Polyhedron};
use super::{PolytopeError, PolytopeOptions, RegionStatus};

pub(crate) use check::check_hull;

/// Convex hull of points in space: vertices (input points), faces counter-clockwise seen from
/// outside, and their planes (`planes[f] = (n, d)`, unit outward `n`, `n . p <= d`); `active`
/// holds `None`. A flat input (within `dist_tol`) gives `dim < 3`, the distinct points and no
/// faces.
///
/// Tolerances: points closer than `merge_tol` are one point (one of them is kept);
/// coplanar faces within `dist_tol` are one face; every kept point is at most `dist_tol`
/// above every returned plane (a dropped duplicate at most `dist_tol + merge_tol`), and every
/// face's vertices lie at most `dist_tol` below its plane. The result passes the check of the
/// `check` module (soundness, convex faces, each edge on two faces, Euler's formula) or is
/// an error.
///
/// ```
/// use polycone::polytope::{hull3, PolytopeOptions};
/// let mut pts = vec![];
/// for x in [0.0, 1.0] { for y in [0.0, 1.0] { for z in [0.0, 1.0] { pts.push([x, y, z]); } } }
/// pts.push([0.5, 0.5, 0.5]);
/// pts.push([0.5, 0.5, 1.0]); // on the top face: not a vertex
/// let hull = hull3(&pts, &PolytopeOptions::default()).unwrap();
/// assert_eq!((hull.vertices.len(), hull.faces.len()), (8, 6));
/// for (n, d) in &hull.planes {
///     assert!(pts.iter().all(|p| n[0] * p[0] + n[1] * p[1] + n[2] * p[2] <= d + 1e-9));
/// }
/// ```
pub fn hull3(points: &[[f64; 3]], opts: &PolytopeOptions) -> Result<Polyhedron, PolytopeError> {
    opts.validate()?;
    check_points(points)?;
    let mut pts = points.to_vec();
    dedup_points(&mut pts, opts.merge_tol);
    let dim = affine_dim(&pts, opts.dist_tol);
    if dim < 3 {
        return Ok(Polyhedron {
            status: RegionStatus::Bounded,
            dim,
            vertices: pts,
            faces: Vec::new(),
            active: Vec::new(),
            planes: Vec::new(),
        });
    }
    let direct = hull3_direct(&pts, opts);
    let direct_failure = match direct {
        Ok(poly) => match check_hull(&pts, &poly, opts) {
            Ok(()) => return Ok(poly),
            Err(why) => why,
        },
        Err(why) => why,
    };
    let polar = polar::hull3_polar(&pts, opts)?;
    match check_hull(&pts, &polar, opts) {
        Ok(()) => Ok(polar),
        Err(polar_failure) => Err(PolytopeError::HullCheck {
            direct: direct_failure,
            polar: polar_failure,
        }),
    }
}

/// The direct route alone (steps 1 and 2 of the module doc), unchecked; for the tests and
/// benchmarks.
pub(crate) fn hull3_direct(
    pts: &[[f64; 3]],
    opts: &PolytopeOptions,
) -> Result<Polyhedron, &'static str> {
    let (tris, marginal) = incremental::exact_hull(pts, opts.dist_tol)
        .ok_or("the exact hull found the points coplanar or lost consistency")?;
    facets::polyhedron_from_triangles(pts, &tris, &marginal, opts)
}

/// The polar route alone, unchecked; for the tests.
#[cfg(test)]
pub(crate) fn hull3_polar(
    pts: &[[f64; 3]],
    opts: &PolytopeOptions,
) -> Result<Polyhedron, PolytopeError> {
    polar::hull3_polar(pts, opts)
}

#[cfg(test)]
mod tests;
