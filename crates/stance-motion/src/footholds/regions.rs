//! Where a stance can hold the CoM at rest: its static-equilibrium polygon (paper Section IV,
//! from the contact forces that balance gravity), and the point of an intersection of such
//! polygons with the largest margin.
//!
//! # Math
//!
//! Each polygon is a set of half-planes `a_i . p <= b_i` with unit `a_i`, so `b_i - a_i . p` is
//! the distance of `p` inside edge `i`. The point of largest margin of an intersection of
//! polygons solves the Chebyshev-centre LP
//!
//! ```text
//! maximize r  subject to  a_i . p + r <= b_i  for every half-plane i of every polygon.
//! ```
//!
//! When the polygons intersect, `r >= 0` is the radius of the largest disc inside all of them.
//! When they do not, the LP still has an optimum, with `r < 0`: the point whose worst distance
//! outside a polygon is smallest, between the two regions, where a CoM can cross from one
//! stance to the next only with momentum; `-2 r` is then the width of the gap it must cross
//! (exactly, for two polygons whose nearest edges face each other).
//!
//! The LP has three unknowns and a few dozen rows: its optimum is a vertex where three rows are
//! tight, found by enumerating the triples (exact up to rounding, no solver tolerance). When the
//! optimum is not unique (a long rectangle's centre line) the mean of the optimal vertices is
//! returned: the middle of the optimal set when it is a segment.

use stance_contact::equilibrium::PolygonWorkspace;
use stance_contact::Stance;

use crate::StanceError;

/// Half-planes `(a, b)`, `a . p <= b`, unit `a`.
pub type Halfplanes = Vec<([f64; 2], f64)>;

/// The static-equilibrium polygon of `stance` under `gravity`, as half-planes (world `x, y`).
///
/// # Errors
///
/// [`StanceError::BadMotion`] naming `what` when the stance holds no CoM at rest.
pub fn static_halfplanes(
    stance: &Stance,
    gravity: [f64; 3],
    what: &str,
) -> Result<Halfplanes, StanceError> {
    let out = PolygonWorkspace::new().static_polygon(stance, gravity, 0.0, &Default::default())?;
    let p = out.polygon;
    if p.status == polycone::polytope::RegionStatus::Empty || p.dim < 2 {
        return Err(StanceError::BadMotion(format!(
            "{what}: its contacts cannot hold the robot at rest anywhere (their static-equilibrium \
             region is empty); add a contact or more friction"
        )));
    }
    Ok(p.halfplanes)
}

/// The point of largest margin of the intersection of half-planes, and that margin (m;
/// negative when they do not intersect: module doc). `None` when the LP is unbounded (fewer
/// than three half-planes in general position).
pub fn largest_margin(h: &[([f64; 2], f64)]) -> Option<([f64; 2], f64)> {
    let n = h.len();
    let mut best = f64::NEG_INFINITY;
    let mut points: Vec<[f64; 2]> = Vec::new();
    let scale = h.iter().map(|(_, b)| b.abs()).fold(1.0, f64::max);
    let eps = 1e-12 * scale;
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let Some((p, r)) = solve3([h[i], h[j], h[k]]) else {
                    continue;
                };
                if h.iter()
                    .any(|(a, b)| a[0] * p[0] + a[1] * p[1] + r > b + eps)
                {
                    continue;
                }
                if r > best + eps {
                    best = r;
                    points.clear();
                }
                if r >= best - eps {
                    points.push(p);
                }
            }
        }
    }
    if points.is_empty() {
        return None;
    }
    // the optimal set is convex: the mean of its extreme points lies in it
    let (lo, hi) = extremes(&points);
    Some(([0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])], best))
}

