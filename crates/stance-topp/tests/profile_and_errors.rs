//! The exact s(t) of a profile (round trips at the grid points, monotonicity, speeds), its
//! inverse t(s), and the errors for bad input.

use proptest::prelude::*;
use stance_topp::{
    solve, CanonicalConstraints, Discretization, Profile, Row, SolveOptions, ToppError,
};

proptest! {
    /// Random admissible states: s(t_i) = s_i, s'(t_i)^2 = x_i, s(t) non-decreasing, and
    /// s'(t) continuous across grid points.
    #[test]
    fn time_to_path_inverse_is_exact(
        deltas in prop::collection::vec(0.01f64..1.0, 1..30),
        xs in prop::collection::vec(0.0f64..4.0, 31),
    ) {
        let mut s = vec![0.0];
        for d in &deltas {
            s.push(s.last().unwrap() + d);
        }
        let n = s.len();
        let mut x: Vec<f64> = xs[..n].to_vec();
        // Avoid two consecutive zero states (an infinite interval).
        for i in 1..n {
            if x[i] == 0.0 && x[i - 1] == 0.0 {
                x[i] = 0.5;
            }
        }
        let u: Vec<f64> = (0..n - 1).map(|i| (x[i + 1] - x[i]) / (2.0 * (s[i + 1] - s[i]))).collect();
        let p = Profile::from_states(s.clone(), x.clone(), u).unwrap();
        prop_assert!(p.duration().is_finite());
        for i in 0..n {
            let q = p.at(p.times()[i]);
            prop_assert!((q.s - s[i]).abs() <= 1e-9 * (1.0 + s[i].abs()), "s({}) = {} vs {}", i, q.s, s[i]);
            prop_assert!((q.sd * q.sd - x[i]).abs() <= 1e-9 * (1.0 + x[i]));
        }
        let samples = p.resample(p.duration() / 97.0).unwrap();
        for w in samples.windows(2) {
            prop_assert!(w[1].s >= w[0].s - 1e-12);
            prop_assert!(w[1].t > w[0].t);
        }
        let last = samples.last().unwrap();
        prop_assert!((last.s - s[n - 1]).abs() <= 1e-9 * (1.0 + s[n - 1]));
        // time_at inverts at: at the grid points and inside the intervals
        for (si, ti) in s.iter().zip(p.times()) {
            let t = p.time_at(*si);
            prop_assert!((t - ti).abs() <= 1e-9 * (1.0 + p.duration()), "{} vs {}", t, ti);
        }
        for smp in &samples {
            let t = p.time_at(smp.s);
            // s(t) is flat where the speed is zero: the times agree through s
            prop_assert!((p.at(t).s - smp.s).abs() <= 1e-9 * (1.0 + smp.s.abs()));
            prop_assert!(t <= smp.t + 1e-9 * (1.0 + p.duration()));
        }
    }
}

#[test]
fn bad_inputs_are_errors_that_say_what_to_fix() {
    let r = Row {
        a: 1.0,
        b: 0.0,
        c: -1.0,
    };
    let e = CanonicalConstraints::new(vec![0.0], vec![0, 0], vec![]).unwrap_err();
    assert!(matches!(e, ToppError::GridTooShort { got: 1 }));
    let e = CanonicalConstraints::new(vec![0.0, 1.0, 0.5], vec![0, 0, 0, 0], vec![]).unwrap_err();
    assert!(e.to_string().contains("strictly increasing"), "{e}");
    let e = CanonicalConstraints::new(vec![0.0, f64::NAN], vec![0, 0, 0], vec![]).unwrap_err();
    assert!(matches!(
        e,
        ToppError::NotFinite {
            what: "s",
            point: 1,
            ..
        }
    ));
    let bad = Row {
        a: f64::INFINITY,
        ..r
    };
    let e = CanonicalConstraints::new(vec![0.0, 1.0], vec![0, 1, 2], vec![r, bad]).unwrap_err();
    assert!(
        matches!(
            e,
            ToppError::NotFinite {
                what: "a",
                point: 1,
                row: 0,
                ..
            }
        ),
        "{e}"
    );
    let e = CanonicalConstraints::new(vec![0.0, 1.0], vec![0, 2, 1], vec![r, r]).unwrap_err();
    assert!(e.to_string().contains("offsets"));
    let e = CanonicalConstraints::from_dense(
        &[0.0, 1.0],
        &[vec![1.0], vec![1.0]],
        &[vec![0.0], vec![]],
        &[vec![0.0], vec![0.0]],
    )
    .unwrap_err();
    assert!(e.to_string().contains("b[1]"), "{e}");
    let k = CanonicalConstraints::new(vec![0.0, 1.0], vec![0, 1, 2], vec![r, r]).unwrap();
    assert!(k.clone().with_x_bounds(vec![[1.0, 0.5]; 2]).is_err());
    assert!(k.clone().with_x_bounds(vec![[0.0, 1.0]]).is_err());
    assert!(k.clone().with_u_bounds(vec![[0.0, f64::NAN]; 2]).is_err());
    for opts in [
        SolveOptions::default().with_start(-1.0),
        SolveOptions::default().with_start(f64::NAN),
        SolveOptions::default().with_end_interval(2.0, 1.0),
        SolveOptions::default().with_end(f64::INFINITY),
    ] {
        let e = solve(&k, &opts).unwrap_err();
        assert!(matches!(e, ToppError::InvalidValue { .. }), "{e}");
    }
    let mut opts = SolveOptions::new(Discretization::Interpolation);
    opts.tol.feasibility = -1.0;
    assert!(solve(&k, &opts).is_err());
}

