//! The rows that touch a grid point's polygon, and those that are redundant there: the LPs of
//! the reachability passes give the same answers over the first alone.
//!
//! # Math
//!
//! A grid point's rows `a_j u + b_j x + c_j <= 0` cut a convex polygon `P` out of the plane of
//! `(u, x)`. **A row that holds strictly at every vertex of `P` is redundant**: leaving it out
//! leaves `P` unchanged. (If `P' = P` without the row were larger, take a point `z` of `P'`
//! outside `P` and a point `p` of `P`: on the segment from `p` to `z`, every other row holds
//! (`P'` is convex) and the row fails at `z`, so it is tight where the segment leaves `P`, a
//! point of `P`; but a row strictly below zero at every vertex of the bounded polygon `P` is
//! strictly below zero on all of it.)
//!
//! With a box `B` that contains `P` (the caller's: `P` bounded by its own rows), `P = B ∩ rows`
//! is found by clipping `B` by each row in turn (Sutherland and Hodgman); a row is kept when
//! its value at some vertex comes within [`REDUNDANT_MARGIN`] of zero, relative to the row's
//! size there, far above the solver's feasibility tolerance (1e-10) and
//! the round-off of the clipped vertices, so that a row left out can never be active in an LP,
//! nor within that LP's tolerance of being active, nor binding by a caller's measure.
//!
//! Humanoid grid points have about 60 contact rows per side (the faces of `U_stance` along
//! the path), of which a dozen or fewer touch the polygon.

use crate::constraints::Row;
use crate::lp2::Box2;

/// Relative margin within which a row counts as touching the polygon (module doc): relative to
/// the larger of `|(a, b)| max(1, |v|)` (the LPs' measure) and `|a u| + |b x| + |c|` (the
/// measure by which callers call a row binding, with tolerances of 1e-6 and below). Since the
/// latter is convex in `v`, a row left out is below `-REDUNDANT_MARGIN` times it everywhere in
/// the polygon, not only at its vertices.
pub const REDUNDANT_MARGIN: f64 = 1e-5;

/// Relative distance within which a vertex of the polygon lies on a side of the box.
const BOX_SIDE: f64 = 1e-9;

/// Reusable buffers of [`redundant_rows`].
#[derive(Debug, Clone, Default)]
pub struct FacetWorkspace {
    poly: Vec<[f64; 2]>,
    next: Vec<[f64; 2]>,
}

