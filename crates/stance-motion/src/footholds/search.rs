//! The margin fraction chosen by the retimed duration: each candidate plan runs through the
//! pipeline (IK, rows, chained retiming; no checks) on a coarser grid, and the fastest optimal
//! one is kept.
//!
//! The search evaluates the middle three candidates of
//! [`crate::tol::SWITCH_MARGIN_FRACTIONS`] in parallel, then walks from the best towards the
//! ends while a step shortens the duration (the duration is
//! unimodal in the fraction on the motions tried: a small margin slows the swings, which need
//! room to accelerate the swinging leg, a large one lengthens the CoM's path).

use std::time::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::assemble::assemble;
use super::geometry::Geometry;
use crate::result::MotionStatus;
use crate::{run_full, RunOptions};

/// One evaluation of the search.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Evaluation {
    /// The margin fraction.
    pub fraction: f64,
    /// The retimed duration on the search's grid (s); `null` when not optimal.
    pub duration: Option<f64>,
    /// Wall time (ms).
    pub millis: f64,
}

/// The duration of the plan for `alpha` on the search's grid.
fn evaluate(g: &Geometry, alpha: f64, options: &RunOptions) -> Evaluation {
    let t0 = Instant::now();
    let (mut spec, _) = assemble(g, alpha);
    spec.retiming.grid = spec.retiming.grid.min(crate::tol::PLANNER_GRID);
    let options = RunOptions {
        base_dir: options.base_dir.clone(),
        skip_checks: true,
        time_scale: None,
        check_friction: None,
        no_limits: options.no_limits,
        progress: None,
    };
    let duration = run_full(spec, &options)
        .ok()
        .filter(|r| r.result.status == MotionStatus::Optimal)
        .and_then(|r| r.result.duration);
    Evaluation {
        fraction: alpha,
        duration,
        millis: t0.elapsed().as_secs_f64() * 1e3,
    }
}

/// The best margin fraction and the evaluations (module doc).
pub fn search(g: &Geometry, options: &RunOptions, t0: Instant) -> (f64, Vec<Evaluation>) {
    let c = crate::tol::SWITCH_MARGIN_FRACTIONS;
    let report = |e: &Evaluation| {
        if let Some(p) = options.progress {
            if t0.elapsed().as_secs_f64() > crate::tol::PLANNER_PROGRESS_AFTER {
                p(&format!(
                    "footholds planner: margin fraction {} -> {} ({:.0} ms so far)",
                    e.fraction,
                    e.duration
                        .map_or("not retimable".into(), |d| format!("{d:.3} s")),
                    t0.elapsed().as_secs_f64() * 1e3
                ));
            }
        }
    };
    let better = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(a), Some(b)) => a < b,
        (Some(_), None) => true,
        _ => false,
    };
    // the middle three at once (independent runs, one per core), then outwards from the best
    // while it improves
    let mid = c.len() / 2;
    let first: Vec<usize> = (mid.saturating_sub(1)..=(mid + 1).min(c.len() - 1)).collect();
    let mut evals: Vec<Evaluation> = first
        .par_iter()
        .map(|&i| evaluate(g, c[i], options))
        .collect();
    evals.iter().for_each(report);
    let mut best = first.iter().zip(&evals).fold((mid, None), |b, (&i, e)| {
        if better(e.duration, b.1) {
            (i, e.duration)
        } else {
            b
        }
    });
    let dir: isize = if best.0 == first[0] {
        -1
    } else if best.0 == first[first.len() - 1] {
        1
    } else {
        0
    };
    let mut i = best.0 as isize + dir;
    while dir != 0 && (0..c.len() as isize).contains(&i) && !first.contains(&(i as usize)) {
        let e = evaluate(g, c[i as usize], options);
        report(&e);
        let d = e.duration;
        evals.push(e);
        if !better(d, best.1) {
            break;
        }
        best = (i as usize, d);
        i += dir;
    }
    (c[best.0], evals)
}
