//! The exact convex hull of points in space as a triangulated surface (quickhull order,
//! beneath-beyond update, exact predicates).
//!
//! Method (Barber, Dobkin and Huhdanpaa 1996, "The quickhull algorithm for convex hulls";
//! conflict lists as in Clarkson and Shor 1989): start from a tetrahedron of the points; each
//! remaining point is kept in the *outside set* of one triangle it sees (it is strictly above
//! the triangle's plane: [`orient`] `> 0`). Repeatedly take the point of an outside set
//! farthest from its triangle, find every triangle it sees (a connected region, found by a
//! walk over neighbours), replace that region by the cone of triangles from the point to the
//! region's boundary (the *horizon*), and hand the outside points of the removed triangles to
//! the new triangles they see (a point that sees none of them is inside the hull).
//!
//! With an exact predicate every decision is the one of exact arithmetic on the input as
//! given, so the result is the exact hull: a closed triangulated surface, every triangle
//! counter-clockwise seen from outside, no point strictly above any triangle. Coplanar
//! triangles (a face of several triangles, points exactly on a face) are kept as they come;
//! [`super::facets`] merges them. "Farthest" is a floating-point heuristic only (it changes the
//! order, not the result).

use super::predicates::orient;

/// Sentinel for "no triangle".
pub(crate) const NONE: u32 = u32::MAX;

/// One triangle of the triangulated hull.
#[derive(Debug, Clone)]
pub(crate) struct Tri {
    /// Vertex indices into the point list, counter-clockwise seen from outside.
    pub v: [u32; 3],
    /// `nb[k]`: the triangle across the edge `v[k] -> v[k + 1]` (indices mod 3).
    pub nb: [u32; 3],
}

