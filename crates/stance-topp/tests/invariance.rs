//! Invariance as a contract: the retiming does not depend on
//!
//! - a positive factor on any row (`a u + b x + c <= 0` and `k (a u + b x + c) <= 0` are the
//!   same half-plane): factors `2^k` from `2^-300` to `2^300` give the same answer bit for bit,
//!   any factor from `1e-90` to `1e90` the same answer up to rounding;
//! - the unit and origin of the path parameter (`s -> alpha s + beta`, with the rows and speeds
//!   rewritten for the new parameter: `a -> a / alpha`, `b -> b / alpha^2`,
//!   `s' -> alpha s'`), for `alpha` from `1e-6` to `1e6` and `|beta|` up to `1e3 alpha`: the
//!   same duration to the solver's state accuracy (`tol.state`, `1e-8` relative) and end speeds
//!   to `1e-10`, except where a profile comes to rest within that accuracy: there `1 / sqrt(x)`
//!   makes the duration ill-conditioned (a stall, or a "finite" 3e6 s, depending on the last bit
//!   of a row);
//! - the unit of time (`c -> lambda c` in every row: `x`, `u` and the bounds scale by `lambda`,
//!   durations by `1 / sqrt(lambda)`), for `lambda` from `1e-12` to `1e12`: the solver decides
//!   in the rows' own time unit (`CanonicalConstraints::on_unit_time`), so the same duration
//!   to the solver's state accuracy, and the closed forms of bounded acceleration and speed are
//!   met across that range.

use proptest::prelude::*;
use stance_topp::{
    end_speed_range, solve, CanonicalConstraints, Discretization, Row, SolveOptions, Status,
};

/// A random instance: `|u| <= u_max`, `x <= x_max` and `m` random rows satisfied at rest, on
/// `n + 1` uneven grid points of `[0, len]`.
fn instance(seed: u64, n: usize, m: usize, len: f64) -> (Vec<f64>, Vec<usize>, Vec<Row>) {
    let mut state = seed;
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut s = vec![0.0];
    for _ in 0..n {
        let step = 0.5 + next();
        s.push(s.last().unwrap() + step);
    }
    let total = *s.last().unwrap();
    s.iter_mut().for_each(|x| *x *= len / total);
    let (mut offsets, mut rows) = (vec![0], Vec::new());
    for _ in 0..=n {
        let (u_max, x_max) = (0.5 + 2.0 * next(), 1.0 + 4.0 * next());
        rows.push(Row {
            a: 1.0,
            b: 0.0,
            c: -u_max,
        });
        rows.push(Row {
            a: -1.0,
            b: 0.0,
            c: -u_max,
        });
        rows.push(Row {
            a: 0.0,
            b: 1.0,
            c: -x_max,
        });
        for _ in 0..m {
            rows.push(Row {
                a: 2.0 * next() - 1.0,
                b: 2.0 * next() - 1.0,
                c: -0.2 - next(),
            });
        }
        offsets.push(rows.len());
    }
    (s, offsets, rows)
}

fn constraints(s: &[f64], offsets: &[usize], rows: &[Row]) -> CanonicalConstraints {
    CanonicalConstraints::new(s.to_vec(), offsets.to_vec(), rows.to_vec()).unwrap()
}

fn opts(interpolation: bool, sd_start: f64) -> SolveOptions {
    let disc = if interpolation {
        Discretization::Interpolation
    } else {
        Discretization::Collocation
    };
    SolveOptions::new(disc).with_start(sd_start)
}

