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

/// Reusable buffers of [`redundant_rows`], and the polygon it clips: built in steps by
/// [`FacetWorkspace::start`], [`FacetWorkspace::clip_all`] and
/// [`FacetWorkspace::mark_redundant`] when the caller needs the polygon of some rows before
/// choosing the others (its bounding box: [`FacetWorkspace::bounds`]).
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
    if !(ws.start(bbox) && ws.clip_all(rows)) {
        redundant.clear();
        redundant.resize(rows.len(), false);
        return None;
    }
    ws.mark_redundant(rows, bbox, redundant)
}

impl FacetWorkspace {
    /// Starts the polygon at the box `bbox`; `false` when a corner is not finite.
    pub fn start(&mut self, bbox: Box2) -> bool {
        self.poly.clear();
        self.poly.extend_from_slice(&[
            [bbox.u_lo, bbox.x_lo],
            [bbox.u_hi, bbox.x_lo],
            [bbox.u_hi, bbox.x_hi],
            [bbox.u_lo, bbox.x_hi],
        ]);
        self.poly.iter().flatten().all(|v| v.is_finite())
    }

    /// Clips the polygon by each row in turn; `false` when it became empty or a row is not
    /// finite (the polygon then says nothing).
    pub fn clip_all<'a>(&mut self, rows: impl IntoIterator<Item = &'a Row>) -> bool {
        for r in rows {
            if !(r.a.is_finite() && r.b.is_finite() && r.c.is_finite()) {
                return false;
            }
            clip(&mut self.poly, &mut self.next, r);
            if self.poly.is_empty() {
                return false;
            }
        }
        true
    }

    /// The bounding box of the polygon as clipped so far (`None` when it is empty).
    pub fn bounds(&self) -> Option<Box2> {
        let first = self.poly.first()?;
        let mut b = Box2 {
            u_lo: first[0],
            u_hi: first[0],
            x_lo: first[1],
            x_hi: first[1],
        };
        for v in &self.poly[1..] {
            b.u_lo = b.u_lo.min(v[0]);
            b.u_hi = b.u_hi.max(v[0]);
            b.x_lo = b.x_lo.min(v[1]);
            b.x_hi = b.x_hi.max(v[1]);
        }
        Some(b)
    }

    /// [`redundant_rows`] once the polygon started at `bbox` has been clipped by every row of
    /// `rows` (in any order, in any number of calls to [`Self::clip_all`]).
    pub fn mark_redundant(
        &mut self,
        rows: &[Row],
        bbox: Box2,
        redundant: &mut Vec<bool>,
    ) -> Option<usize> {
        redundant.clear();
        redundant.resize(rows.len(), false);
        let FacetWorkspace { poly, next } = self;
        // P reaches a side of the box (x_lo aside): the box, not the rows, bounds it there
        let on_side = |v: &[f64; 2]| {
            let near = |a: f64, b: f64| (a - b).abs() <= BOX_SIDE * b.abs().max(1.0);
            near(v[0], bbox.u_lo) || near(v[0], bbox.u_hi) || near(v[1], bbox.x_hi)
        };
        if poly.is_empty() || poly.iter().any(on_side) {
            return None;
        }
        // each vertex with its squared scale max(1, |v|)^2, for the margin
        next.clear();
        next.extend(poly.iter().map(|v| {
            let s = v[0].abs().max(v[1].abs()).max(1.0);
            [s * s, 0.0]
        }));
        // bounds over the vertices of |u|, |x| and the squared scale: a row whose largest
        // value is below the margin by these bounds touches at no vertex (the rounded
        // products and sums are monotonic, so the bounds hold as computed), and only the
        // others are tested vertex by vertex
        let (mut u_max, mut x_max, mut s2_max) = (0.0f64, 0.0f64, 0.0f64);
        for (v, s2) in poly.iter().zip(next.iter()) {
            u_max = u_max.max(v[0].abs());
            x_max = x_max.max(v[1].abs());
            s2_max = s2_max.max(s2[0]);
        }
        let margin2 = REDUNDANT_MARGIN * REDUNDANT_MARGIN;
        let mut count = 0;
        for (r, red) in rows.iter().zip(redundant.iter_mut()) {
            // value >= -margin |(a, b)| scale, on squares
            let m2 = margin2 * (r.a * r.a + r.b * r.b);
            let largest = largest_value(poly, r);
            let terms_max = r.a.abs() * u_max + r.b.abs() * x_max + r.c.abs();
            let surely_below =
                largest < -REDUNDANT_MARGIN * terms_max && largest * largest > m2 * s2_max;
            let touches = !surely_below
                && poly.iter().zip(next.iter()).any(|(v, s2)| {
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
}

/// The largest value of the row `r` at the vertices `poly` (`-inf` for none; the values are
/// finite, the rows and vertices being so).
fn largest_value(poly: &[[f64; 2]], r: &Row) -> f64 {
    let mut largest = f64::NEG_INFINITY;
    for v in poly {
        let value = r.a * v[0] + r.b * v[1] + r.c;
        largest = if value > largest { value } else { largest };
    }
    largest
}

/// Clips the convex polygon `poly` by `r <= 0` (`next`: a buffer).
fn clip(poly: &mut Vec<[f64; 2]>, next: &mut Vec<[f64; 2]>, r: &Row) {
    let value = |v: &[f64; 2]| r.a * v[0] + r.b * v[1] + r.c;
    if largest_value(poly, r) <= 0.0 {
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

    /// The rule of [`REDUNDANT_MARGIN`] at every vertex, without the bounds that spare most
    /// rows the test vertex by vertex.
    fn touches_slowly(poly: &[[f64; 2]], r: &Row) -> bool {
        let m2 = REDUNDANT_MARGIN * REDUNDANT_MARGIN * (r.a * r.a + r.b * r.b);
        poly.iter().any(|v| {
            let s = v[0].abs().max(v[1].abs()).max(1.0);
            let value = r.a * v[0] + r.b * v[1] + r.c;
            let terms = (r.a * v[0]).abs() + (r.b * v[1]).abs() + r.c.abs();
            value >= -REDUNDANT_MARGIN * terms || value * value <= m2 * (s * s)
        })
    }

    /// Random rows near a polygon's edges: some within the margin of touching it, some just
    /// beyond, some far (`near` moves the row's offset by a tiny multiple of its size).
    fn near_rows() -> impl Strategy<Value = Vec<Row>> {
        prop::collection::vec(
            (
                row(),
                prop::sample::select(vec![0.0, 1e-7, 1e-6, 1e-5, 2e-5, 1e-3]),
            ),
            1..40,
        )
        .prop_map(|rows| {
            rows.into_iter()
                .map(|(r, near)| Row {
                    c: r.c - near * (1.0 + r.c.abs()),
                    ..r
                })
                .collect()
        })
    }

    proptest! {
        /// The rows marked redundant are those the rule, applied at every vertex, marks: the
        /// bounds that skip the vertex-by-vertex test never change a decision. Each row is also
        /// given again moved to touch the polygon at a vertex, at the margin's edge.
        #[test]
        fn the_bounds_decide_as_every_vertex_does(rows in near_rows()) {
            let bbox = Box2 { u_lo: -30.0, u_hi: 30.0, x_lo: 0.0, x_hi: 30.0 };
            let mut rows = rows;
            rows.extend([
                Row { a: 1.0, b: 0.0, c: -2.0 },
                Row { a: -1.0, b: 0.0, c: -2.0 },
                Row { a: 0.0, b: 1.0, c: -2.0 },
            ]);
            let mut ws = FacetWorkspace::default();
            prop_assume!(ws.start(bbox) && ws.clip_all(&rows));
            let poly = ws.poly.clone();
            // each row shifted so that its largest value at a vertex is -margin times its terms
            let shifted: Vec<Row> = rows
                .iter()
                .map(|r| {
                    let (v, _) = poly
                        .iter()
                        .map(|v| (v, r.a * v[0] + r.b * v[1]))
                        .max_by(|a, b| a.1.total_cmp(&b.1))
                        .expect("a vertex");
                    let terms = (r.a * v[0]).abs() + (r.b * v[1]).abs();
                    Row { c: -(r.a * v[0] + r.b * v[1]) - REDUNDANT_MARGIN * terms, ..*r }
                })
                .collect();
            let all: Vec<Row> = rows.iter().chain(&shifted).copied().collect();
            let mut red = Vec::new();
            if ws.mark_redundant(&all, bbox, &mut red).is_some() {
                for (r, red) in all.iter().zip(&red) {
                    prop_assert_eq!(*red, !touches_slowly(&poly, r), "{:?}", r);
                }
            }
        }

        /// The polygon built in steps (some rows, its bounding box, the others) marks what
        /// [`redundant_rows`] marks, and its bounding box is that of the LPs over the rows so
        /// far.
        #[test]
        fn the_polygon_in_steps_is_the_polygon_at_once(rows in prop::collection::vec(row(), 1..40), cut in 0usize..40) {
            let bbox = Box2 { u_lo: -3.0, u_hi: 3.0, x_lo: 0.0, x_hi: 3.0 };
            let cut = cut.min(rows.len());
            let mut ws = FacetWorkspace::default();
            let mut red_once = Vec::new();
            let once = redundant_rows(&rows, bbox, &mut FacetWorkspace::default(), &mut red_once);
            prop_assert!(ws.start(bbox));
            if !ws.clip_all(&rows[..cut]) {
                prop_assert_eq!(once, None);
                return Ok(());
            }
            let b = ws.bounds().expect("not empty");
            let tol = Tolerances::default();
            let mut st = Lp2Stats::default();
            let lines = crate::lp2::StageLines::from_rows(&rows[..cut]);
            for (c, want) in [([1.0, 0.0], b.u_hi), ([-1.0, 0.0], -b.u_lo), ([0.0, 1.0], b.x_hi), ([0.0, -1.0], -b.x_lo)] {
                match solve(&lines, bbox, c, [-c[1], c[0]], &[], &tol, &mut st) {
                    Lp2::Optimal { u, x, .. } => {
                        let got = c[0] * u + c[1] * x;
                        prop_assert!((got - want).abs() <= 1e-9, "{got} vs {want}");
                    }
                    other => prop_assert!(false, "{other:?}"),
                }
            }
            let mut red = Vec::new();
            let steps = if ws.clip_all(&rows[cut..]) {
                ws.mark_redundant(&rows, bbox, &mut red)
            } else {
                None
            };
            prop_assert_eq!(steps, once);
            if steps.is_some() {
                prop_assert_eq!(red, red_once);
            }
        }

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
