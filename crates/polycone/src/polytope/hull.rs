//! Planar points -> convex polygon with its irredundant half-planes (the way back from
//! vertices): Andrew's monotone chain with a distance-filtered orientation test. The 3-D hull
//! is in [`super::hull3d`].

use super::polygon::Polygon;
use super::{PolytopeError, PolytopeOptions, RegionStatus};

pub(crate) fn check_points<const D: usize>(points: &[[f64; D]]) -> Result<(), PolytopeError> {
    if points.is_empty() {
        return Err(PolytopeError::NoPoints);
    }
    for (row, p) in points.iter().enumerate() {
        if p.iter().any(|x| !x.is_finite()) {
            return Err(PolytopeError::NonFinite { row });
        }
    }
    Ok(())
}

/// Convex hull of planar points: vertices counter-clockwise; `active` holds `None` (hull edges
/// come from no input half-plane); get the half-planes with [`Polygon::halfplanes`].
/// Points within `dist_tol` of a hull edge are not vertices. A collinear input gives
/// `dim == 1` (the two extreme points), a single repeated point `dim == 0`.
///
/// ```
/// use polycone::polytope::{hull2, PolytopeOptions};
/// let pts = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5], [0.5, 0.0]];
/// let hull = hull2(&pts, &PolytopeOptions::default()).unwrap();
/// assert_eq!(hull.vertices.len(), 4);
/// assert!((hull.area() - 1.0).abs() < 1e-12);
/// assert_eq!(hull.halfplanes().len(), 4);
/// ```
pub fn hull2(points: &[[f64; 2]], opts: &PolytopeOptions) -> Result<Polygon, PolytopeError> {
    opts.validate()?;
    check_points(points)?;
    let mut pts: Vec<[f64; 2]> = points.to_vec();
    pts.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
    pts.dedup_by(|p, q| (p[0] - q[0]).hypot(p[1] - q[1]) <= opts.merge_tol);
    let left = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        let (dx, dy) = (r[0] - p[0], r[1] - p[1]);
        let len = dx.hypot(dy);
        let cr = (q[0] - p[0]) * dy - (q[1] - p[1]) * dx;
        // r strictly left of p -> q (by more than dist_tol): a counter-clockwise turn at q.
        len > 0.0 && cr / len > opts.dist_tol
    };
    let mut chain: Vec<[f64; 2]> = Vec::with_capacity(2 * pts.len());
    for pass in 0..2 {
        let start = chain.len();
        let iter: Box<dyn Iterator<Item = &[f64; 2]>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for &p in iter {
            while chain.len() >= start + 2
                && !left(chain[chain.len() - 2], chain[chain.len() - 1], p)
            {
                chain.pop();
            }
            chain.push(p);
        }
        chain.pop();
    }
    let dim = match chain.len() {
        0 | 1 => 0,
        2 => 1,
        _ => 2,
    };
    if chain.is_empty() {
        chain.push(pts[0]);
    }
    let active = if dim == 2 {
        vec![None; chain.len()]
    } else {
        Vec::new()
    };
    Ok(Polygon {
        status: RegionStatus::Bounded,
        dim,
        vertices: chain,
        active,
    })
}
