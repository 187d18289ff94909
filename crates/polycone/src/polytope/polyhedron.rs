//! Half-spaces `a_i . p <= b_i` in `R^3` -> convex polyhedron (face-by-face clipping of the far
//! box with a cap face per cut, see the module doc of [`crate::polytope`]).

use super::tol::{BOX_ROUNDING, POLISH_MAX_MOVE, REFINE_MARGIN, REFINE_TRIES};
use super::{check_rows, PolytopeError, PolytopeOptions, RegionStatus};

/// A convex polyhedron, the result of [`polyhedron_from_halfspaces`].
#[derive(Debug, Clone, PartialEq)]
pub struct Polyhedron {
    /// Empty, bounded or unbounded (clipped to the far box).
    pub status: RegionStatus,
    /// Affine dimension of the region (3 for a solid; 2, 1, 0 for flat results, which have no
    /// faces). Meaningless when `status` is `Empty`.
    pub dim: usize,
    /// Vertices `[x, y, z]`.
    pub vertices: Vec<[f64; 3]>,
    /// Faces as loops of vertex indices, counter-clockwise seen from outside (the right-hand
    /// rule around the loop gives the outward normal). Empty unless `dim == 3`.
    pub faces: Vec<Vec<usize>>,
    /// `active[f]`: the input half-space on which face `f` lies, or `None` for a far-box face.
    pub active: Vec<Option<usize>>,
    /// `planes[f] = (n, d)`: unit outward normal and offset of face `f` (`n . p <= d`).
    pub planes: Vec<([f64; 3], f64)>,
}

#[derive(Debug, Clone)]
struct Face {
    label: Option<usize>,
    n: [f64; 3],
    d: f64,
    /// Indices into the shared vertex list.
    loop_: Vec<usize>,
}

#[inline]
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
#[inline]
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline]
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
#[inline]
fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// The permutation that orders points lying in the plane with unit normal `n`
/// counter-clockwise around `n`.
pub(crate) fn ccw_order(pts: &[[f64; 3]], n: [f64; 3]) -> Vec<usize> {
    let mut c = [0.0; 3];
    for p in pts.iter() {
        for k in 0..3 {
            c[k] += p[k];
        }
    }
    let m = pts.len().max(1) as f64;
    let c = [c[0] / m, c[1] / m, c[2] / m];
    // An in-plane basis (u, v) with u x v = n.
    let helper = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let u = cross(helper, n);
    let un = norm(u);
    let u = [u[0] / un, u[1] / un, u[2] / un];
    let v = cross(n, u);
    let angle = |p: &[f64; 3]| {
        let d = sub(*p, c);
        dot(d, v).atan2(dot(d, u))
    };
    let mut idx: Vec<usize> = (0..pts.len()).collect();
    idx.sort_by(|&p, &q| angle(&pts[p]).total_cmp(&angle(&pts[q])));
    idx
}

/// Intersects the half-spaces `normals[i] . p <= offsets[i]`.
///
/// Rows are normalized first; rows with a (near) zero normal are constant constraints. See
/// [`Polyhedron`] for the outputs and [`crate::polytope`] for the semantics of the tolerances.
///
/// ```
/// use polycone::polytope::{polyhedron_from_halfspaces, PolytopeOptions, RegionStatus};
/// // The unit cube [0, 1]^3 plus a redundant plane.
/// let a = [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0],
///          [0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 1.0, 1.0]];
/// let b = [1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 5.0];
/// let cube = polyhedron_from_halfspaces(&a, &b, &PolytopeOptions::default()).unwrap();
/// assert_eq!(cube.status, RegionStatus::Bounded);
/// assert_eq!((cube.vertices.len(), cube.faces.len()), (8, 6));
/// assert!(!cube.active.contains(&Some(6)));
/// ```
pub fn polyhedron_from_halfspaces(
    normals: &[[f64; 3]],
    offsets: &[f64],
    opts: &PolytopeOptions,
) -> Result<Polyhedron, PolytopeError> {
    opts.validate()?;
    check_rows(normals, offsets)?;
    // Far from the origin: the same region about a point of it, moved back (`centre`).
    Ok(super::centre::recentred(normals, offsets, opts, |b, o| {
        about_origin(normals, b, o)
    }))
}

