//! Backward controllable sets and the greedy forward pass.

use super::options::{Discretization, Solution, SolveOptions, SolveStats, Status};
use super::separation::{Cuts, OnUnitGrid, Separation};
use crate::constraints::CanonicalConstraints;
use crate::constraints::Row;
use crate::error::ToppError;
use crate::lp2::{self, Box2, Lp2, Lp2Stats, StageLines};
use crate::profile::Profile;
use crate::tol::Tolerances;
use crate::tol::MAX_CUTS_PER_LP;

/// Reusable state of the solver. The passes read the rows in place (a stage is a view of the
/// rows of one or two grid points, see [`lp2::StageLines`]) and allocate nothing but the
/// returned [`Solution`]; the workspace keeps the warm-start memory between stages.
#[derive(Debug, Default, Clone)]
pub struct Workspace {
    _private: (),
}

/// Number of leading rows of a stage: `x + 2 Delta u <= hi` and `x + 2 Delta u >= lo`.
const K_LINES: usize = 2;

impl Workspace {
    /// [`solve`] with this reusable workspace.
    ///
    /// ```
    /// use stance_topp::{CanonicalConstraints, Row, SolveOptions, Workspace};
    /// let rows = vec![Row { a: 1.0, b: 0.0, c: -1.0 }, Row { a: -1.0, b: 0.0, c: -1.0 }];
    /// let s: Vec<f64> = (0..=10).map(|i| i as f64 / 10.0).collect();
    /// let offsets: Vec<usize> = (0..=11).map(|i| 2 * i).collect();
    /// let k = CanonicalConstraints::new(s, offsets, rows.repeat(11)).unwrap();
    /// let mut ws = Workspace::new();
    /// let d1 = ws.solve(&k, &SolveOptions::default()).unwrap().duration().unwrap();
    /// let d2 = ws.solve(&k, &SolveOptions::default()).unwrap().duration().unwrap();
    /// assert_eq!(d1, d2);
    /// ```
    pub fn solve(
        &mut self,
        k: &CanonicalConstraints,
        opts: &SolveOptions,
    ) -> Result<Solution, ToppError> {
        solve_in(k, opts, None)
    }

    /// [`Workspace::solve`] with grid points that have constraints beyond their rows, given by
    /// a separation oracle ([`super::separation`]): every LP's optimum is checked by it and
    /// cut off while it is not admissible, so that the profile is that of the exact sets. The
    /// cuts found are in [`Solution::cuts`].
    ///
    /// # Errors
    ///
    /// As [`Workspace::solve`], and the oracle's errors; [`ToppError::InvalidValue`] when one
    /// LP takes more than 64 cuts (an oracle whose cuts do not converge).
    ///
    /// ```
    /// use stance_topp::{CanonicalConstraints, Cut, Row, Separation, SolveOptions, ToppError,
    ///     Workspace};
    /// // |u| <= 1, and an oracle that also wants u <= 0.5 at every point
    /// struct Half;
    /// impl Separation for Half {
    ///     fn separate(&mut self, _: usize, u: f64, _: f64) -> Result<Option<Cut>, ToppError> {
    ///         Ok((u > 0.5 + 1e-12).then_some(Cut { row: Row { a: 1.0, b: 0.0, c: -0.5 }, tag: 7 }))
    ///     }
    /// }
    /// let rows = vec![Row { a: 1.0, b: 0.0, c: -1.0 }, Row { a: -1.0, b: 0.0, c: -1.0 }];
    /// let s: Vec<f64> = (0..=50).map(|i| i as f64 / 50.0).collect();
    /// let offsets: Vec<usize> = (0..=51).map(|i| 2 * i).collect();
    /// let k = CanonicalConstraints::new(s, offsets, rows.repeat(51)).unwrap();
    /// let sol = Workspace::new().solve_separated(&k, &SolveOptions::default(), &mut Half).unwrap();
    /// // accelerate at 0.5 over [0, 2/3] (to s' = sqrt(2/3), in 2 sqrt(2/3)), brake at 1 over
    /// // [2/3, 1] (in sqrt(2/3)): duration 3 sqrt(2/3) = sqrt(6)
    /// assert!((sol.duration().unwrap() - 6f64.sqrt()).abs() < 0.02, "{:?}", sol.duration());
    /// assert!(sol.cuts.len() > 0 && sol.cuts.tags.iter().flatten().all(|&t| t == 7));
    /// ```
    pub fn solve_separated(
        &mut self,
        k: &CanonicalConstraints,
        opts: &SolveOptions,
        sep: &mut dyn Separation,
    ) -> Result<Solution, ToppError> {
        solve_in(k, opts, Some(sep))
    }

