//! Canonical constraints of time-optimal path parameterization.
//!
//! # Math
//!
//! On a path `q(s)`, `s in [s_0, s_N]`, with `u = s''` and `x = s'^2`, every constraint that is
//! linear in the generalized acceleration (contact stability through the GIWC, paper eq. 13-14;
//! torque limits; ...) reads, at each grid point `s_i`,
//!
//! ```text
//!     a_ij u + b_ij x + c_ij <= 0          j = 0 .. m_i - 1
//! ```
//!
//! plus optional bounds `x_lo_i <= x <= x_hi_i` and `u_lo_i <= u <= u_hi_i`. This module stores
//! the rows of all grid points in one flat buffer with per-point offsets (`rows_at(i)` is a
//! slice), validated once: finite coefficients, matching shapes, a strictly increasing grid.
//!
//! **Scale.** A row and its multiple by a positive factor are the same constraint, and the
//! solver's answer does not depend on such a factor (its tests are relative within a row). Rows
//! whose largest coefficient is below `2^-100` or above `2^100` are stored multiplied by the power
//! of two that brings it into `[0.5, 1)` (exact), so [`CanonicalConstraints::rows`] may return
//! such rows rescaled. The path parameter's unit and origin do not matter either: the solver
//! works on `s~ = (s - s_0) / L` with `L` a power of two when the grid's range or origin is
//! more than a factor 16 away from unit (closer, on the grid as given).

use crate::error::ToppError;

/// One row `a u + b x + c <= 0`.
///
/// `#[repr(C)]`: three `f64` in the order `a, b, c` (24 bytes), which the vectorized fill of
/// [`crate::factored`] writes directly.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[repr(C)]
pub struct Row {
    /// Coefficient of `u = s''`.
    pub a: f64,
    /// Coefficient of `x = s'^2`.
    pub b: f64,
    /// Constant term.
    pub c: f64,
}

impl Row {
    /// Value `a u + b x + c` (the row holds when it is `<= 0`).
    ///
    /// ```
    /// use stance_topp::Row;
    /// assert_eq!(Row { a: 1.0, b: 2.0, c: -3.0 }.value(1.0, 1.0), 0.0);
    /// ```
    #[inline]
    pub fn value(&self, u: f64, x: f64) -> f64 {
        self.a * u + self.b * x + self.c
    }
}

/// Rows `a u + b x + c <= 0` at every grid point, stored contiguously, with optional bounds.
#[derive(Debug, Clone, PartialEq)]
pub struct CanonicalConstraints {
    s: Vec<f64>,
    offsets: Vec<usize>,
    rows: Vec<Row>,
    x_bounds: Option<Vec<[f64; 2]>>,
    u_bounds: Option<Vec<[f64; 2]>>,
    /// Per grid point, how many of its leading rows the interpolation discretization also
    /// imposes at the end of the interval before it (`None`: all; [`Self::with_next_rows`]).
    next_counts: Option<Vec<usize>>,
}

/// Largest `|e|` of the path parameter's unit `L = 2^e` ([`grid_exponent`]):
/// the solution is mapped back with `L^2`, which must stay a normal double.
const MAX_GRID_EXPONENT: i32 = 500;

/// Grids with `|e| <= NEAR_UNIT` ([`grid_exponent`]) and `|s_0|` at most
/// `2^NEAR_UNIT` times their range are solved as they are (see [`CanonicalConstraints::on_unit_grid`]).
const NEAR_UNIT: i32 = 4;

/// Up to this `|e|` ([`grid_exponent`]) the rows are multiplied by `2^e` and
/// `2^2e` directly: rows within `2^+-ROW_WINDOW` stay finite and normal (`100 + 2 * 200 < 1022`).
/// Beyond it each coefficient gets its own power of two (slower: an exponent per coefficient).
const FAST_GRID_EXPONENT: i32 = 200;

/// Time units `T = 4^m` with `|m| <= NEAR_TIME` (a factor of up to 256 in `x` and `u`) are
/// solved in as they are ([`CanonicalConstraints::on_unit_time`]).
const NEAR_TIME: i32 = 4;

/// Largest `|m|` of the time unit `T = 4^m` ([`CanonicalConstraints::time_unit`]): states of
/// order one map back to `2^+-400`, finite and normal.
const MAX_TIME_EXPONENT: i32 = 200;

