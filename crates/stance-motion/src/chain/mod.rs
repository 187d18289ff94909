//! Stage 4, retiming: the segments' rows on one grid, solved as one problem (chained) or segment
//! by segment from rest to rest (the paper's way).
//!
//! # Math
//!
//! The segments' path parameters are laid end to end: segment `k` covers `[S_k, S_k+1]` of the
//! global parameter `s`, and the IK made `q_s` continuous across boundaries (each segment starts
//! from the state where the previous one ended), so `q_s^A s'_A = q_s^B s'_B` holds with one
//! `s'` on both sides: the physical joint velocity is continuous. Each row may be tightened by a
//! margin, `a u + b x + c + margin m |g| <= 0`.
//!
//! **Stance switches.** At a boundary grid point `b` both stances hold the motion at the
//! switching instant, each with its own path acceleration: `u` jumps there (and so may `p_ss`,
//! `l2`). The interpolation discretization imposes a point's rows with the acceleration of the
//! interval after it and of the interval before it; at a switch that would ask the stance
//! before to hold the acceleration after, and the stance after the one before, which forbids
//! every crossing where the acceleration reverses (a CoM that leaves one support falling and is
//! caught by the next: measured on a walk without double support, whose switch then had no
//! feasible state at all). So at `b` only the stance after holds, with `u_b`
//! (`CanonicalConstraints::with_next_rows`: none of `b`'s rows at the end of the interval
//! before), and the stance before holds with `u_b-1` at `x_b = x_b-1 + 2 Delta u_b-1`, written
//! in that interval's own state at `b - 1`: `(a + 2 Delta b) u + b x + c <= 0`. Inside a
//! segment the rows keep the plain interpolation (both sides of a point with both
//! accelerations: slightly conservative where `q_ss` jumps at an IK sample).
//!
//! **No impacts.** Where a contact is made, the landing surface's velocity is `J q_s s'`; the
//! references bring it to rest ([`super::references`]), but tracking leaves a residual `J q_s`,
//! so the retiming bounds the speed there: `x <= (v_max / |J_lin q_s|)^2` and
//! `x <= (w_max / |J_ang q_s|)^2` with [`crate::tol::LANDING_SPEED`] and
//! [`crate::tol::LANDING_ANGULAR_SPEED`]. A path that does not bring the link to rest thus
//! makes the retiming stop there.
//!
//! **Chained**: one reachability problem over the whole grid from rest to rest, so the
//! controllable sets propagate back through every segment: a segment that needs a minimum speed
//! gets it from its neighbours, and a slow later segment constrains earlier ones.
//! **Rest to rest**: each segment separately, `s' = 0` at both of its ends.
//!
//! Chained with actuator limits, the first solve runs while the rows are computed (module
//! `overlap`: each segment's backward pass as soon as its rows are done), with the answer of
//! the solve on all the rows.
//!
//! Per-segment `T_TOPP` of a chained solve is measured by solving each segment again with the
//! boundary speeds of the chained profile; by the principle of optimality its duration matches
//! the chained profile's on that segment (the difference is recorded as a consistency check).

use std::time::{Duration, Instant};

use stance_topp::{CanonicalConstraints, Profile, Row, Solution, SolveOptions, Status, Workspace};

use super::ik_stage::{frame_path_velocity, IkStageWorkspace, SegmentPath};
use super::plan::MotionPlan;
use super::rows::SegmentRows;
use super::separation::LiftedOracle;
use crate::binding::RowOrigin;
use crate::StanceError;
use stance_topp::lifted::Membership;

mod overlap;

/// How the segments are retimed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RetimingMode {
    /// The whole motion as one problem.
    Chained,
    /// Each segment from rest to rest.
    RestToRest,
}

/// A speed bound at a landing.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LandingBound {
    /// Number (from 1) of the segment that starts with the new contact.
    pub segment: usize,
    /// Its name.
    pub segment_name: String,
    /// The landing robot surface.
    pub surface: String,
    /// `|J_lin q_s|` of its frame at the boundary (m per unit path).
    pub path_speed: f64,
    /// `|J_ang q_s|` (rad per unit path).
    pub path_angular_speed: f64,
    /// The bound on the path speed `s'` there (`null` for none).
    pub max_sd: Option<f64>,
}

/// Per segment: its profile's duration and its own solve time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentSolve {
    /// Duration of the segment in the motion's profile (s).
    pub duration: f64,
    /// `s'` at its start and end.
    pub sd: [f64; 2],
    /// Time of its solve (rest to rest), or of its re-solve with the chained boundary speeds.
    pub t_topp: Duration,
    /// Relative difference of the re-solve's duration from the chained profile's (0 rest to
    /// rest).
    pub resolve_mismatch: f64,
}

/// What stopped the retiming of a motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FailureStatus {
    /// The TOPP solver's outcome on the whole motion or a segment (never
    /// [`Status::Optimal`]).
    Solver(Status),
    /// The acceleration-level IK could not track a segment's path (a joint limit, or a
    /// via-point out of reach).
    IkFailed,
}

impl FailureStatus {
    /// Machine-readable name: the solver's ([`Status::name`]) or `"ik_failed"`.
    pub fn name(&self) -> &'static str {
        match self {
            FailureStatus::Solver(s) => s.name(),
            FailureStatus::IkFailed => "ik_failed",
        }
    }
}

