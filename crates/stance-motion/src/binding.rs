//! Which constraint binds at a grid point of a retiming, and which empties it: the diagnostics
//! shared by joint-path retimings ([`crate::joints`]) and whole-body motions
//! ([the crate]).
//!
//! # Math
//!
//! Under the profile, grid point `i` is at `(u_i, x_i)` (the acceleration leaving it; at the
//! last point, the one arriving). A row `a u + b x + c <= 0` **binds** there when its value is
//! within [`crate::tol::BINDING`] of zero, relative to the size of its terms
//! `|a u| + |b x| + |c|` (rows of one kind have one scale: newtons for contact rows, ratios to
//! the limit for actuator rows). Rows that do not involve `u` or `x` are constants and never
//! bind.
//!
//! A grid point whose rows admit no `(u, x)` with `x >= 0` (the solver's `feasible_set_empty`)
//! is explained by the rows whose removal alone makes it feasible (two-variable LPs, one per
//! row; only on failure). When no single row does, the point needs two of them relaxed, and all
//! rows that are tight at the least-infeasible point are named instead.

use std::collections::BTreeMap;

use serde::Serialize;
use stance_topp::limits::{LimitKind, LimitTag};
use stance_topp::lp2::{self, Box2, Lp2, Lp2Stats, StageLines};
use stance_topp::{Row, Tolerances};

/// What a row of a retiming stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RowOrigin {
    /// Contact stability (a row of eq. 14 from `U_stance`).
    Contact,
    /// An actuator limit; `coordinate` indexes the caller's joint names.
    Limit(LimitTag),
    /// A torque limit with the contact forces as unknowns (a row of the projection of that
    /// polytope onto `(u, x)`); `coordinate` indexes the caller's joint names.
    TorqueWithContacts(LimitTag),
}

impl RowOrigin {
    /// The kind's name: `contact`, `velocity`, `acceleration` or `torque`.
    ///
    /// ```
    /// use stance_motion::binding::RowOrigin;
    /// assert_eq!(RowOrigin::Contact.kind(), "contact");
    /// ```
    pub fn kind(&self) -> &'static str {
        match self {
            RowOrigin::Contact => "contact",
            RowOrigin::Limit(t) => t.kind.name(),
            RowOrigin::TorqueWithContacts(_) => LimitKind::Torque.name(),
        }
    }

    /// A readable name: `"contact stability"`, `"torque of R_KNEE (upper limit)"`, ...
    ///
    /// ```
    /// use stance_motion::binding::RowOrigin;
    /// use stance_topp::limits::{LimitKind, LimitTag};
    /// let t = LimitTag { kind: LimitKind::Acceleration, coordinate: 0, upper: false };
    /// assert_eq!(RowOrigin::Limit(t).describe(&["elbow".into()]), "acceleration of elbow (lower limit)");
    /// ```
    pub fn describe(&self, joints: &[String]) -> String {
        let name = |t: &LimitTag| {
            joints
                .get(t.coordinate)
                .cloned()
                .unwrap_or_else(|| format!("coordinate {}", t.coordinate))
        };
        match self {
            RowOrigin::Contact => "contact stability".into(),
            RowOrigin::Limit(t) if t.kind == LimitKind::Velocity => {
                format!("velocity of {}", name(t))
            }
            RowOrigin::Limit(t) => format!(
                "{} of {} ({} limit)",
                t.kind.name(),
                name(t),
                if t.upper { "upper" } else { "lower" }
            ),
            RowOrigin::TorqueWithContacts(t) => format!(
                "torque of {} with the contact forces ({} limit)",
                name(t),
                if t.upper { "upper" } else { "lower" }
            ),
        }
    }

    /// The joint coordinate of a limit row.
    fn coordinate(&self) -> Option<usize> {
        match self {
            RowOrigin::Contact => None,
            RowOrigin::Limit(t) | RowOrigin::TorqueWithContacts(t) => Some(t.coordinate),
        }
    }
}

/// Whether a row binds at `(u, x)` (module doc).
pub fn binds(r: &Row, u: f64, x: f64) -> bool {
    if r.a == 0.0 && r.b == 0.0 {
        return false;
    }
    let scale = (r.a * u).abs() + (r.b * x).abs() + r.c.abs();
    r.value(u, x) >= -crate::tol::BINDING * scale
}

