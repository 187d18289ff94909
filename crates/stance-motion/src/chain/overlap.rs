//! Stage 3 and the first chained solve of stage 4, overlapped: the rows of the segments' grid
//! samples are computed last segment first, and the solver's backward pass over a segment runs
//! as soon as its rows are done, while the rows of the segments before it are computed.
//!
//! # Why
//!
//! With actuator limits the rows (inverse dynamics and the lifted torque rows at every grid
//! sample) are most of the CPU time of `U_stance` + rows + TOPP, and the solve is serial: the
//! second core idled during it. The backward pass computes `K_i` from `K_{i+1}` and the rows of
//! grid points `i` and `i + 1` alone, so segment `k`'s part of it needs only segment `k`'s rows,
//! the first point of segment `k + 1` and the set the pass over `k + 1` found there
//! ([`stance_topp::BackwardPiece`]).
//!
//! # How
//!
//! A queue of tasks, last segment first: each segment's stance, `U_stance` and contacts (its
//! skeleton, `segment_skeleton`, one segment ahead), then its grid samples' rows in chunks of
//! about [`crate::tol::ROWS_CHUNK`] samples. Two threads: one takes tasks until none is left;
//! the other runs the passes, last segment first, each once its segment's chunks are done, and
//! takes tasks while they are not. The forward pass then runs over the whole grid.
//!
//! # Measured
//!
//! On this project's 2-core machines the gain is small (`bench/peers/limits.md`): two threads
//! computing chunks at once take about 1.5 times as long per chunk as one alone, so the
//! second core adds about a third of one, and the backward pass hides in that third only.
//!
//! # The same answer
//!
//! The answer is the one of `solve_layout` on all the rows, bit for bit: a segment's layout is
//! its part of the global layout (`segment_layout`); its oracle tests, at each of its grid
//! points, the sides the global oracle tests there ([`LiftedOracle::of_segment`]: the sides'
//! witnesses and cuts are their own, and the oracles hand their membership workspace on); the
//! pieces' passes are the whole pass step for step, and the forward pass sees the cuts in the
//! order the whole pass found them (module doc of `stance_topp`'s `pieces`). The cuts are kept
//! in the rows in that order too (test below). Where that cannot hold this module gives up and
//! the caller solves the whole layout: a segment whose rows fail (the error is then the one of
//! the rows computed as before), a pass that finds an empty set (the diagnosis is the whole
//! solve's; the sides' witnesses are then warm), or a motion without lifted rows (solved
//! without an oracle, possibly in its own time unit).

use std::sync::atomic::{AtomicBool, AtomicU8, AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError, RwLock};
use std::time::{Duration, Instant};

use stance_topp::lifted::Membership;
use stance_topp::{BackwardPiece, Cut, Separation, Solution, SolveOptions, ToppError, Workspace};

use super::{joined, s_offsets, segment_layout, Layout, LayoutInputs, SegmentLayout};
use crate::limit_rows::LimitWorkspace;
use crate::plan::MotionPlan;
use crate::rows::{chunked, segment_rows, segment_skeleton, SamplesSides, SegmentRows};
use crate::separation::{keep_found, FoundCut, LiftedOracle};
use crate::StanceError;

/// The first solve of the whole layout, made while the rows were computed.
pub(super) struct FirstSolve {
    /// The global layout (the cuts not in it yet).
    pub layout: Layout,
    /// The solver's answer.
    pub solution: Solution,
    /// Cuts of the lifted torque rows found, kept in the rows.
    pub cuts: usize,
    /// Time in the oracle (the segments' passes and the forward pass).
    pub t_oracle: Duration,
    /// The solver's own time: the segments' passes and the forward pass (their layouts and the
    /// waits for rows left out).
    pub t_solve: Duration,
    /// Time of the segments' layouts and of joining them.
    pub t_layout: Duration,
}

/// What a segment's backward pass leaves: its layout, the pass, the cuts its oracle found,
/// the oracle's time, whether the segment has lifted rows, and the times of its layout and
/// pass.
struct SegmentPass {
    layout: SegmentLayout,
    piece: BackwardPiece,
    found: Vec<FoundCut>,
    t_oracle: Duration,
    lifted: bool,
    /// Time of the layout, of the pass.
    t: [Duration; 2],
}

/// An oracle for a segment without lifted rows: the global oracle has no sides there.
struct NoLiftedRows;

impl Separation for NoLiftedRows {
    fn separate(&mut self, _: usize, _: f64, _: f64) -> Result<Option<Cut>, ToppError> {
        Ok(None)
    }
}

