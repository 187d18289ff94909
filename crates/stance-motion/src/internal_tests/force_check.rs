//! The force check's fast path (`crate::fast_forces`: the span form by the dense active-set
//! solver, warm-started) against its slow path (`stance_contact::supporting_forces`: the face
//! form by Clarabel, two phases) at every sample of the built-in motions at the checks' 1 ms,
//! played as retimed and 1.5 times faster (where supporting forces run out): the fast path
//! certifies forces only where the slow path finds them, misses at most 1 % of those (left to
//! the slow path: measured 1 of the stair climbing's 5,566 and 2 of the box climbing's 450 at
//! x1.5, none elsewhere), and the contacts' resultants give the same friction usage and normal
//! forces.

use crate::checks::w_gi_of;
use crate::fast_forces::FastForces;
use crate::{experiments, run_full, RunOptions};
use stance_contact::{supporting_forces, ForcesOutcome};
use stance_robot::Data;

/// Per contact: `(|F_t| / (mu F_n), F_n)` of a resultant.
fn usage(mu: f64, f: &[f64; 3]) -> (f64, f64) {
    (f[0].hypot(f[1]) / (mu * f[2]), f[2])
}

fn compare(name: &str, scale: f64) -> (usize, usize) {
    // the samples of the checks: every check_dt (1 ms)
    let mut spec = experiments::by_name(name).unwrap();
    spec.retiming.dt = spec.retiming.check_dt;
    let run = run_full(
        spec,
        &RunOptions {
            time_scale: Some(scale),
            skip_checks: true,
            ..Default::default()
        },
    )
    .unwrap();
    let m = &run.plan.robot.model;
    let mut data = Data::new(m);
    let mut fast = FastForces::new();
    let tol = stance_contact::tol::ContactTolerances::default();
    let (mut feasible, mut infeasible, mut missed) = (0, 0, 0);
    let (mut t_slow, mut t_fast) = (0.0, 0.0);
    for smp in &run.samples {
        let stance = &run.rows[smp.segment].stance;
        let w = w_gi_of(m, &mut data, &smp.q, &smp.v, &smp.a, run.plan.gravity).unwrap();
        let t0 = std::time::Instant::now();
        let slow = supporting_forces(stance, &w, &tol).unwrap();
        t_slow += t0.elapsed().as_secs_f64();
        let t0 = std::time::Instant::now();
        let quick = fast.resultants(stance, &w, tol.qp_max_residual);
        t_fast += t0.elapsed().as_secs_f64();
        match (slow.outcome, &quick) {
            (ForcesOutcome::Feasible, Some(r)) => {
                feasible += 1;
                let weight = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
                for ((c, cf), rf) in stance.contacts().iter().zip(&slow.contacts).zip(r) {
                    let mut sum = [0.0; 3];
                    for fl in &cf.forces_local {
                        for k in 0..3 {
                            sum[k] += fl[k];
                        }
                    }
                    // the same minimum-norm forces, up to the fast path's regularization and
                    // the slow path's interior-point tolerance
                    for k in 0..3 {
                        assert!(
                            (sum[k] - rf[k]).abs() <= 1e-4 * weight,
                            "{name} x{scale} t = {}: {} resultant {sum:?} against {rf:?}",
                            smp.t,
                            c.name()
                        );
                    }
                    // the usage ratio magnifies the resultants' agreement by the weight over
                    // the normal force: compared where a contact carries a tenth of it or more
                    if sum[2] > 0.1 * weight {
                        let (a, b) = (usage(c.friction(), &sum), usage(c.friction(), rf));
                        assert!(
                            (a.0 - b.0).abs() <= 1e-3,
                            "{name} t = {}: usage {a:?} {b:?}",
                            smp.t
                        );
                    }
                }
            }
            (ForcesOutcome::Infeasible, None) => infeasible += 1,
            (ForcesOutcome::Feasible, None) => missed += 1,
            (outcome, quick) => panic!(
                "{name} x{scale} t = {}: slow path {outcome:?}, fast path {}",
                smp.t,
                if quick.is_some() { "forces" } else { "none" }
            ),
        }
    }
    eprintln!(
        "{name} x{scale}: {feasible} samples with forces on both paths, {infeasible} without, \
         {missed} with forces left to the slow path; per sample {:.1} us (Clarabel) against \
         {:.1} us (fast path, {:.2} KKT solves)",
        1e6 * t_slow / run.samples.len() as f64,
        1e6 * t_fast / run.samples.len() as f64,
        fast.kkt_solves as f64 / run.samples.len() as f64
    );
    // a degenerate working set (a light contact's few free edges) is left to the slow path,
    // which is correct but slow: it must stay rare
    assert!(
        missed * 100 <= run.samples.len(),
        "{name} x{scale}: {missed} of {} samples left to the slow path",
        run.samples.len()
    );
    (feasible, infeasible)
}

#[test]
fn the_fast_path_agrees_with_clarabel_on_small_sway() {
    let (ok, _) = compare("small-sway", 1.0);
    assert!(ok > 100);
    let (_, none) = compare("small-sway", 1.5);
    assert!(none > 0, "played faster, some samples must lack forces");
}

#[test]
fn the_fast_path_agrees_with_clarabel_on_the_paper_experiments() {
    for name in ["stair-climbing", "box-climbing"] {
        let (ok, none) = compare(name, 1.0);
        assert!(ok > 300 && none == 0);
        let (_, none) = compare(name, 1.5);
        assert!(none > 0, "{name} played faster must lack forces somewhere");
    }
}