/// [`polyhedron_from_halfspaces`] for rows near the origin.
fn about_origin(normals: &[[f64; 3]], offsets: &[f64], opts: &PolytopeOptions) -> Polyhedron {
    let far = [[-opts.far; 3], [opts.far; 3]];
    let (first, raw_bounds) = clip_box(normals, offsets, far, opts);
    if first.status != RegionStatus::Bounded || first.dim != 3 {
        return first;
    }
    // Second pass from a box just around the result: the clipping interpolates along box
    // edges, so a box of the result's size keeps the rounding at the result's scale. The box
    // comes from every clipped point (before merging), so nothing the first pass rounded away
    // can fall outside it; should the second pass still touch the box, it grows.
    let [lo, hi] = raw_bounds;
    let ext = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    let mut margin = REFINE_MARGIN * ext + opts.dist_tol;
    for _ in 0..REFINE_TRIES {
        let tight = [
            [lo[0] - margin, lo[1] - margin, lo[2] - margin],
            [hi[0] + margin, hi[1] + margin, hi[2] + margin],
        ];
        // Half-spaces with slack above the margin at every corner of the tight box cannot cut
        // the region (it lies inside the box): skip them in the second pass.
        let mut keep: Vec<usize> = Vec::with_capacity(normals.len());
        for (i, (a, &b)) in normals.iter().zip(offsets).enumerate() {
            let na = norm(*a);
            if na < opts.zero_normal {
                keep.push(i);
                continue;
            }
            let worst: f64 = (0..3)
                .map(|k| (a[k] * tight[0][k]).max(a[k] * tight[1][k]))
                .sum();
            if worst - b > -margin * na {
                keep.push(i);
            }
        }
        let sub_n: Vec<[f64; 3]> = keep.iter().map(|&i| normals[i]).collect();
        let sub_b: Vec<f64> = keep.iter().map(|&i| offsets[i]).collect();
        let (mut second, _) = clip_box(&sub_n, &sub_b, tight, opts);
        if second.status == RegionStatus::Bounded && second.dim == 3 {
            for a in second.active.iter_mut().flatten() {
                *a = keep[*a];
            }
            return second;
        }
        margin *= 4.0;
    }
    first
}

