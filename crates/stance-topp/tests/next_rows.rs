//! Rows that hold only with the acceleration after their grid point
//! (`CanonicalConstraints::with_next_rows`): the interpolation discretization imposes a
//! point's rows with the intervals on both sides of it, unless told otherwise; a constraint
//! that changes at the point (a contact switch) must hold with the interval after it only.

use stance_topp::{solve, CanonicalConstraints, Discretization, Row, SolveOptions, Status};

/// On `s` in `[0, 2]`, from rest to rest, `|u| <= 10` everywhere and, from `s = 1` on, a
/// deceleration of at least 1 (`u <= -1` at point 1). Imposed with the interval before point 1
/// too, the motion could not start (it would have to decelerate from rest); imposed after it
/// only, it speeds up on `[0, 1]` and brakes on `[1, 2]`.
fn braking_after_one() -> CanonicalConstraints {
    let bounds = |c: f64| {
        vec![
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
            Row { a: 1.0, b: 0.0, c },
        ]
    };
    let mut rows = Vec::new();
    let mut offsets = vec![0];
    for c in [-10.0, 1.0, -10.0] {
        rows.extend(bounds(c));
        offsets.push(rows.len());
    }
    CanonicalConstraints::new(vec![0.0, 1.0, 2.0], offsets, rows).unwrap()
}

#[test]
fn rows_held_after_their_point_only_do_not_constrain_the_interval_before() {
    let opts = SolveOptions::new(Discretization::Interpolation);
    let both = solve(&braking_after_one(), &opts).unwrap();
    assert_ne!(both.status, Status::Optimal);
    // point 1 keeps its two bounds on both sides, and its braking row after it only
    let after = braking_after_one().with_next_rows(vec![3, 2, 3]).unwrap();
    let sol = solve(&after, &opts).unwrap();
    assert_eq!(sol.status, Status::Optimal, "{:?}", sol.status);
    let p = sol.profile.unwrap();
    // bang-bang: u = 10 up to s = 1 would reach x = 20, which braking at 1 cannot stop at 2
    // (x_2 = 20 - 2 > 0 needs u <= -10 there: allowed, so x_1 = 20, u_1 = -10)
    assert!((p.x()[1] - 20.0).abs() < 1e-9, "{:?}", p.x());
    assert!(p.u()[1] <= -1.0 + 1e-12);
    // the counts are checked
    assert!(braking_after_one().with_next_rows(vec![3, 4, 3]).is_err());
    assert!(braking_after_one().with_next_rows(vec![3, 3]).is_err());
}
