//! The polar route to the 3-D hull (the fallback of [`super::hull3`]).
//!
//! With `c` the centroid, `W` the whitening of the points' covariance (an affine map, so the
//! hull's combinatorics do not change; it makes needles round) and `s` a scale, the facets
//! `n . p <= d` of `conv(P)` are in one-to-one correspondence with the vertices `y` of the
//! polar polyhedron `{y : (W (p_i - c) / s) . y <= 1}`: `n` is `W^T y` normalized, and `d` is
//! read off the points on the facet. The polar is computed by
//! [`crate::polytope::polyhedron_from_halfspaces`]. Its rounding can split a facet into
//! coplanar pieces when points cluster (closer than about 1e-3 of the extent): the result is
//! checked like the direct route's.

use crate::polytope::polyhedron::{ccw_order, Polyhedron};
use crate::polytope::tol::HULL_SAME_FACET;
use crate::polytope::{polyhedron_from_halfspaces, PolytopeError, PolytopeOptions, RegionStatus};

/// The hull of `pts` (distinct points spanning space) through the polar.
pub(crate) fn hull3_polar(
    pts: &[[f64; 3]],
    opts: &PolytopeOptions,
) -> Result<Polyhedron, PolytopeError> {
    let m = pts.len() as f64;
    let mut c = [0.0; 3];
    for p in pts {
        for k in 0..3 {
            c[k] += p[k] / m;
        }
    }
    // Whitening q = W (p - c), W = L^-1/2 Q^T from the covariance Q L Q^T of the points: an
    // affine map (same hull combinatorics) that makes needles and slabs round, so that the
    // polar below is well conditioned.
    let mut cov = nalgebra::Matrix3::<f64>::zeros();
    for p in pts {
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