struct Work {
    tris: Vec<Tri>,
    alive: Vec<bool>,
    outside: Vec<Vec<u32>>,
    /// Unit float normal of each triangle ([`tri_plane`]): heights of outside points.
    normal: Vec<[f64; 3]>,
    /// Points at most this high above the hull (float height) are not added.
    tol: f64,
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Work {
    fn sees(&self, pts: &[[f64; 3]], t: usize, p: u32) -> bool {
        let v = self.tris[t].v;
        orient(
            &pts[v[0] as usize],
            &pts[v[1] as usize],
            &pts[v[2] as usize],
            &pts[p as usize],
        ) > 0
    }

    fn push(&mut self, pts: &[[f64; 3]], v: [u32; 3], nb: [u32; 3]) -> u32 {
        self.normal.push(tri_plane(pts, v).0);
        self.tris.push(Tri { v, nb });
        self.alive.push(true);
        self.outside.push(Vec::new());
        (self.tris.len() - 1) as u32
    }

    /// Float height of `p` above the plane of triangle `t` (infinite when the triangle is
    /// degenerate in floating point: the exact predicate alone decides then).
    fn height(&self, pts: &[[f64; 3]], t: usize, p: u32) -> f64 {
        let n = self.normal[t];
        if n == [0.0; 3] {
            return f64::INFINITY;
        }
        let a = pts[self.tris[t].v[0] as usize];
        dot(n, sub(pts[p as usize], a))
    }

    /// `p` is an outside point of `t`: exactly above it, and higher than the tolerance.
    fn outside_of(&self, pts: &[[f64; 3]], t: usize, p: u32) -> bool {
        // `tol = -inf` keeps every exactly outside point (the exact hull of all points).
        self.height(pts, t, p) > self.tol && self.sees(pts, t, p)
    }

    /// Index `k` with `tris[t].nb[k] == other`.
    fn slot(&self, t: u32, other: u32) -> Option<usize> {
        self.tris[t as usize].nb.iter().position(|&n| n == other)
    }
}

/// Unit normal (zero for a triangle degenerate in floating point) and area of the triangle
/// `v`, counter-clockwise seen from the side the normal points to. Gram-Schmidt from the
/// longest edge: the normal is orthogonal to that edge to rounding, so the heights of points
/// far along a sliver stay accurate (a plain cross product of two long edges loses
/// `eps |e1| |e2| / area` of relative accuracy).
pub(crate) fn tri_plane(pts: &[[f64; 3]], v: [u32; 3]) -> ([f64; 3], f64) {
    let p = v.map(|i| pts[i as usize]);
    let len2 = |k: usize| {
        let e = sub(p[(k + 1) % 3], p[k]);
        dot(e, e)
    };
    let k = (0..3)
        .max_by(|&a, &b| len2(a).total_cmp(&len2(b)))
        .unwrap_or(0);
    let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
    let e = sub(b, a);
    let le = dot(e, e).sqrt();
    if le == 0.0 || !le.is_finite() {
        return ([0.0; 3], 0.0);
    }
    let u = [e[0] / le, e[1] / le, e[2] / le];
    let w = sub(c, a);
    let wu = dot(w, u);
    let wp = [w[0] - wu * u[0], w[1] - wu * u[1], w[2] - wu * u[2]];
    let lw = dot(wp, wp).sqrt();
    if lw == 0.0 || !lw.is_finite() {
        return ([0.0; 3], 0.0);
    }
    let n = cross(u, [wp[0] / lw, wp[1] / lw, wp[2] / lw]);
    let ln = dot(n, n).sqrt();
    ([n[0] / ln, n[1] / ln, n[2] / ln], 0.5 * le * lw)
}

/// A tetrahedron of the points with non-zero exact volume: `[i0, i1, i2, i3]` with `i3` below
/// the triangle `i0 i1 i2` (so that triangle faces outward). `None` when all points are
/// exactly coplanar.
fn simplex(pts: &[[f64; 3]]) -> Option<[usize; 4]> {
    let n = pts.len();
    if n < 4 {
        return None;
    }
    let i0 = (0..n).min_by(|&a, &b| pts[a][0].total_cmp(&pts[b][0]))?;
    let far = |from: &dyn Fn(usize) -> f64| (0..n).max_by(|&a, &b| from(a).total_cmp(&from(b)));
    let i1 = far(&|k| {
        let d = sub(pts[k], pts[i0]);
        dot(d, d)
    })?;
    let e = sub(pts[i1], pts[i0]);
    let i2 = far(&|k| {
        let c = cross(e, sub(pts[k], pts[i0]));
        dot(c, c)
    })?;
    let nrm = cross(e, sub(pts[i2], pts[i0]));
    let i3 = far(&|k| dot(nrm, sub(pts[k], pts[i0])).abs())?;
    let mut s = [i0, i1, i2, i3];
    let mut o = orient(&pts[i0], &pts[i1], &pts[i2], &pts[i3]);
    if o == 0 {
        // The float choice was degenerate: look for any exact non-coplanar quadruple through
        // the first three, then any at all (rare; quadratic at worst).
        let found = (0..n).find_map(|k| {
            let o = orient(&pts[i0], &pts[i1], &pts[i2], &pts[k]);
            (o != 0).then_some((k, o))
        });
        match found {
            Some((k, ok)) => {
                s[3] = k;
                o = ok;
            }
            None => {
                // i0, i1, i2 may be exactly collinear: try every third point.
                let mut best = None;
                'outer: for j in 0..n {
                    for k in 0..n {
                        let o = orient(&pts[i0], &pts[i1], &pts[j], &pts[k]);
                        if o != 0 {
                            best = Some((j, k, o));
                            break 'outer;
                        }
                    }
                }
                let (j, k, ok) = best?;
                s = [i0, i1, j, k];
                o = ok;
            }
        }
    }
    if o > 0 {
        s.swap(1, 2);
    }
    Some(s)
}