/// Rows whose largest coefficient is outside `[2^-ROW_WINDOW, 2^ROW_WINDOW]` are multiplied
/// by the power of two that brings it into `[0.5, 1)`.
const ROW_WINDOW: i32 = 100;

/// Brings a row's coefficients into the window of [`ROW_WINDOW`] by a power of two (exact; the
/// half-plane is the same). The solver's tests are relative within a row, so this changes no
/// decision; it keeps the products of two rows' squared norms in the kernel (up to `2^400`)
/// from overflowing or flushing to zero, so that a row scaled by any power of two gives the same
/// answer bit for bit.
pub(crate) fn into_window(r: &mut Row) {
    const LO: f64 = pow2(-ROW_WINDOW);
    const HI: f64 = pow2(ROW_WINDOW);
    let m = r.a.abs().max(r.b.abs()).max(r.c.abs());
    if m == 0.0 || !m.is_finite() || (LO..=HI).contains(&m) {
        return;
    }
    let k = -(exponent(m) + 1);
    for c in [&mut r.a, &mut r.b, &mut r.c] {
        *c = ldexp(*c, k);
    }
}

/// `2^k` for a normal power of two (`-1022 <= k <= 1023`), from its bits.
const fn pow2(k: i32) -> f64 {
    assert!(-1022 <= k && k <= 1023);
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// `floor(log2 |x|)` for a finite nonzero `x` (subnormals included), exactly: read from the
/// bits of `x`.
/// The exponent `e` of the power of two `L = 2^e` with `len / L` in `(0.5, 1]`: the unit of
/// the path parameter the solver works in on a grid of range `len`
/// ([`CanonicalConstraints::on_unit_grid`]).
fn grid_exponent(len: f64) -> i32 {
    // len = m 2^f with m in [1, 2): L = 2^(f + 1), or 2^f when len is a power of two.
    let f = exponent(len);
    if ldexp(len, -f) == 1.0 {
        f
    } else {
        f + 1
    }
}

/// Whether a grid from `s_0` to `s_n` (finite) is solved as it is. Near unit range and origin:
/// the solver's tolerances and box are relative to `max(1, |(u, x)|)`, so a factor of up to
/// `2^NEAR_UNIT` changes its decisions by no more than that factor, at the tolerance level;
/// copying and rescaling the rows would cost more than the solve (a 172-row, 101-point
/// instance: 3x).
pub(crate) fn solved_as_given(s_0: f64, s_n: f64) -> bool {
    let len = s_n - s_0;
    len.is_finite() && grid_exponent(len).abs() <= NEAR_UNIT && s_0.abs() <= ldexp(len, NEAR_UNIT)
}

pub(crate) fn exponent(x: f64) -> i32 {
    debug_assert!(x.is_finite() && x != 0.0, "exponent of {x}");
    let bits = x.abs().to_bits();
    let biased = (bits >> 52) as i32;
    if biased == 0 {
        // subnormal: m 2^-1074 with the mantissa's highest set bit giving the power
        let m = bits & ((1u64 << 52) - 1);
        63 - m.leading_zeros() as i32 - 1074
    } else {
        biased - 1023
    }
}

/// `floor(log2 |(a, b)|)` for finite `(a, b)` not both zero, without forming `a^2 + b^2` (which
/// could overflow or flush to zero): the larger magnitude's exponent, plus one when the
/// Euclidean norm reaches the next power of two (the norm is between the larger magnitude and
/// `sqrt 2` times it). Computed on the mantissas, so the same for `(a, b)` and `(a 2^k, b 2^k)`.
pub(crate) fn norm_exponent(a: f64, b: f64) -> i32 {
    let (hi, lo) = if a.abs() >= b.abs() {
        (a.abs(), b.abs())
    } else {
        (b.abs(), a.abs())
    };
    let e = exponent(hi);
    let (h, l) = (ldexp(hi, -e), ldexp(lo, -e));
    e + i32::from(h * h + l * l >= 4.0)
}

/// The row `(a 2^ka, b 2^kb, c 2^kc)` brought into `[0.5, 1)` by one more power of two, computed
/// as one factor per coefficient from their exponents, so that nothing overflows or flushes to
/// zero on the way (a zero row stays as it is).
fn scaled_into_window(r: &Row, [ka, kb, kc]: [i32; 3]) -> Row {
    let Some(top) = [(r.a, ka), (r.b, kb), (r.c, kc)]
        .iter()
        .filter(|(x, _)| *x != 0.0)
        .map(|&(x, k)| exponent(x) + k)
        .max()
    else {
        return *r;
    };
    let k = -(top + 1);
    Row {
        a: ldexp(r.a, ka + k),
        b: ldexp(r.b, kb + k),
        c: ldexp(r.c, kc + k),
    }
}

/// `x 2^k`, in steps that neither overflow nor flush to zero before the end (exact unless the
/// result itself overflows or is subnormal).
pub fn ldexp(mut x: f64, mut k: i32) -> f64 {
    const STEP: i32 = 1000;
    while k > STEP {
        x *= pow2(STEP);
        k -= STEP;
    }
    while k < -STEP {
        x *= pow2(-STEP);
        k += STEP;
    }
    if k >= -1022 {
        x * pow2(k)
    } else {
        // 2^k itself is subnormal: in two exact steps
        x * pow2(k + 1000) * pow2(-1000)
    }
}

pub(crate) fn check_grid(s: &[f64]) -> Result<(), ToppError> {
    if s.len() < 2 {
        return Err(ToppError::GridTooShort { got: s.len() });
    }
    if let Some((i, &v)) = s.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(ToppError::NotFinite {
            what: "s",
            point: i,
            row: 0,
            value: v,
        });
    }
    let span = s[s.len() - 1] - s[0];
    if !(2.0 * span).is_finite() {
        return Err(ToppError::InvalidValue {
            what: "s",
            detail: format!(
                "the grid's span s_N - s_0 = {span:e} overflows when doubled; rescale the path \
                 parameter"
            ),
        });
    }
    for i in 1..s.len() {
        if s[i] <= s[i - 1] {
            return Err(ToppError::GridNotIncreasing {
                index: i,
                value: s[i],
                prev_index: i - 1,
                prev: s[i - 1],
            });
        }
    }
    Ok(())
}