    /// An empty workspace.
    ///
    /// ```
    /// let ws = stance_topp::Workspace::new();
    /// # let _ = ws;
    /// ```
    pub fn new() -> Self {
        Self::default()
    }
}

/// The rows of stage `i` (`k_next = Some(K_{i+1})`) or of the end point alone
/// (`k_next = None`), and the bounding box.
#[allow(clippy::too_many_arguments)]
fn assemble<'a>(
    k: &'a CanonicalConstraints,
    disc: Discretization,
    i: usize,
    k_next: Option<[f64; 2]>,
    with_interp: bool,
    tol: &Tolerances,
    cuts: &'a Cuts,
) -> (StageLines<'a>, Box2) {
    let s = k.grid();
    let mut lines = StageLines {
        head: [Row::default(); 2],
        n_head: 0,
        here: k.rows_at(i),
        here_cuts: cuts.at(i),
        next: &[],
        next_cuts: &[],
        two_delta: 0.0,
    };
    if let Some([lo, hi]) = k_next {
        let two_delta = 2.0 * (s[i + 1] - s[i]);
        let cap = tol.max_x + two_delta * tol.max_u;
        lines.two_delta = two_delta;
        lines.head = [
            Row {
                a: two_delta,
                b: 1.0,
                c: -hi.min(cap),
            },
            Row {
                a: -two_delta,
                b: -1.0,
                c: lo,
            },
        ];
        lines.n_head = K_LINES;
        if with_interp && disc == Discretization::Interpolation {
            lines.next = k.next_rows_at(i + 1);
            lines.next_cuts = cuts.next_at(i + 1);
        }
    }
    let [xl, xh] = k.x_bounds_at(i);
    let [ul, uh] = k.u_bounds_at(i);
    (
        lines,
        Box2 {
            u_lo: ul.max(-tol.max_u),
            u_hi: uh.min(tol.max_u),
            x_lo: xl.max(0.0),
            x_hi: xh.min(tol.max_x),
        },
    )
}

/// Retimes the path: backward controllable sets, then the greedy forward pass.
///
/// ```
/// use stance_topp::{solve, CanonicalConstraints, Discretization, Row, SolveOptions, Status};
/// // x <= 1 (speed limit 1) and |u| <= 1 on s in [0, 4], rest to rest:
/// // accelerate over s in [0, 0.5], cruise, brake over [3.5, 4]: duration 1 + 3 + 1 = 5.
/// let rows = vec![
///     Row { a: 0.0, b: 1.0, c: -1.0 },
///     Row { a: 1.0, b: 0.0, c: -1.0 },
///     Row { a: -1.0, b: 0.0, c: -1.0 },
/// ];
/// let s: Vec<f64> = (0..=400).map(|i| i as f64 / 100.0).collect();
/// let offsets: Vec<usize> = (0..=401).map(|i| 3 * i).collect();
/// let k = CanonicalConstraints::new(s, offsets, rows.repeat(401)).unwrap();
/// let sol = solve(&k, &SolveOptions::new(Discretization::Interpolation)).unwrap();
/// assert_eq!(sol.status, Status::Optimal);
/// assert!((sol.duration().unwrap() - 5.0).abs() < 1e-9);
/// ```
pub fn solve(k: &CanonicalConstraints, opts: &SolveOptions) -> Result<Solution, ToppError> {
    Workspace::new().solve(k, opts)
}

/// The body of [`Workspace::solve`] and [`Workspace::solve_separated`].
fn solve_in(
    k: &CanonicalConstraints,
    opts: &SolveOptions,
    sep: Option<&mut dyn Separation>,
) -> Result<Solution, ToppError> {
    opts.validate()?;
    // Solved on s~ = (s - s_0) / L (L a power of two, s~_N in (0.5, 1]) when the grid is far
    // from unit range or origin: the answer does not depend on the unit or the origin of the
    // path parameter.
    let Some((k_unit, l)) = k.on_unit_grid()? else {
        return solve_timed(k, opts, sep);
    };
    let unit_opts = SolveOptions {
        sd_start: opts.sd_start / l,
        sd_end: [opts.sd_end[0] / l, opts.sd_end[1] / l],
        ..*opts
    };
    let sol = match sep {
        Some(inner) => solve_timed(
            &k_unit,
            &unit_opts,
            Some(&mut OnUnitGrid { inner, l } as &mut dyn Separation),
        )?,
        None => solve_timed(&k_unit, &unit_opts, None)?,
    };
    Ok(from_unit_grid(sol, k.grid(), l))
}