/// Grid points bound by each kind of constraint (a point may count under several kinds), and
/// per joint and kind.
#[derive(Debug, Clone, PartialEq, Default, Serialize, serde::Deserialize)]
pub struct Binding {
    /// Grid points where a contact-stability row binds.
    pub contact: usize,
    /// Grid points where a joint velocity limit binds.
    pub velocity: usize,
    /// Grid points where a joint acceleration limit binds.
    pub acceleration: usize,
    /// Grid points where a joint torque limit binds (with the contact forces as unknowns for
    /// a floating base).
    pub torque: usize,
    /// Grid points where nothing binds (the speed is set by a constraint further along: the
    /// controllable set, or the end speed).
    pub none: usize,
    /// `"kind joint"` -> grid points (e.g. `"torque R_KNEE"`).
    pub joints: BTreeMap<String, usize>,
}

impl Binding {
    /// Adds one grid point whose binding rows are `origins`.
    ///
    /// ```
    /// use stance_motion::binding::{Binding, RowOrigin};
    /// let mut b = Binding::default();
    /// b.add_point([RowOrigin::Contact, RowOrigin::Contact].into_iter(), &[]);
    /// b.add_point(std::iter::empty(), &[]);
    /// assert_eq!((b.contact, b.none), (1, 1));
    /// ```
    pub fn add_point(&mut self, origins: impl Iterator<Item = RowOrigin>, joints: &[String]) {
        let mut kinds = [false; 4];
        let mut named: Vec<String> = Vec::new();
        for o in origins {
            let k = match o.kind() {
                "contact" => 0,
                "velocity" => 1,
                "acceleration" => 2,
                _ => 3,
            };
            kinds[k] = true;
            if let Some(c) = o.coordinate() {
                let joint = joints
                    .get(c)
                    .cloned()
                    .unwrap_or_else(|| format!("coordinate {c}"));
                let key = format!("{} {joint}", o.kind());
                if !named.contains(&key) {
                    named.push(key);
                }
            }
        }
        for (flag, count) in kinds.iter().zip([
            &mut self.contact,
            &mut self.velocity,
            &mut self.acceleration,
            &mut self.torque,
        ]) {
            *count += usize::from(*flag);
        }
        if !kinds.iter().any(|&k| k) {
            self.none += 1;
        }
        for key in named {
            *self.joints.entry(key).or_default() += 1;
        }
    }
}

/// The rows of one grid point that empty its feasible set (module doc): indices into `rows`.
///
/// ```
/// use stance_motion::binding::culprits;
/// use stance_topp::{Row, Tolerances};
/// // u <= -1 and u >= 1: either row alone is satisfiable
/// let rows = [Row { a: 1.0, b: 0.0, c: 1.0 }, Row { a: -1.0, b: 0.0, c: 1.0 },
///             Row { a: 0.0, b: 1.0, c: -5.0 }];
/// assert_eq!(culprits(&rows, &Tolerances::default()), vec![0, 1]);
/// ```
pub fn culprits(rows: &[Row], tol: &Tolerances) -> Vec<usize> {
    let bbox = Box2 {
        u_lo: -tol.max_u,
        u_hi: tol.max_u,
        x_lo: 0.0,
        x_hi: tol.max_x,
    };
    let mut stats = Lp2Stats::default();
    let mut buf: Vec<Row> = Vec::with_capacity(rows.len());
    let mut single = Vec::new();
    for k in 0..rows.len() {
        buf.clear();
        buf.extend(
            rows.iter()
                .enumerate()
                .filter(|(j, _)| *j != k)
                .map(|(_, r)| *r),
        );
        let lines = StageLines::from_rows(&buf);
        if let Lp2::Optimal { .. } =
            lp2::solve(&lines, bbox, [0.0, 1.0], [1.0, 0.0], &[], tol, &mut stats)
        {
            single.push(k);
        }
    }
    if !single.is_empty() {
        return single;
    }
    // Least infeasible point: minimize the largest row value (scaled by each row's size)
    // over a coarse set of (u, x); the rows at that maximum are named.
    let size = |r: &Row| {
        r.a.abs()
            .max(r.b.abs())
            .max(r.c.abs())
            .max(f64::MIN_POSITIVE)
    };
    let mut best = (f64::INFINITY, 0.0, 0.0);
    for iu in -40i32..=40 {
        for ix in 0..=40 {
            let u = 10f64.powf(iu.abs() as f64 / 4.0 - 2.0) * f64::from(iu.signum());
            let x = if ix == 0 {
                0.0
            } else {
                10f64.powf(ix as f64 / 4.0 - 2.0)
            };
            let worst = rows
                .iter()
                .map(|r| r.value(u, x) / size(r))
                .fold(f64::NEG_INFINITY, f64::max);
            if worst < best.0 {
                best = (worst, u, x);
            }
        }
    }
    let (w, u, x) = best;
    rows.iter()
        .enumerate()
        .filter(|(_, r)| r.value(u, x) / size(r) >= w - 1e-3 * w.abs().max(1e-12))
        .map(|(k, _)| k)
        .collect()
}

