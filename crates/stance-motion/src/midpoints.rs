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
//! contact row, interior points `s_m = s_j + d` get the model's exact path terms there and
//! their rows `a u + b x + c <= 0`: first the quarters of the step, then, in each round where
//! one of the step's points failed, the points halfway between those already evaluated, down
//! to a spacing of [`crate::tol::STEP_INTERIOR_SPACING`] of the step. A row's largest value
//! along a step need not be at its middle, and where the retiming holds it at two points `h`
//! apart a concave row of curvature `k` can still exceed its bound by `k h^2 / 8` between them
//! (measured: at 0.88 of a step of the small humanoid's weight shift on a 10-interval grid,
//! 4.6e-6 of the weight over its bound while the midpoint held by 3.9e-5; the quarters alone
//! left 4.3e-6 there). Under the profile, the grid interval
//! `[s_i, s_i+1]` that holds `s_m` has `u = u_i` and `x(s_m) = x_i + 2 u_i (s_m - s_i)`. When
//! an interior row fails, sample `j` joins the grid (its interval then starts at `s_j`) and the
//! row joins `j`'s rows written in `(u_j, x_j)`:
//!
//! ```text
//! a u + b (x_j + 2 u d) + c = (a + 2 b d) u + b x_j + c <= 0,
//! ```
//!
//! exact for every profile on that grid, so the next solve keeps the interior point's rows.

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

/// Per (step, interior point) of a segment: the rows there, and whether they were cut in.
type InteriorRows = HashMap<(usize, usize), (Vec<Row>, bool)>;

/// The interior rows computed so far, per segment, and per segment and step the finest level
/// of interior points evaluated.
#[derive(Debug, Default)]
pub struct Midpoints {
    rows: Vec<InteriorRows>,
    depth: Vec<HashMap<usize, usize>>,
    /// Interior points whose rows were evaluated (for the timings).
    pub evaluated: usize,
}

/// Interior points as numerators over [`FINEST`]: the step cut in `1 / STEP_INTERIOR_SPACING`.
const FINEST: usize = crate::tol::STEP_INTERIOR_SPACING;

/// The interior points of a step down to `depth` (0: the quarters; each level halves the
/// spacing), as numerators over [`FINEST`].
fn interior_points(depth: usize) -> impl Iterator<Item = usize> {
    let step = ((FINEST / 4) >> depth).max(1);
    (1..FINEST / step).map(move |i| i * step)
}

/// The contact rows at `s_j + d` within IK step `j` of `path` (module doc).
fn interior_rows(
    plan: &MotionPlan,
    path: &SegmentPath,
    u: &[[f64; 6]],
    j: usize,
    d: f64,
    data: &mut Data,
) -> Result<Vec<Row>, StanceError> {
    let m = &plan.robot.model;
    let smp = &path.samples[j];
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

/// One round of the refinement between IK samples (module doc): returns how many steps had
/// interior points cut in.
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
        cache.depth.resize_with(paths.len(), HashMap::new);
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
            let h = path.samples[j + 1].s - path.samples[j].s;
            let depth = *cache.depth[k].get(&j).unwrap_or(&0);
            let mut failed = false;
            for q in interior_points(depth) {
                let d = h * q as f64 / FINEST as f64;
                if !cache.rows[k].contains_key(&(j, q)) {
                    let r = interior_rows(plan, path, &rows[k].u, j, d, &mut data)?;
                    cache.evaluated += 1;
                    cache.rows[k].insert((j, q), (r, false));
                }
                let entry = cache.rows[k].get_mut(&(j, q)).expect("inserted above");
                if entry.1 {
                    continue;
                }
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
                failed = true;
            }
            if failed && (4 << depth) < FINEST {
                cache.depth[k].insert(j, depth + 1);
            }
            if !failed {
                continue;
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
