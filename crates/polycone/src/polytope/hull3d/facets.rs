//! From the triangulated exact hull to facets: coplanar triangles (within `dist_tol`) merged
//! into maximal facets with a fitted plane, and the face lattice of the result.
//!
//! A *facet* is a connected set of hull triangles whose vertices lie in a slab of width
//! `dist_tol` below a plane `n . p = d` (the top of the slab, so the facet's vertices are
//! inside its half-space), with every point at most `dist_tol` above that plane. Facets are
//! found in two passes:
//!
//! 1. growth: from the largest unassigned triangle (its plane is the best determined), absorb
//!    neighbouring triangles while the vertices stay in a `dist_tol` slab along the seed's
//!    normal; then fit the normal (least squares in the seed's frame) and keep the better of
//!    the seed and the fitted normal;
//! 2. union: adjacent facets whose union still fits such a slab (most parallel pairs first)
//!    are merged, until no adjacent pair can be (the facets are maximal in that sense,
//!    whatever the seeds).
//!
//! The polytope: a vertex is a *corner* when it lies on three or more facets (vertices inside
//! a facet or on the boundary between two facets are within `dist_tol` of their planes and are
//! dropped); a face is the loop of corners along the boundary of its facet, in the
//! counter-clockwise orientation of the triangles. A facet with fewer than three corners (a
//! sliver along the common edge of two faces) is dissolved into a neighbour. A facet whose
//! boundary is not one simple loop (a hole or a pinch) is an error: the caller falls back.

#[cfg(doc)]
use super::incremental::exact_hull;
use super::incremental::{tri_plane, Tri, NONE};
use crate::polytope::{Polyhedron, PolytopeOptions, RegionStatus};

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: [f64; 3]) -> Option<[f64; 3]> {
    let l = dot(a, a).sqrt();
    (l > 0.0 && l.is_finite()).then(|| [a[0] / l, a[1] / l, a[2] / l])
}

/// A facet under construction.
struct Facet {
    /// Vertices of its triangles (sorted, distinct).
    verts: Vec<u32>,
    /// Unit outward normal and offset of its plane.
    n: [f64; 3],
    d: f64,
    area: f64,
}

/// The plane of the vertices `verts` for the normal `n`: offset at the top of their slab, if
/// the slab is at most `tol` wide and no point of `support` is more than `tol` above it
/// (`support`: the hull's vertices and the marginal points, where every linear function
/// takes its maximum over all the points).
fn slab(pts: &[[f64; 3]], support: &[u32], verts: &[u32], n: [f64; 3], tol: f64) -> Option<f64> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &v in verts {
        let h = dot(n, pts[v as usize]);
        lo = lo.min(h);
        hi = hi.max(h);
    }
    if hi - lo > tol || (hi - lo).is_nan() {
        return None;
    }
    support
        .iter()
        .all(|&p| dot(n, pts[p as usize]) <= hi + tol)
        .then_some(hi)
}

/// Least-squares plane of `verts` around the normal `n0`: heights `h = n0 . (p - c)` fitted as
/// `a x + b y` in an orthonormal frame `(e1, e2)` of the plane (`c` the centroid), normal
/// `n0 - a e1 - b e2`. Well conditioned in the seed's frame; `None` for collinear vertices.
fn fit_normal(pts: &[[f64; 3]], verts: &[u32], n0: [f64; 3]) -> Option<[f64; 3]> {
    let helper = if n0[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let e1 = unit(cross(helper, n0))?;
    let e2 = cross(n0, e1);
    let m = verts.len() as f64;
    let mut c = [0.0; 3];
    for &v in verts {
        for k in 0..3 {
            c[k] += pts[v as usize][k] / m;
        }
    }
    let (mut sxx, mut sxy, mut syy, mut sxh, mut syh) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &v in verts {
        let p = pts[v as usize];
        let q = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
        let (x, y, h) = (dot(e1, q), dot(e2, q), dot(n0, q));
        sxx += x * x;
        sxy += x * y;
        syy += y * y;
        sxh += x * h;
        syh += y * h;
    }
    let det = sxx * syy - sxy * sxy;
    if det.is_nan() || det <= 0.0 {
        return None;
    }
    let a = (sxh * syy - syh * sxy) / det;
    let b = (syh * sxx - sxh * sxy) / det;
    unit([
        n0[0] - a * e1[0] - b * e2[0],
        n0[1] - a * e1[1] - b * e2[1],
        n0[2] - a * e1[2] - b * e2[2],
    ])
}

/// The best plane of `verts` among the normal `n0` and its least-squares refinement: the one
/// with the thinner slab that satisfies [`slab`].
fn best_plane(
    pts: &[[f64; 3]],
    support: &[u32],
    verts: &[u32],
    n0: [f64; 3],
    tol: f64,
) -> Option<([f64; 3], f64)> {
    let width = |n: [f64; 3]| {
        let hs = verts.iter().map(|&v| dot(n, pts[v as usize]));
        let (lo, hi) = hs.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
            (l.min(x), h.max(x))
        });
        hi - lo
    };
    let mut cands = vec![n0];
    if let Some(n1) = fit_normal(pts, verts, n0) {
        if width(n1) < width(n0) {
            cands.insert(0, n1);
        } else {
            cands.push(n1);
        }
    }
    cands
        .into_iter()
        .find_map(|n| slab(pts, support, verts, n, tol).map(|d| (n, d)))
}