/// A solution found on the unit grid `s~ = (s - s_0) / L` back on the caller's `grid`: states
/// times `L^2`, controls times `L`, the cuts `(a / L, b / L^2, c)` scaled into the window.
pub(super) fn from_unit_grid(sol: Solution, grid: &[f64], l: f64) -> Solution {
    let l2 = l * l;
    mapped_back(sol, grid, l2, l, |r| {
        *r = Row {
            a: r.a / l,
            b: r.b / l2,
            c: r.c,
        };
    })
}

/// A solution found in other units, back in the caller's: states (profile, controllable sets,
/// the start status) times `x_scale`, controls times `u_scale`, the profile on `grid`, and each
/// cut row mapped by `row` then brought into the window.
fn mapped_back(
    sol: Solution,
    grid: &[f64],
    x_scale: f64,
    u_scale: f64,
    row: impl Fn(&mut Row),
) -> Solution {
    let status = match sol.status {
        Status::StartOutsideControllable { x_start, lo, hi } => Status::StartOutsideControllable {
            x_start: x_start * x_scale,
            lo: lo * x_scale,
            hi: hi * x_scale,
        },
        other => other,
    };
    let profile = sol.profile.map(|p| {
        let x = p.x().iter().map(|x| x * x_scale).collect();
        let u = p.u().iter().map(|u| u * u_scale).collect();
        Profile::from_valid_states(grid.to_vec(), x, u)
    });
    let mut cuts = sol.cuts;
    for r in cuts
        .rows
        .iter_mut()
        .flatten()
        .chain(cuts.next_rows.iter_mut().flatten())
    {
        row(r);
        crate::constraints::into_window(r);
    }
    Solution {
        status,
        controllable: sol
            .controllable
            .iter()
            .map(|c| c.map(|[lo, hi]| [lo * x_scale, hi * x_scale]))
            .collect(),
        profile,
        cuts,
        ..sol
    }
}

/// [`solve_unit`] in the rows' own time unit `T = 4^m`
/// ([`CanonicalConstraints::on_unit_time`]) when it is far from 1, so that the tolerances and
/// the box, relative to `max(1, |(u, x)|)`, are relative to the problem's own speeds: a path
/// crossed in days and one crossed in microseconds get the same decisions. States map back with
/// `T`, speeds with `2^m` (exact). With a separation oracle (the lifted rows of contact
/// stability, whose cuts are in the caller's units) the problem is solved as it is.
fn solve_timed(
    k: &CanonicalConstraints,
    opts: &SolveOptions,
    sep: Option<&mut dyn Separation>,
) -> Result<Solution, ToppError> {
    if sep.is_some() {
        return solve_unit(k, opts, sep);
    }
    let Some((k_time, m)) = k.on_unit_time() else {
        return solve_unit(k, opts, None);
    };
    let (r, t) = (
        crate::constraints::ldexp(1.0, m),
        crate::constraints::ldexp(1.0, 2 * m),
    );
    let time_opts = SolveOptions {
        sd_start: opts.sd_start / r,
        sd_end: [opts.sd_end[0] / r, opts.sd_end[1] / r],
        ..*opts
    };
    let sol = solve_unit(&k_time, &time_opts, None)?;
    // a u~ + b x~ + c <= 0 with u~ = u / T, x~ = x / T: the cut (a, b, c T)
    Ok(mapped_back(sol, k.grid(), t, t, |r| {
        r.c = crate::constraints::ldexp(r.c, 2 * m);
    }))
}

/// [`Workspace::solve`] on a grid the solver works on as it is (`s_0 = 0`, `s_N` in `(0.5, 1]`).
fn solve_unit(
    k: &CanonicalConstraints,
    opts: &SolveOptions,
    mut sep: Option<&mut dyn Separation>,
) -> Result<Solution, ToppError> {
    let n = k.num_points();
    let mut pass = Backward {
        controllable: vec![None; n],
        // (no storage without an oracle: `Cuts::at` is empty past the end)
        cuts: if sep.is_some() {
            Cuts::new(n)
        } else {
            Cuts::default()
        },
        stats: SolveStats::default(),
        hit_box: false,
    };
    let end = [opts.sd_end[0].powi(2), opts.sd_end[1].powi(2)];
    match backward_pass(k, opts, PassEnd::Speeds(end), &mut pass, &mut sep)? {
        Ok(_) => forward_pass(k, opts, pass, sep),
        Err(i_fail) => Ok(pass.failed(k, opts, i_fail)),
    }
}

