//! Half-planes `a_i . p <= b_i` in `R^2` -> convex polygon (Sutherland-Hodgman clipping of the
//! far box, see the module doc of [`crate::polytope`]).

use super::tol::{BOX_ROUNDING, POLISH_MAX_MOVE};
use super::{check_rows, PolytopeError, PolytopeOptions, RegionStatus};

/// A convex polygon given by its vertices, the result of [`polygon_from_halfplanes`].
#[derive(Debug, Clone, PartialEq)]
pub struct Polygon {
    /// Empty, bounded or unbounded (clipped to the far box).
    pub status: RegionStatus,
    /// Dimension of the region: 2 for a proper polygon, 1 for a segment, 0 for a point
    /// (meaningless when `status` is `Empty`).
    pub dim: usize,
    /// Vertices in counter-clockwise order (for `dim == 2`), `[x, y]`.
    pub vertices: Vec<[f64; 2]>,
    /// `active[i]` is the input half-plane on which the edge from `vertices[i]` to
    /// `vertices[i + 1]` (cyclically) lies, or `None` for an edge of the far box. Empty unless
    /// `dim == 2`.
    pub active: Vec<Option<usize>>,
}

impl Polygon {
    /// The irredundant half-planes `(a, b)` (unit `a`, meaning `a . p <= b`) of the polygon, from
    /// its edges; for `dim == 2` only.
    ///
    /// ```
    /// use polycone::polytope::{polygon_from_halfplanes, PolytopeOptions};
    /// let a = [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0], [1.0, 1.0]];
    /// let b = [1.0, 1.0, 1.0, 1.0, 10.0]; // the last one is redundant
    /// let poly = polygon_from_halfplanes(&a, &b, &PolytopeOptions::default()).unwrap();
    /// assert_eq!(poly.halfplanes().len(), 4);
    /// ```
    pub fn halfplanes(&self) -> Vec<([f64; 2], f64)> {
        if self.dim != 2 {
            return Vec::new();
        }
        let n = self.vertices.len();
        (0..n)
            .map(|i| {
                let p = self.vertices[i];
                let q = self.vertices[(i + 1) % n];
                let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
                let len = dx.hypot(dy);
                let a = [dy / len, -dx / len];
                (a, a[0] * p[0] + a[1] * p[1])
            })
            .collect()
    }

    /// Signed area (positive for counter-clockwise vertices).
    ///
    /// ```
    /// use polycone::polytope::{polygon_from_halfplanes, PolytopeOptions};
    /// let a = [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]];
    /// let poly = polygon_from_halfplanes(&a, &[1.0, 1.0, 2.0, 2.0], &PolytopeOptions::default()).unwrap();
    /// assert!((poly.area() - 8.0).abs() < 1e-12);
    /// ```
    pub fn area(&self) -> f64 {
        let n = self.vertices.len();
        let mut s = 0.0;
        for i in 0..n {
            let p = self.vertices[i];
            let q = self.vertices[(i + 1) % n];
            s += p[0] * q[1] - p[1] * q[0];
        }
        0.5 * s
    }
}