impl std::fmt::Display for FailureStatus {
    /// The machine-readable [`FailureStatus::name`].
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A failure status equals its machine-readable [`FailureStatus::name`].
impl PartialEq<&str> for FailureStatus {
    fn eq(&self, name: &&str) -> bool {
        self.name() == *name
    }
}

/// Serialized as its [`FailureStatus::name`].
impl serde::Serialize for FailureStatus {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// Why the motion cannot be retimed, located.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RetimeFailure {
    /// What stopped it (serialized as its name).
    pub status: FailureStatus,
    /// Segment number, from 1.
    pub segment: usize,
    /// Segment name.
    pub segment_name: String,
    /// Grid point within the segment (from 0, its first point).
    pub grid_point: usize,
    /// Global path parameter there.
    pub s: f64,
    /// The constraints that empty that grid point, or that cannot all hold there with the
    /// speed the rest of the motion needs (`"torque of R_KNEE (upper limit)"`,
    /// `"contact stability"`, `"the speed that grid point N needs"`, ...).
    pub constraints: Vec<String>,
    /// What it means, and what to relax.
    pub reason: String,
}

/// The retimed motion.
#[derive(Debug, Clone)]
pub struct Retimed {
    /// Mode.
    pub mode: RetimingMode,
    /// The whole motion's constraints (global grid).
    pub constraints: CanonicalConstraints,
    /// What each row of `constraints` stands for.
    pub origins: Vec<RowOrigin>,
    /// Global grid index of each segment's first point, and the last point's index at the end.
    pub seg_start: Vec<usize>,
    /// Global path parameter of each segment's start, and the end.
    pub s_offset: Vec<f64>,
    /// The profile, when the motion could be retimed.
    pub profile: Option<Profile>,
    /// The failure, when it could not.
    pub failure: Option<RetimeFailure>,
    /// Per segment.
    pub segments: Vec<SegmentSolve>,
    /// Speed bounds at landings.
    pub landings: Vec<LandingBound>,
    /// Time of the whole-motion solve (chained), or the sum of the segments' (rest to rest).
    pub t_topp: Duration,
    /// Time to lay out the global rows (part of `T_abc`; made while the rows were computed,
    /// chained with limits, the segments' layouts and their joining).
    pub t_assemble: Duration,
    /// Time of the first solve (on the initial grid), its separation oracle and the layout of
    /// the cuts it found included; made while the rows were computed (chained, with limits:
    /// module `overlap`), the solver's own time, its waits for rows left out.
    pub t_first: Duration,
    /// Wall time from the start of the segments' `U_stance` and rows to the end of the first
    /// solve, its layouts included.
    pub t_rows_first: Duration,
    /// Time in the separation oracle of the lifted torque rows during the first solve (part of
    /// `t_first`).
    pub t_lifted: Duration,
    /// Cuts of the lifted torque rows found by the first solve.
    pub cuts: usize,
    /// What the refinement between grid points did.
    pub refinement: Refinement,
    /// Controllable sets `[lo, hi]` of `x = s'^2` at the grid points (`None` where empty or not
    /// computed: after a failure in rest-to-rest mode, the segments not solved).
    pub controllable: Vec<Option<[f64; 2]>>,
    /// Feasible sets of `x` at the grid points (the `x` for which some `s''` satisfies the rows
    /// of that point).
    pub feasible: Vec<Option<[f64; 2]>>,
}

/// Appends rows with the margin added to the contact rows (the actuator-limit rows are ratios
/// to their limits and take no margin), and their origins.
fn extend_with_margin(
    all: &mut Vec<Row>,
    all_origins: &mut Vec<RowOrigin>,
    rows: &[Row],
    origins: &[RowOrigin],
    margin: f64,
) {
    all_origins.extend_from_slice(origins);
    if margin == 0.0 {
        all.extend_from_slice(rows);
    } else {
        all.extend(rows.iter().zip(origins).map(|(r, o)| Row {
            a: r.a,
            b: r.b,
            c: if *o == RowOrigin::Contact {
                r.c + margin
            } else {
                r.c
            },
        }));
    }
}

/// What a failure means and what to relax, with the constraints found at its grid point.
fn reason(status: &Status, constraints: &[String]) -> String {
    let list = constraints.join(", ");
    let named = |what: &str| {
        if constraints.is_empty() {
            String::new()
        } else {
            format!("; {what}: {list}")
        }
    };
    let limits = constraints.iter().any(|c| {
        c.starts_with("torque") || c.starts_with("velocity") || c.starts_with("acceleration")
    });
    match status {
        Status::FeasibleSetEmpty { .. } => format!(
            "no path speed and acceleration hold there{}{}",
            named("what cannot be met"),
            if limits {
                " (the posture needs more than that whatever the timing: raise those limits in \
                 [limits], or change the posture there: the CoM, the contacts)"
            } else {
                " (the gravito-inertial wrench leaves the GIWC whatever the timing: move the CoM \
                 or the contacts)"
            }
        ),
        Status::ControllableSetEmpty { .. } => format!(
            "from there no admissible speed profile reaches the end of the motion: a later part \
             needs a speed that cannot be reached or kept (or, rest to rest, a segment that is \
             not quasi-statically stable){}{}",
            named("what cannot all hold there"),
            if limits {
                " (raise those limits in [limits], or change the motion there)"
            } else {
                ""
            }
        ),
        Status::StartOutsideControllable { .. } => {
            "the motion cannot start from rest: the initial posture is not statically stable".into()
        }
        Status::ForwardPassFailed { .. } => {
            "the forward pass found no admissible acceleration (round-off)".into()
        }
        Status::Stalled { .. } => "the only admissible speed there is zero on a whole interval \
            (a landing whose link does not come to rest, next to a part that is not statically \
            stable)"
            .into(),
        Status::Optimal => String::new(),
    }
}

/// Names for the failures: the actuated joints' and the segments'.
struct Names<'a> {
    joints: &'a [String],
    segments: &'a [String],
}