/// Whether the profile has an interior state at rest within the solver's state accuracy
/// (`tol.state` relative to its largest state) but not exactly at rest.
fn near_stall(sol: &stance_topp::Solution) -> bool {
    let Some(p) = &sol.profile else {
        return false;
    };
    let x = p.x();
    let top = x.iter().copied().fold(0.0, f64::max);
    let eps = stance_topp::Tolerances::default().state * top;
    x[1..x.len() - 1].iter().any(|&xi| xi <= eps)
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, .. ProptestConfig::default() })]

    /// Each row multiplied by its own power of two: the same solution, bit for bit.
    #[test]
    fn row_scaling_by_powers_of_two_changes_nothing(
        seed in any::<u64>(), n in 2usize..40, m in 0usize..6, interp in any::<bool>()
    ) {
        let (s, offsets, rows) = instance(seed, n, m, 1.0);
        let mut e = seed;
        let scaled: Vec<Row> = rows.iter().map(|r| {
            e = e.wrapping_mul(2862933555777941757).wrapping_add(3037000493);
            let f = 2f64.powi(((e >> 33) % 601) as i32 - 300);
            Row { a: r.a * f, b: r.b * f, c: r.c * f }
        }).collect();
        let o = opts(interp, 0.0);
        let a = solve(&constraints(&s, &offsets, &rows), &o).unwrap();
        let b = solve(&constraints(&s, &offsets, &scaled), &o).unwrap();
        prop_assert_eq!(a.status, b.status);
        prop_assert_eq!(a.profile, b.profile);
        prop_assert_eq!(a.controllable, b.controllable);
    }

    /// Each row multiplied by any factor from 1e-90 to 1e90: the same duration up to the
    /// rounding of the scaled rows.
    #[test]
    fn row_scaling_by_any_factor_keeps_the_duration(
        seed in any::<u64>(), n in 2usize..40, m in 0usize..6, interp in any::<bool>()
    ) {
        let (s, offsets, rows) = instance(seed, n, m, 1.0);
        let mut e = seed;
        let scaled: Vec<Row> = rows.iter().map(|r| {
            e = e.wrapping_mul(2862933555777941757).wrapping_add(3037000493);
            let f = 10f64.powf(((e >> 11) as f64 / (1u64 << 53) as f64) * 180.0 - 90.0);
            Row { a: r.a * f, b: r.b * f, c: r.c * f }
        }).collect();
        let o = opts(interp, 0.0);
        let a = solve(&constraints(&s, &offsets, &rows), &o).unwrap();
        let b = solve(&constraints(&s, &offsets, &scaled), &o).unwrap();
        // The rows are rounded once scaled, and the solver's states are accurate to
        // `tol.state` (relative): where a profile brakes to rest within that accuracy (a
        // state of 2e-14 against 0.57 next to it), `1 / sqrt(x)` makes the duration and the
        // status (a stall, or a "finite" 3e6 s) ill-conditioned. Elsewhere: the same status
        // and duration.
        if near_stall(&a) || near_stall(&b) {
            return Ok(());
        }
        prop_assert_eq!(a.status, b.status);
        if let (Some(da), Some(db)) = (a.duration(), b.duration()) {
            prop_assert!(da == db || close(da, db, 1e-9), "{} against {}", da, db);
        }
    }

    /// `s -> alpha s + beta` with the rows and speeds rewritten: the same duration, the same
    /// path speeds (in the new unit) and the same end speed range.
    #[test]
    fn path_parameter_unit_and_origin_do_not_matter(
        seed in any::<u64>(), n in 2usize..40, m in 0usize..6, interp in any::<bool>(),
        log_alpha in -6.0f64..6.0, beta_frac in -1e3f64..1e3, sd in 0.0f64..0.5,
    ) {
        let (s, offsets, rows) = instance(seed, n, m, 1.0);
        let alpha = 10f64.powf(log_alpha);
        let beta = beta_frac * alpha;
        let s2: Vec<f64> = s.iter().map(|x| alpha * x + beta).collect();
        prop_assume!(s2.windows(2).all(|w| w[1] > w[0]));
        let rows2: Vec<Row> = rows
            .iter()
            .map(|r| Row { a: r.a / alpha, b: r.b / (alpha * alpha), c: r.c })
            .collect();
        let (k1, k2) = (constraints(&s, &offsets, &rows), constraints(&s2, &offsets, &rows2));
        let a = solve(&k1, &opts(interp, sd)).unwrap();
        let b = solve(&k2, &opts(interp, sd * alpha)).unwrap();
        // (Profiles at rest within the state accuracy are ill-conditioned: see
        // `row_scaling_by_any_factor_keeps_the_duration`.)
        if near_stall(&a) || near_stall(&b) {
            return Ok(());
        }
        prop_assert_eq!(a.status, b.status);
        if let (Some(da), Some(db)) = (a.duration(), b.duration()) {
            // Equal also when both are infinite (the same stall); otherwise to the solver's
            // state accuracy (`tol.state`): the shifted grid rounds at |beta| / range eps, which
            // a slow profile amplifies (measured: 6.6e-10 on a 24.8 s profile shifted by 289
            // ranges; 1e-13 and below without a shift).
            prop_assert!(da == db || close(da, db, 1e-8), "{} against {}", da, db);
        }
        if let (Some(pa), Some(pb)) = (&a.profile, &b.profile) {
            for (xa, xb) in pa.x().iter().zip(pb.x()) {
                prop_assert!((xa * alpha * alpha - xb).abs() <= 1e-9 * xb.abs().max(alpha * alpha));
            }
        }
        let ea = end_speed_range(&k1, &opts(interp, sd)).unwrap();
        let eb = end_speed_range(&k2, &opts(interp, sd * alpha)).unwrap();
        prop_assert_eq!(ea.is_some(), eb.is_some());
        if let (Some([la, ha]), Some([lb, hb])) = (ea, eb) {
            // Compared as x = s'^2, the solver's variable (the square root of a state at
            // rounding level amplifies its noise), relative to the largest.
            let (a2, b2) = (alpha * alpha, hb * hb);
            // (1e-10: the grid shifted by up to 1e3 ranges rounds at 1e3 eps per point.)
            prop_assert!((la * la * a2 - lb * lb).abs() <= 1e-10 * b2, "{} {}", la * alpha, lb);
            prop_assert!((ha * ha * a2 - b2).abs() <= 1e-10 * b2, "{} {}", ha * alpha, hb);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, .. ProptestConfig::default() })]

    /// `c -> lambda c` (time in a unit `sqrt(lambda)` times larger): the same status, the
    /// duration divided by `sqrt(lambda)`, states multiplied by `lambda`.
    #[test]
    fn the_unit_of_time_does_not_matter(
        seed in any::<u64>(), n in 2usize..40, m in 0usize..6, interp in any::<bool>(),
        log_lambda in -12.0f64..12.0, sd in 0.0f64..0.5,
    ) {
        let (s, offsets, rows) = instance(seed, n, m, 1.0);
        let lambda = 10f64.powf(log_lambda);
        let rows2: Vec<Row> = rows.iter().map(|r| Row { c: r.c * lambda, ..*r }).collect();
        let a = solve(&constraints(&s, &offsets, &rows), &opts(interp, sd)).unwrap();
        let b = solve(&constraints(&s, &offsets, &rows2), &opts(interp, sd * lambda.sqrt())).unwrap();
        if near_stall(&a) || near_stall(&b) {
            return Ok(());
        }
        prop_assert_eq!(a.status, b.status);
        if let (Some(da), Some(db)) = (a.duration(), b.duration()) {
            let db = db * lambda.sqrt();
            prop_assert!(da == db || close(da, db, 1e-8), "{} against {}", da, db);
        }
        if let (Some(pa), Some(pb)) = (&a.profile, &b.profile) {
            let top = pa.x().iter().copied().fold(1.0, f64::max);
            for (xa, xb) in pa.x().iter().zip(pb.x()) {
                prop_assert!((xa * lambda - xb).abs() <= 1e-9 * top * lambda);
            }
        }
    }

    /// `|u| <= A`, `x <= V^2` over a path of length `L` (the sweep's closed forms): rest to
    /// rest in `L / V + V / A` when the cruise is reached, `2 sqrt(L / A)` when the switch is
    /// at the middle, for `L` from `1e-4` to `1e4` and `V` from `1e-2` to `1e2` (speeds and
    /// accelerations over twenty orders of magnitude).
    #[test]
    fn bounded_acceleration_and_speed_meet_their_closed_form(
        log_len in -4.0f64..4.0, log_v in -2.0f64..2.0, k in 1usize..=5, interp in any::<bool>(),
    ) {
        let (len, v) = (10f64.powf(log_len), 10f64.powf(log_v));
        // the switch points on the grid: accelerate over k tenths of the path
        let acc = v * v / (2.0 * len * k as f64 / 10.0);
        let want = if k == 5 { 2.0 * (len / acc).sqrt() } else { len / v + v / acc };
        let n = 11;
        let s: Vec<f64> = (0..n).map(|j| len * j as f64 / (n - 1) as f64).collect();
        let rows: Vec<Row> = (0..n)
            .flat_map(|_| {
                [
                    Row { a: 1.0, b: 0.0, c: -acc },
                    Row { a: -1.0, b: 0.0, c: -acc },
                    Row { a: 0.0, b: 1.0, c: -v * v },
                ]
            })
            .collect();
        let offsets: Vec<usize> = (0..=n).map(|i| 3 * i).collect();
        let sol = solve(&constraints(&s, &offsets, &rows), &opts(interp, 0.0)).unwrap();
        prop_assert_eq!(sol.status, Status::Optimal);
        let got = sol.duration().unwrap();
        prop_assert!(close(got, want, 1e-9), "{} against {}", got, want);
    }
}

