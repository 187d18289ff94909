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
//!
//! Each side of a sample also has the actuator-limit rows of [`crate::limit_rows`]; where the torque
//! limits involve the contact forces (two contacts or more), its lifted rows are kept, and the
//! retiming's separation oracle ([`super::separation`]) adds to the side the cuts in `(u, x)`
//! it needed ([`SegmentRows::add_cut`]): the projection onto `(u, x)` is never computed.
//!
//! Of a side's explicit rows, those redundant at its own polygon in `(u, x)`
//! ([`stance_topp::facets`]; about 90 % of them on the box climbing: 70 rows a side, 6 that
//! touch) are left out of the grid's rows, which the retiming's LPs read, and kept for the
//! samples' checks. Each LP then reads a dozen rows a point instead of about 140, with the same
//! answers.

use std::time::{Duration, Instant};

use stance_contact::{Contact, GiwcOptions, Stance};
use stance_topp::factored::{eq14_vectors, FactoredRows};
use stance_topp::lifted::{LiftedRows, Membership, Witnesses};
use stance_topp::path::PathPoint;
use stance_topp::Row;

use super::ik_stage::{IkSample, SegmentPath};
use super::plan::MotionPlan;
use crate::binding::RowOrigin;
use crate::limit_rows::{
    drop_redundant, prune_and_drop_redundant, sample_limit_rows, LimitWorkspace, SegmentContacts,
};
use crate::StanceError;

/// Rows of several points, each point's in a slice (`offsets`), with what each row stands for.
#[derive(Debug, Clone)]
pub struct PointRows {
    /// The rows, point after point.
    pub rows: Vec<Row>,
    /// What each row stands for.
    pub origins: Vec<RowOrigin>,
    /// Where each point's rows start (one more than the points).
    pub offsets: Vec<usize>,
}

impl Default for PointRows {
    fn default() -> Self {
        Self::new()
    }
}

impl PointRows {
    fn new() -> Self {
        Self {
            rows: Vec::new(),
            origins: Vec::new(),
            offsets: vec![0],
        }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Whether there are no points.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The rows of point `i`.
    pub fn rows_at(&self, i: usize) -> &[Row] {
        &self.rows[self.offsets[i]..self.offsets[i + 1]]
    }

    /// What the rows of point `i` stand for.
    pub fn origins_at(&self, i: usize) -> &[RowOrigin] {
        &self.origins[self.offsets[i]..self.offsets[i + 1]]
    }
}

/// Torque rows with the contact forces as unknowns at one side of a sample (rows in
/// `(u, x, y)`).
#[derive(Debug, Clone)]
pub struct LiftedSide {
    /// The rows.
    pub rows: LiftedRows,
    /// What each row stands for (shared by the sample's two sides).
    pub origins: std::sync::Arc<[RowOrigin]>,
    /// The contact forces of the last admissible states found (module doc of
    /// [`stance_topp::lifted::member`]).
    pub witnesses: Witnesses,
}

/// The rows of one side of an IK sample: the step leaving it (right) or arriving at it (left).
#[derive(Debug, Clone)]
pub struct SideRows {
    /// Contact rows of eq. 14, explicit limit rows, the contact rows of the step's midpoint
    /// when the refinement added them, then the cuts of `lifted` the retiming found.
    pub rows: Vec<Row>,
    /// What each row stands for.
    pub origins: Vec<RowOrigin>,
    /// Rows before the cuts (the explicit rows).
    pub explicit: usize,
    /// The explicit rows redundant at the side's own polygon
    /// ([`stance_topp::facets`]): the samples' checks read them, the grid's LPs
    /// do not.
    pub redundant: std::ops::Range<usize>,
    /// The torque rows with the contact forces as unknowns (two contacts or more).
    pub lifted: Option<Box<LiftedSide>>,
}

/// Both sides of an IK sample (the left is the right's copy at a segment's first sample).
pub type Sides = [SideRows; 2];

/// Both sides of several IK samples, each with its index.
pub(crate) type SamplesSides = Vec<(usize, Box<Sides>)>;

/// `todo` (IK samples) in chunks of about [`crate::tol::ROWS_CHUNK`] samples that share them
/// evenly, so that none has a lone sample when there are two or more.
pub(crate) fn chunked(todo: &[usize]) -> Vec<&[usize]> {
    let parts = todo.len().div_ceil(crate::tol::ROWS_CHUNK);
    let (size, longer) = (todo.len() / parts.max(1), todo.len() % parts.max(1));
    let mut chunks = Vec::with_capacity(parts);
    let mut at = 0;
    for p in 0..parts {
        let n = size + usize::from(p < longer);
        chunks.push(&todo[at..at + n]);
        at += n;
    }
    chunks
}

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
    /// The contacts as the torque limits need them (when torque limits apply).
    pub contacts: Option<SegmentContacts>,
    /// Indices of the IK samples at the retiming grid points (increasing; first and last
    /// sample included).
    pub grid: Vec<usize>,
    /// Rows at the grid points: at an interior point those of both sides (the step arriving
    /// and the step leaving), at the first point the right side, at the last the left side.
    pub points: PointRows,
    /// Segment-local path parameter of every IK sample.
    pub s: Vec<f64>,
    /// The rows of both sides of each IK sample, where computed (the grid's samples, and every
    /// sample once the refinement asked for them).
    pub sides: Vec<Option<Box<Sides>>>,
    /// Time of `U_stance` (the paper's `T_U`).
    pub t_u: Duration,
    /// Time of the rows on the initial retiming grid (`T_abc`), actuator limits included (their
    /// chunks' times summed where they are computed while the solve runs: module `overlap` of
    /// `chain`).
    pub t_abc: Duration,
    /// Time of the actuator-limit rows within `t_abc`.
    pub t_limits: Duration,
    /// Cuts of the lifted torque rows kept in the sides' rows.
    pub cuts: usize,
}