fn check_bounds(
    what: &'static str,
    bounds: &[[f64; 2]],
    n: usize,
    allow_negative: bool,
) -> Result<(), ToppError> {
    if bounds.len() != n {
        return Err(ToppError::Shape {
            what: what.to_string(),
            expected: n,
            got: bounds.len(),
        });
    }
    for (i, &[lo, hi]) in bounds.iter().enumerate() {
        if lo.is_nan() || hi.is_nan() {
            return Err(ToppError::NotFinite {
                what,
                point: i,
                row: 0,
                value: f64::NAN,
            });
        }
        if lo > hi {
            return Err(ToppError::InvalidValue {
                what,
                detail: format!("empty interval [{lo}, {hi}] at grid point {i}; give lo <= hi"),
            });
        }
        if !allow_negative && hi < 0.0 {
            return Err(ToppError::InvalidValue {
                what,
                detail: format!(
                    "upper bound {hi} < 0 at grid point {i}; x = s'^2 is never negative"
                ),
            });
        }
    }
    Ok(())
}

impl CanonicalConstraints {
    /// Builds the constraints from a grid `s` (`N + 1` points), per-point row offsets
    /// (`N + 2` entries, starting at 0, non-decreasing, ending at `rows.len()`) and the rows.
    ///
    /// ```
    /// use stance_topp::{CanonicalConstraints, Row};
    /// // Two grid points, one row each: x <= 1.
    /// let r = Row { a: 0.0, b: 1.0, c: -1.0 };
    /// let k = CanonicalConstraints::new(vec![0.0, 1.0], vec![0, 1, 2], vec![r, r]).unwrap();
    /// assert_eq!(k.num_points(), 2);
    /// assert_eq!(k.rows_at(1), &[r]);
    /// assert!(CanonicalConstraints::new(vec![0.0, 0.0], vec![0, 1, 2], vec![r, r]).is_err());
    /// ```
    pub fn new(s: Vec<f64>, offsets: Vec<usize>, mut rows: Vec<Row>) -> Result<Self, ToppError> {
        check_grid(&s)?;
        if offsets.len() != s.len() + 1 {
            return Err(ToppError::Shape {
                what: "offsets (grid points + 1)".into(),
                expected: s.len() + 1,
                got: offsets.len(),
            });
        }
        if offsets[0] != 0
            || offsets.windows(2).any(|w| w[1] < w[0])
            || offsets[s.len()] != rows.len()
        {
            return Err(ToppError::InvalidValue {
                what: "offsets",
                detail: format!(
                    "offsets must start at 0, never decrease and end at the number of rows ({})",
                    rows.len()
                ),
            });
        }
        for i in 0..s.len() {
            for (j, r) in rows[offsets[i]..offsets[i + 1]].iter().enumerate() {
                for (what, v) in [("a", r.a), ("b", r.b), ("c", r.c)] {
                    if !v.is_finite() {
                        return Err(ToppError::NotFinite {
                            what,
                            point: i,
                            row: j,
                            value: v,
                        });
                    }
                    if v.abs() > crate::tol::MAX_ABS_COEFFICIENT {
                        return Err(ToppError::InvalidValue {
                            what,
                            detail: format!(
                                "{v:e} at grid point {i}, row {j} exceeds {:e} in magnitude; \
                                 rescale that row (dividing a row by a positive factor leaves \
                                 its feasible set unchanged)",
                                crate::tol::MAX_ABS_COEFFICIENT
                            ),
                        });
                    }
                }
            }
        }
        rows.iter_mut().for_each(into_window);
        Ok(Self {
            s,
            offsets,
            rows,
            x_bounds: None,
            u_bounds: None,
            next_counts: None,
        })
    }