/// Marks in `redundant` (resized to `rows.len()`) the rows that hold with the margin at every
/// vertex of `P = {(u, x) in bbox : rows <= 0}` (module doc): the LPs over `bbox`, or over any
/// box with the same `x_lo`, give the same answers without them. Returns the number of
/// redundant rows, or `None` (nothing marked) when `P` is empty (every row may matter to a
/// diagnosis), when `P` reaches a side of `bbox` other than `x = x_lo` (a larger box could
/// make other rows matter), or when a value is not finite.
///
/// ```
/// use stance_topp::{facets::{redundant_rows, FacetWorkspace}, lp2::Box2, Row};
/// // u <= 1, -u <= 1, x <= 2, and u + x <= 10 (redundant)
/// let rows = [
///     Row { a: 1.0, b: 0.0, c: -1.0 },
///     Row { a: -1.0, b: 0.0, c: -1.0 },
///     Row { a: 0.0, b: 1.0, c: -2.0 },
///     Row { a: 1.0, b: 1.0, c: -10.0 },
/// ];
/// let bbox = Box2 { u_lo: -1e8, u_hi: 1e8, x_lo: 0.0, x_hi: 1e8 };
/// let mut redundant = Vec::new();
/// let n = redundant_rows(&rows, bbox, &mut FacetWorkspace::default(), &mut redundant);
/// assert_eq!(n, Some(1));
/// assert_eq!(redundant, [false, false, false, true]);
/// // without the bound on x, the polygon reaches the box: nothing is marked
/// let n = redundant_rows(&rows[..2], bbox, &mut FacetWorkspace::default(), &mut redundant);
/// assert_eq!(n, None);
/// ```
pub fn redundant_rows(
    rows: &[Row],
    bbox: Box2,
    ws: &mut FacetWorkspace,
    redundant: &mut Vec<bool>,
) -> Option<usize> {
    redundant.clear();
    redundant.resize(rows.len(), false);
    let FacetWorkspace { poly, next } = ws;
    poly.clear();
    poly.extend_from_slice(&[
        [bbox.u_lo, bbox.x_lo],
        [bbox.u_hi, bbox.x_lo],
        [bbox.u_hi, bbox.x_hi],
        [bbox.u_lo, bbox.x_hi],
    ]);
    if poly.iter().flatten().any(|v| !v.is_finite()) {
        return None;
    }
    for r in rows {
        if !(r.a.is_finite() && r.b.is_finite() && r.c.is_finite()) {
            return None;
        }
        clip(poly, next, r);
        if poly.is_empty() {
            return None;
        }
    }
    // P reaches a side of the box (x_lo aside): the box, not the rows, bounds it there
    let on_side = |v: &[f64; 2]| {
        let near = |a: f64, b: f64| (a - b).abs() <= BOX_SIDE * b.abs().max(1.0);
        near(v[0], bbox.u_lo) || near(v[0], bbox.u_hi) || near(v[1], bbox.x_hi)
    };
    if poly.iter().any(on_side) {
        return None;
    }
    // each vertex with its squared scale max(1, |v|)^2, for the margin
    next.clear();
    next.extend(poly.iter().map(|v| {
        let s = v[0].abs().max(v[1].abs()).max(1.0);
        [s * s, 0.0]
    }));
    let margin2 = REDUNDANT_MARGIN * REDUNDANT_MARGIN;
    let mut count = 0;
    for (r, red) in rows.iter().zip(redundant.iter_mut()) {
        // value >= -margin |(a, b)| scale, on squares
        let m2 = margin2 * (r.a * r.a + r.b * r.b);
        let touches = poly.iter().zip(next.iter()).any(|(v, s2)| {
            let value = r.a * v[0] + r.b * v[1] + r.c;
            let terms = (r.a * v[0]).abs() + (r.b * v[1]).abs() + r.c.abs();
            value >= -REDUNDANT_MARGIN * terms || value * value <= m2 * s2[0]
        });
        if !touches {
            *red = true;
            count += 1;
        }
    }
    Some(count)
}