impl SegmentRows {
    /// The segment-local path parameter of IK sample `j` (its grid's samples: the layout).
    pub fn s_of(&self, j: usize) -> f64 {
        self.s[j]
    }

    /// The rows at grid point `i`.
    pub fn rows_at(&self, i: usize) -> &[Row] {
        self.points.rows_at(i)
    }

    /// What the rows at grid point `i` stand for.
    pub fn origins_at(&self, i: usize) -> &[RowOrigin] {
        self.points.origins_at(i)
    }

    /// Computes both sides of the IK samples `samples` that have none yet, in chunks of about
    /// [`crate::tol::ROWS_CHUNK`] samples in parallel (a segment's samples are independent, and
    /// the segments differ in size: two threads working a segment each waited for the
    /// largest). The chunks share the samples evenly, so that none has a lone sample when
    /// there are two or more.
    fn compute(
        &mut self,
        plan: &MotionPlan,
        path: &SegmentPath,
        samples: &[usize],
    ) -> Result<(), StanceError> {
        use rayon::prelude::*;
        let todo: Vec<usize> = samples
            .iter()
            .copied()
            .filter(|&j| self.sides[j].is_none())
            .collect();
        if todo.is_empty() {
            return Ok(());
        }
        let this = &*self;
        let done = chunked(&todo)
            .par_iter()
            .map_init(
                || LimitWorkspace::new(plan),
                |ws, chunk| this.sides_of(plan, path, chunk, ws),
            )
            .collect::<Result<Vec<_>, _>>()?;
        self.fill(done);
        Ok(())
    }

    /// Keeps the sides computed by [`Self::sides_of`] (chunks of the samples) and the time of
    /// their actuator-limit rows.
    pub(crate) fn fill(&mut self, done: Vec<(SamplesSides, Duration)>) {
        for (sides, t) in done {
            for (j, s) in sides {
                self.sides[j] = Some(s);
            }
            self.t_limits += t;
        }
    }