fn clip_box(
    normals: &[[f64; 3]],
    offsets: &[f64],
    bounds: [[f64; 3]; 2],
    opts: &PolytopeOptions,
) -> (Polyhedron, [[f64; 3]; 2]) {
    let empty = Polyhedron {
        status: RegionStatus::Empty,
        dim: 0,
        vertices: Vec::new(),
        faces: Vec::new(),
        active: Vec::new(),
        planes: Vec::new(),
    };
    let (mut verts, mut faces) = far_box(bounds);
    let mut kept: Vec<Face> = Vec::with_capacity(32);
    let mut cut: Vec<usize> = Vec::with_capacity(32);
    let mut cut_pts: Vec<[f64; 3]> = Vec::with_capacity(32);
    let mut loop_idx: Vec<usize> = Vec::with_capacity(16);
    let mut dist: Vec<f64> = Vec::with_capacity(64);
    // Edge (i, j) with i < j -> index of its intersection vertex, for the current cut.
    let mut edge_cache: Vec<((usize, usize), usize)> = Vec::with_capacity(32);
    // Decisions finer than the rounding of points at the box's scale are noise: in the huge
    // boxes of the search for an empty first pass's region, they split every face loop
    // (millions of vertices, minutes of work). At the default box this is `dist_tol` itself.
    let extent = (0..3)
        .map(|k| bounds[0][k].abs().max(bounds[1][k].abs()))
        .fold(0.0, f64::max);
    let tol = opts.dist_tol.max(BOX_ROUNDING * extent);
    for (i, (a, &b)) in normals.iter().zip(offsets).enumerate() {
        let na = norm(*a);
        if na < opts.zero_normal {
            if b < -opts.dist_tol {
                return (empty, bounds);
            }
            continue;
        }
        let n = [a[0] / na, a[1] / na, a[2] / na];
        let d = b / na;
        dist.clear();
        dist.extend(verts.iter().map(|&p| dot(n, p) - d));
        // Only vertices still used by some face matter.
        let any_out = faces.iter().any(|f| f.loop_.iter().any(|&v| dist[v] > tol));
        if !any_out {
            continue;
        }
        kept.clear();
        cut.clear();
        edge_cache.clear();
        for f in faces.drain(..) {
            // Faces entirely inside stay as they are (no copy); their on-plane vertices go to
            // the cap.
            if f.loop_.iter().all(|&v| dist[v] <= tol) {
                cut.extend(f.loop_.iter().copied().filter(|&v| dist[v] >= -tol));
                kept.push(f);
                continue;
            }
            loop_idx.clear();
            let m = f.loop_.len();
            for k in 0..m {
                let (p, q) = (f.loop_[k], f.loop_[(k + 1) % m]);
                let (sp, sq) = (dist[p], dist[q]);
                if sp <= tol {
                    loop_idx.push(p);
                    if sp >= -tol {
                        cut.push(p);
                    }
                }
                // A crossing strictly inside -> outside (either way): one new shared vertex.
                if (sp < -tol && sq > tol) || (sp > tol && sq < -tol) {
                    let key = (p.min(q), p.max(q));
                    let x = match edge_cache.iter().find(|(k, _)| *k == key) {
                        Some(&(_, x)) => x,
                        None => {
                            let (vp, vq) = (verts[p], verts[q]);
                            let t = sp / (sp - sq);
                            verts.push([
                                vp[0] + t * (vq[0] - vp[0]),
                                vp[1] + t * (vq[1] - vp[1]),
                                vp[2] + t * (vq[2] - vp[2]),
                            ]);
                            dist.push(0.0);
                            edge_cache.push((key, verts.len() - 1));
                            verts.len() - 1
                        }
                    };
                    loop_idx.push(x);
                    cut.push(x);
                }
            }
            if loop_idx.len() >= 3 {
                kept.push(Face {
                    loop_: loop_idx.clone(),
                    ..f
                });
            }
        }
        std::mem::swap(&mut faces, &mut kept);
        cut.sort_unstable();
        cut.dedup();
        if cut.len() >= 3 {
            // Order the cap counter-clockwise around n (seen from outside).
            cut_pts.clear();
            cut_pts.extend(cut.iter().map(|&v| verts[v]));
            let order = ccw_order(&cut_pts, n);
            faces.push(Face {
                label: Some(i),
                n,
                d,
                loop_: order.iter().map(|&k| cut[k]).collect(),
            });
        }
        if faces.is_empty() {
            // Everything was cut away, except possibly a flat piece.
            if cut.is_empty() {
                return (empty, bounds);
            }
            // The region is flat: keep clipping its boundary loop by the remaining planes.
            let pts: Vec<[f64; 3]> = cut.iter().map(|&v| verts[v]).collect();
            let order = ccw_order(&pts, n);
            let lp: Vec<[f64; 3]> = order.iter().map(|&k| pts[k]).collect();
            let rest = i + 1;
            return match clip_flat(lp, &normals[rest..], &offsets[rest..], opts) {
                Some(lp) => (flat(lp, opts), bounds),
                None => (empty, bounds),
            };
        }
    }
    let mut raw = [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]];
    for f in &faces {
        for &v in &f.loop_ {
            for k in 0..3 {
                raw[0][k] = raw[0][k].min(verts[v][k]);
                raw[1][k] = raw[1][k].max(verts[v][k]);
            }
        }
    }
    (finish(verts, faces, opts), raw)
}

