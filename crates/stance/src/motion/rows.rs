//! Stage 3, contact stability rows: per segment, `U_stance` of its stance (once) and the rows of
//! eq. 14 at its retiming grid points, from the path terms of the IK samples.
//!
//! # Math
//!
//! The stance's contacts are the robot surfaces at their placements at the segment's start
//! (read off the configuration, [`super::ik_stage`]), with the planning friction and the
//! polygons scaled by `sqrt(area_scale)` about their origin (the paper plans with mu = 0.7 and
//! 70 % of each sole's area). `U_stance` is their GIWC's face form (unit rows, `U w_GI <= 0`,
//! world origin; [`stance_contact::Stance::u_stance`]); with the IK's path terms at grid point
//! `i`, eq. 14 gives `a_i = U w_a`, `b_i = U w_b`, `c_i = U w_c`
//! ([`stance_topp::factored::eq14_vectors`], [`stance_topp::factored::FactoredRows`]).
//!
//! The IK's joint path has a constant `q_ss` on each IK step, so `p_ss` and `l2` jump at every
//! IK sample: an interior grid point has the rows of both limits (the step arriving, the step
//! leaving). The refinement between grid points makes the rows at every IK sample, once, and
//! evaluates them under the profile.

use std::time::{Duration, Instant};

use stance_contact::{Contact, GiwcOptions, Stance};
use stance_topp::factored::{eq14_vectors, FactoredRows};
use stance_topp::path::PathPoint;
use stance_topp::Row;

use super::ik_stage::{IkSample, SegmentPath};
use super::plan::MotionPlan;
use crate::StanceError;

/// The GIWC of one segment, and its rows at its current retiming grid.
#[derive(Debug, Clone)]
pub struct SegmentRows {
    /// The stance as planned (planning friction, scaled polygons): the GIWC's contacts, and
    /// those of the independent force check.
    pub stance: Stance,
    /// `U_stance` rows (unit, `U w_GI <= 0`).
    pub u: Vec<[f64; 6]>,
    /// Whether the GIWC conversion certified its face form.
    pub certified: bool,
    /// Indices of the IK samples at the retiming grid points (increasing; first and last
    /// sample included).
    pub grid: Vec<usize>,
    /// Rows at the grid points: at an interior point those of both limits (the step arriving
    /// and the step leaving), at the first point the right limit, at the last the left limit.
    pub rows: Vec<Row>,
    /// Where each grid point's rows start in `rows` (one more than the grid points).
    pub offsets: Vec<usize>,
    /// Rows at every IK sample, right limit (`u.len()` per sample), once the refinement
    /// between grid points has asked for them ([`Self::ensure_sample_rows`]; empty before).
    pub sample_right: Vec<Row>,
    /// Rows at every IK sample, left limit (`u.len()` per sample; the right limit's at the
    /// first sample).
    pub sample_left: Vec<Row>,
    /// Time of `U_stance` (the paper's `T_U`).
    pub t_u: Duration,
    /// Time of the rows on the initial retiming grid (`T_abc`).
    pub t_abc: Duration,
}

/// The rows of eq. 14 at the given IK samples of a path, for the right or the left limit
/// (`u.len()` rows per sample, in sample order).
fn rows_at_samples(
    plan: &MotionPlan,
    path: &SegmentPath,
    u: &[[f64; 6]],
    samples: &[usize],
    left: bool,
) -> Result<Vec<Row>, StanceError> {
    let mass = plan.robot.model.total_mass();
    let s: Vec<f64> = samples.iter().map(|&j| path.samples[j].s).collect();
    let w = samples
        .iter()
        .map(|&j| eq14_of(&path.samples[j], left, mass, plan.gravity))
        .collect();
    let f = FactoredRows::new(u, s, w)?;
    let mut rows = vec![Row::default(); samples.len() * u.len()];
    f.fill(&mut rows)?;
    Ok(rows)
}

impl SegmentRows {
    /// The rows at grid point `i`.
    pub fn rows_at(&self, i: usize) -> &[Row] {
        &self.rows[self.offsets[i]..self.offsets[i + 1]]
    }

    /// Computes the rows at every IK sample (both limits), once.
    pub fn ensure_sample_rows(
        &mut self,
        plan: &MotionPlan,
        path: &SegmentPath,
    ) -> Result<(), StanceError> {
        if self.sample_right.is_empty() {
            let all: Vec<usize> = (0..path.samples.len()).collect();
            self.sample_right = rows_at_samples(plan, path, &self.u, &all, false)?;
            self.sample_left = rows_at_samples(plan, path, &self.u, &all, true)?;
        }
        Ok(())
    }

    /// The rows of IK sample `j`: the right limit (`left = false`) or the left one (after
    /// [`Self::ensure_sample_rows`]).
    pub fn sample_rows(&self, j: usize, left: bool) -> &[Row] {
        let m = self.u.len();
        let all = if left {
            &self.sample_left
        } else {
            &self.sample_right
        };
        &all[j * m..(j + 1) * m]
    }