/// The sweep's two closed forms the solver answered wrongly before it decided in the rows' own
/// time unit: 395,344 s for 530,410 s (accelerations of 4.9e-8 over a path of 3460) and
/// 1.45e-4 s for 1.6e-5 s (2.9e7 over 1.03e-3, which hit the speed box).
#[test]
fn closed_forms_far_from_unit_time() {
    for (len, v, k) in [(3460.0f64, 1.7e-4f64.sqrt(), 5usize), (1.03e-3, 0.0, 5)] {
        let acc = if v > 0.0 {
            v * v / (2.0 * len * k as f64 / 10.0)
        } else {
            2.9e7
        };
        let v = if v > 0.0 { v } else { 1e9 };
        let want = if 2.0 * (len / 2.0) * acc <= v * v {
            2.0 * (len / acc).sqrt()
        } else {
            len / v + v / acc
        };
        let n = 11;
        let s: Vec<f64> = (0..n).map(|j| len * j as f64 / (n - 1) as f64).collect();
        let rows: Vec<Row> = (0..n)
            .flat_map(|_| {
                [
                    Row {
                        a: 1.0,
                        b: 0.0,
                        c: -acc,
                    },
                    Row {
                        a: -1.0,
                        b: 0.0,
                        c: -acc,
                    },
                    Row {
                        a: 0.0,
                        b: 1.0,
                        c: -v * v,
                    },
                ]
            })
            .collect();
        let offsets: Vec<usize> = (0..=n).map(|i| 3 * i).collect();
        for interp in [false, true] {
            let sol = solve(&constraints(&s, &offsets, &rows), &opts(interp, 0.0)).unwrap();
            let got = sol.duration().unwrap();
            assert!(close(got, want, 1e-9), "{got} against {want}");
        }
    }
}