    /// Builds the constraints from dense per-point arrays `a[i][j]`, `b[i][j]`, `c[i][j]` (the
    /// layout of the command-line files; the number of rows may differ between grid points but
    /// must agree between `a`, `b` and `c`).
    ///
    /// ```
    /// use stance_topp::CanonicalConstraints;
    /// let s = [0.0, 0.5, 1.0];
    /// let a = vec![vec![1.0, -1.0]; 3];
    /// let b = vec![vec![0.0, 0.0]; 3];
    /// let c = vec![vec![-1.0, -1.0]; 3]; // |u| <= 1
    /// let k = CanonicalConstraints::from_dense(&s, &a, &b, &c).unwrap();
    /// assert_eq!(k.rows_at(2).len(), 2);
    /// assert!(CanonicalConstraints::from_dense(&s, &a, &b, &c[..2]).is_err());
    /// ```
    pub fn from_dense(
        s: &[f64],
        a: &[Vec<f64>],
        b: &[Vec<f64>],
        c: &[Vec<f64>],
    ) -> Result<Self, ToppError> {
        let n = s.len();
        for (what, arr) in [
            ("a (grid points)", a),
            ("b (grid points)", b),
            ("c (grid points)", c),
        ] {
            if arr.len() != n {
                return Err(ToppError::Shape {
                    what: what.into(),
                    expected: n,
                    got: arr.len(),
                });
            }
        }
        let mut offsets = Vec::with_capacity(n + 1);
        offsets.push(0);
        let mut rows = Vec::with_capacity(a.iter().map(Vec::len).sum());
        for i in 0..n {
            let m = a[i].len();
            for (what, arr) in [("b", &b[i]), ("c", &c[i])] {
                if arr.len() != m {
                    return Err(ToppError::Shape {
                        what: format!("{what}[{i}] (rows, must match a[{i}])"),
                        expected: m,
                        got: arr.len(),
                    });
                }
            }
            for j in 0..m {
                rows.push(Row {
                    a: a[i][j],
                    b: b[i][j],
                    c: c[i][j],
                });
            }
            offsets.push(rows.len());
        }
        Self::new(s.to_vec(), offsets, rows)
    }

    /// Adds bounds `lo_i <= x <= hi_i` on `x = s'^2` at every grid point (`N + 1` pairs; use
    /// `f64::INFINITY` for no upper bound).
    ///
    /// ```
    /// use stance_topp::{CanonicalConstraints, Row};
    /// let r = Row { a: 1.0, b: 0.0, c: -1.0 };
    /// let k = CanonicalConstraints::new(vec![0.0, 1.0], vec![0, 1, 2], vec![r, r]).unwrap();
    /// let k = k.with_x_bounds(vec![[0.0, 4.0]; 2]).unwrap();
    /// assert_eq!(k.x_bounds_at(1), [0.0, 4.0]);
    /// ```
    pub fn with_x_bounds(mut self, bounds: Vec<[f64; 2]>) -> Result<Self, ToppError> {
        check_bounds("x bounds", &bounds, self.s.len(), false)?;
        self.x_bounds = Some(bounds);
        Ok(self)
    }