    /// Lays out the rows of the grid from rows at its points (`right`, `left`: `u.len()` per
    /// grid point).
    fn lay_out(&mut self, grid: Vec<usize>, right: &[Row], left: &[Row], per_point: bool) {
        let (n, m) = (grid.len(), self.u.len());
        self.rows.clear();
        self.offsets.clear();
        self.offsets.push(0);
        for (i, &j) in grid.iter().enumerate() {
            let at = if per_point { i } else { j };
            if i + 1 < n {
                self.rows.extend_from_slice(&right[at * m..(at + 1) * m]);
            }
            if i > 0 {
                self.rows.extend_from_slice(&left[at * m..(at + 1) * m]);
            }
            self.offsets.push(self.rows.len());
        }
        self.grid = grid;
    }

    /// Takes the rows of a new grid (indices of IK samples, increasing, first and last sample
    /// included) from the rows at the IK samples (after [`Self::ensure_sample_rows`]).
    pub fn set_grid(&mut self, grid: Vec<usize>) {
        let (right, left) = (
            std::mem::take(&mut self.sample_right),
            std::mem::take(&mut self.sample_left),
        );
        self.lay_out(grid, &right, &left, false);
        self.sample_right = right;
        self.sample_left = left;
    }
}

/// The planned stance of a segment path's contacts (planning friction and area scale).
///
/// ```
/// use stance::motion::{experiments, plan::MotionPlan, ik_stage::{self, run_segment, IkStageWorkspace}, rows};
/// let plan = MotionPlan::new(experiments::by_name("small-sway").unwrap(), None).unwrap();
/// let mut ws = IkStageWorkspace::new(&plan);
/// let nv = plan.robot.model.nv;
/// let com = ik_stage::com_reference(&plan).unwrap();
/// let path = run_segment(&plan, 0, &com, 0.0, &plan.q0, &vec![0.0; nv], &[], 8, &mut ws).unwrap();
/// let stance = rows::planned_stance(&plan, &path).unwrap();
/// assert_eq!(stance.contacts().len(), 2);
/// ```
pub fn planned_stance(plan: &MotionPlan, path: &SegmentPath) -> Result<Stance, StanceError> {
    let p = &plan.spec.planning;
    stance_of(
        plan,
        path,
        p.area_scale.sqrt(),
        p.friction,
        p.friction_model,
    )
}

/// A segment's contacts as a stance: polygons scaled by `k`, friction `friction` (else each
/// environment surface's), friction model `model`.
pub fn stance_of(
    plan: &MotionPlan,
    path: &SegmentPath,
    k: f64,
    friction: Option<f64>,
    model: stance_contact::FrictionModel,
) -> Result<Stance, StanceError> {
    let contacts = path
        .contacts
        .iter()
        .map(|c| {
            let surf = &plan.robot.surfaces[c.surface];
            let env = &plan.environment[c.environment];
            let r = &c.pose.rotation;
            let rotation = [
                [r[(0, 0)], r[(0, 1)], r[(0, 2)]],
                [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
                [r[(2, 0)], r[(2, 1)], r[(2, 2)]],
            ];
            Contact::new(
                &surf.name,
                c.pose.translation.into(),
                rotation,
                surf.shape.shape(k),
                friction.unwrap_or(env.friction),
                &Default::default(),
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Stance::new(contacts, model)?)
}

/// The three vectors of eq. 14 of an IK sample's right limit (`left = false`) or left limit.
pub fn eq14_of(sample: &IkSample, left: bool, mass: f64, gravity: [f64; 3]) -> [[f64; 6]; 3] {
    let t = if left {
        &sample.terms_left
    } else {
        &sample.terms
    };
    let q = PathPoint {
        p: t.p.into(),
        ps: t.p_s.into(),
        pss: t.p_ss.into(),
    };
    eq14_vectors(&q, mass, gravity, t.l1.into(), t.l2.into())
}

/// `U_stance` and the rows of segment `path` at every `substeps`-th IK sample.
///
/// # Errors
///
/// [`StanceError::BadMotion`] when the stance's GIWC is lower-dimensional (point or line
/// contacts only).
pub fn segment_rows(
    plan: &MotionPlan,
    k: usize,
    path: &SegmentPath,
    substeps: usize,
    ws: &mut polycone::Workspace,
) -> Result<SegmentRows, StanceError> {
    let stance = planned_stance(plan, path)?;
    let t0 = Instant::now();
    let giwc = stance.u_stance_with(ws, &GiwcOptions::default())?;
    let t_u = t0.elapsed();
    if giwc.equations.nrows() > 0 {
        return Err(StanceError::BadMotion(format!(
            "segment {} ({}): the stance's GIWC is lower-dimensional ({} equation(s)); \
             retiming needs surface contacts",
            k + 1,
            plan.segments[k].name,
            giwc.equations.nrows()
        )));
    }
    let u = giwc.facet_rows();
    let t1 = Instant::now();
    let grid: Vec<usize> = (0..path.samples.len()).step_by(substeps).collect();
    let right = rows_at_samples(plan, path, &u, &grid, false)?;
    let left = rows_at_samples(plan, path, &u, &grid, true)?;
    let mut out = SegmentRows {
        stance,
        u,
        certified: giwc.certified,
        grid: Vec::new(),
        rows: Vec::new(),
        offsets: Vec::new(),
        sample_right: Vec::new(),
        sample_left: Vec::new(),
        t_u,
        t_abc: Duration::ZERO,
    };
    out.lay_out(grid, &right, &left, true);
    out.t_abc = t1.elapsed();
    Ok(out)
}