/// What a backward pass fills: the controllable sets, the cuts, the work counters.
#[derive(Debug, Clone)]
pub(super) struct Backward {
    pub controllable: Vec<Option<[f64; 2]>>,
    pub cuts: Cuts,
    pub stats: SolveStats,
    pub hit_box: bool,
}

impl Backward {
    /// The solution of a backward pass that failed at `i_fail` (diagnosed).
    pub fn failed(
        mut self,
        k: &CanonicalConstraints,
        opts: &SolveOptions,
        i_fail: usize,
    ) -> Solution {
        let disc = opts.discretization;
        let status = diagnose(k, disc, &opts.tol, i_fail, &mut self.stats, &self.cuts);
        Solution {
            status,
            discretization: disc,
            controllable: self.controllable,
            profile: None,
            hit_box: self.hit_box,
            stats: self.stats,
            cuts: self.cuts,
        }
    }
}

/// The greedy forward pass from the backward pass's sets and cuts (module doc).
pub(super) fn forward_pass(
    k: &CanonicalConstraints,
    opts: &SolveOptions,
    pass: Backward,
    mut sep: Option<&mut dyn Separation>,
) -> Result<Solution, ToppError> {
    let tol = opts.tol;
    let disc = opts.discretization;
    let n = k.num_points();
    let Backward {
        controllable,
        mut cuts,
        mut stats,
        hit_box,
    } = pass;
    let x_start = opts.sd_start * opts.sd_start;
    let [lo0, hi0] = controllable[0].expect("backward pass succeeded");
    if x_start < lo0 - tol.state * lo0.max(1.0) || x_start > hi0 + tol.state * hi0.max(1.0) {
        return Ok(Solution {
            status: Status::StartOutsideControllable {
                x_start,
                lo: lo0,
                hi: hi0,
            },
            discretization: disc,
            controllable,
            profile: None,
            hit_box,
            stats,
            cuts,
        });
    }
    let s = k.grid();
    let mut x = vec![0.0; n];
    let mut u = vec![0.0; n - 1];
    x[0] = x_start.clamp(lo0, hi0);
    let mut fwd_active = None;
    let mut failed = None;
    for i in 0..n - 1 {
        let [lo1, hi1] = controllable[i + 1].expect("backward pass succeeded");
        let two_delta = 2.0 * (s[i + 1] - s[i]);
        let xi = x[i];
        let mut rounds = 0;
        let u_hi = loop {
            let (lines, bbox) = assemble(k, disc, i, Some([lo1, hi1]), true, &tol, &cuts);
            let Some((u_hi, act)) = forward_step(&lines, bbox, xi, fwd_active, &tol) else {
                break None;
            };
            if opts.warm_start {
                fwd_active = act;
            }
            let Some(sep) = sep.as_deref_mut() else {
                break Some(u_hi);
            };
            // the step's state at its grid point, and with interpolation the next point's
            let x_next = xi + two_delta * u_hi;
            let mut cut = sep.separate(i, u_hi, xi)?.map(|c| (i, c, false));
            if cut.is_none() && disc == Discretization::Interpolation {
                cut = sep
                    .separate_next(i + 1, u_hi, x_next)?
                    .map(|c| (i + 1, c, true));
            }
            let Some((p, c, next)) = cut else {
                break Some(u_hi);
            };
            cuts.push(p, c, next);
            stats.cuts += 1;
            rounds += 1;
            if rounds > MAX_CUTS_PER_LP {
                return Err(too_many_cuts(i));
            }
        };
        let Some(u_hi) = u_hi else {
            failed = Some(i);
            break;
        };
        let x_next = (xi + two_delta * u_hi).clamp(lo1, hi1).max(0.0);
        u[i] = (x_next - xi) / two_delta;
        x[i + 1] = x_next;
    }
    if let Some(index) = failed {
        return Ok(Solution {
            status: Status::ForwardPassFailed { index },
            discretization: disc,
            controllable,
            profile: None,
            hit_box,
            stats,
            cuts,
        });
    }
    let profile = Profile::from_valid_states(s.to_vec(), x, u);
    let status = match profile.first_stall() {
        Some(index) => Status::Stalled { index },
        None => Status::Optimal,
    };
    Ok(Solution {
        status,
        discretization: disc,
        controllable,
        profile: Some(profile),
        hit_box,
        stats,
        cuts,
    })
}