    /// Says, per grid point, how many of its leading rows the interpolation discretization also
    /// imposes at the end of the interval before it (`counts[i]` of `rows_at(i)`; the others
    /// hold with the grid point's own `u_i` only). By default all of them: a point's rows hold on
    /// both sides of it. Fewer where the path's constraints change at the point (a contact
    /// switch): the rows of the stance after it must not hold with the acceleration before it.
    ///
    /// # Errors
    ///
    /// [`ToppError::Shape`] when `counts` does not have one entry per grid point, or one
    /// exceeds its point's rows.
    ///
    /// ```
    /// use stance_topp::{CanonicalConstraints, Row};
    /// let r = Row { a: 1.0, b: 0.0, c: -1.0 };
    /// let k = CanonicalConstraints::new(vec![0.0, 1.0], vec![0, 1, 2], vec![r, r]).unwrap();
    /// let k = k.with_next_rows(vec![1, 0]).unwrap();
    /// assert!(k.next_rows_at(1).is_empty());
    /// assert_eq!(k.rows_at(1).len(), 1);
    /// ```
    pub fn with_next_rows(mut self, counts: Vec<usize>) -> Result<Self, ToppError> {
        if counts.len() != self.s.len() {
            return Err(ToppError::Shape {
                what: "rows imposed at the previous interval's end (one count per grid point)"
                    .into(),
                expected: self.s.len(),
                got: counts.len(),
            });
        }
        if let Some(i) = (0..counts.len()).find(|&i| counts[i] > self.rows_at(i).len()) {
            return Err(ToppError::Shape {
                what: format!("rows imposed at the previous interval's end at grid point {i}"),
                expected: self.rows_at(i).len(),
                got: counts[i],
            });
        }
        self.next_counts = Some(counts);
        Ok(self)
    }

    /// The rows of grid point `i` that the interpolation discretization also imposes at the
    /// end of the interval before it ([`Self::with_next_rows`]; all by default).
    pub fn next_rows_at(&self, i: usize) -> &[Row] {
        let rows = self.rows_at(i);
        match &self.next_counts {
            Some(c) => &rows[..c[i]],
            None => rows,
        }
    }

    /// Adds bounds `lo_i <= u <= hi_i` on `u = s''` at every grid point (`N + 1` pairs).
    ///
    /// ```
    /// use stance_topp::{CanonicalConstraints, Row};
    /// let r = Row { a: 0.0, b: 1.0, c: -1.0 };
    /// let k = CanonicalConstraints::new(vec![0.0, 1.0], vec![0, 1, 2], vec![r, r]).unwrap();
    /// let k = k.with_u_bounds(vec![[-2.0, 2.0]; 2]).unwrap();
    /// assert_eq!(k.u_bounds_at(0), [-2.0, 2.0]);
    /// assert_eq!(k.x_bounds_at(0), [0.0, f64::INFINITY]);
    /// ```
    pub fn with_u_bounds(mut self, bounds: Vec<[f64; 2]>) -> Result<Self, ToppError> {
        check_bounds("u bounds", &bounds, self.s.len(), true)?;
        self.u_bounds = Some(bounds);
        Ok(self)
    }

    /// The same constraints on the path parameter `s~ = (s - s_0) / L` (with `L` from
    /// [`grid_exponent`]): `s' = L s~'`, so `x = L^2 x~`, `u = L u~`, and a row
    /// `a u + b x + c <= 0` is `(a L) u~ + (b L^2) x~ + c <= 0` (exact: `L` is a power of two;
    /// only `s - s_0` rounds). `None` when the grid is already `[0, ...]` with `L = 1`.
    ///
    /// The solver decides everything on this grid, so that its answer does not depend on the
    /// unit or the origin of the path parameter: the tolerances and the bounding box are
    /// relative to `(u~, x~)`, whatever the range of `s`.
    pub(crate) fn on_unit_grid(&self) -> Result<Option<(Self, f64)>, ToppError> {
        self.on_unit_grid_of([self.s[0], self.s[self.s.len() - 1]])
    }