/// The global layout: constraints, segment starts on the grid, landing bounds.
struct Layout {
    constraints: CanonicalConstraints,
    origins: Vec<RowOrigin>,
    seg_start: Vec<usize>,
    s_offset: Vec<f64>,
}

/// What a layout is made from besides the rows.
struct LayoutInputs<'a> {
    paths: &'a [SegmentPath],
    margin: f64,
    boundary_x_max: &'a [f64],
}

impl LayoutInputs<'_> {
    fn lay_out(&self, rows: &[SegmentRows]) -> Result<Layout, StanceError> {
        layout(self.paths, rows, self.margin, self.boundary_x_max)
    }
}

/// One solve of `k` (the layout's points from `offset` on), with the separation oracle of the
/// lifted torque rows when some grid point has them; the cuts found are kept in `rows`.
/// Returns the solution, the cuts kept and the oracle's time.
fn solve_with_oracle(
    k: &CanonicalConstraints,
    opts: &SolveOptions,
    ws: &mut Workspace,
    rows: &mut [SegmentRows],
    seg_start: &[usize],
    offset: usize,
) -> Result<(Solution, usize, Duration), StanceError> {
    Ok(match LiftedOracle::new(rows, seg_start) {
        Some(mut oracle) => {
            oracle.offset = offset;
            let sol = ws.solve_separated(k, opts, &mut oracle)?;
            let t = oracle.elapsed;
            (sol, oracle.keep_cuts(), t)
        }
        None => (ws.solve(k, opts)?, 0, Duration::ZERO),
    })
}

/// One solve of the layout (module doc), its outcome located.
struct Solved {
    profile: Option<Profile>,
    failure: Option<RetimeFailure>,
    /// Solve time (the oracle's and the cuts' layout included).
    t: Duration,
    /// The oracle's time.
    t_oracle: Duration,
    /// Cuts found and kept.
    cuts: usize,
}

