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