    /// [`Self::on_unit_grid`] for points of a longer grid from `whole[0]` to `whole[1]`, on that
    /// grid's unit: these points as they are there.
    pub(crate) fn on_unit_grid_of(
        &self,
        whole: [f64; 2],
    ) -> Result<Option<(Self, f64)>, ToppError> {
        let s0 = whole[0];
        let len = whole[1] - s0;
        if !len.is_finite() {
            return Err(ToppError::InvalidValue {
                what: "s",
                detail: format!(
                    "the grid's range s_N - s_0 overflows ({s0:e} to {:e}); use a path \
                     parameter closer to unit range",
                    whole[1]
                ),
            });
        }
        let e = grid_exponent(len);
        if solved_as_given(s0, whole[1]) {
            return Ok(None);
        }
        let s: Vec<f64> = self.s.iter().map(|&si| ldexp(si - s0, -e)).collect();
        if check_grid(&s).is_err() {
            return Err(ToppError::InvalidValue {
                what: "s",
                detail: format!(
                    "grid points closer together than the rounding of s - s_0 (s_0 = {s0:e}); \
                     shift the path parameter so that it starts near 0"
                ),
            });
        }
        // (a 2^e, b 2^2e, c), then the whole row by the power of two that brings its largest
        // coefficient into [0.5, 1): computed as one factor per coefficient, so that nothing
        // overflows or flushes to zero on the way.
        let mut rows = self.rows.clone();
        if e.abs() <= FAST_GRID_EXPONENT {
            // Rows are within 2^+-ROW_WINDOW: times 2^e and 2^2e they neither overflow nor
            // flush to zero (exact), and only rows that leave the window are rescaled.
            let (l, l2) = (ldexp(1.0, e), ldexp(1.0, 2 * e));
            for r in rows.iter_mut() {
                r.a *= l;
                r.b *= l2;
                into_window(r);
            }
        } else {
            self.rescale_rows_far(&mut rows, e);
        }
        // Speeds and accelerations are mapped back with L^2 and L: both must stay normal.
        if e.abs() > MAX_GRID_EXPONENT {
            return Err(ToppError::InvalidValue {
                what: "s",
                detail: format!(
                    "the path parameter's range {len:e} is outside 2^-{MAX_GRID_EXPONENT} to \
                     2^{MAX_GRID_EXPONENT} (about 1e-150 to 1e150): squared path speeds in its \
                     unit would overflow or vanish; use a path parameter closer to unit range"
                ),
            });
        }
        let l = ldexp(1.0, e);
        let scale = |b: &Option<Vec<[f64; 2]>>, k: i32| {
            b.as_ref().map(|v| {
                v.iter()
                    .map(|&[lo, hi]| [ldexp(lo, k), ldexp(hi, k)])
                    .collect()
            })
        };
        Ok(Some((
            Self {
                s,
                offsets: self.offsets.clone(),
                rows,
                x_bounds: scale(&self.x_bounds, -2 * e),
                u_bounds: scale(&self.u_bounds, -e),
                next_counts: self.next_counts.clone(),
            },
            l,
        )))
    }

    /// The time unit the solver decides in: `T = 4^m` with `T` near the rows' typical
    /// distance from the origin of the `(u, x)` plane (the median, in powers of two, of
    /// `-c / |(a, b)|` over the rows with `c < 0`, and of the finite bounds on `x` and `u`), so
    /// that the states the solver compares with its tolerances are of order one whatever the
    /// unit of time. `m = 0` without such rows. Unit: `1/time^2`; `|m| <=` [`MAX_TIME_EXPONENT`].
    pub(crate) fn time_unit(&self) -> i32 {
        // A histogram of the powers of two (each within +-2100), read at its median: the
        // rows of a whole motion number tens of thousands, and this runs at every solve.
        const HALF: i32 = 2200;
        let mut counts = vec![0u32; 2 * HALF as usize + 1];
        let mut n = 0usize;
        let mut add = |e: i32| {
            counts[(e + HALF) as usize] += 1;
            n += 1;
        };
        for r in &self.rows {
            if r.c < 0.0 && (r.a != 0.0 || r.b != 0.0) && r.a.is_finite() && r.b.is_finite() {
                // the distance's power of two, without dividing (which could overflow or
                // flush to zero)
                add(exponent(r.c) - norm_exponent(r.a, r.b));
            }
        }
        for b in [&self.x_bounds, &self.u_bounds].into_iter().flatten() {
            for &[lo, hi] in b {
                for v in [lo, hi] {
                    if v.is_finite() && v != 0.0 {
                        add(exponent(v));
                    }
                }
            }
        }
        if n == 0 {
            return 0;
        }
        // the element at index n / 2 of the sorted list
        let mid = n / 2;
        let mut seen = 0usize;
        let mut median = 0;
        for (i, &c) in counts.iter().enumerate() {
            seen += c as usize;
            if seen > mid {
                median = i as i32 - HALF;
                break;
            }
        }
        // T = 4^m: its square root 2^m maps speeds back exactly
        (median.div_euclid(2)).clamp(-MAX_TIME_EXPONENT, MAX_TIME_EXPONENT)
    }

