//! Constraints given by a separation oracle (`Workspace::solve_separated`) against the same
//! constraints given as rows: on random instances whose rows are split into explicit rows and
//! rows only an oracle knows, both solves give the same status, controllable sets and profile;
//! on a grid far from unit range and origin too (the oracle sees and returns the caller's
//! units); every cut returned is one of the hidden rows; an oracle whose cuts do not cut ends
//! the solve with an error. Solved in pieces (the backward pass piece by piece, last first,
//! then the forward pass over the whole grid), the same solution to the last bit.

mod common;

use common::random::random_instance;
use proptest::prelude::*;
use stance_topp::{
    BackwardPiece, CanonicalConstraints, Cut, Discretization, Row, Separation, SolveOptions,
    ToppError, Workspace,
};

/// The hidden rows of every grid point; returns the most violated one (by normalized
/// violation) as the cut, tagged with its index.
struct Hidden {
    rows: Vec<Vec<Row>>,
    calls: usize,
}

impl Separation for Hidden {
    fn separate(&mut self, point: usize, u: f64, x: f64) -> Result<Option<Cut>, ToppError> {
        self.calls += 1;
        let mut best: Option<(f64, usize)> = None;
        for (j, r) in self.rows[point].iter().enumerate() {
            let v = (r.a * u + r.b * x + r.c) / r.a.hypot(r.b);
            if v > 1e-10 * u.hypot(x).max(1.0) && best.is_none_or(|(b, _)| v > b) {
                best = Some((v, j));
            }
        }
        Ok(best.map(|(_, j)| Cut {
            row: self.rows[point][j],
            tag: j as u32,
        }))
    }
}

/// `k` with the first `keep` rows of every point explicit and the others hidden.
fn split(k: &CanonicalConstraints, keep: usize) -> (CanonicalConstraints, Hidden) {
    let mut rows = Vec::new();
    let mut offsets = vec![0];
    let mut hidden = Vec::new();
    for i in 0..k.num_points() {
        let r = k.rows_at(i);
        rows.extend_from_slice(&r[..keep.min(r.len())]);
        offsets.push(rows.len());
        hidden.push(r[keep.min(r.len())..].to_vec());
    }
    let explicit = CanonicalConstraints::new(k.grid().to_vec(), offsets, rows).unwrap();
    (
        explicit,
        Hidden {
            rows: hidden,
            calls: 0,
        },
    )
}

/// The same rows on the grid `origin + scale * s` (a row `(a, b, c)` in `s` is
/// `(a / scale, b / scale^2, c)` in the new parameter).
fn rescaled(k: &CanonicalConstraints, scale: f64, origin: f64) -> CanonicalConstraints {
    let s: Vec<f64> = k.grid().iter().map(|s| origin + scale * s).collect();
    let mut rows = Vec::new();
    let mut offsets = vec![0];
    for i in 0..k.num_points() {
        for r in k.rows_at(i) {
            rows.push(Row {
                a: r.a / scale,
                b: r.b / (scale * scale),
                c: r.c,
            });
        }
        offsets.push(rows.len());
    }
    CanonicalConstraints::new(s, offsets, rows).unwrap()
}

fn agree(
    full: &CanonicalConstraints,
    keep: usize,
    disc: Discretization,
) -> Result<(), TestCaseError> {
    let opts = SolveOptions::new(disc);
    let mut ws = Workspace::new();
    let reference = ws.solve(full, &opts).unwrap();
    let (explicit, mut oracle) = split(full, keep);
    let sol = ws.solve_separated(&explicit, &opts, &mut oracle).unwrap();
    prop_assert_eq!(sol.status, reference.status);
    for (a, b) in sol.controllable.iter().zip(&reference.controllable) {
        match (a, b) {
            (Some(a), Some(b)) => {
                for q in 0..2 {
                    prop_assert!(
                        (a[q] - b[q]).abs() <= 1e-9 * b[q].abs().max(1.0),
                        "controllable {:?} vs {:?}",
                        a,
                        b
                    );
                }
            }
            (None, None) => {}
            _ => prop_assert!(false, "controllable {:?} vs {:?}", a, b),
        }
    }
    match (&sol.profile, &reference.profile) {
        (Some(p), Some(q)) => {
            for (a, b) in p.x().iter().zip(q.x()) {
                prop_assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "x {} vs {}", a, b);
            }
        }
        (None, None) => {}
        _ => prop_assert!(false, "one profile missing"),
    }
    // every cut is a hidden row of its point, in the caller's units up to a positive factor
    prop_assert_eq!(sol.stats.cuts, sol.cuts.len());
    for (i, (rows, tags)) in sol.cuts.rows.iter().zip(&sol.cuts.tags).enumerate() {
        for (r, &t) in rows.iter().zip(tags) {
            let h = oracle.rows[i][t as usize];
            let f = r.a.hypot(r.b) / h.a.hypot(h.b);
            prop_assert!(f > 0.0);
            for (p, q) in [(r.a, h.a), (r.b, h.b), (r.c, h.c)] {
                prop_assert!(
                    (p - f * q).abs() <= 1e-12 * (f * q).abs().max(f),
                    "{:?} vs {:?}",
                    r,
                    h
                );
            }
        }
    }
    Ok(())
}

