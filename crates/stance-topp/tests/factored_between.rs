//! Eq. 14 rows from the factored form (U and the CoM path) against the shared a, b, c; the
//! violation between grid points; grid refinement; paths whose tangent vanishes at an end.

mod common;

use common::BowPath;
use stance_topp::between::{check_between, refine_until, PathRows};
use stance_topp::factored::FactoredRows;
use stance_topp::path::{CubicSpline, PathCurve, PathPoint, SplineEnds};
use stance_topp::tol::DEFAULT_BETWEEN_GRID_FRACTION;
use stance_topp::{solve, Discretization, SolveOptions, Status};

fn weight(inst: &common::Instance) -> f64 {
    inst.mass * inst.gravity.iter().map(|g| g * g).sum::<f64>().sqrt()
}

#[test]
fn factored_rows_reproduce_the_shared_rows() {
    for name in common::NAMES {
        let inst = common::load(name);
        let samples: Vec<PathPoint> = (0..inst.s.len())
            .map(|i| PathPoint {
                p: inst.com_path.p[i],
                ps: inst.com_path.ps[i],
                pss: inst.com_path.pss[i],
            })
            .collect();
        let f = FactoredRows::from_samples(
            &inst.u,
            inst.s.clone(),
            &samples,
            inst.mass,
            inst.gravity,
            None,
        )
        .unwrap();
        let k = f.to_constraints();
        let mut worst = 0.0f64;
        for i in 0..inst.s.len() {
            for (j, r) in k.rows_at(i).iter().enumerate() {
                let scale = inst.c[i][j].abs().max(1.0);
                worst = worst.max((r.a - inst.a[i][j]).abs() / scale);
                worst = worst.max((r.b - inst.b[i][j]).abs() / scale);
                worst = worst.max((r.c - inst.c[i][j]).abs() / scale);
            }
        }
        assert!(worst < 1e-12, "{name}: {worst:e}");
        // The recovered analytic path reproduces the samples.
        let path = BowPath::from_instance(&inst);
        for (i, &s) in inst.s.iter().enumerate() {
            let q = path.eval(s);
            for d in 0..3 {
                assert!((q.p[d] - inst.com_path.p[i][d]).abs() < 1e-12);
                assert!((q.ps[d] - inst.com_path.ps[i][d]).abs() < 1e-12);
                assert!((q.pss[d] - inst.com_path.pss[i][d]).abs() < 1e-12);
            }
        }
    }
}

#[test]
fn violation_between_grid_points_is_measured_and_refined_away() {
    for name in common::NAMES {
        let inst = common::load(name);
        let mg = weight(&inst);
        let rows = PathRows::new(
            inst.u.clone(),
            BowPath::from_instance(&inst),
            inst.mass,
            inst.gravity,
        )
        .unwrap();
        for disc in [Discretization::Collocation, Discretization::Interpolation] {
            let opts = SolveOptions::new(disc);
            let k = rows.on_grid(inst.s.clone()).unwrap();
            let sol = solve(&k, &opts).unwrap();
            let (rep, per) = check_between(sol.profile.as_ref().unwrap(), &rows, 20, mg);
            assert_eq!(per.len(), 100);
            println!(
                "{name} {disc:?} N=100: max violation {:.3} N = {:.2} % of m|g| at s = {:.3}",
                rep.max_violation,
                100.0 * rep.fraction,
                rep.at_s
            );
            let bound = DEFAULT_BETWEEN_GRID_FRACTION * mg;
            let r = refine_until(&rows, inst.s.clone(), &opts, bound, mg, 20_000, 20).unwrap();
            println!(
                "   refined: {} rounds, +{} points, {:.1} ms, violation {:.3} % of m|g|, duration {:.6} (was {:.6})",
                r.rounds,
                r.points_added,
                r.elapsed.as_secs_f64() * 1e3,
                100.0 * r.between.fraction,
                r.solution.duration().unwrap(),
                sol.duration().unwrap()
            );
            assert!(r.converged, "{name} {disc:?}");
            assert!(r.between.max_violation <= bound);
            assert_eq!(r.solution.status, Status::Optimal);
            // The refined grid keeps the original points.
            assert!(inst.s.iter().all(|s| r.grid.contains(s)));
        }
    }
}