fn union_sorted(a: &[u32], b: &[u32]) -> Vec<u32> {
    let mut u = Vec::with_capacity(a.len() + b.len());
    u.extend_from_slice(a);
    u.extend_from_slice(b);
    u.sort_unstable();
    u.dedup();
    u
}

/// A boundary edge of a facet: `(facet, start vertex, end vertex, facet beyond)`.
type Edge = (usize, u32, u32, usize);

/// Corners (vertices on three or more facets) and boundary edges sorted by facet then start
/// vertex, for the facet of each triangle `face_of`.
fn lattice(
    tris: &[Tri],
    face_of: &[usize],
    n_points: usize,
) -> Result<(Vec<bool>, Vec<Edge>), &'static str> {
    // Facets around each vertex (the first three distinct ones).
    let mut around: Vec<[usize; 3]> = vec![[usize::MAX; 3]; n_points];
    for (t, tri) in tris.iter().enumerate() {
        for &v in &tri.v {
            let slots = &mut around[v as usize];
            let f = face_of[t];
            if let Some(k) = slots.iter().position(|&x| x == f || x == usize::MAX) {
                slots[k] = f;
            }
        }
    }
    let corner: Vec<bool> = around.iter().map(|a| a[2] != usize::MAX).collect();
    let mut boundary: Vec<Edge> = Vec::with_capacity(3 * tris.len());
    for (t, tri) in tris.iter().enumerate() {
        for k in 0..3 {
            let s = tri.nb[k];
            if s == NONE {
                return Err("the triangulated hull is not closed");
            }
            let (f, g) = (face_of[t], face_of[s as usize]);
            if f != g {
                boundary.push((f, tri.v[k], tri.v[(k + 1) % 3], g));
            }
        }
    }
    boundary.sort_unstable();
    if boundary
        .windows(2)
        .any(|w| w[0].0 == w[1].0 && w[0].1 == w[1].1)
    {
        return Err("a facet touches itself at a vertex (pinched boundary)");
    }
    Ok((corner, boundary))
}

fn find(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

/// Facets and face lattice of the triangulated hull `tris` of `pts` (see the module doc), in
/// phases: facets grown from the largest triangles, adjacent facets merged while their union
/// fits one slab, sliver facets dissolved, then each facet's boundary walked into a face.
/// `marginal`: the points outside the exact hull by at most `dist_tol` ([`exact_hull`]).
/// `Err` names the first structural problem found.
pub(crate) fn polyhedron_from_triangles(
    pts: &[[f64; 3]],
    tris: &[Tri],
    marginal: &[u32],
    opts: &PolytopeOptions,
) -> Result<Polyhedron, &'static str> {
    let tol = opts.dist_tol;
    let mut support: Vec<u32> = tris.iter().flat_map(|t| t.v).collect();
    support.extend_from_slice(marginal);
    support.sort_unstable();
    support.dedup();
    let (group, mut facets) = grow_facets(pts, tris, &support, tol)?;
    let mut parent = merge_facets(pts, tris, &support, &group, &mut facets, tol);
    // Final facet ids 0..F.
    let mut id = vec![usize::MAX; facets.len()];
    let mut roots = Vec::new();
    for g in 0..facets.len() {
        let r = find(&mut parent, g);
        if id[r] == usize::MAX {
            id[r] = roots.len();
            roots.push(r);
        }
    }
    let face_of: Vec<usize> = group.iter().map(|&g| id[find(&mut parent, g)]).collect();
    let lattice = dissolve_slivers(pts, tris, face_of, roots.len())?;
    let faces = walk_faces(&lattice)?;
    let Lattice { corner, alive, .. } = lattice;
    // Corners, renumbered in input order.
    let mut index = vec![usize::MAX; pts.len()];
    let mut vertices = Vec::new();
    for v in 0..pts.len() {
        if corner[v] {
            index[v] = vertices.len();
            vertices.push(pts[v]);
        }
    }
    let faces: Vec<Vec<usize>> = faces
        .into_iter()
        .map(|f| f.into_iter().map(|v| index[v as usize]).collect())
        .collect();
    let planes = roots
        .iter()
        .zip(&alive)
        .filter(|(_, &a)| a)
        .map(|(&r, _)| (facets[r].n, facets[r].d))
        .collect();
    Ok(Polyhedron {
        status: RegionStatus::Bounded,
        dim: 3,
        vertices,
        active: vec![None; faces.len()],
        faces,
        planes,
    })
}