fn too_many_cuts(i: usize) -> ToppError {
    ToppError::InvalidValue {
        what: "separation oracle",
        detail: format!(
            "its cuts did not converge at grid point {i} ({MAX_CUTS_PER_LP} cuts on one LP); \
             report this input"
        ),
    }
}

/// One greedy step: the largest `u` with `(u, x_i)` admissible at the stage (its rows include
/// `x_i + 2 Delta u <= hi_{i+1}`), by a 1-D version of the incremental algorithm: start from the
/// box, lower `u` onto every row it violates (the previous step's limiting row first, so that
/// usually one screening pass over the rows suffices), then check that the rows bounding `u`
/// from below (and the rows on `x` alone) still hold, within `tol.state`. Returns `u` and the
/// limiting row, or `None` when no `u` is admissible.
fn forward_step(
    lines: &StageLines<'_>,
    bbox: Box2,
    xi: f64,
    warm: Option<usize>,
    tol: &Tolerances,
) -> Option<(f64, Option<usize>)> {
    let feas2 = tol.feasibility * tol.feasibility;
    let par2 = tol.parallel * tol.parallel;
    let mut u = bbox.u_hi;
    let mut active = None;
    let mut changed = false;
    // Lowers u onto row r (global index j) if it bounds u from above; else reports whether the
    // violation is within tol.state.
    let fix = |r: Row, j: usize, u: &mut f64, active: &mut Option<usize>, changed: &mut bool| {
        let nn = r.a * r.a + r.b * r.b;
        let val = r.a * *u + r.b * xi + r.c;
        if r.a > 0.0 && r.a * r.a > par2 * nn {
            *u = -(r.b * xi + r.c) / r.a;
            *active = Some(j);
            *changed = true;
            true
        } else {
            let scale2 = (*u * *u + xi * xi).max(1.0);
            val * val <= tol.state * tol.state * scale2 * nn
        }
    };
    if let Some(j) = warm.filter(|&j| j < lines.len()) {
        let r = lines.get(j);
        if r.a * u + r.b * xi + r.c > 0.0 && !fix(r, j, &mut u, &mut active, &mut changed) {
            return None;
        }
    }
    for _pass in 0..2 {
        changed = false;
        for (rows, td, base) in lines.segments() {
            let mut from = 0;
            while let Some(q) = lp2::first_violated(rows, from, td, u, xi, feas2) {
                let r = lines.get(base + q);
                if !fix(r, base + q, &mut u, &mut active, &mut changed) {
                    return None;
                }
                from = q + 1;
            }
        }
        // Lowering u can only break rows that bound it from below, scanned earlier: one more
        // pass checks them (it lowers u again only by round-off).
        if !changed {
            break;
        }
    }
    if u < bbox.u_lo - tol.state * bbox.u_lo.abs().max(1.0) {
        return None;
    }
    Some((u, active))
}

fn add_stats(stats: &mut SolveStats, s: &Lp2Stats) {
    stats.lps += 1;
    stats.moves += s.moves;
    stats.inner_steps += s.inner_steps;
}

/// Where a backward pass starts at the grid's last point.
#[derive(Debug, Clone, Copy)]
pub(super) enum PassEnd {
    /// The end interval of `x` (squared end speeds): `K_N` is its part feasible at `s_N`.
    Speeds([f64; 2]),
    /// `K_N` itself, as the pass over the grid after this one found it, with the lines active
    /// at its two optima there (the warm start of the stage before): the pass resumes as if it
    /// had run over both grids at once (module `pieces`).
    Given([f64; 2], Actives),
}

