//! The projection of lifted rows onto `(u, x)` (`stance_topp::lifted`) against an independent
//! LP solver (clarabel, interior point): on random lifted polytopes with 0 to 12 extra
//! variables, every row of the projection is valid (its support over the lifted polytope, by
//! clarabel, is at most its constant) and the projection is tight (its support in 48 directions
//! equals clarabel's support of the lifted polytope); empty polytopes are found empty; the warm
//! start across a sequence of slowly changing polytopes changes no answer.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus,
};
use stance_topp::lifted::{LiftedRows, Projection, Projector};
use stance_topp::lp2::{self, Box2, Lp2, Lp2Stats, StageLines};
use stance_topp::Tolerances;

/// `max c . (u, x)` over the lifted rows and the boxes, by clarabel; `None` when infeasible.
fn support_clarabel(rows: &LiftedRows, bbox: Box2, c: [f64; 2]) -> Option<f64> {
    let k = rows.extra();
    let n = 2 + k;
    let mut a_rows: Vec<Vec<f64>> = Vec::new();
    let mut b = Vec::new();
    for j in 0..rows.len() {
        let (ra, rb, rc, d) = rows.row(j);
        let mut r = vec![ra, rb];
        r.extend_from_slice(&d);
        a_rows.push(r);
        b.push(-rc);
    }
    let mut bound = |i: usize, s: f64, v: f64| {
        let mut r = vec![0.0; n];
        r[i] = s;
        a_rows.push(r);
        b.push(v);
    };
    bound(0, 1.0, bbox.u_hi);
    bound(0, -1.0, -bbox.u_lo);
    bound(1, 1.0, bbox.x_hi);
    bound(1, -1.0, -bbox.x_lo);
    for i in 0..k {
        bound(2 + i, 1.0, rows.y_bound);
        bound(2 + i, -1.0, rows.y_bound);
    }
    let m = a_rows.len();
    let mut a = CscMatrix::zeros((m, n));
    let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    for (i, r) in a_rows.iter().enumerate() {
        for (j, &v) in r.iter().enumerate() {
            if v != 0.0 {
                cols[j].push((i, v));
            }
        }
    }
    a.colptr = vec![0];
    a.rowval.clear();
    a.nzval.clear();
    for col in &cols {
        for &(i, v) in col {
            a.rowval.push(i);
            a.nzval.push(v);
        }
        a.colptr.push(a.rowval.len());
    }
    let p = CscMatrix::zeros((n, n));
    let mut q = vec![0.0; n];
    q[0] = -c[0];
    q[1] = -c[1];
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(1e-11)
        .tol_gap_rel(1e-11)
        .tol_feas(1e-11)
        .build()
        .unwrap();
    let cones = [NonnegativeConeT(m)];
    let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings).unwrap();
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => Some(-solver.solution.obj_val),
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => None,
        s => panic!("clarabel: {s:?}"),
    }
}

/// `max c . (u, x)` over the projection's rows and the box, by the crate's 2-variable LP.
fn support_rows(p: &Projection, bbox: Box2, c: [f64; 2]) -> Option<f64> {
    let lines = StageLines::from_rows(&p.rows);
    let t = [-c[1], c[0]];
    match lp2::solve(
        &lines,
        bbox,
        c,
        t,
        &[],
        &Tolerances::default(),
        &mut Lp2Stats::default(),
    ) {
        Lp2::Optimal { u, x, .. } => Some(c[0] * u + c[1] * x),
        Lp2::Infeasible => None,
    }
}

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % 2_000_001) as f64 / 1_000_000.0 - 1.0
    }
}