/// What the rows and the first solve are made from.
pub(super) struct Inputs<'a> {
    pub plan: &'a MotionPlan,
    /// The paths, the margin and the landing bounds.
    pub layout: &'a LayoutInputs<'a>,
    pub opts: &'a SolveOptions,
}

/// Every segment's `U_stance` and rows, and the first solve of the whole layout when it could
/// be made while they were computed (module doc; `None`: solve the whole layout).
pub(super) fn rows_and_first_solve(
    inputs: &Inputs<'_>,
    ws: &mut Workspace,
) -> Result<(Vec<SegmentRows>, Option<FirstSolve>), StanceError> {
    // on a thread of the pool (from outside it, the join would wait for a worker to wake up)
    rayon::scope(|_| overlapped(inputs, ws))
}

/// The body of [`rows_and_first_solve`], on a thread of the pool.
#[inline(never)] // (a frame of its own in profiles: the figure)
fn overlapped(
    inputs: &Inputs<'_>,
    ws: &mut Workspace,
) -> Result<(Vec<SegmentRows>, Option<FirstSolve>), StanceError> {
    let nseg = inputs.layout.paths.len();
    let s_offset = s_offsets(inputs.layout.paths);
    let queue = Queue::new(inputs);
    // the passes on this thread, which takes tasks while a segment's rows are not done; the
    // other thread takes tasks until none are left
    let (passes, ()) = rayon::join(
        || passer(inputs, &queue, &s_offset, ws),
        || {
            let mut task_ws = TaskWorkspace::new(inputs.plan);
            while queue.take_task(inputs, &mut task_ws) {}
        },
    );
    // a chunk's error first, as when the rows are computed before the solve
    let Some(mut rows) = queue.into_rows() else {
        return Ok((all_segment_rows(inputs)?, None));
    };
    let (mut passes, mut member) = passes?;
    if passes.len() < nseg || passes.last().is_some_and(|p| p.piece.failed_at().is_some()) {
        return Ok((rows, None));
    }
    passes.reverse();
    if !passes.iter().any(|p| p.lifted) {
        return Ok((rows, None));
    }
    let mut pieces = Vec::with_capacity(nseg);
    let mut seg_layouts = Vec::with_capacity(nseg);
    let mut found = Vec::with_capacity(nseg);
    let (mut t_oracle, mut t_layout, mut t_solve) =
        (Duration::ZERO, Duration::ZERO, Duration::ZERO);
    for p in passes {
        pieces.push(p.piece);
        seg_layouts.push(p.layout);
        found.push(p.found);
        t_oracle += p.t_oracle;
        t_layout += p.t[0];
        t_solve += p.t[1];
    }
    let t_join = Instant::now();
    let layout = joined(&seg_layouts, s_offset)?;
    t_layout += t_join.elapsed();
    let t_forward = Instant::now();
    let mut oracle =
        LiftedOracle::new(&mut rows, &layout.seg_start).expect("a segment has lifted rows");
    std::mem::swap(oracle.member_mut(), &mut member);
    let solution =
        ws.forward_over_pieces(&layout.constraints, inputs.opts, &pieces, &mut oracle)?;
    t_oracle += oracle.elapsed;
    let forward = std::mem::take(&mut oracle.found);
    // the cuts in the order they were found: the segments' passes last first, then forward
    let mut cuts = forward.len();
    for (k, f) in found.iter().enumerate().rev() {
        keep_found(std::slice::from_mut(&mut rows[k]), f);
        cuts += f.len();
    }
    keep_found(&mut rows, &forward);
    t_solve += t_forward.elapsed();
    Ok((
        rows,
        Some(FirstSolve {
            layout,
            solution,
            cuts,
            t_oracle,
            t_solve,
            t_layout,
        }),
    ))
}

/// What there is to compute of the segments' rows, last segment first: each segment's stance,
/// `U_stance` and contacts (its skeleton, a segment ahead of its chunks), then its grid
/// samples' rows in chunks.
enum Task {
    Skeleton(usize),
    Chunk(usize, Vec<usize>),
}

/// A skeleton not computed yet, computed, failed.
const PENDING: u8 = 0;
const READY: u8 = 1;
const FAILED: u8 = 2;

/// The tasks, taken in order by both threads, and the segments' rows as their tasks are done.
struct Queue {
    tasks: Vec<Task>,
    /// The next task to take.
    next: AtomicUsize,
    /// The segments' rows (from their skeletons; their samples' sides once their chunks are
    /// kept).
    rows: Vec<RwLock<Option<SegmentRows>>>,
    /// Per segment, whether its skeleton is computed ([`PENDING`], [`READY`], [`FAILED`]).
    skeleton: Vec<AtomicU8>,
    /// Each chunk's sides, the time of their limit rows and the chunk's time, once done.
    done: Vec<Mutex<Option<ChunkRows>>>,
    /// Per segment, its chunks not done yet.
    left: Vec<AtomicUsize>,
    /// Whether a skeleton or a chunk failed.
    failed: AtomicBool,
}