/// The exact hull of `pts` (distinct points, not all coplanar) as triangles with their
/// neighbours. `None` when the points are exactly coplanar or the surface became inconsistent
/// (which exact predicates rule out; kept as a guard so that a bug falls back instead of
/// returning a wrong hull).
///
/// Points at most `tol` above the current hull (by the float height above the triangles they
/// see) are not added: they are within `tol` of the hull (of the hull at that time; the final
/// check of [`super::check`] verifies every point against the final faces).
///
/// Returns the triangles and the *marginal* points: exactly outside the hull but at most
/// `tol` above its triangles. Every other point that is no hull vertex is inside the hull.
///
/// Each step of the module doc's loop: the farthest outside point `p` of the next triangle
/// with outside points, the triangles it sees ([`Work::visible_region`]), the horizon cycle
/// ([`Step::horizon_cycle`]), the cone from `p` over it ([`Work::add_cone`]) and the outside
/// points of the removed triangles handed on ([`Work::reassign_orphans`]).
pub(crate) fn exact_hull(pts: &[[f64; 3]], tol: f64) -> Option<(Vec<Tri>, Vec<u32>)> {
    let (mut w, mut marginal) = Work::start(pts, tol)?;
    let mut st = Step::new(pts.len());
    let mut cursor = 0usize;
    loop {
        // Next triangle with a non-empty outside set (triangles are only appended).
        while cursor < w.tris.len() && (!w.alive[cursor] || w.outside[cursor].is_empty()) {
            cursor += 1;
        }
        if cursor == w.tris.len() {
            if !w.sweep_marginal(pts, &mut marginal) {
                break;
            }
            cursor = 0;
            continue;
        }
        let t0 = cursor;
        let p = *w.outside[t0]
            .iter()
            .max_by(|&&a, &&b| w.height(pts, t0, a).total_cmp(&w.height(pts, t0, b)))?;
        w.visible_region(pts, t0, p, &mut st);
        st.horizon_cycle(&w)?;
        w.add_cone(pts, p, &mut st)?;
        w.reassign_orphans(pts, p, &mut st, &mut marginal);
        // Triangles before the cursor are dead or empty for good (outside sets only go to new
        // triangles, which are appended), so the cursor moves back only after the sweep.
    }
    w.compact(&marginal)
}

/// Buffers of one step of [`exact_hull`], reused across steps.
struct Step {
    /// The triangles that see the point, and a flag per triangle.
    visible: Vec<u32>,
    is_visible: Vec<bool>,
    stack: Vec<u32>,
    /// `(a, b, triangle beyond the edge, visible triangle on this side)`.
    horizon: Vec<(u32, u32, u32, u32)>,
    /// `next_of[a]`: position in `horizon` of the edge leaving `a` (`NONE` between steps).
    next_of: Vec<u32>,
    /// Positions in `horizon` along the cycle.
    order: Vec<usize>,
    orphans: Vec<u32>,
    new_tris: Vec<u32>,
}

impl Step {
    fn new(n: usize) -> Self {
        Self {
            visible: Vec::new(),
            is_visible: Vec::new(),
            stack: Vec::new(),
            horizon: Vec::new(),
            next_of: vec![NONE; n],
            order: Vec::new(),
            orphans: Vec::new(),
            new_tris: Vec::new(),
        }
    }

    /// The horizon: edges of visible triangles whose neighbour is not visible, in the
    /// orientation of the visible triangle, chained into one cycle (`order`). `None` when they
    /// do not form a simple cycle of at least three edges.
    #[inline(always)]
    fn horizon_cycle(&mut self, w: &Work) -> Option<()> {
        let Step {
            visible,
            is_visible,
            horizon,
            next_of,
            order,
            ..
        } = self;
        horizon.clear();
        for &t in visible.iter() {
            let tri = &w.tris[t as usize];
            for k in 0..3 {
                let u = tri.nb[k];
                if !is_visible[u as usize] {
                    horizon.push((tri.v[k], tri.v[(k + 1) % 3], u, t));
                }
            }
        }
        // Chain the horizon into one cycle: next_of[a] = position of the edge leaving a.
        for (j, &(a, ..)) in horizon.iter().enumerate() {
            if next_of[a as usize] != NONE {
                return None; // a vertex twice on the horizon: not a simple cycle
            }
            next_of[a as usize] = j as u32;
        }
        let m = horizon.len();
        order.clear();
        order.reserve(m);
        let mut j = 0usize;
        for _ in 0..m {
            order.push(j);
            let b = horizon[j].1;
            let nj = next_of[b as usize];
            if nj == NONE {
                break;
            }
            j = nj as usize;
        }
        for &(a, ..) in horizon.iter() {
            next_of[a as usize] = NONE;
        }
        if order.len() != m || j != 0 || m < 3 {
            return None;
        }
        Some(())
    }
}