    /// The same constraints in the time unit `T = 4^m` of [`Self::time_unit`]: `x = T x~`,
    /// `u = T u~`, so a row `a u + b x + c <= 0` is `a u~ + b x~ + c / T <= 0` (exact: `T` is a
    /// power of two; each row brought back into the window), and the bounds divide by `T`.
    /// `None` when `|m| <=` [`NEAR_TIME`]: the tolerances, relative to `max(1, |(u, x)|)`, then
    /// change their decisions by at most that factor, and the copy would cost more than it
    /// gives.
    pub(crate) fn on_unit_time(&self) -> Option<(Self, i32)> {
        let m = self.time_unit();
        if m.abs() <= NEAR_TIME {
            return None;
        }
        let rows = self
            .rows
            .iter()
            .map(|r| scaled_into_window(r, [0, 0, -2 * m]))
            .collect();
        let scale = |b: &Option<Vec<[f64; 2]>>| {
            b.as_ref().map(|v| {
                v.iter()
                    .map(|&[lo, hi]| [ldexp(lo, -2 * m), ldexp(hi, -2 * m)])
                    .collect()
            })
        };
        Some((
            Self {
                s: self.s.clone(),
                offsets: self.offsets.clone(),
                rows,
                x_bounds: scale(&self.x_bounds),
                u_bounds: scale(&self.u_bounds),
                next_counts: self.next_counts.clone(),
            },
            m,
        ))
    }

    /// The rows' rescaling of [`Self::on_unit_grid`] for a far-off unit (`|e|` above
    /// [`FAST_GRID_EXPONENT`]): one power of two per coefficient, from their exponents, so that
    /// nothing overflows or flushes to zero on the way.
    fn rescale_rows_far(&self, rows: &mut [Row], e: i32) {
        for r in rows.iter_mut() {
            *r = scaled_into_window(r, [e, 2 * e, 0]);
        }
    }

    /// The grid `s_0 < ... < s_N`.
    ///
    /// ```
    /// use stance_topp::{CanonicalConstraints, Row};
    /// let k = CanonicalConstraints::new(vec![0.0, 2.0], vec![0, 0, 0], vec![]).unwrap();
    /// assert_eq!(k.grid(), &[0.0, 2.0]);
    /// ```
    pub fn grid(&self) -> &[f64] {
        &self.s
    }

    /// Number of grid points `N + 1`.
    ///
    /// ```
    /// use stance_topp::CanonicalConstraints;
    /// let k = CanonicalConstraints::new(vec![0.0, 1.0, 2.0], vec![0, 0, 0, 0], vec![]).unwrap();
    /// assert_eq!(k.num_points(), 3);
    /// ```
    pub fn num_points(&self) -> usize {
        self.s.len()
    }

    /// The rows of grid point `i` (panics if `i >= num_points()`, a programming error).
    ///
    /// ```
    /// use stance_topp::{CanonicalConstraints, Row};
    /// let r = Row { a: 1.0, b: 0.0, c: -1.0 };
    /// let k = CanonicalConstraints::new(vec![0.0, 1.0], vec![0, 0, 1], vec![r]).unwrap();
    /// assert!(k.rows_at(0).is_empty());
    /// assert_eq!(k.rows_at(1).len(), 1);
    /// ```
    pub fn rows_at(&self, i: usize) -> &[Row] {
        &self.rows[self.offsets[i]..self.offsets[i + 1]]
    }

    /// All rows, grid point after grid point (see [`Self::offsets`]).
    ///
    /// ```
    /// use stance_topp::{CanonicalConstraints, Row};
    /// let r = Row { a: 1.0, b: 0.0, c: -1.0 };
    /// let k = CanonicalConstraints::new(vec![0.0, 1.0], vec![0, 1, 2], vec![r, r]).unwrap();
    /// assert_eq!(k.rows().len(), 2);
    /// ```
    pub fn rows(&self) -> &[Row] {
        &self.rows
    }