/// A chunk's sides and the time of their limit rows, and the chunk's time.
type ChunkRows = (Result<(SamplesSides, Duration), StanceError>, Duration);

/// A thread's workspaces for the tasks.
struct TaskWorkspace {
    cone: polycone::Workspace,
    limits: LimitWorkspace,
}

impl TaskWorkspace {
    fn new(plan: &MotionPlan) -> Self {
        Self {
            cone: polycone::Workspace::new(),
            limits: LimitWorkspace::new(plan),
        }
    }
}

impl Queue {
    fn new(inputs: &Inputs<'_>) -> Self {
        let nseg = inputs.layout.paths.len();
        let mut tasks = Vec::new();
        let mut left = Vec::with_capacity(nseg);
        for k in (0..nseg).rev() {
            // the segment's grid (as `segment_skeleton` makes it)
            let grid: Vec<usize> = (0..inputs.layout.paths[k].samples.len())
                .step_by(inputs.plan.spec.ik.substeps)
                .collect();
            let parts = chunked(&grid);
            left.push(AtomicUsize::new(parts.len()));
            if k + 1 == nseg {
                tasks.push(Task::Skeleton(k));
            }
            if k > 0 {
                tasks.push(Task::Skeleton(k - 1));
            }
            tasks.extend(parts.into_iter().map(|c| Task::Chunk(k, c.to_vec())));
        }
        left.reverse();
        Self {
            done: tasks.iter().map(|_| Mutex::new(None)).collect(),
            tasks,
            next: AtomicUsize::new(0),
            rows: (0..nseg).map(|_| RwLock::new(None)).collect(),
            skeleton: (0..nseg).map(|_| AtomicU8::new(PENDING)).collect(),
            left,
            failed: AtomicBool::new(false),
        }
    }

    /// Computes the next task; `false` when none is left.
    fn take_task(&self, inputs: &Inputs<'_>, ws: &mut TaskWorkspace) -> bool {
        let i = self.next.fetch_add(1, Ordering::Relaxed);
        let Some(task) = self.tasks.get(i) else {
            return false;
        };
        // marks the task done however it ends, a panic included: the other thread may be
        // waiting for it
        let _end = TaskEnd { queue: self, task };
        match task {
            &Task::Skeleton(k) => {
                let (plan, path) = (inputs.plan, &inputs.layout.paths[k]);
                if let Ok(rows) =
                    segment_skeleton(plan, k, path, inputs.plan.spec.ik.substeps, &mut ws.cone)
                {
                    *write(&self.rows[k]) = Some(rows);
                    self.skeleton[k].store(READY, Ordering::Release);
                }
            }
            Task::Chunk(k, samples) => {
                let k = *k;
                // its skeleton, a task before it, may still be computed by the other thread
                while self.skeleton[k].load(Ordering::Acquire) == PENDING {
                    std::thread::yield_now();
                }
                let t = Instant::now();
                let sides = read(&self.rows[k]).as_ref().map(|rows| {
                    rows.sides_of(
                        inputs.plan,
                        &inputs.layout.paths[k],
                        samples,
                        &mut ws.limits,
                    )
                });
                if let Some(sides) = sides {
                    *lock(&self.done[i]) = Some((sides, t.elapsed()));
                }
            }
        }
        true
    }

    /// Segment `k`'s rows complete, computing tasks (or waiting for the other thread's) until
    /// its chunks are done; `false` when its skeleton or a chunk failed.
    fn finish(&self, k: usize, inputs: &Inputs<'_>, ws: &mut TaskWorkspace) -> bool {
        while self.left[k].load(Ordering::Acquire) > 0 {
            if !self.take_task(inputs, ws) {
                std::thread::yield_now();
            }
        }
        let mut sides = Vec::new();
        let mut t_chunks = Duration::ZERO;
        for (i, task) in self.tasks.iter().enumerate() {
            if matches!(task, Task::Chunk(seg, _) if *seg == k) {
                let Some((Ok(chunk), t)) = lock(&self.done[i]).take() else {
                    self.failed.store(true, Ordering::Relaxed);
                    return false;
                };
                sides.push(chunk);
                t_chunks += t;
            }
        }
        let mut rows = write(&self.rows[k]);
        let Some(rows) = rows.as_mut() else {
            return false;
        };
        let t = Instant::now();
        rows.fill(sides);
        rows.refresh();
        rows.t_abc += t_chunks + t.elapsed();
        true
    }

