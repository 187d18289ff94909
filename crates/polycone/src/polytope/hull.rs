//! Points -> convex hull with its irredundant half-spaces (the way back from vertices).
//!
//! 2-D: Andrew's monotone chain with a distance-filtered orientation test. 3-D: through the
//! polar. With `c` the centroid, `W` the whitening of the points' covariance (an affine map,
//! so the hull's combinatorics do not change; it makes needles round) and `s` a scale, the
//! facets `n . p <= d` of `conv(P)` are in one-to-one correspondence with the vertices `y` of
//! the polar polyhedron `{y : (W (p_i - c) / s) . y <= 1}`: `n` is `W^T y` normalized, and `d`
//! is read off the points on the facet. The polar is computed by
//! [`super::polyhedron_from_halfspaces`].

use super::polygon::Polygon;
use super::polyhedron::{affine_dim, ccw_order, dedup_points, Polyhedron};
use super::tol::HULL_SAME_FACET;
use super::{polyhedron_from_halfspaces, PolytopeError, PolytopeOptions, RegionStatus};

fn check_points<const D: usize>(points: &[[f64; D]]) -> Result<(), PolytopeError> {
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

/// Convex hull of points in space: vertices, faces counter-clockwise seen from outside, and
/// their planes (`planes[f] = (n, d)`, unit outward `n`, `n . p <= d`); `active` holds `None`.
/// A flat input gives `dim < 3`, the distinct points and no faces.
///
/// Limitation: clusters of nearly coincident points (closer than about 1e-3 of the extent) may
/// split a face into coplanar pieces.
///
/// ```
/// use polycone::polytope::{hull3, PolytopeOptions};
/// let mut pts = vec![];
/// for x in [0.0, 1.0] { for y in [0.0, 1.0] { for z in [0.0, 1.0] { pts.push([x, y, z]); } } }
/// pts.push([0.5, 0.5, 0.5]);
/// let hull = hull3(&pts, &PolytopeOptions::default()).unwrap();
/// assert_eq!((hull.vertices.len(), hull.faces.len()), (8, 6));
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
    let m = pts.len() as f64;
    let mut c = [0.0; 3];
    for p in &pts {
        for k in 0..3 {
            c[k] += p[k] / m;
        }
    }
    // Whitening q = W (p - c), W = L^-1/2 Q^T from the covariance Q L Q^T of the points: an
    // affine map (same hull combinatorics) that makes needles and slabs round, so that the
    // polar below is well conditioned.
    let mut cov = nalgebra::Matrix3::<f64>::zeros();
    for p in &pts {
        let d = nalgebra::Vector3::new(p[0] - c[0], p[1] - c[1], p[2] - c[2]);
        cov += d * d.transpose() / m;
    }
    let eig = cov.symmetric_eigen();
    let mut w = eig.eigenvectors.transpose();
    let mut smax = 0.0f64;
    for k in 0..3 {
        let sd = eig.eigenvalues[k].max(0.0).sqrt();
        smax = smax.max(sd);
        let f = if sd > 0.0 { 1.0 / sd } else { 0.0 };
        for j in 0..3 {
            w[(k, j)] *= f;
        }
    }
    let whiten = |p: &[f64; 3]| {
        let q = w * nalgebra::Vector3::new(p[0] - c[0], p[1] - c[1], p[2] - c[2]);
        [q[0], q[1], q[2]]
    };
    let qs: Vec<[f64; 3]> = pts.iter().map(whiten).collect();
    let s = qs
        .iter()
        .map(|q| (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt())
        .fold(0.0, f64::max);
    let normals: Vec<[f64; 3]> = qs.iter().map(|q| [q[0] / s, q[1] / s, q[2] / s]).collect();
    let ones = vec![1.0; normals.len()];
    // Tolerances in the polar's unit scale: the whitening shrinks lengths by at least 1/smax
    // and the scaling by 1/s (conservative: the smallest resulting tolerance).
    let polar_opts = PolytopeOptions {
        dist_tol: opts.dist_tol / (smax * s),
        merge_tol: opts.merge_tol / (smax * s),
        ..*opts
    };
    let polar = polyhedron_from_halfspaces(&normals, &ones, &polar_opts)?;
    let mut out_vertices: Vec<[f64; 3]> = Vec::new();
    let mut faces = Vec::new();
    let mut planes = Vec::new();
    // Extreme points: the polar's active faces.
    let mut extreme: Vec<usize> = polar.active.iter().flatten().copied().collect();
    extreme.sort_unstable();
    extreme.dedup();
    let mut index = vec![usize::MAX; pts.len()];
    for &e in &extreme {
        index[e] = out_vertices.len();
        out_vertices.push(pts[e]);
    }
    // The input points on facet j are the labels of the polar faces around polar vertex j
    // (topology, not a distance test: robust to the polar's rounding).
    let mut around: Vec<Vec<usize>> = vec![Vec::new(); polar.vertices.len()];
    for (face, label) in polar.faces.iter().zip(&polar.active) {
        if let Some(point) = label {
            for &v in face {
                around[v].push(*point);
            }
        }
    }
    // Facets: (unit normal, points on it); polar vertices a rounding error apart (a polar
    // vertex of degree > 3 split by rounding) give the same facet and are united.
    let mut facets: Vec<([f64; 3], Vec<usize>)> = Vec::new();
    for (y, on) in polar.vertices.iter().zip(&around) {
        // Back from whitened coordinates: y . W (p - c) <= s, so the normal is W^T y.
        let r = w.transpose() * nalgebra::Vector3::new(y[0], y[1], y[2]);
        let ny = r.norm();
        let n = [r[0] / ny, r[1] / ny, r[2] / ny];
        let same = facets.iter_mut().find(|(m, _)| {
            ((n[0] - m[0]).powi(2) + (n[1] - m[1]).powi(2) + (n[2] - m[2]).powi(2)).sqrt()
                <= HULL_SAME_FACET
        });
        match same {
            Some((_, pts_on)) => {
                pts_on.extend(on);
                pts_on.sort_unstable();
                pts_on.dedup();
            }
            None => facets.push((n, on.clone())),
        }
    }
    for (n, on) in &facets {
        let n = *n;
        let on_pts: Vec<[f64; 3]> = on.iter().map(|&e| pts[e]).collect();
        // Offset from the points themselves (the polar vertex carries rounding).
        let d = on_pts
            .iter()
            .map(|p| n[0] * p[0] + n[1] * p[1] + n[2] * p[2])
            .fold(f64::NEG_INFINITY, f64::max);
        let face: Vec<usize> = ccw_order(&on_pts, n)
            .into_iter()
            .map(|k| index[on[k]])
            .collect();
        if face.len() >= 3 {
            faces.push(face);
            planes.push((n, d));
        }
    }
    Ok(Polyhedron {
        status: RegionStatus::Bounded,
        dim: 3,
        vertices: out_vertices,
        active: vec![None; faces.len()],
        faces,
        planes,
    })
}