/// Clips a flat convex loop (a polygon in some plane, a segment as a 2-point loop, or a point)
/// by half-spaces; `None` when nothing is left.
fn clip_flat(
    mut lp: Vec<[f64; 3]>,
    normals: &[[f64; 3]],
    offsets: &[f64],
    opts: &PolytopeOptions,
) -> Option<Vec<[f64; 3]>> {
    let tol = opts.dist_tol;
    let mut next = Vec::with_capacity(lp.len() + 2);
    for (a, &b) in normals.iter().zip(offsets) {
        let na = norm(*a);
        if na < opts.zero_normal {
            if b < -tol {
                return None;
            }
            continue;
        }
        let n = [a[0] / na, a[1] / na, a[2] / na];
        let d = b / na;
        let m = lp.len();
        next.clear();
        for k in 0..m {
            let (p, q) = (lp[k], lp[(k + 1) % m]);
            let (sp, sq) = (dot(n, p) - d, dot(n, q) - d);
            if sp <= tol {
                next.push(p);
            }
            if m > 1 && ((sp < -tol && sq > tol) || (sp > tol && sq < -tol)) {
                let t = sp / (sp - sq);
                next.push([
                    p[0] + t * (q[0] - p[0]),
                    p[1] + t * (q[1] - p[1]),
                    p[2] + t * (q[2] - p[2]),
                ]);
            }
        }
        std::mem::swap(&mut lp, &mut next);
        if lp.is_empty() {
            return None;
        }
    }
    Some(lp)
}

fn far_box(bounds: [[f64; 3]; 2]) -> (Vec<[f64; 3]>, Vec<Face>) {
    // Vertex k has bit 0 -> x, bit 1 -> y, bit 2 -> z set to the upper bound.
    let verts: Vec<[f64; 3]> = (0..8)
        .map(|k| {
            let s = |bit: usize, c: usize| {
                if k & bit != 0 {
                    bounds[1][c]
                } else {
                    bounds[0][c]
                }
            };
            [s(1, 0), s(2, 1), s(4, 2)]
        })
        .collect();
    let mk = |n: [f64; 3], loop_: [usize; 4]| Face {
        label: None,
        n,
        d: dot(n, verts[loop_[0]]),
        loop_: loop_.to_vec(),
    };
    let faces = vec![
        mk([1.0, 0.0, 0.0], [1, 3, 7, 5]),
        mk([-1.0, 0.0, 0.0], [0, 4, 6, 2]),
        mk([0.0, 1.0, 0.0], [2, 6, 7, 3]),
        mk([0.0, -1.0, 0.0], [0, 1, 5, 4]),
        mk([0.0, 0.0, 1.0], [4, 5, 7, 6]),
        mk([0.0, 0.0, -1.0], [0, 2, 3, 1]),
    ];
    (verts, faces)
}

/// Removes points within `tol` of a kept point, keeping the order of the others. A sweep
/// along x (only points within `tol` in x can be merged): `O(n log n)` unless many points
/// share an x within `tol`.
pub(crate) fn dedup_points(pts: &mut Vec<[f64; 3]>, tol: f64) {
    let mut order: Vec<usize> = (0..pts.len()).collect();
    order.sort_by(|&a, &b| pts[a][0].total_cmp(&pts[b][0]).then(a.cmp(&b)));
    let mut keep = vec![true; pts.len()];
    for k in 0..order.len() {
        let p = pts[order[k]];
        let mut j = k;
        while j > 0 {
            j -= 1;
            let q = pts[order[j]];
            if p[0] - q[0] > tol {
                break;
            }
            if keep[order[j]] && norm(sub(p, q)) <= tol {
                keep[order[k]] = false;
                break;
            }
        }
    }
    let mut i = 0;
    pts.retain(|_| {
        i += 1;
        keep[i - 1]
    });
}