/// Largest `a . p - b` over the unit-normal rows `lines` (zero rows count as `-b`).
fn max_violation(lines: &[([f64; 2], f64)], p: [f64; 2]) -> f64 {
    lines
        .iter()
        .map(|(a, b)| a[0] * p[0] + a[1] * p[1] - b)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// A running vertex and the label of its outgoing edge.
#[derive(Debug, Clone, Copy)]
struct Vx {
    p: [f64; 2],
    edge: Option<usize>,
}

/// Intersects the half-planes `normals[i] . p <= offsets[i]`.
///
/// Rows are normalized first; rows with a (near) zero normal are constant constraints `0 <=
/// b` (empty result if `b < -dist_tol`). See [`Polygon`] for the outputs and
/// [`crate::polytope`] for the semantics of the tolerances.
///
/// ```
/// use polycone::polytope::{polygon_from_halfplanes, PolytopeOptions, RegionStatus};
/// // The triangle x >= 0, y >= 0, x + y <= 1.
/// let a = [[-1.0, 0.0], [0.0, -1.0], [1.0, 1.0]];
/// let poly = polygon_from_halfplanes(&a, &[0.0, 0.0, 1.0], &PolytopeOptions::default()).unwrap();
/// assert_eq!(poly.status, RegionStatus::Bounded);
/// assert_eq!(poly.vertices.len(), 3);
/// assert!((poly.area() - 0.5).abs() < 1e-12);
/// // A half-plane alone is unbounded; two opposite half-planes with a gap are empty.
/// let half = polygon_from_halfplanes(&[[1.0, 0.0]], &[0.0], &PolytopeOptions::default()).unwrap();
/// assert_eq!(half.status, RegionStatus::Unbounded);
/// let none = polygon_from_halfplanes(&[[1.0, 0.0], [-1.0, 0.0]], &[0.0, -1.0], &PolytopeOptions::default()).unwrap();
/// assert_eq!(none.status, RegionStatus::Empty);
/// ```
pub fn polygon_from_halfplanes(
    normals: &[[f64; 2]],
    offsets: &[f64],
    opts: &PolytopeOptions,
) -> Result<Polygon, PolytopeError> {
    opts.validate()?;
    check_rows(normals, offsets)?;
    // Far from the origin: the same region about a point of it, moved back (`centre`).
    Ok(super::centre::recentred(normals, offsets, opts, |b, o| {
        about_origin(normals, b, o)
    }))
}

/// [`polygon_from_halfplanes`] for rows near the origin.
fn about_origin(normals: &[[f64; 2]], offsets: &[f64], opts: &PolytopeOptions) -> Polygon {
    let empty = Polygon {
        status: RegionStatus::Empty,
        dim: 0,
        vertices: Vec::new(),
        active: Vec::new(),
    };
    let f = opts.far;
    // Decisions finer than the rounding at the box's scale are noise (see `BOX_ROUNDING`).
    let tol = opts.dist_tol.max(BOX_ROUNDING * f);
    let mut poly: Vec<Vx> = [[-f, -f], [f, -f], [f, f], [-f, f]]
        .iter()
        .map(|&p| Vx { p, edge: None })
        .collect();
    let mut next: Vec<Vx> = Vec::with_capacity(16);
    let mut dist: Vec<f64> = Vec::with_capacity(16);
    // Unit-normal rows (a zero row stays zero and is skipped below).
    let lines: Vec<([f64; 2], f64)> = normals
        .iter()
        .zip(offsets)
        .map(|(a, &b)| {
            let norm = a[0].hypot(a[1]);
            if norm < opts.zero_normal {
                ([0.0, 0.0], b)
            } else {
                ([a[0] / norm, a[1] / norm], b / norm)
            }
        })
        .collect();
    for (i, &(a, b)) in lines.iter().enumerate() {
        if a == [0.0, 0.0] {
            if b < -opts.dist_tol {
                return empty;
            }
            continue;
        }
        let (ax, ay) = (a[0], a[1]);
        dist.clear();
        dist.extend(poly.iter().map(|v| ax * v.p[0] + ay * v.p[1] - b));
        if dist.iter().all(|&s| s <= tol) {
            continue;
        }
        next.clear();
        let n = poly.len();
        for k in 0..n {
            let cur = poly[k];
            let nxt = poly[(k + 1) % n];
            let (sc, sn) = (dist[k], dist[(k + 1) % n]);
            let (ic, inx) = (sc <= tol, sn <= tol);
            if ic {
                next.push(cur);
            }
            if ic != inx {
                let t = sc / (sc - sn);
                let p = [
                    cur.p[0] + t * (nxt.p[0] - cur.p[0]),
                    cur.p[1] + t * (nxt.p[1] - cur.p[1]),
                ];
                // Leaving: the new edge runs along the clip line; entering: along the old edge.
                let edge = if ic { Some(i) } else { cur.edge };
                next.push(Vx { p, edge });
            }
        }
        std::mem::swap(&mut poly, &mut next);
        if poly.is_empty() {
            return empty;
        }
    }
    finish(poly, &lines, opts)
}

/// Merges close vertices, drops non-corners, classifies the result.
/// Merges consecutive vertices closer than `merge_tol`; the surviving vertex keeps the later
/// outgoing edge (the sliver edge between them goes).
fn merge_close(poly: &mut Vec<Vx>, opts: &PolytopeOptions) {
    let close = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]) <= opts.merge_tol;
    let mut changed = true;
    while changed && poly.len() > 1 {
        changed = false;
        let n = poly.len();
        for k in 0..n {
            let j = (k + 1) % n;
            if close(poly[k].p, poly[j].p) {
                poly[k].edge = poly[j].edge;
                poly.remove(j);
                changed = true;
                break;
            }
        }
    }
}