#[test]
fn bounds_on_x_and_u_are_enforced() {
    // |u| <= 10 from the rows, u in [-1, 1] and x <= 0.25 from the bounds: speed limit 0.5.
    let rows = [
        Row {
            a: 1.0,
            b: 0.0,
            c: -10.0,
        },
        Row {
            a: -1.0,
            b: 0.0,
            c: -10.0,
        },
    ];
    // Grid step 1/200 so that the switches at s = 0.125 and 1.875 are grid points.
    let n = 401;
    let s: Vec<f64> = (0..n).map(|i| i as f64 / 200.0).collect();
    let offsets: Vec<usize> = (0..=n).map(|i| 2 * i).collect();
    let k = CanonicalConstraints::new(s, offsets, rows.repeat(n))
        .unwrap()
        .with_u_bounds(vec![[-1.0, 1.0]; n])
        .unwrap()
        .with_x_bounds(vec![[0.0, 0.25]; n])
        .unwrap();
    let sol = solve(&k, &SolveOptions::default()).unwrap();
    let p = sol.profile.unwrap();
    assert!(p.x().iter().all(|&x| x <= 0.25 + 1e-12));
    assert!(p
        .u()
        .iter()
        .all(|&u| (-1.0 - 1e-12..=1.0 + 1e-12).contains(&u)));
    // Accelerate over 0.125, cruise at 0.5 over 1.75, brake over 0.125: 0.5 + 3.5 + 0.5.
    assert!((p.duration() - 4.5).abs() < 1e-9, "{}", p.duration());
}

/// A tiny time step used to saturate the sample count (`usize::MAX` samples: a capacity
/// overflow panic or an exhausted memory); it must be an error that names a usable `dt`.
#[test]
fn resample_with_tiny_dt_is_an_error_not_an_allocation() {
    let p = Profile::from_states(vec![0.0, 0.5], vec![0.0, 1.0], vec![1.0]).unwrap();
    for dt in [1e-300, 1e-9, f64::MIN_POSITIVE] {
        let e = p.resample(dt).unwrap_err();
        assert!(e.to_string().contains("give dt >="), "{e}");
    }
    // The largest allowed count still works (and is exactly at the limit's side).
    let dt = p.duration() / (stance_topp::tol::MAX_RESAMPLE_POINTS - 2) as f64;
    assert!(p.resample(dt * 1.01).unwrap().len() <= stance_topp::tol::MAX_RESAMPLE_POINTS);
    for dt in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(p.resample(dt).is_err(), "dt {dt}");
    }
    // A stalled profile (infinite duration) has nothing to resample.
    let stalled = Profile::from_states(vec![0.0, 1.0], vec![0.0, 0.0], vec![0.0]).unwrap();
    assert!(stalled
        .resample(0.1)
        .unwrap_err()
        .to_string()
        .contains("stalls"));
}