/// Pass 1: facets grown from the largest triangles: a neighbour joins while the facet's
/// vertices stay within a slab of width `tol` along the seed's normal. Returns each
/// triangle's facet and the facets (with their best supporting planes).
fn grow_facets(
    pts: &[[f64; 3]],
    tris: &[Tri],
    support: &[u32],
    tol: f64,
) -> Result<(Vec<usize>, Vec<Facet>), &'static str> {
    let planes: Vec<([f64; 3], f64)> = tris.iter().map(|t| tri_plane(pts, t.v)).collect();
    let mut order: Vec<usize> = (0..tris.len()).collect();
    order.sort_by(|&a, &b| planes[b].1.total_cmp(&planes[a].1));
    let mut group = vec![usize::MAX; tris.len()];
    let mut facets: Vec<Facet> = Vec::new();
    let mut stack: Vec<usize> = Vec::new();
    for &seed in &order {
        if group[seed] != usize::MAX {
            continue;
        }
        let (n0, area) = planes[seed];
        if area == 0.0 {
            return Err("a hull triangle is degenerate in floating point and no facet absorbs it");
        }
        let g = facets.len();
        let h = |v: u32| dot(n0, pts[v as usize]);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &v in &tris[seed].v {
            lo = lo.min(h(v));
            hi = hi.max(h(v));
        }
        let mut members = vec![seed];
        group[seed] = g;
        stack.clear();
        stack.push(seed);
        while let Some(t) = stack.pop() {
            for &s in &tris[t].nb {
                let s = s as usize;
                if group[s] != usize::MAX {
                    continue;
                }
                let (mut l, mut u) = (lo, hi);
                for &v in &tris[s].v {
                    l = l.min(h(v));
                    u = u.max(h(v));
                }
                if u - l <= tol {
                    (lo, hi) = (l, u);
                    group[s] = g;
                    members.push(s);
                    stack.push(s);
                }
            }
        }
        let mut verts: Vec<u32> = members.iter().flat_map(|&t| tris[t].v).collect();
        verts.sort_unstable();
        verts.dedup();
        let (n, d) = best_plane(pts, support, &verts, n0, tol)
            .ok_or("a facet's vertices do not fit a supporting slab of width dist_tol")?;
        let area = members.iter().map(|&t| planes[t].1).sum();
        facets.push(Facet { verts, n, d, area });
    }
    Ok((group, facets))
}