#[test]
fn tangent_vanishing_at_the_start() {
    // A clamped spline with zero start tangent through the ds_flat waypoints: at s = 0 the rows
    // have a = -U (m p_s, ...) = 0 (zero inertia): only x-bounds remain there.
    let inst = common::load("ds_flat");
    let path = BowPath::from_instance(&inst);
    let knots: Vec<f64> = (0..=4).map(|i| i as f64 / 4.0).collect();
    let pts: Vec<[f64; 3]> = knots.iter().map(|&s| path.eval(s).p).collect();
    let end_tangent = path.eval(1.0).ps;
    let spline = CubicSpline::new(
        knots,
        pts,
        SplineEnds::Clamped {
            start: [0.0; 3],
            end: end_tangent,
        },
    )
    .unwrap();
    assert!(spline.eval(0.0).ps.iter().all(|v| v.abs() < 1e-14));
    let f =
        FactoredRows::from_path(&inst.u, inst.s.clone(), &spline, inst.mass, inst.gravity).unwrap();
    let k = f.to_constraints();
    assert!(k.rows_at(0).iter().all(|r| r.a.abs() < 1e-12));
    for disc in [Discretization::Collocation, Discretization::Interpolation] {
        let sol = solve(&k, &SolveOptions::new(disc)).unwrap();
        assert_eq!(sol.status, Status::Optimal, "{disc:?}");
        let res = sol.profile.as_ref().unwrap().residuals(&k, disc);
        assert!(res.enforced_max <= 1e-9);
        let d = sol.duration().unwrap();
        assert!(d.is_finite() && d > 0.0);
        if disc == Discretization::Collocation {
            // With a = 0 at s_0, collocation leaves u_0 unbounded by the rows: the greedy pass
            // jumps to x_1 = hi_1 and must brake back to rest at s_2 (x = [0, 0.88, 0, ...]).
            // Finite, admissible at the grid points, but physically a bounce: use
            // interpolation for such paths. (The one-shot LP maximizing sum x_i even stalls:
            // x_1 = 0.)
            let x = sol.profile.as_ref().unwrap().x();
            assert!(x[1] > 0.0);
            continue;
        }
        let common::lp::LpOutcome::Optimal(x_lp) = common::lp::one_shot(&k, disc, 0.0, 0.0) else {
            panic!("LP")
        };
        let d_lp = stance_topp::Profile::from_states(
            inst.s.clone(),
            x_lp.iter().map(|v| v.max(0.0)).collect(),
            vec![0.0; 100],
        )
        .unwrap()
        .duration();
        println!("tangent-vanishing {disc:?}: duration {d:.8}, one-shot LP profile {d_lp:.8}");
        assert!(((d - d_lp) / d_lp).abs() < 1e-5);
    }
}

mod angular {
    use proptest::prelude::*;
    use stance_topp::between::{ContinuousConstraints, PathRows};
    use stance_topp::path::{AngularTerms, PathCurve, Polyline};
    use stance_topp::Row;