    /// Both sides of the IK samples `todo`, and the time of their actuator-limit rows.
    pub(crate) fn sides_of(
        &self,
        plan: &MotionPlan,
        path: &SegmentPath,
        todo: &[usize],
        ws: &mut LimitWorkspace,
    ) -> Result<(SamplesSides, Duration), StanceError> {
        let m = self.u.len();
        let mass = plan.robot.model.total_mass();
        // the contact rows' factorization is over a grid of two points or more: a lone sample
        // takes a neighbour along, whose rows are not kept
        let mut factored = todo.to_vec();
        if let &[j] = todo {
            let other = if j + 1 < path.samples.len() {
                j + 1
            } else {
                j - 1
            };
            factored = vec![j.min(other), j.max(other)];
        }
        let at = |i: usize| factored.binary_search(&todo[i]).expect("a factored sample");
        let s: Vec<f64> = factored.iter().map(|&j| path.samples[j].s).collect();
        let mut contact = [Vec::new(), Vec::new()];
        for (side, left) in [false, true].into_iter().enumerate() {
            let w = factored
                .iter()
                .map(|&j| eq14_of(&path.samples[j], left, mass, plan.gravity))
                .collect();
            let f = FactoredRows::new(&self.u, s.clone(), w)?;
            contact[side] = vec![Row::default(); factored.len() * m];
            f.fill(&mut contact[side])?;
        }
        let t0 = Instant::now();
        // each side is built and pruned in the workspace's buffers, then kept at its size: most
        // limit rows are pruned, and writing them into the kept rows made most of this stage's
        // time the kernel's (fresh pages for rows that were then dropped)
        let mut scratch = std::mem::take(&mut ws.scratch);
        let mut out = Vec::with_capacity(todo.len());
        for (i, &j) in todo.iter().enumerate() {
            let smp = &path.samples[j];
            for (side, (rows, origins)) in scratch.iter_mut().enumerate() {
                rows.clear();
                rows.extend_from_slice(&contact[side][at(i) * m..(at(i) + 1) * m]);
                origins.clear();
                origins.resize(m, RowOrigin::Contact);
            }
            let mut lifted_sides: [Option<Box<LiftedSide>>; 2] = [None, None];
            if let Some(lp) = plan.limits.as_ref() {
                let last = path.samples.len() - 1;
                let left_qss = if j > 0 {
                    &path.samples[j - 1].q_ss
                } else {
                    &smp.q_ss
                };
                // q_s at the other end of each side's step
                let q_s_next = &path.samples[(j + 1).min(last)].q_s;
                let q_s_prev = &path.samples[j.saturating_sub(1)].q_s;
                let [(right_rows, right_origins), (left_rows, left_origins)] = &mut scratch;
                let lifted = sample_limit_rows(
                    plan,
                    lp,
                    self.contacts.as_ref(),
                    smp,
                    [&smp.q_ss, left_qss],
                    [q_s_next, q_s_prev],
                    ws,
                    [(right_rows, right_origins), (left_rows, left_origins)],
                )?;
                for (q, l) in lifted.into_iter().enumerate() {
                    lifted_sides[q] = l.map(|(rows, origins)| {
                        Box::new(LiftedSide {
                            witnesses: Witnesses::new(),
                            rows,
                            origins,
                        })
                    });
                }
            }
            let limits = plan.limits.is_some();
            let kept = [0, 1].map(|q| {
                let (rows, origins) = &mut scratch[q];
                if limits {
                    prune_and_drop_redundant(rows, origins, m, ws)
                } else {
                    drop_redundant(rows, origins, ws)
                }
            });
            let [lifted_r, lifted_l] = lifted_sides;
            let keep = |(rows, origins): &(Vec<Row>, Vec<RowOrigin>), kept, lifted| SideRows {
                rows: rows.clone(),
                origins: origins.clone(),
                explicit: rows.len(),
                redundant: kept..rows.len(),
                lifted,
            };
            let sides: Sides = [
                keep(&scratch[0], kept[0], lifted_r),
                keep(&scratch[1], kept[1], lifted_l),
            ];
            out.push((j, Box::new(sides)));
        }
        ws.scratch = scratch;
        Ok((out, t0.elapsed()))
    }

    /// Computes the rows at every IK sample (both sides), once.
    pub fn ensure_sample_rows(
        &mut self,
        plan: &MotionPlan,
        path: &SegmentPath,
    ) -> Result<(), StanceError> {
        let all: Vec<usize> = (0..path.samples.len()).collect();
        self.compute(plan, path, &all)
    }

    /// The rows of IK sample `j`: the right side (`left = false`) or the left one (after
    /// [`Self::ensure_sample_rows`]).
    pub fn sample_rows(&self, j: usize, left: bool) -> (&[Row], &[RowOrigin]) {
        let s = &self.sides[j]
            .as_ref()
            .expect("rows computed at this sample")[usize::from(left)];
        (&s.rows, &s.origins)
    }

    /// The side of IK sample `j` (computed).
    pub fn side_mut(&mut self, j: usize, left: bool) -> &mut SideRows {
        &mut self.sides[j]
            .as_mut()
            .expect("rows computed at this sample")[usize::from(left)]
    }