/// `Profile::from_states` is public: malformed caller data (short grid, wrong lengths, NaN,
/// negative x, unordered grid) used to index out of bounds or produce NaN times.
#[test]
fn profile_from_bad_states_is_an_error_not_a_panic() {
    let ok = |s: Vec<f64>, x: Vec<f64>, u: Vec<f64>| Profile::from_states(s, x, u);
    assert!(matches!(
        ok(vec![], vec![], vec![]),
        Err(ToppError::GridTooShort { got: 0 })
    ));
    assert!(matches!(
        ok(vec![0.0, 1.0], vec![0.0], vec![0.0]),
        Err(ToppError::Shape {
            expected: 2,
            got: 1,
            ..
        })
    ));
    assert!(matches!(
        ok(vec![0.0, 1.0], vec![0.0, 1.0], vec![]),
        Err(ToppError::Shape {
            expected: 1,
            got: 0,
            ..
        })
    ));
    assert!(matches!(
        ok(vec![0.0, 1.0], vec![0.0, f64::NAN], vec![0.5]),
        Err(ToppError::NotFinite {
            what: "x",
            point: 1,
            ..
        })
    ));
    let e = ok(vec![0.0, 1.0], vec![0.0, -1.0], vec![0.5]).unwrap_err();
    assert!(e.to_string().contains("never negative"), "{e}");
    assert!(matches!(
        ok(vec![1.0, 0.0], vec![1.0, 1.0], vec![0.0]),
        Err(ToppError::GridNotIncreasing { .. })
    ));
}

/// `u + x <= 1`, `u >= -1` on `[0, 1]` (3 grid points), every row multiplied by `scale`.
fn scaled_rows(scale: f64, s: Vec<f64>) -> Result<CanonicalConstraints, ToppError> {
    let rows = [
        Row {
            a: scale,
            b: scale,
            c: -scale,
        },
        Row {
            a: -scale,
            b: 0.0,
            c: -scale,
        },
    ];
    let n = s.len();
    CanonicalConstraints::new(s, (0..=n).map(|i| 2 * i).collect(), rows.repeat(n))
}

/// Rows with coefficients near 1e160 overflowed in the LP kernel (`a^2 + b^2 = inf`), which then
/// accepted every point: `stance topp` answered "optimal" at the bounding box (s' = 1e4) with
/// rows violated by 1e8. Scaling a row by a positive factor does not change its feasible set,
/// so the answer must not depend on it; beyond the limit, an error that says to rescale.
#[test]
fn huge_coefficients_are_an_error_not_a_wrong_optimum() {
    let s = vec![0.0, 0.5, 1.0];
    let reference = solve(
        &scaled_rows(1.0, s.clone()).unwrap(),
        &SolveOptions::default(),
    )
    .unwrap()
    .duration()
    .unwrap();
    assert!((reference - 2.0).abs() < 1e-12, "{reference}");
    // (Rows uniformly below `tol.zero_row` are treated as constant rows by design: no tiny
    // scale here.)
    for scale in [1e-6, 1e90, stance_topp::tol::MAX_ABS_COEFFICIENT] {
        let k = scaled_rows(scale, s.clone()).unwrap();
        let d = solve(&k, &SolveOptions::default())
            .unwrap()
            .duration()
            .unwrap();
        assert!((d - reference).abs() < 1e-12, "scale {scale:e}: {d}");
    }
    for scale in [1e160, 1e300] {
        let e = scaled_rows(scale, s.clone()).unwrap_err();
        assert!(e.to_string().contains("rescale"), "{e}");
    }
}

/// A grid whose span overflows when doubled (2 Delta = inf) gave a stalled profile with a
/// positive speed; the LP box must stay within what the kernel can square.
#[test]
fn overflowing_grid_span_and_box_are_errors() {
    let e = scaled_rows(1.0, vec![0.0, 1e300, 1.7e308]).unwrap_err();
    assert!(e.to_string().contains("span"), "{e}");
    let k = scaled_rows(1.0, vec![0.0, 0.5, 1.0]).unwrap();
    let mut opts = SolveOptions::default();
    opts.tol.max_x = 1e300;
    let e = solve(&k, &opts).unwrap_err();
    assert!(e.to_string().contains("max_x"), "{e}");
}

/// Finite `U` and eq. 14 vectors whose products exceed the coefficient limit bypassed the
/// check of the canonical rows (the fill writes them after validation).
#[test]
fn factored_rows_whose_products_overflow_are_an_error() {
    use stance_topp::factored::FactoredRows;
    let u = [[1e60, 0.0, 0.0, 0.0, 0.0, 0.0]];
    let w = vec![[[1e60; 6], [0.0; 6], [-1.0; 6]]; 2];
    let e = FactoredRows::new(&u, vec![0.0, 1.0], w).unwrap_err();
    assert!(e.to_string().contains("rescale"), "{e}");
}