/// An oracle seen from a piece of the grid that starts at global point `offset`.
struct Shifted<'a> {
    inner: &'a mut Hidden,
    offset: usize,
}

impl Separation for Shifted<'_> {
    fn separate(&mut self, point: usize, u: f64, x: f64) -> Result<Option<Cut>, ToppError> {
        self.inner.separate(point + self.offset, u, x)
    }
}

/// Grid points `a..=b` of `k` as constraints of their own.
fn piece(k: &CanonicalConstraints, a: usize, b: usize) -> CanonicalConstraints {
    let mut rows = Vec::new();
    let mut offsets = vec![0];
    for i in a..=b {
        rows.extend_from_slice(k.rows_at(i));
        offsets.push(rows.len());
    }
    CanonicalConstraints::new(k.grid()[a..=b].to_vec(), offsets, rows)
        .unwrap()
        .with_x_bounds((a..=b).map(|i| k.x_bounds_at(i)).collect())
        .unwrap()
        .with_next_rows((a..=b).map(|i| k.next_rows_at(i).len()).collect())
        .unwrap()
}

/// `k` with upper bounds on `x` and fewer next rows at some points (from `seed`), as a
/// motion's layout has at its stance switches.
fn with_switches(k: CanonicalConstraints, seed: u64) -> CanonicalConstraints {
    let n = k.num_points();
    let pick = |i: usize| {
        let h = seed
            .wrapping_add(i as u64)
            .wrapping_mul(6364136223846793005);
        (h >> 33).is_multiple_of(7)
    };
    let x_bounds = (0..n)
        .map(|i| [0.0, if pick(i) { 1.5 } else { f64::INFINITY }])
        .collect();
    let next = (0..n)
        .map(|i| if pick(i + 1) { 0 } else { k.rows_at(i).len() })
        .collect();
    k.with_x_bounds(x_bounds)
        .unwrap()
        .with_next_rows(next)
        .unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]
    /// The backward pass in pieces (last piece first, each from the next one's set) then the
    /// forward pass over the whole grid: the whole solve's solution, sets, cuts and counters
    /// equal, on grids near unit range and far from it (solved on a rescaled parameter); when a
    /// piece's pass fails, the whole solve fails too.
    #[test]
    fn solved_in_pieces_as_a_whole(
        seed in any::<u64>(),
        n in 5usize..60,
        keep in 0usize..5,
        cuts_at in prop::collection::vec(0.0f64..1.0, 0..5),
        interp in any::<bool>(),
        scale in prop::sample::select(vec![1.0, 1e-3, 0.3, 7.0, 1e3]),
        origin in prop::sample::select(vec![0.0, -250.0, 1e4]),
    ) {
        let disc = if interp { Discretization::Interpolation } else { Discretization::Collocation };
        let opts = SolveOptions::new(disc);
        let full = with_switches(rescaled(&random_instance(seed, n, 3, false), scale, origin), seed);
        let (explicit, mut oracle) = split(&full, keep);
        let whole = Workspace::new().solve_separated(&explicit, &opts, &mut oracle).unwrap();
        // the pieces' first points
        let mut starts: Vec<usize> = cuts_at.iter().map(|f| 1 + (f * (n - 1) as f64) as usize).collect();
        starts.push(0);
        starts.sort_unstable();
        starts.dedup();
        let (explicit, mut oracle) = split(&full, keep);
        let mut ws = Workspace::new();
        let mut pieces: Vec<BackwardPiece> = Vec::new();
        let mut failed = false;
        for (p, &a) in starts.iter().enumerate().rev() {
            let b = starts.get(p + 1).copied().unwrap_or(n);
            let mut sep = Shifted { inner: &mut oracle, offset: a };
            let after = pieces.first();
            let whole_ends = [explicit.grid()[0], explicit.grid()[n]];
            let piece = ws.backward_piece(&piece(&explicit, a, b), &opts, whole_ends, after, &mut sep).unwrap();
            failed = piece.failed_at().is_some();
            pieces.insert(0, piece);
            if failed {
                break;
            }
        }
        if failed {
            prop_assert!(whole.profile.is_none(), "{:?}", whole.status);
            prop_assert!(ws.forward_over_pieces(&explicit, &opts, &pieces, &mut oracle).is_err());
        } else {
            let sol = ws.forward_over_pieces(&explicit, &opts, &pieces, &mut oracle).unwrap();
            prop_assert_eq!(sol, whole);
        }
    }

    #[test]
    fn oracle_rows_give_the_same_profile_as_explicit_rows(
        seed in any::<u64>(),
        n in 5usize..60,
        m in 1usize..6,
        keep in 0usize..5,
        interp in any::<bool>(),
    ) {
        let disc = if interp { Discretization::Interpolation } else { Discretization::Collocation };
        agree(&random_instance(seed, n, m, false), keep, disc)?;
    }

    /// The oracle works in the caller's units when the solver moves to the unit grid.
    #[test]
    fn oracle_in_the_callers_units_on_a_far_grid(
        seed in any::<u64>(),
        n in 5usize..40,
        scale in prop::sample::select(vec![1e-3, 0.3, 37.0, 1e3]),
        origin in prop::sample::select(vec![0.0, -250.0, 1e4]),
        interp in any::<bool>(),
    ) {
        let disc = if interp { Discretization::Interpolation } else { Discretization::Collocation };
        agree(&rescaled(&random_instance(seed, n, 3, false), scale, origin), 3, disc)?;
    }
}