/// Pass 2: adjacent facets merged while their union fits one slab, most parallel pairs first,
/// until no pair merges. Returns the union-find forest over `facets` (roots are the merged
/// facets, which hold the union's vertices and plane).
fn merge_facets(
    pts: &[[f64; 3]],
    tris: &[Tri],
    support: &[u32],
    group: &[usize],
    facets: &mut [Facet],
    tol: f64,
) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..facets.len()).collect();
    loop {
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for (t, tri) in tris.iter().enumerate() {
            for &s in &tri.nb {
                let (a, b) = (
                    find(&mut parent, group[t]),
                    find(&mut parent, group[s as usize]),
                );
                if a < b {
                    pairs.push((dot(facets[a].n, facets[b].n), a, b));
                }
            }
        }
        pairs.sort_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
        pairs.dedup_by(|x, y| x.1 == y.1 && x.2 == y.2);
        let mut merged = false;
        for &(_, a, b) in &pairs {
            let (a, b) = (find(&mut parent, a), find(&mut parent, b));
            if a == b {
                continue;
            }
            let (big, small) = if facets[a].area >= facets[b].area {
                (a, b)
            } else {
                (b, a)
            };
            let verts = union_sorted(&facets[big].verts, &facets[small].verts);
            if let Some((n, d)) = best_plane(pts, support, &verts, facets[big].n, tol) {
                parent[small] = big;
                facets[big].area += facets[small].area;
                facets[big].verts = verts;
                facets[big].n = n;
                facets[big].d = d;
                merged = true;
            }
        }
        if !merged {
            return parent;
        }
    }
}

/// The face lattice of the merged facets: which points are corners, the facets' boundary edges
/// (see [`lattice`]), and which facets are alive (not dissolved).
struct Lattice {
    corner: Vec<bool>,
    boundary: Vec<Edge>,
    alive: Vec<bool>,
}

/// The corners and facet boundaries of the lattice ([`lattice`]), after dissolving each facet
/// with fewer than three corners (a sliver between two faces, all its vertices on their two
/// common lines) into a neighbour: its vertices lie below every plane within `dist_tol` (the
/// slabs support all points), and the check verifies the result.
fn dissolve_slivers(
    pts: &[[f64; 3]],
    tris: &[Tri],
    mut face_of: Vec<usize>,
    nf: usize,
) -> Result<Lattice, &'static str> {
    let mut alive = vec![true; nf];
    loop {
        let (corner, boundary) = lattice(tris, &face_of, pts.len())?;
        let mut lo = 0;
        let mut dissolve = None;
        while lo < boundary.len() {
            let f = boundary[lo].0;
            let hi = lo + boundary[lo..].iter().take_while(|e| e.0 == f).count();
            let corners = boundary[lo..hi]
                .iter()
                .filter(|e| corner[e.1 as usize])
                .count();
            if corners < 3 {
                dissolve = Some((f, boundary[lo].3));
                break;
            }
            lo = hi;
        }
        match dissolve {
            None => {
                return Ok(Lattice {
                    corner,
                    boundary,
                    alive,
                })
            }
            Some((f, g)) => {
                for x in face_of.iter_mut().filter(|x| **x == f) {
                    *x = g;
                }
                alive[f] = false;
            }
        }
    }
}

/// Each live facet's face: its boundary walked from a corner, keeping the corners in order;
/// an error when a boundary is not one closed loop through at least three corners, or two
/// facets meet at a vertex that is not a corner.
fn walk_faces(lattice: &Lattice) -> Result<Vec<Vec<u32>>, &'static str> {
    let Lattice {
        corner,
        boundary,
        alive,
    } = lattice;
    let mut faces: Vec<Vec<u32>> = Vec::with_capacity(alive.len());
    let mut lo = 0;
    for f in (0..alive.len()).filter(|&f| alive[f]) {
        let hi = lo + boundary[lo..].iter().take_while(|e| e.0 == f).count();
        let edges = &boundary[lo..hi];
        lo = hi;
        let leaving = |v: u32| {
            edges
                .binary_search_by(|e| e.1.cmp(&v))
                .ok()
                .map(|i| (edges[i].2, edges[i].3))
        };
        let start = edges
            .iter()
            .map(|e| e.1)
            .find(|&v| corner[v as usize])
            .ok_or("a facet has no corner on its boundary")?;
        let mut face = Vec::new();
        let mut v = start;
        let mut beyond_run = usize::MAX;
        let mut walked = 0;
        loop {
            let (w, g) = leaving(v).ok_or("a facet boundary is not closed")?;
            if corner[v as usize] {
                face.push(v);
                beyond_run = g;
            } else if g != beyond_run {
                return Err("two facets meet at a vertex that is not a corner");
            }
            walked += 1;
            v = w;
            if v == start {
                break;
            }
            if walked > edges.len() {
                return Err("a facet boundary is not one closed loop");
            }
        }
        if walked != edges.len() {
            return Err("a facet has a hole (more than one boundary loop)");
        }
        if face.len() < 3 {
            return Err("a facet has fewer than three corners");
        }
        faces.push(face);
    }
    Ok(faces)
}