/// The grid point and the constraints of a failed retiming (module doc): `origins` follow the
/// rows of `k` (one per row, in order), `controllable` are the solver's controllable sets,
/// `sd_end` the end speeds asked.
///
/// - `feasible_set_empty` at `i`: the rows of `i` whose removal alone makes it feasible;
/// - `controllable_set_empty`: the last grid point whose controllable set is empty, with its
///   rows and the speed the next point needs (or the end speed) as two more rows;
/// - otherwise (the start speed, a stall) no constraint is named.
///
/// Returns the point and the names, the speed requirement named `"the speed that grid point
/// N needs"` or `"the end speed"`; grid points are named by their index plus `offset` (the
/// index of `k`'s first point in the caller's grid).
#[allow(clippy::too_many_arguments)]
pub fn explain(
    k: &stance_topp::CanonicalConstraints,
    origins: &[RowOrigin],
    joints: &[String],
    status: stance_topp::Status,
    controllable: &[Option<[f64; 2]>],
    sd_end: [f64; 2],
    tol: &Tolerances,
    offset: usize,
) -> (usize, Vec<String>) {
    use stance_topp::Status;
    let n = k.num_points();
    let i = status.grid_index().unwrap_or(0).min(n - 1);
    let at = |j: usize| {
        let o = k.offsets();
        (o[j], o[j + 1])
    };
    let describe = |j: usize, rows: &[usize]| -> Vec<String> {
        let (a, _) = at(j);
        let mut out: Vec<String> = Vec::new();
        for &r in rows {
            let d = origins
                .get(a + r)
                .map_or_else(|| "a row".to_string(), |o| o.describe(joints));
            if !out.contains(&d) {
                out.push(d);
            }
        }
        out
    };
    match status {
        Status::FeasibleSetEmpty { .. } => (i, describe(i, &culprits(k.rows_at(i), tol))),
        Status::ControllableSetEmpty { .. } => {
            // most often a later point cannot be held statically ((u, x) = (0, 0) violates a
            // row: a posture beyond a limit): the motion can only pass it moving, which the
            // end at rest (or a slow part before it) forbids
            for j in i + 1..n {
                let rows = k.rows_at(j);
                let over: Vec<usize> = rows
                    .iter()
                    .enumerate()
                    .filter(|(_, r)| r.c > tol.state * r.a.abs().max(r.b.abs()).max(1.0))
                    .map(|(q, _)| q)
                    .collect();
                if !over.is_empty() {
                    let mut c = describe(j, &over);
                    c.push(format!("holding grid point {} at rest", j + offset));
                    return (j, c);
                }
            }
            let j = (i..n)
                .rev()
                .find(|&j| controllable.get(j).copied().flatten().is_none())
                .unwrap_or(i);
            let mut rows = k.rows_at(j).to_vec();
            let m = rows.len();
            let s = k.grid();
            let next = if j + 1 < n {
                controllable
                    .get(j + 1)
                    .copied()
                    .flatten()
                    .map(|set| (set, 2.0 * (s[j + 1] - s[j])))
            } else {
                Some(([sd_end[0] * sd_end[0], sd_end[1] * sd_end[1]], 0.0))
            };
            if let Some(([lo, hi], td)) = next {
                rows.push(Row {
                    a: td,
                    b: 1.0,
                    c: -hi,
                });
                rows.push(Row {
                    a: -td,
                    b: -1.0,
                    c: lo,
                });
            }
            let found = culprits(&rows, tol);
            let mut c = describe(
                j,
                &found.iter().copied().filter(|&r| r < m).collect::<Vec<_>>(),
            );
            if found.iter().any(|&r| r >= m) {
                c.push(if j + 1 == n {
                    "the end speed".into()
                } else {
                    format!("the speed that grid point {} needs", j + 1 + offset)
                });
            }
            (j, c)
        }
        _ => (i, Vec::new()),
    }
}