/// The robustness sweep's case: `|u| <= 1`, `x <= 1` written with rows of norm 1e-10 on 11
/// grid points take 2 s rest to rest, as with unit rows (it was "optimal" in 0.0002 s: rows
/// that small were within the absolute slack everywhere).
#[test]
fn tiny_rows_are_constraints() {
    for f in [1.0, 1e-10, 1e-20, 1e-100, 1e50] {
        let s: Vec<f64> = (0..=10).map(|i| i as f64 / 10.0).collect();
        let row = |a: f64, b: f64| Row {
            a: a * f,
            b: b * f,
            c: -f,
        };
        let rows = [row(1.0, 0.0), row(-1.0, 0.0), row(0.0, 1.0)].repeat(11);
        let offsets: Vec<usize> = (0..=11).map(|i| 3 * i).collect();
        let k = CanonicalConstraints::new(s, offsets, rows).unwrap();
        let sol = solve(&k, &SolveOptions::default()).unwrap();
        assert_eq!(sol.status, Status::Optimal);
        let d = sol.duration().unwrap();
        assert!((d - 2.0).abs() < 1e-9, "{f:e}: {d}");
    }
}

/// A row 1e-20 times smaller than the others among unit rows is honoured (it was violated).
#[test]
fn a_tiny_row_among_unit_rows_is_honoured() {
    let s: Vec<f64> = (0..=10).map(|i| i as f64 / 10.0).collect();
    let mut rows = Vec::new();
    let mut offsets = vec![0];
    for _ in 0..=10 {
        rows.push(Row {
            a: 1.0,
            b: 0.0,
            c: -1.0,
        });
        rows.push(Row {
            a: -1.0,
            b: 0.0,
            c: -1.0,
        });
        // x <= 0.25, written 1e-20 times smaller.
        rows.push(Row {
            a: 0.0,
            b: 1e-20,
            c: -0.25e-20,
        });
        offsets.push(rows.len());
    }
    let sol = solve(
        &CanonicalConstraints::new(s, offsets, rows).unwrap(),
        &SolveOptions::default(),
    )
    .unwrap();
    let x_max = sol
        .profile
        .as_ref()
        .unwrap()
        .x()
        .iter()
        .copied()
        .fold(0.0, f64::max);
    assert!(x_max <= 0.25 * (1.0 + 1e-9), "{x_max}");
}