#[test]
fn the_oracle_is_only_called_where_it_matters() {
    // hidden rows that never bind: one call per LP optimum, no cut
    let full = random_instance(5, 40, 2, false);
    let (explicit, _) = split(&full, 5);
    let mut oracle = Hidden {
        rows: vec![
            vec![Row {
                a: 0.0,
                b: 1.0,
                c: -1e6
            }];
            full.num_points()
        ],
        calls: 0,
    };
    let sol = Workspace::new()
        .solve_separated(&explicit, &SolveOptions::default(), &mut oracle)
        .unwrap();
    assert!(sol.cuts.is_empty());
    assert!(oracle.calls > 0);
}

/// An oracle that returns rows its point already satisfies: the LP never changes, and the solve
/// stops with an error instead of looping.
#[test]
fn an_oracle_whose_cuts_do_not_cut_is_an_error() {
    struct Useless;
    impl Separation for Useless {
        fn separate(&mut self, _: usize, _: f64, _: f64) -> Result<Option<Cut>, ToppError> {
            Ok(Some(Cut {
                row: Row {
                    a: 0.0,
                    b: 1.0,
                    c: -1e9,
                },
                tag: 0,
            }))
        }
    }
    let k = random_instance(1, 10, 1, false);
    let err = Workspace::new()
        .solve_separated(&k, &SolveOptions::default(), &mut Useless)
        .unwrap_err();
    assert!(err.to_string().contains("did not converge"), "{err}");
}

/// The oracle's errors end the solve.
#[test]
fn the_oracles_errors_end_the_solve() {
    struct Failing;
    impl Separation for Failing {
        fn separate(&mut self, point: usize, _: f64, _: f64) -> Result<Option<Cut>, ToppError> {
            Err(ToppError::InvalidValue {
                what: "test oracle",
                detail: format!("fails at {point}"),
            })
        }
    }
    let k = random_instance(2, 10, 1, false);
    let err = Workspace::new()
        .solve_separated(&k, &SolveOptions::default(), &mut Failing)
        .unwrap_err();
    assert!(err.to_string().contains("test oracle"), "{err}");
}