/// Lays out the segments' rows on the global grid (module doc), with `x` bounded above by
/// `x_max[k]` at the boundary before segment `k` (chained) or zero there (rest to rest): the
/// segments' layouts ([`segment_layout`]) end to end.
fn layout(
    paths: &[SegmentPath],
    rows: &[SegmentRows],
    margin: f64,
    boundary_x_max: &[f64],
) -> Result<Layout, StanceError> {
    let s_offset = s_offsets(paths);
    let pieces = (0..paths.len())
        .map(|k| {
            segment_layout(
                &paths[k],
                &rows[k],
                rows.get(k + 1),
                k,
                s_offset[k],
                margin,
                boundary_x_max,
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    joined(&pieces, s_offset)
}

/// Where each segment starts on the global path parameter, and the end.
fn s_offsets(paths: &[SegmentPath]) -> Vec<f64> {
    let mut s_offset = vec![0.0];
    for path in paths {
        let end = path.samples.last().map_or(0.0, |x| x.s);
        s_offset.push(s_offset[s_offset.len() - 1] + end);
    }
    s_offset
}

/// Segment `k`'s grid points on the global grid, both ends included (a segment's last point is
/// the next one's first), with their rows' origins.
struct SegmentLayout {
    constraints: CanonicalConstraints,
    origins: Vec<RowOrigin>,
}

/// Segment `k`'s grid points as the global layout has them (module doc): each point's rows with
/// the margin; at a switch to the next segment (`next`), the stance before it at the point
/// before (shifted into that interval's state) and the stance after it at the switch point,
/// none of whose rows hold at the end of the interval before, and `x` there bounded by
/// `boundary_x_max[k + 1]`. Its first point, for `k > 0`, is the previous segment's switch
/// point, laid out the same way.
fn segment_layout(
    path: &SegmentPath,
    r: &SegmentRows,
    next: Option<&SegmentRows>,
    k: usize,
    s_offset: f64,
    margin: f64,
    boundary_x_max: &[f64],
) -> Result<SegmentLayout, StanceError> {
    let last = r.grid.len() - 1;
    let mut s = Vec::with_capacity(last + 1);
    let mut offsets = vec![0];
    let mut all = Vec::with_capacity(r.points.rows.len() + 200);
    let mut origins = Vec::with_capacity(all.capacity());
    let mut x_bounds = Vec::with_capacity(last + 1);
    // per point, its rows also imposed at the end of the interval before it (module doc,
    // "Stance switches")
    let mut next_counts = Vec::with_capacity(last + 1);
    // a switch point: the stance after it only, with the next interval's acceleration
    let switch_point = |all: &mut Vec<Row>, origins: &mut Vec<RowOrigin>, after: &SegmentRows| {
        extend_with_margin(all, origins, after.rows_at(0), after.origins_at(0), margin);
    };
    for i in 0..=last {
        let mut bound = [0.0, f64::INFINITY];
        if i == 0 && k > 0 {
            s.push(s_offset);
            switch_point(&mut all, &mut origins, r);
            next_counts.push(0);
            bound[1] = boundary_x_max[k];
        } else if let (true, Some(after)) = (i == last, next) {
            s.push(s_offset + path.samples[r.grid[i]].s);
            switch_point(&mut all, &mut origins, after);
            next_counts.push(0);
            bound[1] = boundary_x_max[k + 1];
        } else {
            s.push(s_offset + path.samples[r.grid[i]].s);
            extend_with_margin(
                &mut all,
                &mut origins,
                r.rows_at(i),
                r.origins_at(i),
                margin,
            );
            next_counts.push(all.len() - offsets[i]);
            if next.is_some() && i + 1 == last {
                // the stance before the switch at the switch sample: with this interval's
                // acceleration only, in this interval's state
                let two_delta = 2.0 * (path.samples[r.grid[last]].s - path.samples[r.grid[i]].s);
                let shifted: Vec<Row> = r
                    .rows_at(last)
                    .iter()
                    .map(|row| Row {
                        a: row.a + two_delta * row.b,
                        b: row.b,
                        c: row.c,
                    })
                    .collect();
                extend_with_margin(&mut all, &mut origins, &shifted, r.origins_at(last), margin);
            }
        }
        x_bounds.push(bound);
        offsets.push(all.len());
    }
    let constraints = CanonicalConstraints::new(s, offsets, all)?
        .with_x_bounds(x_bounds)?
        .with_next_rows(next_counts)?;
    Ok(SegmentLayout {
        constraints,
        origins,
    })
}

/// The global layout from the segments' layouts (each segment's first point but the first
/// segment's is the previous segment's last).
fn joined(pieces: &[SegmentLayout], s_offset: Vec<f64>) -> Result<Layout, StanceError> {
    let total: usize = pieces.iter().map(|p| p.origins.len()).sum();
    let mut s = Vec::new();
    let mut offsets = vec![0];
    let mut all = Vec::with_capacity(total);
    let mut origins = Vec::with_capacity(total);
    let mut x_bounds = Vec::new();
    let mut next_counts = Vec::new();
    let mut seg_start = Vec::with_capacity(pieces.len() + 1);
    for (k, p) in pieces.iter().enumerate() {
        let c = &p.constraints;
        let first = usize::from(k > 0);
        seg_start.push(s.len() - first);
        s.extend_from_slice(&c.grid()[first..]);
        let row0 = c.offsets()[first];
        all.extend_from_slice(&c.rows()[row0..]);
        origins.extend_from_slice(&p.origins[row0..]);
        let base = offsets[offsets.len() - 1] - row0;
        offsets.extend(c.offsets()[first + 1..].iter().map(|o| base + o));
        for i in first..c.num_points() {
            x_bounds.push(c.x_bounds_at(i));
            next_counts.push(c.next_rows_at(i).len());
        }
    }
    seg_start.push(s.len() - 1);
    let constraints = CanonicalConstraints::new(s, offsets, all)?
        .with_x_bounds(x_bounds)?
        .with_next_rows(next_counts)?;
    Ok(Layout {
        constraints,
        origins,
        seg_start,
        s_offset,
    })
}

/// The constraints of segment `k` alone (its boundary points free; the caller sets the speeds).
fn segment_constraints(l: &Layout, k: usize) -> Result<CanonicalConstraints, StanceError> {
    let (a, b) = (l.seg_start[k], l.seg_start[k + 1]);
    let c = &l.constraints;
    let grid = c.grid()[a..=b].to_vec();
    let mut offsets = vec![0];
    let mut rows = Vec::new();
    let mut xb = Vec::new();
    let mut next = Vec::new();
    for i in a..=b {
        rows.extend_from_slice(c.rows_at(i));
        offsets.push(rows.len());
        next.push(c.next_rows_at(i).len());
        xb.push(if i == a || i == b {
            [0.0, f64::INFINITY]
        } else {
            c.x_bounds_at(i)
        });
    }
    Ok(CanonicalConstraints::new(grid, offsets, rows)?
        .with_x_bounds(xb)?
        .with_next_rows(next)?)
}

/// A solve's constraints `k`, whose first grid point is `first` of the global grid and first
/// row `row0` of the layout's, with its controllable sets and end speeds.
struct Located<'a> {
    k: &'a CanonicalConstraints,
    first: usize,
    row0: usize,
    sets: &'a [Option<[f64; 2]>],
    sd_end: [f64; 2],
}

/// The failure `status` of a solve located on the layout: its segment, grid point and the
/// constraints that empty it, and what to relax.
fn locate(
    l: &Layout,
    status: &Status,
    at: Located<'_>,
    opts: &SolveOptions,
    names: &Names<'_>,
) -> RetimeFailure {
    let Located {
        k,
        first,
        row0,
        sets,
        sd_end,
    } = at;
    let nseg = l.seg_start.len() - 1;
    let origins = &l.origins[row0..row0 + k.offsets()[k.num_points()]];
    let (_, constraints) = crate::binding::explain(
        k,
        origins,
        names.joints,
        *status,
        sets,
        sd_end,
        &opts.tol,
        first,
    );
    // the segment and point of the failure itself (the constraints may name a later point)
    let global = first + status.grid_index().unwrap_or(0).min(k.num_points() - 1);
    let seg = (0..nseg)
        .rev()
        .find(|&q| l.seg_start[q] <= global)
        .unwrap_or(0);
    let grid_point = global - l.seg_start[seg];
    let s = l.constraints.grid()[global.min(l.constraints.num_points() - 1)];
    RetimeFailure {
        status: FailureStatus::Solver(*status),
        segment: seg + 1,
        segment_name: names.segments.get(seg).cloned().unwrap_or_default(),
        grid_point,
        s,
        reason: format!(
            "in {}, grid point {grid_point} (s = {s:.3}): {}",
            crate::plan::segment_label(seg, names.segments.get(seg).map_or("", String::as_str)),
            reason(status, &constraints)
        ),
        constraints,
    }
}

/// The profile, or the located failure, of a solve of the whole layout.
fn chained_outcome(
    l: &Layout,
    sol: Solution,
    opts: &SolveOptions,
    names: &Names<'_>,
) -> (Option<Profile>, Option<RetimeFailure>) {
    match (&sol.status, sol.profile) {
        (Status::Optimal, Some(p)) => (Some(p), None),
        (status, _) => {
            let at = Located {
                k: &l.constraints,
                first: 0,
                row0: 0,
                sets: &sol.controllable,
                sd_end: opts.sd_end,
            };
            (None, Some(locate(l, status, at, opts, names)))
        }
    }
}

/// One solve of the layout: the profile or the located failure, and the per-segment solves
/// (rest to rest). The cuts of the lifted torque rows found are kept in `rows` and the layout
/// made again with them (so that the failure's constraints and the binding see them).
#[allow(clippy::too_many_arguments)]
fn solve_layout(
    l: &mut Layout,
    inputs: &LayoutInputs<'_>,
    rows: &mut [SegmentRows],
    mode: RetimingMode,
    opts: &SolveOptions,
    ws: &mut Workspace,
    segments: &mut Vec<SegmentSolve>,
    controllable: &mut Vec<Option<[f64; 2]>>,
    names: &Names<'_>,
) -> Result<Solved, StanceError> {
    segments.clear();
    controllable.clear();
    controllable.resize(l.constraints.num_points(), None);
    match mode {
        RetimingMode::Chained => {
            let t1 = Instant::now();
            let (sol, cuts, t_oracle) =
                solve_with_oracle(&l.constraints, opts, ws, rows, &l.seg_start, 0)?;
            if cuts > 0 {
                rows.iter_mut().for_each(SegmentRows::refresh);
                *l = inputs.lay_out(rows)?;
            }
            let t = t1.elapsed();
            controllable.clone_from(&sol.controllable);
            let (profile, failure) = chained_outcome(l, sol, opts, names);
            Ok(Solved {
                profile,
                failure,
                t,
                t_oracle,
                cuts,
            })
        }
        RetimingMode::RestToRest => {
            let (mut s_all, mut x_all, mut u_all) = (Vec::new(), Vec::new(), Vec::new());
            let mut total = Duration::ZERO;
            let (mut t_oracle, mut cuts) = (Duration::ZERO, 0);
            for k in 0..l.seg_start.len() - 1 {
                let mut kk = segment_constraints(l, k)?;
                let t2 = Instant::now();
                let (sol, n_cuts, t_o) =
                    solve_with_oracle(&kk, opts, ws, rows, &l.seg_start, l.seg_start[k])?;
                if n_cuts > 0 {
                    rows.iter_mut().for_each(SegmentRows::refresh);
                    *l = inputs.lay_out(rows)?;
                    kk = segment_constraints(l, k)?;
                }
                let t = t2.elapsed();
                total += t;
                t_oracle += t_o;
                cuts += n_cuts;
                for (i, c) in sol.controllable.iter().enumerate() {
                    controllable[l.seg_start[k] + i] = *c;
                }
                match (&sol.status, &sol.profile) {
                    (Status::Optimal, Some(p)) => {
                        let skip = usize::from(k > 0);
                        s_all.extend_from_slice(&p.grid()[skip..]);
                        x_all.extend_from_slice(&p.x()[skip..]);
                        u_all.extend_from_slice(p.u());
                        segments.push(SegmentSolve {
                            duration: p.duration(),
                            sd: [0.0, 0.0],
                            t_topp: t,
                            resolve_mismatch: 0.0,
                        });
                    }
                    (status, _) => {
                        let a = l.seg_start[k];
                        let at = Located {
                            k: &kk,
                            first: a,
                            row0: l.constraints.offsets()[a],
                            sets: &sol.controllable,
                            sd_end: [0.0, 0.0],
                        };
                        let f = locate(l, status, at, opts, names);
                        return Ok(Solved {
                            profile: None,
                            failure: Some(f),
                            t: total,
                            t_oracle,
                            cuts,
                        });
                    }
                }
            }
            Ok(Solved {
                profile: Some(Profile::from_states(s_all, x_all, u_all)?),
                failure: None,
                t: total,
                t_oracle,
                cuts,
            })
        }
    }
}

/// The margin of the contact rows (module doc): the plan's, times the robot's weight (N).
fn contact_margin(plan: &MotionPlan) -> f64 {
    let mass = plan.robot.model.total_mass();
    let weight = mass * plan.gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
    plan.spec.planning.margin * weight
}

/// The layout and outcome of a first solve made while the rows were computed (module
/// `overlap`), as [`solve_layout`]'s (the layout made again with the cuts found; its time the
/// solver's own time and that layout's).
fn overlapped_outcome(
    f: overlap::FirstSolve,
    inputs: &LayoutInputs<'_>,
    rows: &mut [SegmentRows],
    opts: &SolveOptions,
    names: &Names<'_>,
) -> Result<(Layout, Solved), StanceError> {
    let t = Instant::now();
    let mut l = f.layout;
    if f.cuts > 0 {
        rows.iter_mut().for_each(SegmentRows::refresh);
        l = inputs.lay_out(rows)?;
    }
    let (profile, failure) = chained_outcome(&l, f.solution, opts, names);
    let first = Solved {
        profile,
        failure,
        t: f.t_solve + t.elapsed(),
        t_oracle: f.t_oracle,
        cuts: f.cuts,
    };
    Ok((l, first))
}

/// Lays out the segments' rows on the global grid, solves, refines the grid where the rows are
/// violated at IK samples between grid points, and measures per-segment solves.
pub fn retime_chained(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    mode: RetimingMode,
    ik_ws: &mut IkStageWorkspace,
) -> Result<(Vec<SegmentRows>, Retimed), StanceError> {
    let nseg = paths.len();
    let margin = contact_margin(plan);
    let (boundary_x_max, landings) = boundary_bounds(plan, paths, mode, ik_ws)?;
    let opts = SolveOptions::new(plan.spec.retiming.discretization);
    let segment_names: Vec<String> = plan.segments.iter().map(|s| s.name.clone()).collect();
    let joints = &Names {
        joints: plan.limits.as_ref().map_or(&[], |lp| &lp.names),
        segments: &segment_names,
    };
    let mut ws = Workspace::new();
    let mut segments = Vec::with_capacity(nseg);
    let mut refine = Refinement::default();
    let inputs = LayoutInputs {
        paths,
        margin,
        boundary_x_max: &boundary_x_max,
    };
    let mut controllable = Vec::new();
    let over = overlap::Inputs {
        plan,
        layout: &inputs,
        opts: &opts,
    };
    let t_rows = Instant::now();
    let (mut rows_owned, overlapped) = match (mode, &plan.limits) {
        (RetimingMode::Chained, Some(_)) => overlap::rows_and_first_solve(&over, &mut ws)?,
        _ => (overlap::all_segment_rows(&over)?, None),
    };
    let rows = &mut rows_owned[..];
    let (mut l, first, mut t_assemble) = match overlapped {
        Some(f) => {
            controllable.clone_from(&f.solution.controllable);
            let t_layout = f.t_layout;
            let (l, first) = overlapped_outcome(f, &inputs, rows, &opts, joints)?;
            (l, first, t_layout)
        }
        None => {
            let t_layout = Instant::now();
            let mut l = inputs.lay_out(rows)?;
            let t_assemble = t_layout.elapsed();
            let first = solve_layout(
                &mut l,
                &inputs,
                rows,
                mode,
                &opts,
                &mut ws,
                &mut segments,
                &mut controllable,
                joints,
            )?;
            (l, first, t_assemble)
        }
    };
    let t_rows_first = t_rows.elapsed();
    let (t_first, t_lifted, cuts) = (first.t, first.t_oracle, first.cuts);
    let (mut profile, mut failure, mut t_topp) = (first.profile, first.failure, first.t);
    // The refinement: IK samples where the rows do not hold (with half the margin), or whose
    // lifted torque rows admit no contact forces, become grid points.
    let t_refine = Instant::now();
    let mut sample_rows_ready = false;
    let mut midpoints = crate::midpoints::Midpoints::default();
    while let Some(p) = &profile {
        if refine.rounds >= crate::tol::MAX_REFINE_ROUNDS {
            break;
        }
        if !sample_rows_ready {
            use rayon::prelude::*;
            rows.par_iter_mut()
                .zip(paths.par_iter())
                .try_for_each(|(r, path)| r.ensure_sample_rows(plan, path))?;
            sample_rows_ready = true;
        }
        let values = sample_row_values(paths, rows, &l.s_offset, p);
        let added = add_failing_samples(plan, paths, rows, &l.s_offset, p, margin, &values)?
            + crate::midpoints::add_failing_midpoints(
                plan,
                paths,
                rows,
                &l.s_offset,
                p,
                margin,
                &values,
                &mut midpoints,
            )?;
        if added == 0 {
            break;
        }
        refine.rounds += 1;
        refine.points_added += added;
        let t_lay = Instant::now();
        l = inputs.lay_out(rows)?;
        t_assemble = t_lay.elapsed();
        let again = solve_layout(
            &mut l,
            &inputs,
            rows,
            mode,
            &opts,
            &mut ws,
            &mut segments,
            &mut controllable,
            joints,
        )?;
        (profile, failure, t_topp) = (again.profile, again.failure, again.t);
    }
    refine.elapsed = t_refine.elapsed();
    // per-segment re-solves of a chained profile, for their T_TOPP
    if let (RetimingMode::Chained, Some(p)) = (mode, &profile) {
        resolve_segments(&l, rows, p, &opts, &mut ws, &mut segments)?;
    }
    let feasible = (0..l.constraints.num_points())
        .map(|i| crate::retime::feasible_set(&l.constraints, i, &opts.tol))
        .collect();
    let retimed = Retimed {
        mode,
        constraints: l.constraints,
        origins: l.origins,
        seg_start: l.seg_start,
        s_offset: l.s_offset,
        profile,
        failure,
        segments,
        landings,
        t_topp,
        t_assemble,
        t_first,
        t_rows_first,
        t_lifted,
        cuts,
        refinement: refine,
        controllable,
        feasible,
    };
    Ok((rows_owned, retimed))
}

/// Speed bounds at the segment boundaries, as `x = s'^2` before each segment (infinite before
/// the first): zero in rest-to-rest mode; chained, the landings' bounds (module doc, "No
/// impacts"): a contact of segment `k` that segment `k - 1` does not have lands at the end of
/// `k - 1`, where its frame moves at `(v, w) = J q_s` per unit path, so
/// `x <= min((v_max / |v|)^2, (w_max / |w|)^2)`. Returns the bounds and the landings.
fn boundary_bounds(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    mode: RetimingMode,
    ik_ws: &mut IkStageWorkspace,
) -> Result<(Vec<f64>, Vec<LandingBound>), StanceError> {
    let nseg = paths.len();
    let mut boundary_x_max = vec![f64::INFINITY; nseg];
    let mut landings = Vec::new();
    for k in 1..nseg {
        if mode == RetimingMode::RestToRest {
            boundary_x_max[k] = 0.0;
            continue;
        }
        let end = &paths[k - 1].samples[paths[k - 1].samples.len() - 1];
        for c in &paths[k].contacts {
            if plan.segments[k - 1]
                .stance
                .iter()
                .any(|&(x, _)| x == c.surface)
            {
                continue;
            }
            let frame = plan.robot.surfaces[c.surface].frame;
            let (v, w) = frame_path_velocity(plan, ik_ws, &end.q, &end.q_s, frame)?;
            let mut x_max = f64::INFINITY;
            if v.norm() > 0.0 {
                x_max = x_max.min((crate::tol::LANDING_SPEED / v.norm()).powi(2));
            }
            if w.norm() > 0.0 {
                x_max = x_max.min((crate::tol::LANDING_ANGULAR_SPEED / w.norm()).powi(2));
            }
            boundary_x_max[k] = boundary_x_max[k].min(x_max);
            landings.push(LandingBound {
                segment: k + 1,
                segment_name: plan.segments[k].name.clone(),
                surface: plan.robot.surfaces[c.surface].name.clone(),
                path_speed: v.norm(),
                path_angular_speed: w.norm(),
                max_sd: x_max.is_finite().then(|| x_max.sqrt()),
            });
        }
    }
    Ok((boundary_x_max, landings))
}

/// One round of the refinement's grid update: the IK samples off the grid where a contact row
/// exceeds `-margin / 2` or a limit row exceeds zero under the profile `p`
/// ([`sample_row_values`]), or whose lifted torque rows admit no contact forces
/// ([`lifted_samples_failing`]), join their segment's grid. Returns how many were added.
fn add_failing_samples(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    rows: &mut [SegmentRows],
    s_offset: &[f64],
    p: &Profile,
    margin: f64,
    values: &[Vec<SampleValues>],
) -> Result<usize, StanceError> {
    let lifted_bad = lifted_samples_failing(plan, paths, rows, s_offset, p)?;
    let mut added = 0;
    for k in 0..paths.len() {
        let mut bad: Vec<usize> = values[k]
            .iter()
            .enumerate()
            .filter(|&(j, v)| {
                (v.contact > -0.5 * margin || v.limit > 0.0)
                    && rows[k].grid.binary_search(&j).is_err()
            })
            .map(|(j, _)| j)
            .collect();
        bad.extend(lifted_bad[k].iter().copied());
        bad.sort_unstable();
        bad.dedup();
        if bad.is_empty() {
            continue;
        }
        added += bad.len();
        let mut grid = rows[k].grid.clone();
        grid.extend(bad);
        grid.sort_unstable();
        rows[k].set_grid(grid);
    }
    Ok(added)
}

/// The per-segment re-solves of a chained profile `p` (module doc): each segment alone with
/// the profile's speeds at its ends, timed for its `T_TOPP`, with the relative difference of
/// its duration from the profile's on that segment; appended to `segments`.
fn resolve_segments(
    l: &Layout,
    rows: &mut [SegmentRows],
    p: &Profile,
    opts: &SolveOptions,
    ws: &mut Workspace,
    segments: &mut Vec<SegmentSolve>,
) -> Result<(), StanceError> {
    let sd = p.sd();
    for k in 0..l.seg_start.len() - 1 {
        let (a, b) = (l.seg_start[k], l.seg_start[k + 1]);
        let duration = p.times()[b] - p.times()[a];
        let kk = segment_constraints(l, k)?;
        let o = opts.with_start(sd[a]).with_end(sd[b]);
        let t2 = Instant::now();
        // (cuts found here are valid but not kept: the motion's profile is solved)
        let again = match LiftedOracle::new(rows, &l.seg_start) {
            Some(mut oracle) => {
                oracle.offset = a;
                ws.solve_separated(&kk, &o, &mut oracle)?
            }
            None => ws.solve(&kk, &o)?,
        };
        let t = t2.elapsed();
        let d = again.duration().unwrap_or(f64::INFINITY);
        segments.push(SegmentSolve {
            duration,
            sd: [sd[a], sd[b]],
            t_topp: t,
            resolve_mismatch: (d - duration).abs() / duration.max(f64::MIN_POSITIVE),
        });
    }
    Ok(())
}

/// What the refinement between grid points did.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct Refinement {
    /// Rounds of refine-and-solve.
    pub rounds: usize,
    /// IK samples added to the grid.
    pub points_added: usize,
    /// Wall time of the rounds.
    #[serde(skip)]
    pub elapsed: Duration,
}

/// The largest row values at an IK sample under the profile, over its two limits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleValues {
    /// Of the contact rows (N, no margin).
    pub contact: f64,
    /// Of the actuator-limit rows (ratio to the limit minus one; `-inf` without limits).
    pub limit: f64,
}