/// Random rows around a feasible point `(u0, x0, y0)` (each row's constant leaves it a random
/// slack), or with `infeasible`, two rows that contradict each other.
fn random_rows(rng: &mut Rng, k: usize, m: usize, infeasible: bool) -> LiftedRows {
    let mut rows = LiftedRows::new(k, 50.0);
    let (u0, x0) = (rng.next() * 3.0, 2.0 + rng.next());
    let y0: Vec<f64> = (0..k).map(|_| rng.next() * 5.0).collect();
    for _ in 0..m {
        let a = rng.next();
        let b = rng.next();
        let d: Vec<f64> = (0..k).map(|_| rng.next() * 2.0).collect();
        let at = a * u0 + b * x0 + d.iter().zip(&y0).map(|(p, q)| p * q).sum::<f64>();
        let slack = 0.2 + rng.next().abs() * 3.0;
        rows.push(a, b, -at - slack, &d);
    }
    if infeasible {
        let d: Vec<f64> = (0..k).map(|_| 1.0).collect();
        let nd: Vec<f64> = d.iter().map(|x| -x).collect();
        rows.push(1.0, 0.0, 10.0, &d); // u + sum y <= -10
        rows.push(-1.0, 0.0, 10.0, &nd); // u + sum y >= 10
    }
    rows
}

#[test]
fn projection_matches_clarabel_on_random_lifted_polytopes() {
    let mut rng = Rng(0x9E3779B97F4A7C15);
    let bbox = Box2 {
        u_lo: -40.0,
        u_hi: 40.0,
        x_lo: 0.0,
        x_hi: 30.0,
    };
    let mut projector = Projector::new();
    let mut out = Projection::default();
    let mut worst: f64 = 0.0;
    let (mut lps, mut cases) = (0, 0);
    for case in 0..120 {
        let k = [0, 1, 2, 6, 6, 12][case % 6];
        let m = 4 + (case * 7) % 40;
        let infeasible = case % 11 == 5;
        let rows = random_rows(&mut rng, k, m, infeasible);
        projector.reset();
        projector.project(&rows, bbox, 1e-10, &mut out).unwrap();
        lps += out.lps;
        cases += 1;
        let reference = support_clarabel(&rows, bbox, [1.0, 0.0]);
        if infeasible {
            assert!(
                out.empty && reference.is_none(),
                "case {case}: should be empty"
            );
            continue;
        }
        assert!(!out.empty, "case {case}: empty, clarabel {reference:?}");
        // every row is valid
        for (r, sup) in out.rows.iter().zip(&out.support) {
            let h = support_clarabel(&rows, bbox, [r.a, r.b]).unwrap();
            assert!(
                h + r.c <= 1e-6 * (1.0 + h.abs()),
                "case {case}: row {r:?} cuts ({h}), support {sup:?}"
            );
        }
        // tight in every direction
        for q in 0..48 {
            let th = q as f64 * std::f64::consts::TAU / 48.0 + 0.01;
            let c = [th.cos(), th.sin()];
            let ours = support_rows(&out, bbox, c).unwrap();
            let theirs = support_clarabel(&rows, bbox, c).unwrap();
            let e = (ours - theirs).abs() / (1.0 + theirs.abs());
            worst = worst.max(e);
            assert!(
                e < 1e-6,
                "case {case} (k = {k}, m = {m}), direction {c:?}: ours {ours}, clarabel {theirs}"
            );
        }
    }
    eprintln!(
        "worst relative support difference {worst:.1e}; {:.1} LPs per projection",
        lps as f64 / cases as f64
    );
}