/// Affine dimension of a point set, with a distance tolerance.
pub(crate) fn affine_dim(pts: &[[f64; 3]], tol: f64) -> usize {
    if pts.is_empty() {
        return 0;
    }
    let o = pts[0];
    // Farthest point from o.
    let (mut best, mut e1) = (0.0, [0.0; 3]);
    for &p in pts {
        let d = sub(p, o);
        if norm(d) > best {
            best = norm(d);
            e1 = d;
        }
    }
    if best <= tol {
        return 0;
    }
    let e1 = [e1[0] / best, e1[1] / best, e1[2] / best];
    // Farthest point from the line.
    let (mut best2, mut e2) = (0.0, [0.0; 3]);
    for &p in pts {
        let d = sub(p, o);
        let w = cross(e1, d);
        if norm(w) > best2 {
            best2 = norm(w);
            e2 = w;
        }
    }
    if best2 <= tol {
        return 1;
    }
    let nrm = [e2[0] / best2, e2[1] / best2, e2[2] / best2];
    if pts.iter().any(|&p| dot(nrm, sub(p, o)).abs() > tol) {
        3
    } else {
        2
    }
}

fn flat(mut pts: Vec<[f64; 3]>, opts: &PolytopeOptions) -> Polyhedron {
    dedup_points(&mut pts, opts.merge_tol);
    let dim = affine_dim(&pts, opts.dist_tol).min(2);
    let far = pts
        .iter()
        .any(|p| p.iter().any(|x| x.abs() >= opts.far - opts.dist_tol));
    Polyhedron {
        status: if far {
            RegionStatus::Unbounded
        } else {
            RegionStatus::Bounded
        },
        dim,
        vertices: pts,
        faces: Vec::new(),
        active: Vec::new(),
        planes: Vec::new(),
    }
}