/// Fills `pass.controllable` from `end`; `Ok(Err(i))` when `K_i` is empty (or grid point `i`
/// has a violated constant row), else `Ok(Ok(actives))`, the lines active at the first stage's
/// optima. With a separation oracle, each stage's optima are cut off until it accepts them
/// (module [`super::separation`]).
pub(super) fn backward_pass(
    k: &CanonicalConstraints,
    opts: &SolveOptions,
    end: PassEnd,
    pass: &mut Backward,
    sep: &mut Option<&mut dyn Separation>,
) -> Result<Result<Actives, usize>, ToppError> {
    let (disc, tol, warm) = (opts.discretization, &opts.tol, opts.warm_start);
    let Backward {
        controllable,
        cuts,
        stats,
        hit_box,
    } = pass;
    let n = k.num_points();
    let s = k.grid();
    let mut active = [None, None];
    match end {
        PassEnd::Given(set, act) => {
            controllable[n - 1] = Some(set);
            active = act;
        }
        PassEnd::Speeds(end) => match end_set(k, disc, end, tol, stats, hit_box, sep, cuts)? {
            Some(kn) => controllable[n - 1] = Some(kn),
            None => return Ok(Err(n - 1)),
        },
    }
    for i in (0..n - 1).rev() {
        let k_next = controllable[i + 1].expect("set above");
        let two_delta = 2.0 * (s[i + 1] - s[i]);
        let mut rounds = 0;
        loop {
            let (lines, bbox) = assemble(k, disc, i, Some(k_next), true, tol, cuts);
            let warm_idx = if warm { active } else { [None, None] };
            let Some((set, act, optima)) = x_range(&lines, bbox, tol, warm_idx, stats, hit_box)
            else {
                return Ok(Err(i));
            };
            let Some(sep) = sep.as_deref_mut() else {
                controllable[i] = Some(set);
                active = act;
                break;
            };
            let mut cut = None;
            for (u, x) in optima {
                if let Some(c) = sep.separate(i, u, x)? {
                    cut = Some((i, c, false));
                    break;
                }
                if disc == Discretization::Interpolation {
                    if let Some(c) = sep.separate_next(i + 1, u, x + two_delta * u)? {
                        cut = Some((i + 1, c, true));
                        break;
                    }
                }
            }
            let Some((p, c, next)) = cut else {
                controllable[i] = Some(set);
                active = act;
                break;
            };
            cuts.push(p, c, next);
            stats.cuts += 1;
            rounds += 1;
            if rounds > MAX_CUTS_PER_LP {
                return Err(too_many_cuts(i));
            }
        }
    }
    Ok(Ok(active))
}

/// `K_N`: the end interval `end` intersected with the states feasible at `s_N` (`None` when
/// empty), cut by the oracle until it accepts both optima.
#[allow(clippy::too_many_arguments)]
fn end_set(
    k: &CanonicalConstraints,
    disc: Discretization,
    end: [f64; 2],
    tol: &Tolerances,
    stats: &mut SolveStats,
    hit_box: &mut bool,
    sep: &mut Option<&mut dyn Separation>,
    cuts: &mut Cuts,
) -> Result<Option<[f64; 2]>, ToppError> {
    let n = k.num_points();
    let mut rounds = 0;
    let mut kn = loop {
        let (lines, mut bbox) = assemble(k, disc, n - 1, None, false, tol, cuts);
        bbox.x_lo = bbox.x_lo.max(end[0]);
        bbox.x_hi = bbox.x_hi.min(end[1]);
        let Some((set, _, optima)) = x_range(&lines, bbox, tol, [None, None], stats, hit_box)
        else {
            return Ok(None);
        };
        let Some(sep) = sep.as_deref_mut() else {
            break set;
        };
        let mut cut = None;
        for (u, x) in optima {
            if let Some(c) = sep.separate(n - 1, u, x)? {
                cut = Some(c);
                break;
            }
        }
        let Some(c) = cut else {
            break set;
        };
        cuts.push(n - 1, c, false);
        stats.cuts += 1;
        rounds += 1;
        if rounds > MAX_CUTS_PER_LP {
            return Err(too_many_cuts(n - 1));
        }
    };
    // A fixed end speed: keep it exact (the LP returns it up to round-off).
    if end[0] == end[1] {
        kn = [end[0], end[0]];
    }
    Ok(Some(kn))
}

/// Lines active at the two optima of [`x_range`] (`[max-x actives, min-x actives]`).
pub(super) type Actives = [Option<[Option<usize>; 2]>; 2];

/// What [`x_range`] finds: `[min x, max x]`, the lines active at the two optima, and the
/// optima `(u, x)` (max first).
type XRange = ([f64; 2], Actives, [(f64, f64); 2]);