/// A grid `[0, 1e-12, 2e-12]` starts at rest when asked to (it started at `s' = 2e-6`), and
/// its duration is that of `[0, 1, 2]` rewritten.
#[test]
fn a_tiny_grid_starts_at_rest() {
    for len in [1e-12, 1e-6, 1.0, 1e6] {
        let s = vec![0.0, len, 2.0 * len];
        let rows = [
            Row {
                a: 1.0 / len,
                b: 0.0,
                c: -1.0,
            },
            Row {
                a: -1.0 / len,
                b: 0.0,
                c: -1.0,
            },
        ]
        .repeat(3);
        let k = CanonicalConstraints::new(s, vec![0, 2, 4, 6], rows).unwrap();
        let sol = solve(&k, &SolveOptions::default()).unwrap();
        let p = sol.profile.unwrap();
        assert_eq!(p.x()[0], 0.0, "{len:e}");
        assert_eq!(p.x()[2], 0.0, "{len:e}");
        assert!(
            (p.duration() - 2.0 * 2f64.sqrt()).abs() < 1e-9,
            "{len:e}: {}",
            p.duration()
        );
    }
}

/// Found by the `topp` fuzz target: a grid starting at -3.1e231 with subnormal rows made the
/// rescaling of the path parameter overflow an exponent (a panic). Now solved or refused with
/// an error, never a panic.
#[test]
fn fuzz_regression_huge_grid_origin_and_subnormal_rows() {
    let s = vec![
        -3.1050361846125374e231,
        4.072905671284e-312,
        -1.004150390625,
    ];
    let rows = vec![
        Row {
            a: 3.1e-322,
            b: 3.3156184e-316,
            c: 2.42764e-319,
        },
        Row {
            a: 4.4145465352782875e-305,
            b: 0.0,
            c: -1.004150390625,
        },
        Row {
            a: 3.47328271065196e-310,
            b: 0.0,
            c: 0.0,
        },
    ];
    // Not increasing: refused at construction.
    assert!(CanonicalConstraints::new(s, vec![0, 1, 2, 3], rows.clone()).is_err());
    // Increasing, from -3.1e231: solved on the rescaled grid or refused, without a panic.
    let s = vec![-3.1050361846125374e231, 4.072905671284e-312, 1.004150390625];
    let k = CanonicalConstraints::new(s, vec![0, 1, 2, 3], rows).unwrap();
    let _ = solve(&k, &SolveOptions::default());
    // A range that overflows is an error that says so.
    let e = CanonicalConstraints::new(
        vec![-1.5e308, 1.5e308],
        vec![0, 1, 2],
        vec![
            Row {
                a: 1.0,
                b: 0.0,
                c: -1.0
            };
            2
        ],
    )
    .unwrap_err();
    assert!(e.to_string().contains("overflows"), "{e}");
    // Found by the fuzz target: a range of 6.8e303 (finite) whose squared unit overflows: the
    // profile came back as NaN. Now an error naming the range.
    let k = CanonicalConstraints::new(
        vec![-5.486124068793689e303, 0.25, 1.3715310171984222e303],
        vec![0, 1, 2, 3],
        vec![
            Row {
                a: 1.0,
                b: 0.0,
                c: -1.0
            };
            3
        ],
    )
    .unwrap();
    let e = solve(&k, &SolveOptions::default()).unwrap_err();
    assert!(e.to_string().contains("1e-150 to 1e150"), "{e}");
}
