//! Merging the slivers of an exact fallback into the tolerance-mode answer.
//!
//! When the floating-point certificate fails, the conversion returns the exact answer for the
//! input as given ([`crate::DdOptions::exact_fallback`]). Rounding of the input breaks the
//! degeneracies of the intended geometry, so that answer carries *slivers*: rows that cut off
//! a wedge of the cone no wider than the rounding (two coplanar feet written in decimals: 40
//! exact facets where the intended geometry has 16). Both passes below only **remove** rows
//! of the exact answer `{x : U x <= 0, E x = 0}`, so the merged cone still contains the exact
//! one (every input generator satisfies every kept row), and each pass proves how much larger
//! it is: no unit vector `x` the merged rows admit violates any row `u` of the exact answer
//! (unit) by more than the recorded [`crate::Certificate::merge_distance`], which is at most
//! the tolerance `delta` ([`crate::tol::Tolerances::certificate`]).
//!
//! 1. **Near-parallel rows.** A row `u` within distance `delta` of an earlier kept row `k`
//!    (unit rows) is dropped: `u . x = k . x + (u - k) . x <= |u - k|` for unit `x` with
//!    `k . x <= 0`.
//! 2. **Shallow rows.** A row whose removal enlarges the cone by at most `delta` is dropped,
//!    even when its normal is far from every other row's (a sliver facet through two nearly
//!    coplanar feet tilts freely). The bound: let `C_K = {x : U_K x <= 0, E x = 0}` be the cone
//!    of the kept rows, pointed, with unit extreme rays `r_1..r_q`, `s` the unit vector along
//!    `sum r_i` and `sigma = min_i s . r_i > 0`. Every `x` in `C_K` is `sum lambda_i r_i` with
//!    `lambda >= 0`, and `sum lambda_i <= sum lambda_i (s . r_i) / sigma = s . x / sigma <=
//!    |x| / sigma`, so for every row `u` of the exact answer
//!
//!    `u . x <= max_i max(u . r_i, 0) * |x| / sigma = beta |x|`.
//!
//!    Which rows to try comes from floating-point conversions of the candidate row sets
//!    (uncertified: only a guess, cheapest first); the kept set is then checked once with an
//!    exact conversion (its rays rounded to `f64`, so `beta` is exact up to rounding of the
//!    products, far below `delta`). If `beta > delta`, or `C_K` is not pointed, the pass is
//!    undone and only the near-parallel merge stays.
//!
//! Both passes run only on exact fallbacks in the default mode: an answer that was asked for
//! in exact arithmetic is returned as computed.
//!
//! # Cost and limitation
//!
//! One floating-point face -> span per row of the near-parallel result, one more per
//! candidate, and one exact face -> span when a row was dropped: on the 6-D wrench cones of
//! two feet (24 to 42 rows after pass 1) the whole fallback takes 22 to 61 ms instead of about
//! 20 ms. The drop-one guesses cost `m` conversions of `m` rows, so pass 2 is skipped above
//! [`SHALLOW_MERGE_MAX_ROWS`] rows (a three-contact stance rolled by 0.01 degree: 222 rows
//! would take over a second; its slivers stay).

use nalgebra::{DMatrix, DVector};

use crate::convert::Polar;
use crate::tol::SHALLOW_MERGE_MAX_ROWS;
use crate::{face_to_span, Arithmetic, DdOptions, FaceForm, SpanForm};

/// Both merges of the module docs on the exact fallback's answer `p` (its `facets` rows).
pub(crate) fn merge_fallback_rows(p: &mut Polar, opts: &DdOptions) {
    let delta = opts.tol.certificate;
    let original = p.facets.clone();
    let near = merge_near_parallel(p, delta);
    let dropped = merge_shallow(p, &original, opts);
    let m = original.nrows() - p.facets.nrows();
    if m > 0 {
        p.certificate.merged_rows = m;
        p.certificate.merge_distance = near.max(dropped);
    }
}