    /// Lays out the rows of the grid from the sides of its samples (computed).
    fn lay_out(&mut self) {
        let n = self.grid.len();
        let mut out = PointRows::new();
        for (i, &j) in self.grid.iter().enumerate() {
            let sides = self.sides[j]
                .as_ref()
                .expect("rows computed at the grid's samples");
            for (side, on) in [(0, i + 1 < n), (1, i > 0)] {
                if on {
                    let sd = &sides[side];
                    let (skip_from, skip_to) = (sd.redundant.start, sd.redundant.end);
                    out.rows.extend_from_slice(&sd.rows[..skip_from]);
                    out.rows.extend_from_slice(&sd.rows[skip_to..]);
                    out.origins.extend_from_slice(&sd.origins[..skip_from]);
                    out.origins.extend_from_slice(&sd.origins[skip_to..]);
                }
            }
            out.offsets.push(out.rows.len());
        }
        self.points = out;
    }

    /// Takes a new grid (indices of IK samples, increasing, first and last sample included)
    /// whose samples have rows (after [`Self::ensure_sample_rows`]).
    pub fn set_grid(&mut self, grid: Vec<usize>) {
        self.grid = grid;
        self.lay_out();
    }

    /// Adds a cut of the lifted rows of sample `j`'s side (valid for every admissible state of
    /// that side) to its rows; the grid's rows change at the next [`Self::refresh`].
    pub fn add_cut(&mut self, j: usize, left: bool, row: Row, origin: RowOrigin) {
        let side = self.side_mut(j, left);
        side.rows.push(row);
        side.origins.push(origin);
        self.cuts += 1;
    }

    /// Adds an explicit contact row to sample `j`'s right side (a row of the model at a point
    /// inside the step that leaves `j`, written in `j`'s state: module `midpoints`), before
    /// the lifted rows' cuts; the grid's rows change at the next [`Self::refresh`] or
    /// [`Self::set_grid`].
    pub fn add_step_row(&mut self, j: usize, row: Row) {
        let side = self.side_mut(j, false);
        side.rows.insert(side.explicit, row);
        side.origins.insert(side.explicit, RowOrigin::Contact);
        side.explicit += 1;
    }

    /// Re-lays the grid out after cuts.
    pub fn refresh(&mut self) {
        self.lay_out();
    }

    /// Whether the lifted rows of sample `j`'s side (if any) hold at `(u, x)`.
    pub fn lifted_holds(
        &mut self,
        j: usize,
        left: bool,
        u: f64,
        x: f64,
        member: &mut Membership,
    ) -> Result<bool, StanceError> {
        let side = self.side_mut(j, left);
        match side.lifted.as_mut() {
            Some(l) => Ok(member.contains(&l.rows, u, x, &mut l.witnesses)?),
            None => Ok(true),
        }
    }
}

/// The planned stance of a segment path's contacts (planning friction and area scale).
pub fn planned_stance(plan: &MotionPlan, path: &SegmentPath) -> Result<Stance, StanceError> {
    let p = &plan.spec.planning;
    stance_of(plan, path, p.area_scale.sqrt(), p.friction, p.friction_cone)
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
    let contacts: Vec<_> = path
        .contacts
        .iter()
        .map(|c| (c.surface, c.environment, c.pose))
        .collect();
    stance_from(plan, &contacts, k, friction, model)
}

