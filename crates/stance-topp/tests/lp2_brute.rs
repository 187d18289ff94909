//! The 2-variable LP kernel against brute-force vertex enumeration (every intersection of two
//! lines or box sides, kept when feasible, best objective).

use proptest::prelude::*;
use stance_topp::lp2::{solve, Box2, Lp2, Lp2Stats, StageLines};
use stance_topp::{Row, Tolerances};

/// Best objective over feasible vertices, or None if no vertex is feasible (then the region,
/// bounded by the box, is empty).
fn brute(rows: &[Row], bbox: Box2, c: [f64; 2], slack: f64) -> Option<f64> {
    let mut all: Vec<Row> = rows.to_vec();
    all.push(Row {
        a: 1.0,
        b: 0.0,
        c: -bbox.u_hi,
    });
    all.push(Row {
        a: -1.0,
        b: 0.0,
        c: bbox.u_lo,
    });
    all.push(Row {
        a: 0.0,
        b: 1.0,
        c: -bbox.x_hi,
    });
    all.push(Row {
        a: 0.0,
        b: -1.0,
        c: bbox.x_lo,
    });
    let mut best: Option<f64> = None;
    for i in 0..all.len() {
        for j in i + 1..all.len() {
            let (p, q) = (all[i], all[j]);
            let det = p.a * q.b - p.b * q.a;
            if det.abs() < 1e-12 {
                continue;
            }
            let u = (-p.c * q.b + q.c * p.b) / det;
            let x = (-q.c * p.a + p.c * q.a) / det;
            let ok = all.iter().all(|r| {
                r.a * u + r.b * x + r.c <= slack * (r.a * r.a + r.b * r.b).sqrt().max(1.0)
            });
            if ok {
                let v = c[0] * u + c[1] * x;
                best = Some(best.map_or(v, |b: f64| b.max(v)));
            }
        }
    }
    best
}

fn row() -> impl Strategy<Value = Row> {
    (-2.0f64..2.0, -2.0f64..2.0, -2.0f64..1.0, 0u8..5).prop_map(|(a, b, c, kind)| match kind {
        0 => Row { a: 0.0, b, c }, // zero-inertia row
        1 => Row { a, b: 0.0, c },
        _ => Row { a, b, c },
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]
    #[test]
    fn kernel_matches_vertex_enumeration(
        head in prop::collection::vec(row(), 0..3),
        here in prop::collection::vec(row(), 0..12),
        next in prop::collection::vec(row(), 0..6),
        td in 0.0f64..0.5,
        obj in 0usize..4,
        warm in prop::collection::vec(0usize..20, 0..4),
        split in (0usize..13, 0usize..7),
    ) {
        let mut h = [Row::default(); 2];
        let n_head = head.len().min(2);
        h[..n_head].copy_from_slice(&head[..n_head]);
        // a grid point's rows and the cuts added to it are the same kind of line
        let (here, here_cuts) = here.split_at(split.0.min(here.len()));
        let (next, next_cuts) = next.split_at(split.1.min(next.len()));
        let lines = StageLines { head: h, n_head, here, here_cuts, next, next_cuts, two_delta: td };
        let all: Vec<Row> = (0..lines.len()).map(|j| lines.get(j)).collect();
        let bbox = Box2 { u_lo: -5.0, u_hi: 5.0, x_lo: 0.0, x_hi: 5.0 };
        let (c, t) = [([0.0, 1.0], [1.0, 0.0]), ([0.0, -1.0], [-1.0, 0.0]), ([0.6, 0.8], [-0.8, 0.6]), ([-0.6, -0.8], [0.8, -0.6])][obj];
        let tol = Tolerances::default();
        let r = solve(&lines, bbox, c, t, &warm, &tol, &mut Lp2Stats::default());
        let b = brute(&all, bbox, c, 1e-9);
        match (r, b) {
            (Lp2::Optimal { u, x, .. }, Some(best)) => {
                prop_assert!((c[0] * u + c[1] * x - best).abs() < 1e-7, "kernel {} brute {}", c[0] * u + c[1] * x, best);
                for r in &all {
                    prop_assert!(r.a * u + r.b * x + r.c <= 1e-8 * (r.a * r.a + r.b * r.b).sqrt().max(1.0));
                }
            }
            (Lp2::Infeasible, None) => {}
            (Lp2::Infeasible, Some(best)) => {
                // Only acceptable when the region is thinner than the tolerances.
                let b_tight = brute(&all, bbox, c, -1e-7);
                prop_assert!(b_tight.is_none(), "kernel infeasible, brute {}", best);
            }
            (Lp2::Optimal { u, x, .. }, None) => {
                let b_loose = brute(&all, bbox, c, 1e-7);
                prop_assert!(b_loose.is_some(), "kernel optimal at ({}, {}), brute infeasible", u, x);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1000, ..ProptestConfig::default() })]
    /// Two LPs in one pass give the same optima as two single solves.
    #[test]
    fn pair_matches_two_single_solves(
        here in prop::collection::vec(row(), 0..12),
        next in prop::collection::vec(row(), 0..6),
        td in 0.0f64..0.5,
        warm0 in prop::collection::vec(0usize..20, 0..4),
        warm1 in prop::collection::vec(0usize..20, 0..4),
    ) {
        use stance_topp::lp2::solve_pair;
        let lines = StageLines { next: &next, two_delta: td, ..StageLines::from_rows(&here) };
        let bbox = Box2 { u_lo: -5.0, u_hi: 5.0, x_lo: 0.0, x_hi: 5.0 };
        let tol = Tolerances::default();
        let objs = [([0.0, 1.0], [1.0, 0.0]), ([0.0, -1.0], [-1.0, 0.0])];
        let pair = solve_pair(&lines, bbox, objs, [&warm0, &warm1], &tol, &mut Lp2Stats::default());
        for (p, w) in [&warm0, &warm1].into_iter().enumerate() {
            let single = solve(&lines, bbox, objs[p].0, objs[p].1, w, &tol, &mut Lp2Stats::default());
            match (pair[p], single) {
                (Lp2::Optimal { x: a, .. }, Lp2::Optimal { x: b, .. }) => prop_assert!((a - b).abs() < 1e-9),
                (Lp2::Infeasible, Lp2::Infeasible) => {}
                (a, b) => prop_assert!(false, "pair {:?} single {:?}", a, b),
            }
        }
    }
}
