//! The contact rows between IK samples: the refinement's second look.
//!
//! # Math
//!
//! The IK integrates the joint path with `q_ss` constant per step, so on `[s_j, s_j+1]`,
//! with `d = s - s_j`, `q(s) = q_j (+) (q_s,j d + q_ss,j d^2 / 2)` (the path the trajectory
//! and the independent force check follow, module [`crate::trajectory`]). The rows of eq. 14
//! are exact at the IK samples, where the retiming enforces them; between two samples the
//! path terms `p, p_s, p_ss, l1, l2` vary with `q(s)` while the profile's `x` varies linearly,
//! so a row that holds at both ends of a step can fail inside it, by a second-order amount
//! (measured: 1e-6 to 1e-5 of the weight at two 1 ms samples of a planned stair climbing).
//!
//! Where a step's end samples are within [`crate::tol::MIDPOINT_WATCH`] of the weight of a
//! contact row, its midpoint `s_m = s_j + d` gets the model's exact path terms there and their
//! rows `a u + b x + c <= 0`. Under the profile, the grid interval `[s_i, s_i+1]` that holds
//! `s_m` has `u = u_i` and `x(s_m) = x_i + 2 u_i (s_m - s_i)`. When a midpoint row fails, sample
//! `j` joins the grid (its interval then starts at `s_j`) and the row joins `j`'s rows written in
//! `(u_j, x_j)`:
//!
//! ```text
//! a u + b (x_j + 2 u d) + c = (a + 2 b d) u + b x_j + c <= 0,
//! ```
//!
//! exact for every profile on that grid, so the next solve keeps the midpoint's rows.

use std::collections::HashMap;

use stance_robot::{integrate, path_terms, Data};
use stance_topp::factored::eq14_vectors;
use stance_topp::path::PathPoint;
use stance_topp::{Profile, Row};

use super::chain::{state_at, SampleValues};
use super::ik_stage::SegmentPath;
use super::plan::MotionPlan;
use super::rows::SegmentRows;
use crate::StanceError;

/// The midpoint rows computed so far, per segment and step, and whether each was cut in.
#[derive(Debug, Default)]
pub struct Midpoints {
    rows: Vec<HashMap<usize, (Vec<Row>, bool)>>,
    /// Midpoints whose rows were evaluated (for the timings).
    pub evaluated: usize,
}

/// The contact rows at the midpoint of IK step `j` of `path` (module doc).
fn midpoint_rows(
    plan: &MotionPlan,
    path: &SegmentPath,
    u: &[[f64; 6]],
    j: usize,
    data: &mut Data,
) -> Result<Vec<Row>, StanceError> {
    let m = &plan.robot.model;
    let smp = &path.samples[j];
    let d = 0.5 * (path.samples[j + 1].s - smp.s);
    let delta: Vec<f64> = smp
        .q_s
        .iter()
        .zip(&smp.q_ss)
        .map(|(v, a)| v * d + 0.5 * a * d * d)
        .collect();
    let q = integrate(m, &smp.q, &delta).map_err(StanceError::Robot)?;
    let q_s: Vec<f64> = smp
        .q_s
        .iter()
        .zip(&smp.q_ss)
        .map(|(v, a)| v + a * d)
        .collect();
    let t = path_terms(m, data, &q, &q_s, &smp.q_ss).map_err(StanceError::Robot)?;
    let point = PathPoint {
        p: t.p.into(),
        ps: t.p_s.into(),
        pss: t.p_ss.into(),
    };
    let w = eq14_vectors(
        &point,
        m.total_mass(),
        plan.gravity,
        t.l1.into(),
        t.l2.into(),
    );
    let dot = |a: &[f64; 6], b: &[f64; 6]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    Ok(u.iter()
        .map(|r| Row {
            a: dot(r, &w[0]),
            b: dot(r, &w[1]),
            c: dot(r, &w[2]),
        })
        .collect())
}

/// One round of the midpoint refinement (module doc): returns how many midpoints were cut in.
#[allow(clippy::too_many_arguments)]
pub fn add_failing_midpoints(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    rows: &mut [SegmentRows],
    s_offset: &[f64],
    p: &Profile,
    margin: f64,
    values: &[Vec<SampleValues>],
    cache: &mut Midpoints,
) -> Result<usize, StanceError> {
    let m = &plan.robot.model;
    let weight = m.total_mass() * plan.gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
    let watch = crate::tol::MIDPOINT_WATCH * weight;
    if cache.rows.len() < paths.len() {
        cache.rows.resize_with(paths.len(), HashMap::new);
    }
    let mut data = Data::new(m);
    let mut added = 0;
    for (k, path) in paths.iter().enumerate() {
        let n = path.samples.len();
        let mut new_grid = rows[k].grid.clone();
        let mut cut = false;
        for j in 0..n.saturating_sub(1) {
            if values[k][j].contact <= -watch && values[k][j + 1].contact <= -watch {
                continue;
            }
            if !cache.rows[k].contains_key(&j) {
                let r = midpoint_rows(plan, path, &rows[k].u, j, &mut data)?;
                cache.evaluated += 1;
                cache.rows[k].insert(j, (r, false));
            }
            let entry = cache.rows[k].get_mut(&j).expect("inserted above");
            if entry.1 {
                continue;
            }
            let d = 0.5 * (path.samples[j + 1].s - path.samples[j].s);
            let (ui, xm) = state_at(p, s_offset[k] + path.samples[j].s + d, false);
            let worst = entry
                .0
                .iter()
                .map(|r| r.a * ui + r.b * xm + r.c)
                .fold(f64::NEG_INFINITY, f64::max);
            if worst <= -0.5 * margin {
                continue;
            }
            entry.1 = true;
            for r in &entry.0 {
                if r.a * ui + r.b * xm + r.c > -watch {
                    let row = Row {
                        a: r.a + 2.0 * r.b * d,
                        b: r.b,
                        c: r.c,
                    };
                    rows[k].add_step_row(j, row);
                }
            }
            if let Err(pos) = new_grid.binary_search(&j) {
                new_grid.insert(pos, j);
            }
            cut = true;
            added += 1;
        }
        if cut {
            rows[k].set_grid(new_grid);
        }
    }
    Ok(added)
}