fn finish(mut vertices: Vec<[f64; 3]>, faces: Vec<Face>, opts: &PolytopeOptions) -> Polyhedron {
    // Weld vertices closer than merge_tol (a plane through an existing corner can leave two
    // copies of it a rounding error apart).
    let mut alias: Vec<usize> = (0..vertices.len()).collect();
    let mut in_use = vec![false; vertices.len()];
    for f in &faces {
        for &v in &f.loop_ {
            in_use[v] = true;
        }
    }
    // Sweep along x: only vertices within merge_tol in x can be merged (O(L log L)).
    let mut live: Vec<usize> = (0..vertices.len()).filter(|&v| in_use[v]).collect();
    live.sort_by(|&a, &b| vertices[a][0].total_cmp(&vertices[b][0]).then(a.cmp(&b)));
    for k in 0..live.len() {
        let v = live[k];
        let mut j = k;
        while j > 0 {
            j -= 1;
            let w = live[j];
            if vertices[v][0] - vertices[w][0] > opts.merge_tol {
                break;
            }
            if alias[w] == w && norm(sub(vertices[v], vertices[w])) <= opts.merge_tol {
                alias[v] = w;
                break;
            }
        }
    }
    let mut loops: Vec<Vec<usize>> = faces
        .iter()
        .map(|f| f.loop_.iter().map(|&v| alias[v]).collect())
        .collect();
    for l in &mut loops {
        l.dedup();
        if l.len() > 1 && l.first() == l.last() {
            l.pop();
        }
    }
    let mut used = vec![false; vertices.len()];
    for l in &loops {
        for &v in l {
            used[v] = true;
        }
    }
    let used_pts: Vec<[f64; 3]> = (0..vertices.len())
        .filter(|&v| used[v])
        .map(|v| vertices[v])
        .collect();
    let dim = affine_dim(&used_pts, opts.dist_tol);
    if dim < 3 {
        return flat(used_pts, opts);
    }
    // A vertex is a corner iff the unit normals of its incident faces have rank 3.
    let mut incident: Vec<Vec<usize>> = vec![Vec::new(); vertices.len()];
    for (fi, l) in loops.iter().enumerate() {
        for &v in l {
            incident[v].push(fi);
        }
    }
    let corner: Vec<bool> = incident
        .iter()
        .map(|inc| {
            let ns: Vec<[f64; 3]> = inc.iter().map(|&f| faces[f].n).collect();
            rank3(&ns, opts.rank_tol)
        })
        .collect();
    // Polish: recompute each corner from its incident planes (least squares on the normal
    // equations), since clipping interpolates along edges of the far box.
    for (v, inc) in incident.iter().enumerate() {
        if !corner[v] {
            continue;
        }
        let mut m = nalgebra::Matrix3::<f64>::zeros();
        let mut r = nalgebra::Vector3::<f64>::zeros();
        for &f in inc {
            let nv = nalgebra::Vector3::from(faces[f].n);
            m += nv * nv.transpose();
            r += nv * faces[f].d;
        }
        if let Some(p) = m.cholesky().map(|c| c.solve(&r)) {
            // Safety net as in 2-D: reject a polish that moves the corner by more than the
            // clipping error (wrong incident planes).
            // The clipping error grows as 1 / sqrt(smallest eigenvalue of N^T N).
            let old = vertices[v];
            // Cheap lower bound of the smallest eigenvalue: det / trace^2 (no eigen solver).
            let tr = m.trace();
            let lmin = (m.determinant().max(0.0) / (tr * tr).max(f64::MIN_POSITIVE)).sqrt();
            let scale = (1.0 + old.iter().fold(0.0f64, |a, x| a.max(x.abs()))) / lmin.min(1.0);
            let moved = norm(sub([p[0], p[1], p[2]], old));
            if p.iter().all(|x| x.is_finite()) && moved <= POLISH_MAX_MOVE * scale {
                vertices[v] = [p[0], p[1], p[2]];
            }
        }
    }
    // Renumber corners, rebuild loops.
    let mut new_index = vec![usize::MAX; vertices.len()];
    let mut out_vertices = Vec::new();
    for (v, &c) in corner.iter().enumerate() {
        if c {
            new_index[v] = out_vertices.len();
            out_vertices.push(vertices[v]);
        }
    }
    let mut out_faces = Vec::new();
    let mut active = Vec::new();
    let mut planes = Vec::new();
    for (f, l) in faces.iter().zip(&loops) {
        let nl: Vec<usize> = l
            .iter()
            .filter(|&&v| corner[v])
            .map(|&v| new_index[v])
            .collect();
        if nl.len() >= 3 {
            out_faces.push(nl);
            active.push(f.label);
            planes.push((f.n, f.d));
        }
    }
    let status = if active.iter().any(|a| a.is_none()) {
        RegionStatus::Unbounded
    } else {
        RegionStatus::Bounded
    };
    Polyhedron {
        status,
        dim: 3,
        vertices: out_vertices,
        faces: out_faces,
        active,
        planes,
    }
}

fn rank3(ns: &[[f64; 3]], tol: f64) -> bool {
    if ns.len() < 3 {
        return false;
    }
    let a = ns[0];
    let (mut best, mut b) = (0.0, a);
    for &n in ns {
        let c = norm(cross(a, n));
        if c > best {
            best = c;
            b = n;
        }
    }
    if best <= tol {
        return false;
    }
    let ab = cross(a, b);
    ns.iter().any(|&n| dot(ab, n).abs() / best > tol)
}

impl super::centre::Region<3> for Polyhedron {
    fn status(&self) -> RegionStatus {
        self.status
    }
    fn vertices(&self) -> &[[f64; 3]] {
        &self.vertices
    }
    fn translate(&mut self, c: &[f64; 3]) {
        for v in &mut self.vertices {
            for k in 0..3 {
                v[k] += c[k];
            }
        }
        for (n, d) in &mut self.planes {
            *d += n[0] * c[0] + n[1] * c[1] + n[2] * c[2];
        }
    }
}