/// Contacts `(robot surface, environment surface, pose)` as a stance: polygons scaled by `k`,
/// friction `friction` (else each environment surface's), friction model `model`.
pub fn stance_from(
    plan: &MotionPlan,
    contacts: &[(usize, usize, stance_robot::Pose)],
    k: f64,
    friction: Option<f64>,
    model: stance_contact::FrictionModel,
) -> Result<Stance, StanceError> {
    let contacts = contacts
        .iter()
        .map(|(surface, environment, pose)| {
            let surf = &plan.robot.surfaces[*surface];
            let env = &plan.environment[*environment];
            let r = &pose.rotation;
            let rotation = [
                [r[(0, 0)], r[(0, 1)], r[(0, 2)]],
                [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
                [r[(2, 0)], r[(2, 1)], r[(2, 2)]],
            ];
            Contact::new(
                &surf.name,
                pose.translation.into(),
                rotation,
                surf.shape.scaled(k),
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

/// `U_stance` and the rows of segment `path` at every `substeps`-th IK sample (contact rows
/// and, when the plan has them, actuator-limit rows).
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
    let mut out = segment_skeleton(plan, k, path, substeps, ws)?;
    let t1 = Instant::now();
    let grid = out.grid.clone();
    out.compute(plan, path, &grid)?;
    out.lay_out();
    out.t_abc += t1.elapsed();
    Ok(out)
}

/// [`segment_rows`] before the rows of its grid's samples: the stance, `U_stance`, the
/// contacts, the grid (the samples' rows are then [`SegmentRows::sides_of`] chunks of the grid,
/// [`SegmentRows::fill`], [`SegmentRows::refresh`]). Its `t_abc` is the time of the contacts.
///
/// # Errors
///
/// As [`segment_rows`].
pub(crate) fn segment_skeleton(
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
            "{}: the stance's GIWC is lower-dimensional ({} equation(s)); retiming needs \
             surface contacts",
            crate::plan::segment_label(k, &plan.segments[k].name),
            giwc.equations.nrows()
        )));
    }
    let u = giwc.facet_rows();
    let t1 = Instant::now();
    let contacts = match &plan.limits {
        Some(lp) if lp.any_torque() => {
            let surfaces: Vec<usize> = path.contacts.iter().map(|c| c.surface).collect();
            let poses: Vec<stance_robot::Pose> = path.contacts.iter().map(|c| c.pose).collect();
            Some(SegmentContacts::new(plan, &surfaces, &poses, &stance)?)
        }
        _ => None,
    };
    let grid: Vec<usize> = (0..path.samples.len()).step_by(substeps).collect();
    Ok(SegmentRows {
        stance,
        u,
        certified: giwc.certified,
        contacts,
        grid,
        points: PointRows::new(),
        s: path.samples.iter().map(|x| x.s).collect(),
        sides: vec![None; path.samples.len()],
        t_u,
        t_abc: t1.elapsed(),
        t_limits: Duration::ZERO,
        cuts: 0,
    })
}

#[cfg(test)]
mod doc_examples {
    //! The examples that were in the docs of this private module.

    use crate::{
        experiments,
        ik_stage::{self, run_segment, IkStageWorkspace, SegmentPath},
        plan::MotionPlan,
        rows,
    };

    /// The small sway's plan and the IK path of its first segment, in 8 steps.
    fn sway_segment() -> (MotionPlan, SegmentPath) {
        let plan = MotionPlan::new(experiments::by_name("small-sway").unwrap(), None).unwrap();
        let mut ws = IkStageWorkspace::new(&plan);
        let nv = plan.robot.model.nv;
        let com = ik_stage::com_reference(&plan).unwrap();
        let path = run_segment(
            &plan,
            0,
            &com,
            0.0,
            &plan.q0,
            &vec![0.0; nv],
            &[],
            8,
            &mut ws,
        )
        .unwrap();
        (plan, path)
    }

    #[test]
    fn planned_stance_example() {
        let (plan, path) = sway_segment();
        let stance = rows::planned_stance(&plan, &path).unwrap();
        assert_eq!(stance.contacts().len(), 2);
    }

    /// A sample whose rows are computed alone (the contact rows' factorization needs two
    /// points: it takes a neighbour along) has the rows it has among all the samples.
    #[test]
    fn a_lone_sample_has_the_rows_it_has_among_all() {
        let (plan, path) = sway_segment();
        let last = path.samples.len() - 1;
        let mut cone = polycone::Workspace::new();
        let all = {
            let mut r = rows::segment_rows(&plan, 0, &path, 4, &mut cone).unwrap();
            r.ensure_sample_rows(&plan, &path).unwrap();
            r
        };
        // the last sample alone (its neighbour before it), then one inside alone
        for j in [last, 1] {
            let mut alone = rows::segment_rows(&plan, 0, &path, 4, &mut cone).unwrap();
            assert!(alone.sides[j].is_none());
            alone.compute(&plan, &path, &[j]).unwrap();
            for left in [false, true] {
                assert_eq!(
                    alone.sample_rows(j, left),
                    all.sample_rows(j, left),
                    "sample {j}"
                );
            }
        }
    }
}