/// Clips the convex polygon `poly` by `r <= 0` (`next`: a buffer).
fn clip(poly: &mut Vec<[f64; 2]>, next: &mut Vec<[f64; 2]>, r: &Row) {
    let value = |v: &[f64; 2]| r.a * v[0] + r.b * v[1] + r.c;
    if poly.iter().all(|v| value(v) <= 0.0) {
        return;
    }
    next.clear();
    let n = poly.len();
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        let (vp, vq) = (value(&p), value(&q));
        if vp <= 0.0 {
            next.push(p);
        }
        if (vp <= 0.0) != (vq <= 0.0) {
            let t = vp / (vp - vq);
            next.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    std::mem::swap(poly, next);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lp2::{solve, Lp2, Lp2Stats};
    use crate::Tolerances;
    use proptest::prelude::*;

    fn row() -> impl Strategy<Value = Row> {
        (-1.0..1.0f64, -1.0..1.0f64, -2.0..0.5f64).prop_map(|(a, b, c)| Row { a, b, c })
    }

    proptest! {
        /// Leaving the redundant rows out changes no LP's optimum: random polygons, eight
        /// objective directions, against the LP over every row.
        #[test]
        fn the_lps_over_the_kept_rows_agree_with_those_over_every_row(
            rows in prop::collection::vec(row(), 1..60),
        ) {
            let bbox = Box2 { u_lo: -3.0, u_hi: 3.0, x_lo: 0.0, x_hi: 3.0 };
            // the polygon bounded by rows of its own (|u| <= 2, x <= 2) within the box, at
            // the end, so that the random rows come first; and two rows looser than those
            // (u <= 2.5, 2 u + x <= 8), redundant whatever the random rows
            let mut rows = rows;
            let looser = [rows.len(), rows.len() + 1];
            rows.extend([
                Row { a: 1.0, b: 0.0, c: -2.5 },
                Row { a: 2.0, b: 1.0, c: -8.0 },
                Row { a: 1.0, b: 0.0, c: -2.0 },
                Row { a: -1.0, b: 0.0, c: -2.0 },
                Row { a: 0.0, b: 1.0, c: -2.0 },
            ]);
            let tol = Tolerances::default();
            let mut redundant = Vec::new();
            let found = redundant_rows(&rows, bbox, &mut FacetWorkspace::default(), &mut redundant);
            // the polygon is empty (nothing marked) or the looser rows are left out
            if let Some(n) = found {
                prop_assert!(n >= 2 && looser.iter().all(|&j| redundant[j]), "{redundant:?}");
            }
            let kept: Vec<Row> = rows
                .iter()
                .zip(&redundant)
                .filter(|(_, r)| !**r)
                .map(|(row, _)| *row)
                .collect();
            for k in 0..8 {
                let th = k as f64 * std::f64::consts::FRAC_PI_4 + 0.1;
                let c = [th.cos(), th.sin()];
                let t = [-c[1], c[0]];
                let mut st = Lp2Stats::default();
                // over a larger box with the same x_lo
                let big = Box2 { u_lo: -10.0, u_hi: 10.0, x_lo: 0.0, x_hi: 10.0 };
                let all = solve(&crate::lp2::StageLines::from_rows(&rows), big, c, t, &[], &tol, &mut st);
                let some = solve(&crate::lp2::StageLines::from_rows(&kept), big, c, t, &[], &tol, &mut st);
                match (all, some) {
                    (Lp2::Optimal { u: u1, x: x1, .. }, Lp2::Optimal { u: u2, x: x2, .. }) => {
                        prop_assert!((u1 - u2).abs() <= 1e-9 && (x1 - x2).abs() <= 1e-9,
                            "{:?} vs {:?}", (u1, x1), (u2, x2));
                    }
                    (Lp2::Infeasible, Lp2::Infeasible) => {}
                    (a, b) => prop_assert!(false, "{a:?} vs {b:?} ({found:?} redundant)"),
                }
            }
        }
    }

    #[test]
    fn an_empty_polygon_marks_nothing() {
        let rows = [
            Row {
                a: 1.0,
                b: 0.0,
                c: 1.0,
            }, // u <= -1
            Row {
                a: -1.0,
                b: 0.0,
                c: 1.0,
            }, // u >= 1
            Row {
                a: 0.0,
                b: 1.0,
                c: -5.0,
            },
        ];
        let bbox = Box2 {
            u_lo: -2.0,
            u_hi: 2.0,
            x_lo: 0.0,
            x_hi: 2.0,
        };
        let mut red = Vec::new();
        assert_eq!(
            redundant_rows(&rows, bbox, &mut FacetWorkspace::default(), &mut red),
            None
        );
        assert!(red.iter().all(|r| !r));
    }

    /// A row scaled by a positive factor, or every row moved with the origin of `u`, is kept or
    /// dropped alike.
    #[test]
    fn scaling_a_row_does_not_change_what_is_kept() {
        let rows = [
            Row {
                a: 1.0,
                b: 0.2,
                c: -1.0,
            },
            Row {
                a: -1.0,
                b: 0.1,
                c: -1.0,
            },
            Row {
                a: 0.0,
                b: 1.0,
                c: -2.0,
            },
            Row {
                a: 0.3,
                b: 1.0,
                c: -2.3,
            },
            Row {
                a: 1.0,
                b: 1.0,
                c: -10.0,
            },
        ];
        let bbox = Box2 {
            u_lo: -4.0,
            u_hi: 4.0,
            x_lo: 0.0,
            x_hi: 4.0,
        };
        let mut base = Vec::new();
        redundant_rows(&rows, bbox, &mut FacetWorkspace::default(), &mut base).unwrap();
        for f in [1e-6, 3.0, 1e6] {
            let scaled: Vec<Row> = rows
                .iter()
                .map(|r| Row {
                    a: r.a * f,
                    b: r.b * f,
                    c: r.c * f,
                })
                .collect();
            let mut red = Vec::new();
            redundant_rows(&scaled, bbox, &mut FacetWorkspace::default(), &mut red).unwrap();
            assert_eq!(red, base, "factor {f}");
        }
    }
}