    /// Mutable rows, for the factored form's refill (rows it writes are finite and bounded);
    /// crate-private so that validated constraints cannot be made non-finite from outside.
    pub(crate) fn rows_mut(&mut self) -> &mut [Row] {
        &mut self.rows
    }

    /// Row offsets: the rows of grid point `i` are `rows()[offsets()[i]..offsets()[i + 1]]`.
    ///
    /// ```
    /// use stance_topp::CanonicalConstraints;
    /// let k = CanonicalConstraints::new(vec![0.0, 1.0], vec![0, 0, 0], vec![]).unwrap();
    /// assert_eq!(k.offsets(), &[0, 0, 0]);
    /// ```
    pub fn offsets(&self) -> &[usize] {
        &self.offsets
    }

    /// Bounds on `x` at grid point `i` (`[0, inf]` when none were given).
    ///
    /// ```
    /// use stance_topp::CanonicalConstraints;
    /// let k = CanonicalConstraints::new(vec![0.0, 1.0], vec![0, 0, 0], vec![]).unwrap();
    /// assert_eq!(k.x_bounds_at(0), [0.0, f64::INFINITY]);
    /// ```
    pub fn x_bounds_at(&self, i: usize) -> [f64; 2] {
        match &self.x_bounds {
            Some(b) => [b[i][0].max(0.0), b[i][1]],
            None => [0.0, f64::INFINITY],
        }
    }

    /// Bounds on `u` at grid point `i` (`[-inf, inf]` when none were given).
    ///
    /// ```
    /// use stance_topp::CanonicalConstraints;
    /// let k = CanonicalConstraints::new(vec![0.0, 1.0], vec![0, 0, 0], vec![]).unwrap();
    /// assert_eq!(k.u_bounds_at(1), [f64::NEG_INFINITY, f64::INFINITY]);
    /// ```
    pub fn u_bounds_at(&self, i: usize) -> [f64; 2] {
        match &self.u_bounds {
            Some(b) => b[i],
            None => [f64::NEG_INFINITY, f64::INFINITY],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn exponents_at_the_ends_of_the_range() {
        assert_eq!(exponent(1.0), 0);
        assert_eq!(exponent(-3.0), 1);
        assert_eq!(exponent(0.75), -1);
        assert_eq!(exponent(f64::MAX), 1023);
        assert_eq!(exponent(f64::MIN_POSITIVE), -1022);
        assert_eq!(exponent(f64::MIN_POSITIVE / 2.0), -1023);
        assert_eq!(exponent(5e-324), -1074);
        assert_eq!(norm_exponent(3.0, 4.0), 2);
        assert_eq!(norm_exponent(1.0, 1.0), 0);
        assert_eq!(norm_exponent(0.0, -1.5), 0);
        assert_eq!(norm_exponent(f64::MAX, f64::MAX), 1024);
        assert_eq!(norm_exponent(5e-324, 0.0), -1074);
        assert_eq!(ldexp(1.0, -1074), 5e-324);
        assert_eq!(
            ldexp(f64::MAX, -2046),
            ldexp(f64::MAX, -1023) / 8.0_f64.powi(341)
        );
        assert_eq!(ldexp(3.0, 1022), 3.0 * 2f64.powi(1022));
    }

    proptest! {
        /// `2^e <= |x| < 2^(e+1)`, and the norm's exponent as `hypot`'s where `hypot` is not
        /// within an ulp of a power of two.
        #[test]
        fn exponents_bracket_the_value(m in 1.0f64..2.0, e in -1074i32..1024, r in 0.0f64..1.0) {
            let x = ldexp(m, e);
            prop_assume!(x.is_finite() && x > 0.0);
            let k = exponent(x);
            prop_assert!(ldexp(1.0, k) <= x && x < ldexp(2.0, k), "{x:e}: {k}");
            let (a, b) = (x, x * r);
            let h = a.hypot(b);
            prop_assume!(h.is_finite() && h >= f64::MIN_POSITIVE);
            let f = exponent(h);
            let near = (h / ldexp(1.0, f) - 1.0).abs() < 1e-15 || (h / ldexp(2.0, f) - 1.0).abs() < 1e-15;
            prop_assume!(!near);
            prop_assert_eq!(norm_exponent(a, b), f);
            prop_assert_eq!(norm_exponent(-b, a), f);
        }
    }
}