/// Pass 1: drops rows closer than `delta` (unit rows) to an earlier kept row; returns the
/// largest such distance (0 when nothing was dropped).
fn merge_near_parallel(p: &mut Polar, delta: f64) -> f64 {
    let (m, d) = p.facets.shape();
    if m < 2 {
        return 0.0;
    }
    let unit = unit_rows(&p.facets);
    let mut kept: Vec<usize> = Vec::with_capacity(m);
    let mut worst = 0.0f64;
    for i in 0..m {
        let near = kept
            .iter()
            .map(|&k| (&unit[i] - &unit[k]).norm())
            .filter(|&dist| dist <= delta)
            .fold(None, |best: Option<f64>, dist| {
                Some(best.map_or(dist, |b| b.min(dist)))
            });
        match near {
            Some(dist) => worst = worst.max(dist),
            None => kept.push(i),
        }
    }
    if kept.len() < m {
        p.facets = DMatrix::from_fn(kept.len(), d, |i, j| p.facets[(kept[i], j)]);
    }
    worst
}

/// Pass 2: drops shallow rows (module docs); returns the proven bound `beta` (0 when nothing
/// was dropped). `original`: the exact answer's rows before any merge.
fn merge_shallow(p: &mut Polar, original: &DMatrix<f64>, opts: &DdOptions) -> f64 {
    let delta = opts.tol.certificate;
    let m = p.facets.nrows();
    if !(2..=SHALLOW_MERGE_MAX_ROWS).contains(&m) || p.lineality.nrows() > 0 {
        return 0.0;
    }
    let all = unit_rows(original);
    let guess_opts = DdOptions {
        arithmetic: Arithmetic::Tolerance,
        exact_fallback: false,
        allow_uncertified: true,
        ..opts.clone()
    };
    let guess = |rows: &[usize]| {
        cone_of(&p.facets, rows, &p.equations, &guess_opts)
            .map_or(f64::INFINITY, |s| enlargement(&s, &all))
    };
    // Cheapest first: each row's enlargement when dropped alone.
    let mut candidates: Vec<(f64, usize)> = (0..m)
        .filter_map(|j| {
            let rest: Vec<usize> = (0..m).filter(|&k| k != j).collect();
            let e = guess(&rest);
            (e <= delta).then_some((e, j))
        })
        .collect();
    if candidates.is_empty() {
        return 0.0;
    }
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut kept: Vec<usize> = (0..m).collect();
    for &(_, j) in &candidates {
        let trial: Vec<usize> = kept.iter().copied().filter(|&k| k != j).collect();
        if guess(&trial) <= delta {
            kept = trial;
        }
    }
    if kept.len() == m {
        return 0.0;
    }
    // The proof: the exact cone of the kept rows.
    let exact = DdOptions {
        arithmetic: Arithmetic::Exact,
        ..opts.clone()
    };
    let beta = cone_of(&p.facets, &kept, &p.equations, &exact)
        .map_or(f64::INFINITY, |s| enlargement(&s, &all));
    if beta > delta {
        return 0.0;
    }
    p.facets = p.facets.select_rows(kept.iter());
    beta
}

/// Unit copies of the rows of `m` (a zero row stays zero).
fn unit_rows(m: &DMatrix<f64>) -> Vec<DVector<f64>> {
    m.row_iter()
        .map(|r| {
            let n = r.norm();
            let r = r.transpose();
            if n > 0.0 {
                r / n
            } else {
                r
            }
        })
        .collect()
}

/// The span form of `{x : facets[rows] x <= 0, equations x = 0}`, or `None` when the
/// conversion fails.
fn cone_of(
    facets: &DMatrix<f64>,
    rows: &[usize],
    equations: &DMatrix<f64>,
    opts: &DdOptions,
) -> Option<SpanForm> {
    let face = FaceForm::new(facets.select_rows(rows.iter()), equations.clone()).ok()?;
    face_to_span(&face, opts).ok().map(|r| r.span)
}

/// `beta` of the module docs: a bound on `u . x / |x|` over `x` in the cone `span` and `u` in
/// `all` (unit rows); infinite when the cone is not pointed.
fn enlargement(span: &SpanForm, all: &[DVector<f64>]) -> f64 {
    if span.lineality.nrows() > 0 {
        return f64::INFINITY;
    }
    let rays = unit_rows(&span.generators);
    if rays.is_empty() {
        return 0.0;
    }
    let sum = rays.iter().fold(DVector::zeros(span.dim), |acc, r| acc + r);
    let ns = sum.norm();
    let sigma = rays
        .iter()
        .map(|r| r.dot(&sum) / ns)
        .fold(f64::INFINITY, f64::min);
    if sigma.is_nan() || sigma <= 0.0 {
        return f64::INFINITY;
    }
    let worst = all
        .iter()
        .flat_map(|u| rays.iter().map(move |r| u.dot(r)))
        .fold(0.0f64, f64::max);
    worst / sigma
}