/// The largest row values at every IK sample of every segment under the profile, over its two
/// limits (module doc of [`super::checks`]).
pub fn sample_row_values(
    paths: &[SegmentPath],
    rows: &[SegmentRows],
    s_offset: &[f64],
    profile: &Profile,
) -> Vec<Vec<SampleValues>> {
    let grid = profile.grid();
    let (x, u) = (profile.x(), profile.u());
    let interval = |s: f64, left: bool| {
        // the grid interval traversed just after (right limit) or just before (left limit) s
        let p = if left {
            grid.partition_point(|&g| g < s)
        } else {
            grid.partition_point(|&g| g <= s)
        };
        p.saturating_sub(1).min(u.len() - 1)
    };
    use rayon::prelude::*;
    paths
        .par_iter()
        .enumerate()
        .map(|(k, path)| {
            let n = path.samples.len();
            path.samples
                .iter()
                .enumerate()
                .map(|(j, smp)| {
                    let s = s_offset[k] + smp.s;
                    let mut worst = SampleValues {
                        contact: f64::NEG_INFINITY,
                        limit: f64::NEG_INFINITY,
                    };
                    for left in [false, true] {
                        if (!left && j + 1 == n) || (left && j == 0) {
                            continue;
                        }
                        let i = interval(s, left);
                        let ui = u[i];
                        let xs = (x[i] + 2.0 * ui * (s - grid[i])).max(0.0);
                        let (r, o) = rows[k].sample_rows(j, left);
                        for (r, o) in r.iter().zip(o) {
                            let v = r.a * ui + r.b * xs + r.c;
                            if *o == RowOrigin::Contact {
                                worst.contact = worst.contact.max(v);
                            } else {
                                worst.limit = worst.limit.max(v);
                            }
                        }
                    }
                    worst
                })
                .collect()
        })
        .collect()
}