/// `[min x, max x]` over the current stage lines and `bbox`, the lines active at the two
/// optima, and the optima `(u, x)` themselves (max first), or `None` when empty.
fn x_range(
    lines: &StageLines<'_>,
    bbox: Box2,
    tol: &Tolerances,
    warm: Actives,
    stats: &mut SolveStats,
    hit_box: &mut bool,
) -> Option<XRange> {
    // Warm start: the K lines (almost always active) and the previous stage's actives.
    let mut first = [[0usize; 2 + K_LINES]; 2];
    let mut nf = [0usize; 2];
    for p in 0..2 {
        for j in 0..lines.n_head {
            first[p][nf[p]] = j;
            nf[p] += 1;
        }
        if let Some(w) = warm[p] {
            for j in w.into_iter().flatten() {
                first[p][nf[p]] = j;
                nf[p] += 1;
            }
        }
    }
    let mut st = Lp2Stats::default();
    let objs = [([0.0, 1.0], [1.0, 0.0]), ([0.0, -1.0], [-1.0, 0.0])];
    let [hi, lo] = lp2::solve_pair(
        lines,
        bbox,
        objs,
        [&first[0][..nf[0]], &first[1][..nf[1]]],
        tol,
        &mut st,
    );
    add_stats(stats, &st);
    stats.lps += 1; // two LPs solved in one pass
    let Lp2::Optimal {
        u: u_hi,
        x: x_hi,
        active: a_hi,
    } = hi
    else {
        return None;
    };
    let Lp2::Optimal {
        u: u_lo,
        x: x_lo,
        active: a_lo,
    } = lo
    else {
        return None;
    };
    // The box side counts as touched when an optimum lies on it (to BOX_TOUCH relative).
    let near = |v: f64, side: f64| (v.abs() - side).abs() <= crate::tol::BOX_TOUCH * side;
    if near(x_hi, tol.max_x) || near(u_hi, tol.max_u) || near(u_lo, tol.max_u) {
        *hit_box = true;
    }
    let optima = [(u_hi, x_hi), (u_lo, x_lo)];
    let x_lo = x_lo.max(0.0);
    let x_hi = x_hi.max(x_lo);
    Some(([x_lo, x_hi], [Some(a_hi), Some(a_lo)], optima))
}

/// After the backward pass failed at `i_fail`: the smallest grid point whose own rows admit no
/// `(u, x)` (with `u` free in its bounds); else the smallest stage whose feasible set `Omega_i`
/// (with interpolation: also the rows of `i + 1` at the next state, and `x_{i+1} >= 0`) is
/// empty; else the controllable-set failure.
fn diagnose(
    k: &CanonicalConstraints,
    disc: Discretization,
    tol: &Tolerances,
    i_fail: usize,
    stats: &mut SolveStats,
    cuts: &Cuts,
) -> Status {
    let n = k.num_points();
    let mut hit = false;
    for i in 0..n {
        let (lines, bbox) = assemble(k, disc, i, None, false, tol, cuts);
        if x_range(&lines, bbox, tol, [None, None], stats, &mut hit).is_none() {
            return Status::FeasibleSetEmpty { index: i };
        }
    }
    for i in 0..n - 1 {
        let (lines, bbox) = assemble(k, disc, i, Some([0.0, f64::INFINITY]), true, tol, cuts);
        if x_range(&lines, bbox, tol, [None, None], stats, &mut hit).is_none() {
            return Status::FeasibleSetEmpty { index: i };
        }
    }
    Status::ControllableSetEmpty { index: i_fail }
}

/// The admissible range of end speeds `[sd_lo, sd_hi]` at `s_N` from the start speed of `opts`
/// (its `sd_end` is ignored), for chaining segments: every end speed in the range is reachable
/// by some admissible profile, none outside. `None` when no end speed is reachable.
///
/// Computed as forward reachable sets `R_{i+1} = {x + 2 Delta_i u : x in R_i, (u, x) in
/// Omega_i} ∩ K_{i+1}` with `K` the controllable sets towards any end speed; two LPs per stage.
///
/// ```
/// use stance_topp::{end_speed_range, CanonicalConstraints, Row, SolveOptions};
/// // |u| <= 1 on s in [0, 1] from rest: the end speed is at most sqrt(2 * 1 * 1).
/// let rows = vec![Row { a: 1.0, b: 0.0, c: -1.0 }, Row { a: -1.0, b: 0.0, c: -1.0 }];
/// let s: Vec<f64> = (0..=10).map(|i| i as f64 / 10.0).collect();
/// let offsets: Vec<usize> = (0..=11).map(|i| 2 * i).collect();
/// let k = CanonicalConstraints::new(s, offsets, rows.repeat(11)).unwrap();
/// let [lo, hi] = end_speed_range(&k, &SolveOptions::default()).unwrap().unwrap();
/// assert!(lo.abs() < 1e-9 && (hi - 2f64.sqrt()).abs() < 1e-9);
/// ```
pub fn end_speed_range(
    k: &CanonicalConstraints,
    opts: &SolveOptions,
) -> Result<Option<[f64; 2]>, ToppError> {
    opts.validate()?;
    // On the unit grid, as in `Workspace::solve`: speeds s' = L s~'.
    let Some((k_unit, l)) = k.on_unit_grid()? else {
        return end_speed_range_timed(k, opts);
    };
    let unit_opts = SolveOptions {
        sd_start: opts.sd_start / l,
        sd_end: [opts.sd_end[0] / l, opts.sd_end[1] / l],
        ..*opts
    };
    Ok(end_speed_range_timed(&k_unit, &unit_opts)?.map(|[lo, hi]| [lo * l, hi * l]))
}