    /// The rows of every segment, `None` when a task failed (all done: the queue is empty).
    fn into_rows(self) -> Option<Vec<SegmentRows>> {
        let failed =
            |d: &Mutex<Option<ChunkRows>>| lock(d).as_ref().is_some_and(|(r, _)| r.is_err());
        if self.failed.load(Ordering::Relaxed) || self.done.iter().any(failed) {
            return None;
        }
        self.rows
            .into_iter()
            .map(|r| r.into_inner().unwrap_or_else(PoisonError::into_inner))
            .collect()
    }
}

/// The end of a task, however it ends: a skeleton not computed is marked failed, a chunk is
/// counted done (its rows missing when it failed: [`Queue::finish`] sees it).
struct TaskEnd<'a> {
    queue: &'a Queue,
    task: &'a Task,
}

impl Drop for TaskEnd<'_> {
    fn drop(&mut self) {
        let q = self.queue;
        match self.task {
            &Task::Skeleton(k) => {
                if q.skeleton[k].load(Ordering::Acquire) == PENDING {
                    q.failed.store(true, Ordering::Relaxed);
                    q.skeleton[k].store(FAILED, Ordering::Release);
                }
            }
            Task::Chunk(k, _) => {
                q.left[*k].fetch_sub(1, Ordering::Release);
            }
        }
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

fn read<T>(m: &RwLock<T>) -> std::sync::RwLockReadGuard<'_, T> {
    m.read().unwrap_or_else(PoisonError::into_inner)
}

fn write<T>(m: &RwLock<T>) -> std::sync::RwLockWriteGuard<'_, T> {
    m.write().unwrap_or_else(PoisonError::into_inner)
}

/// The segments' backward passes, last first, each once its rows are done, until a chunk or a
/// pass fails (the other segments' rows then completed all the same); with the oracles'
/// membership workspace, handed from one to the next as the whole solve's one oracle keeps it
/// (its recent witnesses).
fn passer(
    inputs: &Inputs<'_>,
    queue: &Queue,
    s_offset: &[f64],
    ws: &mut Workspace,
) -> Result<(Vec<SegmentPass>, Membership), StanceError> {
    let nseg = inputs.layout.paths.len();
    let mut task_ws = TaskWorkspace::new(inputs.plan);
    let mut passes: Vec<SegmentPass> = Vec::with_capacity(nseg);
    let mut member = Membership::new();
    let mut stop = false;
    for k in (0..nseg).rev() {
        // (after a failure too: the whole layout is then solved, with every segment's rows)
        let rows_done = queue.finish(k, inputs, &mut task_ws);
        stop = stop || !rows_done;
        if stop {
            continue;
        }
        let next = (k + 1 < nseg).then(|| read(&queue.rows[k + 1]));
        let mut rows = write(&queue.rows[k]);
        let rows = rows.as_mut().expect("its rows are done");
        let next_rows = next.as_ref().and_then(|r| r.as_ref());
        let after = next_rows.zip(passes.last().map(|p| &p.piece));
        let pass = segment_pass(inputs, k, rows, after, s_offset, ws, &mut member)?;
        stop = pass.piece.failed_at().is_some();
        passes.push(pass);
    }
    Ok((passes, member))
}

/// Segment `k`'s layout and backward pass (from the pass over `k + 1`, `after`), its oracle's
/// cuts not kept yet.
fn segment_pass(
    inputs: &Inputs<'_>,
    k: usize,
    rows: &mut SegmentRows,
    after: Option<(&SegmentRows, &BackwardPiece)>,
    s_offset: &[f64],
    ws: &mut Workspace,
    member: &mut Membership,
) -> Result<SegmentPass, StanceError> {
    let nseg = inputs.layout.paths.len();
    let t_layout = Instant::now();
    let layout = segment_layout(
        &inputs.layout.paths[k],
        rows,
        after.map(|(r, _)| r),
        k,
        s_offset[k],
        inputs.layout.margin,
        inputs.layout.boundary_x_max,
    )?;
    let t_pass = Instant::now();
    let t = |t_pass: Instant| [t_pass - t_layout, t_pass.elapsed()];
    let next = after.map(|(_, p)| p);
    let k_rows = &layout.constraints;
    // the global grid's ends (its first point is the first IK sample)
    let whole = [inputs.layout.paths[0].samples[0].s, s_offset[nseg]];
    Ok(
        match LiftedOracle::of_segment(rows, [k > 0, k + 1 < nseg]) {
            Some(mut oracle) => {
                std::mem::swap(oracle.member_mut(), member);
                let piece = ws.backward_piece(k_rows, inputs.opts, whole, next, &mut oracle);
                std::mem::swap(oracle.member_mut(), member);
                let piece = piece?;
                SegmentPass {
                    piece,
                    found: std::mem::take(&mut oracle.found),
                    t_oracle: oracle.elapsed,
                    lifted: true,
                    layout,
                    t: t(t_pass),
                }
            }
            None => SegmentPass {
                piece: ws.backward_piece(k_rows, inputs.opts, whole, next, &mut NoLiftedRows)?,
                found: Vec::new(),
                t_oracle: Duration::ZERO,
                lifted: false,
                layout,
                t: t(t_pass),
            },
        },
    )
}