/// The profile's state `(u, x)` leaving (`left = false`) or arriving at (`left = true`) the
/// global path parameter `s`.
pub fn state_at(profile: &Profile, s: f64, left: bool) -> (f64, f64) {
    let grid = profile.grid();
    let (x, u) = (profile.x(), profile.u());
    let p = if left {
        grid.partition_point(|&g| g < s)
    } else {
        grid.partition_point(|&g| g <= s)
    };
    let i = p.saturating_sub(1).min(u.len() - 1);
    (u[i], (x[i] + 2.0 * u[i] * (s - grid[i])).max(0.0))
}

/// The IK samples off the grid whose lifted torque rows (module doc of [`super::rows`]) admit
/// no contact forces at the profile's state there (each side at its own interval's state),
/// per segment.
fn lifted_samples_failing(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    rows: &mut [SegmentRows],
    s_offset: &[f64],
    profile: &Profile,
) -> Result<Vec<Vec<usize>>, StanceError> {
    use rayon::prelude::*;
    if plan.limits.as_ref().is_none_or(|lp| !lp.any_torque()) {
        return Ok(vec![Vec::new(); rows.len()]);
    }
    rows.par_iter_mut()
        .zip(paths.par_iter())
        .enumerate()
        .map(|(k, (r, path))| -> Result<Vec<usize>, StanceError> {
            let mut member = Membership::new();
            let last = path.samples.len() - 1;
            let mut bad = Vec::new();
            for j in 0..=last {
                if r.grid.binary_search(&j).is_ok() || r.sides[j].is_none() {
                    continue;
                }
                let s = s_offset[k] + path.samples[j].s;
                for left in [false, true] {
                    if (left && j == 0) || (!left && j == last) {
                        continue;
                    }
                    let (u, x) = state_at(profile, s, left);
                    if !r.lifted_holds(j, left, u, x, &mut member)? {
                        bad.push(j);
                        break;
                    }
                }
            }
            Ok(bad)
        })
        .collect()
}

#[cfg(test)]
mod doc_examples {
    //! The examples that were in the docs of this private module.

    #[test]
    fn name_example() {
        use crate::chain::FailureStatus;
        use stance_topp::Status;
        assert_eq!(FailureStatus::IkFailed.name(), "ik_failed");
        assert_eq!(
            FailureStatus::Solver(Status::Stalled { index: 2 }),
            "stalled"
        );
    }
}