fn finish(mut poly: Vec<Vx>, lines: &[([f64; 2], f64)], opts: &PolytopeOptions) -> Polygon {
    merge_close(&mut poly, opts);
    // Drop vertices lying on the segment between their neighbours (within dist_tol).
    let mut changed = true;
    while changed && poly.len() > 2 {
        changed = false;
        let n = poly.len();
        for k in 0..n {
            let p = poly[(k + n - 1) % n].p;
            let v = poly[k].p;
            let q = poly[(k + 1) % n].p;
            let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
            let len = dx.hypot(dy);
            let off = if len > 0.0 {
                ((v[0] - p[0]) * dy - (v[1] - p[1]) * dx).abs() / len
            } else {
                0.0
            };
            if off <= opts.dist_tol {
                // The merged edge p -> q keeps the line of the longer of the two edges it
                // replaces (a tiny edge's line is ill-determined).
                let kp = (k + n - 1) % n;
                let lin = (v[0] - p[0]).hypot(v[1] - p[1]);
                let lout = (q[0] - v[0]).hypot(q[1] - v[1]);
                if lout > lin {
                    poly[kp].edge = poly[k].edge;
                }
                poly.remove(k);
                changed = true;
                break;
            }
        }
    }
    // Polish: recompute each corner as the intersection of its two lines (the clipping
    // interpolates along edges of the far box, which costs accuracy far from the origin).
    let n = poly.len();
    if n >= 3 {
        let fixed: Vec<[f64; 2]> = (0..n)
            .map(|k| {
                let (Some(i), Some(j)) = (poly[(k + n - 1) % n].edge, poly[k].edge) else {
                    return poly[k].p;
                };
                let (ai, aj) = (lines[i], lines[j]);
                let det = ai.0[0] * aj.0[1] - ai.0[1] * aj.0[0];
                if det.abs() <= opts.rank_tol {
                    return poly[k].p;
                }
                let x = [
                    (ai.1 * aj.0[1] - ai.0[1] * aj.1) / det,
                    (ai.0[0] * aj.1 - ai.1 * aj.0[0]) / det,
                ];
                // Safety net: a polish that moves the vertex by more than the clipping error
                // means the edge labels do not describe this corner; keep the clipped point.
                // The clipping error grows as 1 / |det| for nearly parallel lines.
                let p = poly[k].p;
                let scale = (1.0 + p[0].abs().max(p[1].abs())) / det.abs().min(1.0);
                if (x[0] - p[0]).hypot(x[1] - p[1]) > POLISH_MAX_MOVE * scale {
                    return p;
                }
                // Second net: after a merge (above) an edge keeps the line of only one of the
                // edges it replaced, and the corner on it can then leave the other's half-plane
                // by more than `dist_tol` (nearly parallel lines amplify it); the clipped point
                // never does, as merging only drops slivers. Keep whichever violates less.
                let (vx, vp) = (max_violation(lines, x), max_violation(lines, p));
                if vx <= opts.dist_tol || vx <= vp {
                    x
                } else {
                    p
                }
            })
            .collect();
        for (v, p) in poly.iter_mut().zip(fixed) {
            v.p = p;
        }
        // The polish can move vertices that were clipped apart onto one corner where several
        // lines meet: merge them again, or the edges between them (1e-14 long) would give
        // `halfplanes` meaningless normals.
        merge_close(&mut poly, opts);
    }
    let dim = match poly.len() {
        0 | 1 => 0,
        2 => 1,
        _ => 2,
    };
    let status = if poly.iter().any(|v| v.edge.is_none() && dim == 2)
        || poly
            .iter()
            .any(|v| v.p[0].abs().max(v.p[1].abs()) >= opts.far - opts.dist_tol)
    {
        RegionStatus::Unbounded
    } else {
        RegionStatus::Bounded
    };
    let vertices = poly.iter().map(|v| v.p).collect();
    let active = if dim == 2 {
        poly.iter().map(|v| v.edge).collect()
    } else {
        Vec::new()
    };
    Polygon {
        status,
        dim,
        vertices,
        active,
    }
}

impl super::centre::Region<2> for Polygon {
    fn status(&self) -> RegionStatus {
        self.status
    }
    fn vertices(&self) -> &[[f64; 2]] {
        &self.vertices
    }
    fn translate(&mut self, c: &[f64; 2]) {
        for v in &mut self.vertices {
            v[0] += c[0];
            v[1] += c[1];
        }
    }
}
