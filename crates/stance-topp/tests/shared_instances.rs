//! The shared retiming instances (paper eq. 14 on two stances, N = 100) against toppra 0.6.10's
//! answers stored in the files.
//!
//! toppra's forward pass deliberately aims slightly inside the next controllable set, so its
//! profile is a little slower than the exact greedy one: our durations are shorter by
//! 2e-8 (ds_flat) to 8e-7 (mc_minvel) relative, never longer.

mod common;

use stance_topp::{solve, Discretization, SolveOptions, Status};

/// Our duration may be shorter than toppra's by this much (relative), never longer (beyond
/// round-off `1e-12`). Measured: 7.7e-7 at most.
const TOPPRA_CONSERVATISM: f64 = 1e-6;
/// Largest residual of an enforced row scaled to `|(a, b)| = 1` (unit 1/s^2). Measured: 6e-13.
const RESIDUAL_BOUND: f64 = 1e-9;

#[test]
fn durations_match_toppra_and_rows_hold() {
    for name in common::NAMES {
        let inst = common::load(name);
        let k = inst.constraints();
        for (disc, reference) in [
            (
                Discretization::Collocation,
                inst.reference.duration_collocation,
            ),
            (
                Discretization::Interpolation,
                inst.reference.duration_interpolation,
            ),
        ] {
            let opts = SolveOptions::new(disc)
                .with_start(inst.sd_start)
                .with_end(inst.sd_end);
            let sol = solve(&k, &opts).unwrap();
            assert_eq!(sol.status, Status::Optimal, "{name} {disc:?}");
            assert_eq!(sol.discretization, disc);
            let d = sol.duration().unwrap();
            let rel = (d - reference) / reference;
            assert!(
                (-TOPPRA_CONSERVATISM..=1e-12).contains(&rel),
                "{name} {disc:?}: ours {d} toppra {reference} rel {rel:e}"
            );
            let res = sol.profile.as_ref().unwrap().residuals(&k, disc);
            assert!(
                res.enforced_max <= RESIDUAL_BOUND,
                "{name} {disc:?}: {}",
                res.enforced_max
            );
        }
    }
}

#[test]
fn collocation_profile_matches_toppra_and_one_shot_lp() {
    for name in common::NAMES {
        let inst = common::load(name);
        let k = inst.constraints();
        let sol = solve(&k, &SolveOptions::default()).unwrap();
        let sd = sol.profile.as_ref().unwrap().sd();
        let worst = sd
            .iter()
            .zip(&inst.reference.sd_collocation)
            .map(|(a, b)| (a - b).abs() / b.max(1.0))
            .fold(0.0, f64::max);
        // toppra's speeds are below ours by its forward-pass margin.
        assert!(worst < 1e-4, "{name}: sd differs from toppra by {worst:e}");
        let lp = inst.reference.duration_one_shot_lp_collocation;
        let d = sol.duration().unwrap();
        assert!(
            ((d - lp) / lp).abs() < 2e-6,
            "{name}: ours {d} one-shot LP {lp}"
        );
    }
}

#[test]
fn mc_minvel_needs_a_minimum_speed_mid_path() {
    let inst = common::load("mc_minvel");
    let k = inst.constraints();
    let sol = solve(&k, &SolveOptions::default()).unwrap();
    assert_eq!(sol.status, Status::Optimal);
    // Somewhere mid-path the controllable set excludes rest: lo_i > 0.
    let needs_speed: Vec<usize> = sol
        .controllable
        .iter()
        .enumerate()
        .filter(|(_, kk)| kk.unwrap()[0] > 1e-6)
        .map(|(i, _)| i)
        .collect();
    assert!(!needs_speed.is_empty());
    assert!(needs_speed.iter().all(|&i| i > 0 && i < 100));
    let x = sol.profile.as_ref().unwrap().x();
    for &i in &needs_speed {
        assert!(x[i] >= sol.controllable[i].unwrap()[0] * (1.0 - 1e-9));
    }
    // Starting at rest where a minimum speed is needed is reported as a value.
    let i0 = needs_speed[0];
    let sub = stance_topp::CanonicalConstraints::from_dense(
        &inst.s[i0..],
        &inst.a[i0..],
        &inst.b[i0..],
        &inst.c[i0..],
    )
    .unwrap();
    let sol = solve(&sub, &SolveOptions::default()).unwrap();
    assert!(
        matches!(sol.status, Status::StartOutsideControllable { x_start, lo, .. } if x_start == 0.0 && lo > 0.0),
        "{:?}",
        sol.status
    );
    assert!(sol.profile.is_none());
}

#[test]
fn warm_start_does_not_change_the_answer() {
    for name in common::NAMES {
        let inst = common::load(name);
        let k = inst.constraints();
        for disc in [Discretization::Collocation, Discretization::Interpolation] {
            let mut opts = SolveOptions::new(disc);
            let warm = solve(&k, &opts).unwrap();
            opts.warm_start = false;
            let cold = solve(&k, &opts).unwrap();
            let (dw, dc) = (warm.duration().unwrap(), cold.duration().unwrap());
            assert!(
                ((dw - dc) / dc).abs() < 1e-12,
                "{name} {disc:?}: {dw} vs {dc}"
            );
        }
    }
}