/// Every segment's `U_stance` and rows, the segments in parallel, each thread with its own cone
/// workspace; within a segment, its samples' rows in parallel chunks too
/// ([`SegmentRows::compute`]).
pub(super) fn all_segment_rows(inputs: &Inputs<'_>) -> Result<Vec<SegmentRows>, StanceError> {
    use rayon::prelude::*;
    inputs
        .layout
        .paths
        .par_iter()
        .enumerate()
        .map_init(polycone::Workspace::new, |cone_ws, (k, path)| {
            segment_rows(inputs.plan, k, path, inputs.plan.spec.ik.substeps, cone_ws)
        })
        .collect::<Result<Vec<_>, _>>()
}

#[cfg(test)]
mod tests {
    //! The first solve made while the rows are computed against the whole layout's solve on
    //! all the rows.

    use super::*;
    use crate::chain::{boundary_bounds, contact_margin, solve_with_oracle, RetimingMode};
    use crate::experiments;
    use crate::ik_stage::IkStageWorkspace;

    /// The box climbing with its torque limits (lifted rows, cuts): the same
    /// solution, layout and rows (with their cuts) as the whole solve's.
    #[test]
    fn the_overlapped_first_solve_is_the_whole_solve() {
        let spec = experiments::by_name("box-climbing").unwrap();
        let plan = MotionPlan::new(spec, None).unwrap();
        assert!(plan.limits.is_some());
        let mut ik_ws = IkStageWorkspace::new(&plan);
        let (paths, failure) = crate::ik_paths(&plan, &mut ik_ws).unwrap();
        assert!(failure.is_none());
        let (bounds, _) =
            boundary_bounds(&plan, &paths, RetimingMode::Chained, &mut ik_ws).unwrap();
        let opts = SolveOptions::new(plan.spec.retiming.discretization);
        let layout_inputs = LayoutInputs {
            paths: &paths,
            margin: contact_margin(&plan),
            boundary_x_max: &bounds,
        };
        let inputs = Inputs {
            plan: &plan,
            layout: &layout_inputs,
            opts: &opts,
        };
        let (mut rows, first) = rows_and_first_solve(&inputs, &mut Workspace::new()).unwrap();
        let first = first.expect("solved while the rows were computed");
        assert!(first.cuts > 0, "the oracle cuts");
        let mut whole_rows = all_segment_rows(&inputs).unwrap();
        let l = layout_inputs.lay_out(&whole_rows).unwrap();
        assert_eq!(first.layout.constraints, l.constraints);
        assert_eq!(first.layout.origins, l.origins);
        assert_eq!(first.layout.seg_start, l.seg_start);
        let mut ws = Workspace::new();
        let (whole, cuts, _) = solve_with_oracle(
            &l.constraints,
            &opts,
            &mut ws,
            &mut whole_rows,
            &l.seg_start,
            0,
        )
        .unwrap();
        let sol = &first.solution;
        assert_eq!(sol.status, whole.status);
        assert_eq!(sol.profile, whole.profile);
        assert_eq!(sol.controllable, whole.controllable);
        assert_eq!(sol.stats, whole.stats);
        // the cuts (their tags number each oracle's own)
        assert_eq!(sol.cuts.rows, whole.cuts.rows);
        assert_eq!(sol.cuts.next_rows, whole.cuts.next_rows);
        assert_eq!(first.cuts, cuts);
        for (a, b) in rows.iter_mut().zip(&mut whole_rows) {
            a.refresh();
            b.refresh();
            assert_eq!(a.grid, b.grid);
            for i in 0..a.grid.len() {
                assert_eq!(a.rows_at(i), b.rows_at(i));
                assert_eq!(a.origins_at(i), b.origins_at(i));
            }
        }
    }
}