/// A slowly changing sequence (as along a path): the warm start gives the same polygons as
/// fresh projections.
#[test]
fn warm_start_changes_no_answer() {
    let mut rng = Rng(42);
    let base = random_rows(&mut rng, 6, 30, false);
    let bbox = Box2 {
        u_lo: -40.0,
        u_hi: 40.0,
        x_lo: 0.0,
        x_hi: 30.0,
    };
    let mut warm = Projector::new();
    let (mut a, mut b) = (Projection::default(), Projection::default());
    for step in 0..50 {
        let mut rows = LiftedRows::new(6, 50.0);
        let t = step as f64 * 0.01;
        for j in 0..base.len() {
            let (ra, rb, rc, d) = base.row(j);
            rows.push(ra + 0.3 * t.sin(), rb, rc, &d);
        }
        warm.project(&rows, bbox, 1e-10, &mut a).unwrap();
        let mut fresh = Projector::new();
        fresh.project(&rows, bbox, 1e-10, &mut b).unwrap();
        for q in 0..24 {
            let th = q as f64 * std::f64::consts::TAU / 24.0 + 0.1;
            let c = [th.cos(), th.sin()];
            let (sa, sb) = (
                support_rows(&a, bbox, c).unwrap(),
                support_rows(&b, bbox, c).unwrap(),
            );
            assert!(
                (sa - sb).abs() < 1e-7 * (1.0 + sa.abs()),
                "step {step}: {sa} vs {sb}"
            );
        }
    }
}

/// The membership test agrees with the projection on random states (those within 1e-6 of the
/// polygon's boundary skipped), and a positive answer's witness satisfies every row.
#[test]
fn membership_agrees_with_the_projection() {
    use stance_topp::lifted::Membership;
    let mut rng = Rng(7);
    let bbox = Box2 {
        u_lo: -40.0,
        u_hi: 40.0,
        x_lo: 0.0,
        x_hi: 30.0,
    };
    let mut member = Membership::new();
    let (mut inside, mut outside) = (0, 0);
    for case in 0..60 {
        let k = [0, 1, 6, 12][case % 4];
        let rows = random_rows(&mut rng, k, 10 + case % 30, false);
        let mut out = Projection::default();
        Projector::new()
            .project(&rows, bbox, 1e-10, &mut out)
            .unwrap();
        let mut witness = stance_topp::lifted::Witnesses::new();
        for _ in 0..200 {
            let (u, x) = (rng.next() * 6.0, 2.5 + rng.next() * 2.0);
            let worst = out
                .rows
                .iter()
                .map(|r| (r.a * u + r.b * x + r.c) / r.a.hypot(r.b).max(1e-300))
                .fold(f64::NEG_INFINITY, f64::max);
            if worst.abs() < 1e-6 {
                continue;
            }
            let got = member.contains(&rows, u, x, &mut witness).unwrap();
            assert_eq!(
                got,
                worst < 0.0,
                "case {case}: ({u}, {x}) at distance {worst}"
            );
            if got {
                let y = witness.first().unwrap_or(&[]);
                assert!(Membership::holds_at(&rows, u, x, y));
                inside += 1;
            } else {
                outside += 1;
            }
        }
    }
    eprintln!(
        "{inside} inside, {outside} outside; {} programs, {} answered by the witness",
        member.lps, member.witnessed
    );
    assert!(inside > 100 && outside > 100);
}

