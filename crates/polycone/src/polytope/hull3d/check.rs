//! The check every 3-D hull passes before it is returned (cheap, and independent of how the
//! hull was built: it reads only the points and the [`Polyhedron`]).
//!
//! For points `P` and a result with vertices `V`, faces `F` (vertex loops) and planes
//! `n_f . p <= d_f`:
//!
//! 1. soundness: `n_f . p <= d_f + dist_tol` for every point `p` and face `f`, and `|n_f| = 1`;
//! 2. vertices: every vertex is within `merge_tol` of a point of `P`, and lies on three or
//!    more faces;
//! 3. faces: at least three vertices, all within `dist_tol` of the face's plane, forming a
//!    convex loop counter-clockwise around `n_f` (angles swept around its centroid summing
//!    to `2 pi` when the centroid is clear of the edges by more than their in-plane accuracy
//!    below, positive area along `n_f`, all in the face plane, and no vertex inside the chord of its two
//!    neighbours by more than `dist_tol / sin theta`, with `theta` the smallest angle between
//!    the face and another face at that vertex: a corner of nearly parallel planes is only
//!    located to that accuracy in the plane);
//! 4. lattice: every edge is shared by exactly two faces, in opposite directions, two faces
//!    share at most one edge, and Euler's formula `V - E + F = 2` holds.
//!
//! 1 and 2 say the returned region contains the points and has its corners among them; 3 and
//! 4 say the faces close up into the boundary of a convex polyhedron.

use crate::polytope::tol::{HULL_CHECK_UNIT_NORMAL, HULL_CHECK_WINDING};
use crate::polytope::{Polyhedron, PolytopeOptions, RegionStatus};

/// `a <= b`, false when either is NaN (so a NaN fails every check).
fn le(a: f64, b: f64) -> bool {
    a <= b
}
/// `a < b`, false when either is NaN.
fn lt(a: f64, b: f64) -> bool {
    a < b
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Distance from the point `x` to the segment from the origin to `e` (both in one plane).
fn segment_distance(x: [f64; 3], e: [f64; 3]) -> f64 {
    let ee = dot(e, e);
    let t = if ee > 0.0 {
        (dot(x, e) / ee).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let r = sub(x, [t * e[0], t * e[1], t * e[2]]);
    dot(r, r).sqrt()
}

/// `Ok` when `poly` passes the checks of the module doc for the points `pts`, else the first
/// failed check.
pub(crate) fn check_hull(
    pts: &[[f64; 3]],
    poly: &Polyhedron,
    opts: &PolytopeOptions,
) -> Result<(), &'static str> {
    let (nv, nf) = (poly.vertices.len(), poly.faces.len());
    if poly.status != RegionStatus::Bounded || poly.dim != 3 {
        return Err("not a bounded solid");
    }
    if nf < 4 || nv < 4 || poly.planes.len() != nf || poly.active.len() != nf {
        return Err("fewer than four faces or vertices, or inconsistent lengths");
    }
    check_soundness(pts, poly, opts.dist_tol)?;
    check_vertices(pts, poly, opts.merge_tol)?;
    let around = FacesAround::new(poly)?;
    for fi in 0..nf {
        check_face(poly, fi, &around, opts.dist_tol)?;
    }
    check_lattice(poly)
}

/// 1. Soundness: unit normals, finite offsets, and every point within `tol` of the inner side
///    of every face plane.
fn check_soundness(pts: &[[f64; 3]], poly: &Polyhedron, tol: f64) -> Result<(), &'static str> {
    for &(n, d) in &poly.planes {
        if !le((dot(n, n).sqrt() - 1.0).abs(), HULL_CHECK_UNIT_NORMAL) || !d.is_finite() {
            return Err("a face normal is not a unit vector");
        }
        if pts.iter().any(|&p| !le(dot(n, p), d + tol)) {
            return Err("a point lies outside a face plane by more than dist_tol");
        }
    }
    Ok(())
}

/// 2. Vertices are input points (each within `merge_tol` of one).
fn check_vertices(pts: &[[f64; 3]], poly: &Polyhedron, merge_tol: f64) -> Result<(), &'static str> {
    for &v in &poly.vertices {
        let near = pts
            .iter()
            .any(|&p| dot(sub(p, v), sub(p, v)).sqrt() <= merge_tol);
        if !near {
            return Err("a vertex is not an input point");
        }
    }
    Ok(())
}

/// The faces around each vertex, as compressed rows: `faces_at[start[v]..start[v + 1]]`.
struct FacesAround {
    start: Vec<usize>,
    faces_at: Vec<usize>,
}

impl FacesAround {
    /// The rows of `poly`, after checking that every face has at least three vertices with
    /// valid indices and that every vertex lies on at least three faces.
    fn new(poly: &Polyhedron) -> Result<Self, &'static str> {
        let nv = poly.vertices.len();
        let mut start = vec![0usize; nv + 1];
        for face in &poly.faces {
            if face.len() < 3 || face.iter().any(|&v| v >= nv) {
                return Err("a face has fewer than three vertices or a bad index");
            }
            for &v in face {
                start[v + 1] += 1;
            }
        }
        for v in 0..nv {
            start[v + 1] += start[v];
        }
        let mut faces_at = vec![0usize; start[nv]];
        let mut fill = start.clone();
        for (f, face) in poly.faces.iter().enumerate() {
            for &v in face {
                faces_at[fill[v]] = f;
                fill[v] += 1;
            }
        }
        if (0..nv).any(|v| start[v + 1] - start[v] < 3) {
            return Err("a vertex lies on fewer than three faces");
        }
        Ok(Self { start, faces_at })
    }

    /// The faces at vertex `v`.
    fn at(&self, v: usize) -> &[usize] {
        &self.faces_at[self.start[v]..self.start[v + 1]]
    }
}