    /// Round-off allowed between the eq. 14 rows of the crate and the naive formula written
    /// here, relative to the sum of the magnitudes of the products (plus 1 N): each side rounds
    /// about ten times at `EPSILON / 2`; 1e-14 (about 45 `EPSILON`) bounds the difference.
    const ROWS_AGREE: f64 = 1e-14;

    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    proptest! {
        /// With angular-momentum samples, the rows on a grid (factored fill) and the continuous
        /// rows (check between grid points) both equal the formula
        /// `a = -U (m p_s, m p x p_s + l1)`, `b = -U (m p_ss, m p x p_ss + l2)`,
        /// `c = U (m g, m p x g)` with `l1`, `l2` interpolated linearly here, independently.
        #[test]
        fn angular_terms_enter_a_and_b_as_in_eq14(
            u in prop::collection::vec(prop::array::uniform6(-1.0f64..1.0), 1..12),
            pts in prop::collection::vec(prop::array::uniform3(-1.0f64..1.0), 2..5),
            l in prop::collection::vec(prop::array::uniform2(prop::array::uniform3(-5.0f64..5.0)), 3),
            grid_n in 2usize..20,
        ) {
            let knots: Vec<f64> = (0..pts.len()).map(|i| i as f64).collect();
            let s_end = knots[knots.len() - 1];
            let path = Polyline::new(knots, pts).unwrap();
            let l_knots = vec![0.0, 0.3 * s_end, s_end];
            let l1: Vec<[f64; 3]> = l.iter().map(|v| v[0]).collect();
            let l2: Vec<[f64; 3]> = l.iter().map(|v| v[1]).collect();
            let (m, g) = (38.0, [0.1, -0.2, -9.81]);
            let rows = PathRows::new(u.clone(), path.clone(), m, g)
                .unwrap()
                .with_angular(AngularTerms::new(l_knots.clone(), l1.clone(), l2.clone()).unwrap())
                .unwrap();
            let grid: Vec<f64> = (0..=grid_n).map(|i| s_end * i as f64 / grid_n as f64).collect();
            let k = rows.on_grid(grid.clone()).unwrap();
            let mut cont = vec![Row::default(); u.len()];
            for (i, &s) in grid.iter().enumerate() {
                let q = path.eval(s);
                let seg = if s <= l_knots[1] { 0 } else { 1 };
                let t = (s - l_knots[seg]) / (l_knots[seg + 1] - l_knots[seg]);
                let lerp = |v: &[[f64; 3]]| [0, 1, 2].map(|d| v[seg][d] + t * (v[seg + 1][d] - v[seg][d]));
                let (la, lb) = (lerp(&l1), lerp(&l2));
                let wa = { let c = cross(q.p, q.ps); [0, 1, 2, 3, 4, 5].map(|j| if j < 3 { -m * q.ps[j] } else { -(m * c[j - 3] + la[j - 3]) }) };
                let wb = { let c = cross(q.p, q.pss); [0, 1, 2, 3, 4, 5].map(|j| if j < 3 { -m * q.pss[j] } else { -(m * c[j - 3] + lb[j - 3]) }) };
                let wc = { let c = cross(q.p, g); [0, 1, 2, 3, 4, 5].map(|j| if j < 3 { m * g[j] } else { m * c[j - 3] }) };
                rows.eval(s, &mut cont);
                for (j, r) in u.iter().enumerate() {
                    let dot = |w: &[f64; 6]| (0..6).map(|q| r[q] * w[q]).sum::<f64>();
                    let mag = |w: &[f64; 6]| (0..6).map(|q| (r[q] * w[q]).abs()).sum::<f64>() + 1.0;
                    let want = [dot(&wa), dot(&wb), dot(&wc)];
                    let scale = [mag(&wa), mag(&wb), mag(&wc)];
                    for got in [k.rows_at(i)[j], cont[j]] {
                        for ((g, e), sc) in [got.a, got.b, got.c].iter().zip(want).zip(scale) {
                            prop_assert!((g - e).abs() <= ROWS_AGREE * sc, "s {}: {} vs {}", s, g, e);
                        }
                    }
                }
            }
        }
    }

    /// Samples that do not cover the path are an error that says so.
    #[test]
    fn angular_samples_must_cover_the_path() {
        let path = Polyline::new(vec![0.0, 2.0], vec![[0.0; 3], [1.0; 3]]).unwrap();
        let l = AngularTerms::new(vec![0.0, 1.0], vec![[0.0; 3]; 2], vec![[0.0; 3]; 2]).unwrap();
        let e = PathRows::new(vec![[1.0; 6]], path, 1.0, [0.0, 0.0, -9.81])
            .unwrap()
            .with_angular(l)
            .unwrap_err();
        assert!(e.to_string().contains("cover"), "{e}");
    }
}