/// [`end_speed_range_unit`] in the rows' own time unit, as [`solve_timed`]: speeds `2^m s~'`.
fn end_speed_range_timed(
    k: &CanonicalConstraints,
    opts: &SolveOptions,
) -> Result<Option<[f64; 2]>, ToppError> {
    let Some((k_time, m)) = k.on_unit_time() else {
        return end_speed_range_unit(k, opts);
    };
    let r = crate::constraints::ldexp(1.0, m);
    let time_opts = SolveOptions {
        sd_start: opts.sd_start / r,
        sd_end: [opts.sd_end[0] / r, opts.sd_end[1] / r],
        ..*opts
    };
    Ok(end_speed_range_unit(&k_time, &time_opts)?.map(|[lo, hi]| [lo * r, hi * r]))
}

/// [`end_speed_range`] on a grid the solver works on as it is.
fn end_speed_range_unit(
    k: &CanonicalConstraints,
    opts: &SolveOptions,
) -> Result<Option<[f64; 2]>, ToppError> {
    let tol = opts.tol;
    let disc = opts.discretization;
    let n = k.num_points();
    let mut pass = Backward {
        controllable: vec![None; n],
        cuts: Cuts::default(),
        stats: SolveStats::default(),
        hit_box: false,
    };
    let any_end = PassEnd::Speeds([0.0, f64::INFINITY]);
    if backward_pass(k, opts, any_end, &mut pass, &mut None)?.is_err() {
        return Ok(None);
    }
    let (controllable, cuts) = (&pass.controllable, &pass.cuts);
    let x_start = opts.sd_start * opts.sd_start;
    let [lo0, hi0] = controllable[0].expect("backward pass succeeded");
    if x_start < lo0 - tol.state * lo0.max(1.0) || x_start > hi0 + tol.state * hi0.max(1.0) {
        return Ok(None);
    }
    let s = k.grid();
    let mut reach = [x_start.clamp(lo0, hi0); 2];
    for i in 0..n - 1 {
        let k_next = controllable[i + 1].expect("backward pass succeeded");
        let (lines, mut bbox) = assemble(k, disc, i, Some(k_next), true, &tol, cuts);
        bbox.x_lo = bbox.x_lo.max(reach[0]);
        bbox.x_hi = bbox.x_hi.min(reach[1]);
        let two_delta = 2.0 * (s[i + 1] - s[i]);
        let norm = two_delta.hypot(1.0);
        let c = [two_delta / norm, 1.0 / norm];
        let t = [-c[1], c[0]];
        let mut st = Lp2Stats::default();
        let hi = lp2::solve(&lines, bbox, c, t, &[0, 1], &tol, &mut st);
        let lo = lp2::solve(
            &lines,
            bbox,
            [-c[0], -c[1]],
            [-t[0], -t[1]],
            &[0, 1],
            &tol,
            &mut st,
        );
        match (lo, hi) {
            (Lp2::Optimal { u: ul, x: xl, .. }, Lp2::Optimal { u: uh, x: xh, .. }) => {
                let a = (xl + two_delta * ul).max(k_next[0]);
                let b = (xh + two_delta * uh).min(k_next[1]);
                reach = [a.max(0.0), b.max(a).max(0.0)];
            }
            _ => return Ok(None),
        }
    }
    Ok(Some([reach[0].sqrt(), reach[1].sqrt()]))
}