impl Work {
    /// The starting tetrahedron (`None` when the points are exactly coplanar) and the outside
    /// sets of its four triangles; the points exactly outside it but within `tol` are flagged
    /// marginal.
    fn start(pts: &[[f64; 3]], tol: f64) -> Option<(Work, Vec<bool>)> {
        let [i0, i1, i2, i3] = simplex(pts)?.map(|i| i as u32);
        let mut w = Work {
            tris: Vec::with_capacity(4 * pts.len()),
            alive: Vec::with_capacity(4 * pts.len()),
            outside: Vec::with_capacity(4 * pts.len()),
            normal: Vec::with_capacity(4 * pts.len()),
            tol,
        };
        // Faces of the tetrahedron (i3 below i0 i1 i2); neighbours by shared edges:
        // t0 = (i0 i1 i2), t1 = (i0 i3 i1), t2 = (i1 i3 i2), t3 = (i2 i3 i0).
        w.push(pts, [i0, i1, i2], [1, 2, 3]);
        w.push(pts, [i0, i3, i1], [3, 2, 0]);
        w.push(pts, [i1, i3, i2], [1, 3, 0]);
        w.push(pts, [i2, i3, i0], [2, 1, 0]);
        // Points exactly outside the hull but skipped as within `tol` of it ("marginal"): the
        // only ones that can end up above a later triangle. A point found inside the exact hull
        // stays inside every later one.
        let mut marginal = vec![false; pts.len()];
        for p in 0..pts.len() as u32 {
            if [i0, i1, i2, i3].contains(&p) {
                continue;
            }
            if let Some(t) = (0..4).find(|&t| w.outside_of(pts, t, p)) {
                w.outside[t].push(p);
            } else if (0..4).any(|t| w.sees(pts, t, p)) {
                marginal[p as usize] = true;
            }
        }
        Some((w, marginal))
    }

    /// Points skipped as within `tol` of the hull at their time may be higher above a
    /// triangle made later (near a sharp corner): sweeps them against the live triangles and
    /// hands those still outside to a triangle. `true` when any was (the loop goes on).
    fn sweep_marginal(&mut self, pts: &[[f64; 3]], marginal: &mut [bool]) -> bool {
        let mut again = false;
        for q in 0..pts.len() as u32 {
            if !marginal[q as usize] {
                continue;
            }
            if let Some(t) =
                (0..self.tris.len()).find(|&t| self.alive[t] && self.outside_of(pts, t, q))
            {
                self.outside[t].push(q);
                marginal[q as usize] = false;
                again = true;
            }
        }
        again
    }

    /// The visible region of `p` from the triangle `t0` that sees it: the connected set of
    /// triangles that see `p` (a walk over neighbours), into `st.visible` and `st.is_visible`.
    #[inline(always)]
    fn visible_region(&self, pts: &[[f64; 3]], t0: usize, p: u32, st: &mut Step) {
        st.is_visible.resize(self.tris.len(), false);
        st.visible.clear();
        st.stack.clear();
        st.stack.push(t0 as u32);
        st.is_visible[t0] = true;
        while let Some(t) = st.stack.pop() {
            st.visible.push(t);
            for k in 0..3 {
                let u = self.tris[t as usize].nb[k];
                if !st.is_visible[u as usize] && self.sees(pts, u as usize, p) {
                    st.is_visible[u as usize] = true;
                    st.stack.push(u);
                }
            }
        }
    }

    /// The cone from `p` over the horizon cycle (new triangles into `st.new_tris`), with the
    /// triangles beyond the horizon re-linked to them. `None` when a link is missing (an
    /// inconsistent surface).
    #[inline(always)]
    fn add_cone(&mut self, pts: &[[f64; 3]], p: u32, st: &mut Step) -> Option<()> {
        st.new_tris.clear();
        let m = st.horizon.len();
        let base = self.tris.len() as u32;
        for (q, &j) in st.order.iter().enumerate() {
            let (a, b, beyond, old) = st.horizon[j];
            let next = base + ((q + 1) % m) as u32;
            let prev = base + ((q + m - 1) % m) as u32;
            let t = self.push(pts, [a, b, p], [beyond, next, prev]);
            st.new_tris.push(t);
            // Re-link the triangle beyond the edge: it pointed to the visible triangle.
            let k = self.slot(beyond, old)?;
            self.tris[beyond as usize].nb[k] = t;
        }
        st.is_visible.resize(self.tris.len(), false);
        Some(())
    }