/// The cuts of `Membership::separate`: none at admissible states, at the others a row that the
/// state violates and that clarabel finds valid over the whole lifted polytope; and the
/// cutting-plane loop (maximize over the cuts so far, separate the optimum) reaches clarabel's
/// support of the polytope in every direction, in few cuts.
#[test]
fn cuts_separate_and_converge_to_the_support() {
    use stance_topp::lifted::Membership;
    let mut rng = Rng(99);
    let bbox = Box2 {
        u_lo: -40.0,
        u_hi: 40.0,
        x_lo: 0.0,
        x_hi: 30.0,
    };
    let mut member = Membership::new();
    let (mut cuts_checked, mut max_rounds, mut loops) = (0, 0, 0);
    for case in 0..40 {
        let k = [0, 1, 6, 12][case % 4];
        let rows = random_rows(&mut rng, k, 10 + case % 30, false);
        let mut witness = stance_topp::lifted::Witnesses::new();
        for _ in 0..30 {
            let (u, x) = (rng.next() * 20.0, 15.0 + rng.next() * 15.0);
            let inside = support_clarabel(
                &rows,
                Box2 {
                    u_lo: u,
                    u_hi: u,
                    x_lo: x,
                    x_hi: x,
                },
                [1.0, 0.0],
            )
            .is_some();
            match member.separate(&rows, u, x, &mut witness).unwrap() {
                None => assert!(
                    inside,
                    "case {case}: ({u}, {x}) accepted, clarabel: outside"
                ),
                Some(cut) => {
                    let r = cut.row;
                    assert!(!inside, "case {case}: ({u}, {x}) cut, clarabel: inside");
                    assert!(
                        r.a * u + r.b * x + r.c > 0.0,
                        "case {case}: {r:?} not violated"
                    );
                    let h = support_clarabel(&rows, bbox, [r.a, r.b]).unwrap();
                    let n = r.a.hypot(r.b).max(r.c.abs() * 1e-12);
                    assert!(
                        (h + r.c) / n <= 1e-6 * (1.0 + h.abs() / n),
                        "case {case}: cut {r:?} invalid (support {h})"
                    );
                    cuts_checked += 1;
                }
            }
        }
        // the cutting-plane loop in 16 directions
        for q in 0..16 {
            let th = q as f64 * std::f64::consts::TAU / 16.0 + 0.05;
            let c = [th.cos(), th.sin()];
            let mut cuts: Vec<stance_topp::Row> = Vec::new();
            let mut rounds = 0;
            let value = loop {
                let lines = StageLines::from_rows(&cuts);
                let Lp2::Optimal { u, x, .. } = lp2::solve(
                    &lines,
                    bbox,
                    c,
                    [-c[1], c[0]],
                    &[],
                    &Tolerances::default(),
                    &mut Lp2Stats::default(),
                ) else {
                    panic!("case {case}: the cuts emptied a nonempty polytope");
                };
                match member.separate(&rows, u, x, &mut witness).unwrap() {
                    None => break c[0] * u + c[1] * x,
                    Some(cut) => cuts.push(cut.row),
                }
                rounds += 1;
                assert!(rounds < 64, "case {case}: the cuts do not converge");
            };
            let theirs = support_clarabel(&rows, bbox, c).unwrap();
            assert!(
                (value - theirs).abs() <= 1e-6 * (1.0 + theirs.abs()),
                "case {case}, direction {c:?}: {value} vs clarabel {theirs}"
            );
            max_rounds = max_rounds.max(rounds);
            loops += 1;
        }
    }
    eprintln!("{cuts_checked} cuts checked; {loops} loops, at most {max_rounds} cuts each");
    assert!(cuts_checked > 100);
}

/// A lifted set of the box climbing (right foot and hand, torque limits) on which the
/// projection's program once failed (cycling): projected, and checked against clarabel.
#[test]
fn box_climbing_regression() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/lifted_box_climbing.json");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let k = v["k"].as_u64().unwrap() as usize;
    let mut rows = LiftedRows::new(k, v["y_bound"].as_f64().unwrap());
    for r in v["rows"].as_array().unwrap() {
        let r: Vec<f64> = r
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        rows.push(r[0], r[1], r[2], &r[3..]);
    }
    let b: Vec<f64> = v["bbox"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let bbox = Box2 {
        u_lo: b[0],
        u_hi: b[1],
        x_lo: b[2],
        x_hi: b[3],
    };
    let mut out = Projection::default();
    Projector::new()
        .project(&rows, bbox, 1e-9, &mut out)
        .unwrap();
    for q in 0..24 {
        let th = q as f64 * std::f64::consts::TAU / 24.0 + 0.01;
        let c = [th.cos(), th.sin()];
        let ours = support_rows(&out, bbox, c);
        let theirs = support_clarabel(&rows, bbox, c);
        match (ours, theirs) {
            (Some(a), Some(b)) => {
                assert!((a - b).abs() < 1e-6 * (1.0 + b.abs()), "{c:?}: {a} vs {b}")
            }
            (None, None) => {}
            other => panic!("{c:?}: {other:?}"),
        }
    }
}