/// The two optimal vertices farthest apart (the ends of the optimal set when it is a segment).
fn extremes(points: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let mut out = (points[0], points[0]);
    let mut d = -1.0;
    for (i, p) in points.iter().enumerate() {
        for q in &points[i..] {
            let dd = (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
            if dd > d {
                d = dd;
                out = (*p, *q);
            }
        }
    }
    out
}

/// `a_i . p + r = b_i` for three rows: `(p, r)`, `None` when singular.
fn solve3(rows: [([f64; 2], f64); 3]) -> Option<([f64; 2], f64)> {
    let m = nalgebra::Matrix3::from_fn(|i, j| if j < 2 { rows[i].0[j] } else { 1.0 });
    let b = nalgebra::Vector3::new(rows[0].1, rows[1].1, rows[2].1);
    if m.determinant().abs() < 1e-12 {
        return None;
    }
    let x = m.lu().solve(&b)?;
    x.iter()
        .all(|v| v.is_finite())
        .then(|| ([x[0], x[1]], x[2]))
}

/// The point closest to `nominal` among those with margin at least `m` in the intersection
/// of half-planes: the projection of `nominal` onto the intersection shrunk by `m` (a convex
/// polygon). `None` when that set is empty.
///
/// The projection is `nominal` itself when it has the margin; otherwise it lies on an edge of
/// the shrunk polygon (the foot of the perpendicular from `nominal`) or at one of its vertices:
/// every such candidate is tried and the closest feasible one kept.
pub fn closest_with_margin(h: &[([f64; 2], f64)], nominal: [f64; 2], m: f64) -> Option<[f64; 2]> {
    let shrunk: Halfplanes = h.iter().map(|(a, b)| (*a, b - m)).collect();
    let scale = h.iter().map(|(_, b)| b.abs()).fold(1.0, f64::max);
    let eps = 1e-12 * scale;
    let feasible = |p: [f64; 2]| margin(&shrunk, p) >= -eps;
    if feasible(nominal) {
        return Some(nominal);
    }
    let mut best: Option<([f64; 2], f64)> = None;
    let mut consider = |p: [f64; 2]| {
        if p.iter().all(|x| x.is_finite()) && feasible(p) {
            let d = (p[0] - nominal[0]).powi(2) + (p[1] - nominal[1]).powi(2);
            if best.is_none_or(|(_, bd)| d < bd) {
                best = Some((p, d));
            }
        }
    };
    for (i, (a, b)) in shrunk.iter().enumerate() {
        let t = a[0] * nominal[0] + a[1] * nominal[1] - b;
        consider([nominal[0] - t * a[0], nominal[1] - t * a[1]]);
        for (c, d) in &shrunk[i + 1..] {
            let det = a[0] * c[1] - a[1] * c[0];
            if det.abs() > 1e-12 {
                consider([(b * c[1] - a[1] * d) / det, (a[0] * d - c[0] * b) / det]);
            }
        }
    }
    best.map(|(p, _)| p)
}

/// The margin of `p` in the intersection: the smallest `b_i - a_i . p`.
pub fn margin(h: &[([f64; 2], f64)], p: [f64; 2]) -> f64 {
    h.iter()
        .map(|(a, b)| b - a[0] * p[0] - a[1] * p[1])
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(x0: f64, x1: f64, y0: f64, y1: f64) -> Halfplanes {
        vec![
            ([1.0, 0.0], x1),
            ([-1.0, 0.0], -x0),
            ([0.0, 1.0], y1),
            ([0.0, -1.0], -y0),
        ]
    }

    #[test]
    fn the_centre_of_a_rectangle_and_of_an_overlap() {
        let (p, r) = largest_margin(&rect(0.0, 0.4, 0.0, 0.1)).unwrap();
        assert!((p[0] - 0.2).abs() < 1e-12 && (p[1] - 0.05).abs() < 1e-12);
        assert!((r - 0.05).abs() < 1e-12);
        let mut both = rect(0.0, 0.4, 0.0, 0.4);
        both.extend(rect(0.3, 0.7, 0.1, 0.3));
        let (p, r) = largest_margin(&both).unwrap();
        assert!(
            (r - 0.05).abs() < 1e-12 && (p[0] - 0.35).abs() < 1e-12,
            "{p:?} {r}"
        );
        assert!((margin(&both, p) - r).abs() < 1e-12);
    }

    #[test]
    fn disjoint_regions_give_the_middle_of_the_gap_and_minus_half_its_width() {
        let mut both = rect(0.0, 0.2, 0.0, 0.1);
        both.extend(rect(0.5, 0.7, 0.0, 0.1));
        let (p, r) = largest_margin(&both).unwrap();
        assert!((r + 0.15).abs() < 1e-12, "{r}");
        assert!((p[0] - 0.35).abs() < 1e-12, "{p:?}");
        // an independent check: no point of a fine grid has a better worst margin
        let mut grid_best = f64::NEG_INFINITY;
        for i in 0..=100 {
            for j in 0..=100 {
                let q = [-0.1 + 0.01 * i as f64, -0.5 + 0.01 * j as f64];
                grid_best = grid_best.max(margin(&both, q));
            }
        }
        assert!(grid_best <= r + 1e-12);
    }

    #[test]
    fn the_closest_point_with_a_margin_is_a_projection() {
        let r = rect(0.0, 0.4, 0.0, 0.2);
        assert_eq!(closest_with_margin(&r, [0.1, 0.1], 0.05), Some([0.1, 0.1]));
        let p = closest_with_margin(&r, [0.2, 0.5], 0.05).unwrap();
        assert!(
            (p[0] - 0.2).abs() < 1e-12 && (p[1] - 0.15).abs() < 1e-12,
            "{p:?}"
        );
        let p = closest_with_margin(&r, [-1.0, -1.0], 0.05).unwrap();
        assert!(
            (p[0] - 0.05).abs() < 1e-12 && (p[1] - 0.05).abs() < 1e-12,
            "{p:?}"
        );
        assert!(closest_with_margin(&r, [0.0, 0.0], 0.11).is_none());
        // an independent check: no grid point with the margin is closer
        let n = [0.7, -0.3];
        let p = closest_with_margin(&r, n, 0.03).unwrap();
        let d = ((p[0] - n[0]).powi(2) + (p[1] - n[1]).powi(2)).sqrt();
        for i in 0..=80 {
            for j in 0..=40 {
                let q = [0.005 * i as f64, 0.005 * j as f64];
                if margin(&r, q) >= 0.03 {
                    assert!(((q[0] - n[0]).powi(2) + (q[1] - n[1]).powi(2)).sqrt() >= d - 1e-12);
                }
            }
        }
    }

    #[test]
    fn an_open_set_has_no_centre() {
        assert!(largest_margin(&[([1.0, 0.0], 1.0), ([0.0, 1.0], 1.0)]).is_none());
    }
}