/// 3. Face `fi`: distinct vertices within `tol` of its plane, forming a convex loop (no vertex
///    inside the chord of its neighbours by more than `tol / sin theta`) that winds once
///    counter-clockwise around the normal (decided when the centroid is clear of the edges by
///    more than their in-plane accuracy) with positive area along it.
fn check_face(
    poly: &Polyhedron,
    fi: usize,
    around: &FacesAround,
    tol: f64,
) -> Result<(), &'static str> {
    let (face, (n, d)) = (&poly.faces[fi], poly.planes[fi]);
    let m = face.len();
    let mut sorted = face.clone();
    sorted.sort_unstable();
    sorted.dedup();
    if sorted.len() != m {
        return Err("a face repeats a vertex");
    }
    let p: Vec<[f64; 3]> = face.iter().map(|&v| poly.vertices[v]).collect();
    if p.iter().any(|&q| !le((dot(n, q) - d).abs(), tol)) {
        return Err("a face vertex is farther than dist_tol from the face plane");
    }
    let mut winding = 0.0;
    // In-plane accuracy of the loop (the largest dist_tol / sin theta of its corners) and
    // the distance from the centroid to the nearest edge.
    let mut accuracy = tol;
    let mut clearance = f64::INFINITY;
    let mut area = [0.0; 3];
    // Vectors projected on the face plane (out-of-plane parts, up to dist_tol, would
    // distort short edges).
    let flat = |x: [f64; 3]| {
        let h = dot(x, n);
        [x[0] - h * n[0], x[1] - h * n[1], x[2] - h * n[2]]
    };
    let mut centre = [0.0; 3];
    for q in &p {
        for k in 0..3 {
            centre[k] += q[k] / m as f64;
        }
    }
    for i in 0..m {
        let (a, b, c) = (p[i], p[(i + 1) % m], p[(i + 2) % m]);
        let e = flat(sub(b, a));
        if !lt(0.0, dot(e, e)) {
            return Err("a face has a zero-length edge");
        }
        // Dent depth of b: its signed distance to the left of (inside) the chord a -> c,
        // in the face plane (at most |b - a|, so short edges cannot inflate it). The
        // in-plane position of b, a corner of this face and of faces at angles theta to
        // it, is known to dist_tol / sin(theta): the allowed depth.
        let chord = flat(sub(c, a));
        let lc = dot(chord, chord).sqrt();
        let vb = face[(i + 1) % m];
        let sin_min = around
            .at(vb)
            .iter()
            .filter(|&&g| g != fi)
            .map(|&g| {
                let x = cross(n, poly.planes[g].0);
                dot(x, x).sqrt()
            })
            .fold(1.0, f64::min);
        if lt(0.0, lc) && dot(n, cross(chord, flat(sub(b, a)))) / lc * sin_min > tol {
            return Err("a face is not convex (a vertex inside by more than dist_tol / sin)");
        }
        accuracy = accuracy.max(tol / sin_min);
        clearance = clearance.min(segment_distance(flat(sub(centre, a)), e));
        // The loop seen from its centroid: the angle swept from a to b (short edges in
        // a cluster far from the centroid sweep tiny angles whatever their direction).
        let (ra, rb) = (flat(sub(a, centre)), flat(sub(b, centre)));
        winding += dot(n, cross(ra, rb)).atan2(dot(ra, rb));
        let w = cross(sub(a, p[0]), sub(b, p[0]));
        for k in 0..3 {
            area[k] += 0.5 * w[k];
        }
    }
    // The winding is decided only when the centroid is clear of the edges by more than
    // their accuracy (not for needle faces, whose centroid lies within it).
    if clearance > accuracy && !le((winding - std::f64::consts::TAU).abs(), HULL_CHECK_WINDING) {
        return Err("a face loop does not wind once around its normal");
    }
    if !lt(0.0, dot(area, n)) {
        return Err("a face has no positive area along its normal");
    }
    Ok(())
}

/// 4. Lattice: every directed edge appears once and its reverse on another face, two faces
///    share at most one edge, and Euler's formula `V - E + F = 2` holds.
fn check_lattice(poly: &Polyhedron) -> Result<(), &'static str> {
    let (nv, nf) = (poly.vertices.len(), poly.faces.len());
    // Directed edges (a, b, face), sorted.
    let mut edge_face: Vec<(usize, usize, usize)> = Vec::new();
    for (f, face) in poly.faces.iter().enumerate() {
        let m = face.len();
        for i in 0..m {
            edge_face.push((face[i], face[(i + 1) % m], f));
        }
    }
    edge_face.sort_unstable();
    if edge_face
        .windows(2)
        .any(|w| (w[0].0, w[0].1) == (w[1].0, w[1].1))
    {
        return Err("a directed edge appears twice");
    }
    let mut face_pairs: Vec<(usize, usize)> = Vec::with_capacity(edge_face.len());
    for &(a, b, f) in &edge_face {
        let Ok(i) = edge_face.binary_search_by(|e| (e.0, e.1).cmp(&(b, a))) else {
            return Err("an edge lies on only one face");
        };
        let g = edge_face[i].2;
        if f == g {
            return Err("an edge has the same face on both sides");
        }
        face_pairs.push((f.min(g), f.max(g)));
    }
    // Each shared edge gives its face pair twice (once per direction).
    face_pairs.sort_unstable();
    if face_pairs.windows(3).any(|w| w[0] == w[2]) {
        return Err("two faces share more than one edge");
    }
    let ne = edge_face.len() / 2;
    if nv + nf != ne + 2 {
        return Err("Euler's formula V - E + F = 2 fails");
    }
    Ok(())
}