    /// Removes the visible triangles and hands their outside points (but `p`) to a new
    /// triangle they are outside of; a point that is not, but still sees a new triangle,
    /// goes to any live triangle it is outside of (rare; full scan), else becomes marginal.
    /// Points that see no new triangle are inside the hull. Clears the visible flags.
    #[inline(always)]
    fn reassign_orphans(&mut self, pts: &[[f64; 3]], p: u32, st: &mut Step, marginal: &mut [bool]) {
        st.orphans.clear();
        for &t in &st.visible {
            self.alive[t as usize] = false;
            st.orphans.append(&mut self.outside[t as usize]);
        }
        for &q in &st.orphans {
            if q == p {
                continue;
            }
            if let Some(&t) = st
                .new_tris
                .iter()
                .find(|&&t| self.outside_of(pts, t as usize, q))
            {
                self.outside[t as usize].push(q);
            } else if st.new_tris.iter().any(|&t| self.sees(pts, t as usize, q)) {
                // Outside the new hull but not by more than the tolerance above the new
                // triangles: it may still be high above an older one (rare; full scan).
                if let Some(t) =
                    (0..self.tris.len()).find(|&t| self.alive[t] && self.outside_of(pts, t, q))
                {
                    self.outside[t].push(q);
                } else {
                    marginal[q as usize] = true;
                }
            }
        }
        for &t in &st.visible {
            st.is_visible[t as usize] = false;
        }
    }

    /// The live triangles, renumbered (neighbours too), and the marginal points. `None` when a
    /// live triangle has a dead neighbour.
    fn compact(&self, marginal: &[bool]) -> Option<(Vec<Tri>, Vec<u32>)> {
        let mut index = vec![NONE; self.tris.len()];
        let mut out = Vec::new();
        for (t, tri) in self.tris.iter().enumerate() {
            if self.alive[t] {
                index[t] = out.len() as u32;
                out.push(tri.clone());
            }
        }
        for tri in &mut out {
            for nb in &mut tri.nb {
                *nb = index[*nb as usize];
                if *nb == NONE {
                    return None;
                }
            }
        }
        let marginal = (0..marginal.len() as u32)
            .filter(|&q| marginal[q as usize])
            .collect();
        Some((out, marginal))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Closed, consistently oriented, and no point strictly above any triangle (exactly).
    fn assert_exact_hull(pts: &[[f64; 3]], tris: &[Tri]) {
        for (t, tri) in tris.iter().enumerate() {
            for k in 0..3 {
                let u = &tris[tri.nb[k] as usize];
                let (a, b) = (tri.v[k], tri.v[(k + 1) % 3]);
                let back = (0..3).position(|j| u.v[j] == b && u.v[(j + 1) % 3] == a);
                assert!(back.is_some(), "edge {a}-{b} of triangle {t} has no twin");
                assert_eq!(u.nb[back.unwrap()] as usize, t);
            }
            for p in pts {
                let [a, b, c] = tri.v.map(|i| &pts[i as usize]);
                assert!(orient(a, b, c, p) <= 0);
            }
        }
        let mut verts: Vec<u32> = tris.iter().flat_map(|t| t.v).collect();
        verts.sort_unstable();
        verts.dedup();
        // Euler for a triangulated sphere: F = 2 V - 4.
        assert_eq!(tris.len(), 2 * verts.len() - 4);
    }

    #[test]
    fn cube_with_points_on_faces_edges_and_inside() {
        let mut pts = vec![];
        for x in [0.0, 0.5, 1.0] {
            for y in [0.0, 0.5, 1.0] {
                for z in [0.0, 0.5, 1.0] {
                    pts.push([x, y, z]);
                }
            }
        }
        let (tris, marginal) = exact_hull(&pts, f64::NEG_INFINITY).unwrap();
        assert!(marginal.is_empty());
        assert_exact_hull(&pts, &tris);
    }

    #[test]
    fn random_points_on_a_sphere() {
        let mut pts = vec![];
        let mut s = 12345u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..200 {
            let p = [rnd(), rnd(), rnd()];
            let n = dot(p, p).sqrt();
            pts.push([p[0] / n, p[1] / n, p[2] / n]);
        }
        let (tris, marginal) = exact_hull(&pts, f64::NEG_INFINITY).unwrap();
        assert!(marginal.is_empty());
        assert_exact_hull(&pts, &tris);
    }

    #[test]
    fn coplanar_points_have_no_hull() {
        let pts = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        assert!(exact_hull(&pts, f64::NEG_INFINITY).is_none());
    }
}
