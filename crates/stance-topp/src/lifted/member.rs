//! Whether a state `(u, x)` admits extra variables `y` satisfying lifted rows: a witness `y`
//! is tried first (the rows evaluated at it), then a linear program finds the `y` of largest
//! margin, which becomes the next witness.
//!
//! # Math
//!
//! With every row normalized, `r_j = (a_j, b_j, d_j) / |(a_j, b_j, d_j)|`, the state is
//! admissible when some `y` in the box has `a_j u + b_j x + c_j + d_j . y <= 0` for all `j`.
//! The program `maximize t subject to d_j . y + t <= -(a_j u + b_j x + c_j)` (rows normalized
//! again with their `t` column) gives the `y` whose smallest slack `t` is largest: the state is
//! admissible when `t >= -eps`, and that `y`, being central, stays a witness for nearby states
//! (the next grid point, the next check), so most checks cost one evaluation of the rows.
//! A positive answer is always certified by a witness evaluated in the rows themselves.

use super::lp::{LpStatus, Program, Simplex, MAX_VARS};
use super::project::LiftedRows;
use crate::error::ToppError;

/// Reusable state of [`Membership::contains`].
#[derive(Debug, Clone, Default)]
pub struct Membership {
    program: Program,
    simplex: Simplex,
    c: Vec<f64>,
    /// The last witness found (tried after the caller's: neighbouring states along a path
    /// share their forces).
    last: Vec<f64>,
    /// Programs solved (the witnesses failed).
    pub lps: usize,
    /// Checks answered by the witness alone.
    pub witnessed: usize,
}

/// Relative tolerance of a row at a state: `value <= EPS |row| max(1, |(u, x, y)|)`.
const EPS: f64 = 1e-9;

/// Largest margin the program looks for (in the rows' normalized units): far beyond any state.
const MAX_MARGIN: f64 = 1e12;

impl Membership {
    /// An empty workspace.
    pub fn new() -> Self {
        Self::default()
    }

    /// Whether every row holds at `(u, x, y)` (within the tolerance; the rows are unit).
    pub fn holds_at(rows: &LiftedRows, u: f64, x: f64, y: &[f64]) -> bool {
        if y.len() != rows.extra() {
            return false;
        }
        let scale = y
            .iter()
            .fold(u.abs().max(x.abs()).max(1.0), |a, v| a.max(v.abs()));
        let lim = EPS * scale;
        (0..rows.len()).all(|j| {
            let (a, b, c, d) = rows.row(j);
            let mut v = a * u + b * x + c;
            for (dk, yk) in d.iter().zip(y) {
                v += dk * yk;
            }
            v <= lim
        })
    }

    /// Whether `(u, x)` admits a `y` with `|y_i| <= rows.y_bound` (module doc); `witness` is
    /// tried first, then the last witness this workspace found, and it is replaced by the
    /// program's `y` when both fail.
    ///
    /// # Errors
    ///
    /// [`ToppError::InvalidValue`] when the program fails (a guard).
    ///
    /// ```
    /// use stance_topp::lifted::{LiftedRows, Membership};
    /// // |u - y| <= 1, |y| <= 2: u in [-3, 3]
    /// let mut r = LiftedRows::new(1, 10.0);
    /// r.push(1.0, 0.0, -1.0, &[-1.0]);
    /// r.push(-1.0, 0.0, -1.0, &[1.0]);
    /// r.push(0.0, 0.0, -2.0, &[1.0]);
    /// r.push(0.0, 0.0, -2.0, &[-1.0]);
    /// let (mut m, mut w) = (Membership::new(), vec![0.0]);
    /// assert!(m.contains(&r, 2.9, 1.0, &mut w).unwrap());
    /// assert!(!m.contains(&r, 3.1, 1.0, &mut w).unwrap());
    /// ```
    pub fn contains(
        &mut self,
        rows: &LiftedRows,
        u: f64,
        x: f64,
        witness: &mut Vec<f64>,
    ) -> Result<bool, ToppError> {
        let k = rows.extra();
        if Self::holds_at(rows, u, x, witness) {
            self.witnessed += 1;
            return Ok(true);
        }
        if self.last.len() == k && Self::holds_at(rows, u, x, &self.last) {
            self.witnessed += 1;
            witness.clone_from(&self.last);
            return Ok(true);
        }
        if k == 0 {
            return Ok(false);
        }
        if k + 1 > MAX_VARS {
            return Err(ToppError::InvalidValue {
                what: "lifted rows",
                detail: format!(
                    "{k} extra variables; at most {} are supported",
                    MAX_VARS - 1
                ),
            });
        }
        // maximize t over (y, t): (d_j . y + t) / s_j <= -(a_j u + b_j x + c_j) / s_j
        let p = &mut self.program;
        p.n = k + 1;
        p.g.clear();
        p.h.clear();
        for j in 0..rows.len() {
            let (a, b, c, d) = rows.row(j);
            let norm = (a * a + b * b + d.iter().map(|v| v * v).sum::<f64>()).sqrt();
            if norm == 0.0 {
                if c > 0.0 {
                    return Ok(false);
                }
                continue;
            }
            let s = (d.iter().map(|v| v * v).sum::<f64>() / (norm * norm) + 1.0).sqrt();
            p.g.extend(d.iter().map(|v| v / norm / s));
            p.g.push(1.0 / s);
            p.h.push(-(a * u + b * x + c) / norm / s);
        }
        p.lo.clear();
        p.hi.clear();
        p.lo.extend(std::iter::repeat_n(-rows.y_bound, k));
        p.hi.extend(std::iter::repeat_n(rows.y_bound, k));
        p.lo.push(-MAX_MARGIN);
        p.hi.push(MAX_MARGIN);
        self.c.clear();
        self.c.resize(k + 1, 0.0);
        self.c[k] = 1.0;
        self.lps += 1;
        let status = self.simplex.solve_or_retry(&self.program, &self.c);
        match status {
            LpStatus::Optimal => {
                witness.clear();
                witness.extend_from_slice(&self.simplex.v[..k]);
                let ok = Self::holds_at(rows, u, x, witness);
                if ok {
                    self.last.clone_from(witness);
                }
                Ok(ok)
            }
            LpStatus::Infeasible => Ok(false),
            LpStatus::Failed => Err(ToppError::InvalidValue {
                what: "lifted rows",
                detail: "the membership program failed (singular or cycling); report this \
                         input"
                    .into(),
            }),
        }
    }
}
