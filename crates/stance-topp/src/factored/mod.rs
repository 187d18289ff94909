//! Factored rows: `a_i = U w_a(s_i)`, `b_i = U w_b(s_i)`, `c_i = U w_c(s_i)` for a fixed matrix
//! `U` (m x 6) and three 6-vectors per grid point, produced in one cache-friendly sweep.
//!
//! # Math (paper eq. 14)
//!
//! For contact stability `U` is the GIWC face matrix (`U w_GI <= 0`; computed once per stance
//! elsewhere) and, for a CoM path `p(s)` with mass `m`, gravity `g` and angular-momentum terms
//! `L' = l1 s'' + l2 s'^2`,
//!
//! ```text
//!     w_a = -(m p_s , m p x p_s  + l1)
//!     w_b = -(m p_ss, m p x p_ss + l2)
//!     w_c =  (m g   , m p x g)
//! ```
//!
//! Since `p'' = p_s u + p_ss x` and `L' = l1 u + l2 x` along the path, the gravito-inertial
//! wrench is `w_GI = w_c + w_a u + w_b x`, so `a u + b x + c = U w_GI` and the rows hold exactly
//! when `U w_GI <= 0` ([`eq14_vectors`]). This module only multiplies:
//! it knows nothing about contacts. The units of the rows are those of `U w` (for unit-norm face
//! rows and wrenches in N and N m: newtons).
//!
//! # Cost
//!
//! A general product costs 18 multiply-adds per row and grid point. Two structures of eq. 14
//! are detected once, at construction, and exploited by the fill: the force part `m g` of `w_c`
//! is the same at every grid point, so `U_f (m g)` is computed once per stance and
//! `c = U_f (m g) + U_t (m p x g)` costs 3 multiply-adds; and for a vertical `g`, the third
//! component of `p x g` is exactly zero, which drops one more (14 in all instead of 18).
//!
//! # Kernels ([`FillKernel`], chosen at run time)
//!
//! - `kernel`: the portable fill and the AVX2 + FMA one (the same source, vectorized over rows
//!   by the compiler).
//! - `avx512`: eight rows per step, written as three whole, aligned 64-byte cache lines.
//!   Measured on the development machine, the fill is bound by writing its 24-byte rows into
//!   the second-level cache rather than by the multiply-adds; aligning the steps on the output
//!   (not on the rows of `U`) is what the kernel is built around (see its module docs).
//!   [`FillKernel::Avx512Gz`] is the same kernel with one load fewer per 8 rows for vertical
//!   gravity (the default where AVX-512F runs).
//!
//! The kernels with fused multiply-adds give bit-identical rows; the portable one differs from
//! them by round-off only.

#[cfg(target_arch = "x86_64")]
mod avx512;
mod kernel;

use crate::constraints::{CanonicalConstraints, Row};
use crate::error::ToppError;
use crate::path::{PathCurve, PathPoint};
use kernel::{madd, CMode};

/// Which implementation of [`FactoredRows::fill`] runs. All compute the same products; the
/// ones with fused multiply-adds ([`FillKernel::Avx2Fma`], [`FillKernel::Avx512`]) give
/// bit-identical rows, the portable one differs from them by round-off (one rounding more per
/// multiply-add).
///
/// ```
/// use stance_topp::factored::FillKernel;
/// assert!(FillKernel::Portable.is_available());
/// assert!(FillKernel::Auto.resolve().is_available());
/// assert_ne!(FillKernel::Auto.resolve(), FillKernel::Auto);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FillKernel {
    /// The fastest available on this CPU: [`FillKernel::Avx512Gz`], else
    /// [`FillKernel::Avx2Fma`], else [`FillKernel::Portable`].
    Auto,
    /// Plain Rust, any CPU (vectorized by the compiler for the baseline target).
    Portable,
    /// x86-64 with AVX2 and FMA: 4 rows per vector, vectorized by the compiler.
    Avx2Fma,
    /// x86-64 with AVX-512F and FMA: 8 rows per step written as three whole cache lines
    /// (module `avx512`).
    Avx512,
    /// [`FillKernel::Avx512`], except that for vertical gravity (eq. 14 with `g = (0, 0, g_z)`)
    /// the constant part `U_f (m g) = U_z m g_z` of `c` is recomputed at every row (one
    /// multiply) instead of loaded: one load fewer per 8 rows, measured faster (the fill is
    /// bound by the first-level cache's loads and stores as much as by the multiply-adds; see
    /// the module docs). Same rows bit for bit; otherwise identical to [`FillKernel::Avx512`].
    Avx512Gz,
}

impl FillKernel {
    /// Whether this CPU can run the kernel ([`FillKernel::Auto`] always can).
    ///
    /// ```
    /// use stance_topp::factored::FillKernel;
    /// assert!(FillKernel::Auto.is_available());
    /// // The two AVX-512 kernels need the same CPU features.
    /// assert_eq!(FillKernel::Avx512Gz.is_available(), FillKernel::Avx512.is_available());
    /// ```
    pub fn is_available(self) -> bool {
        match self {
            FillKernel::Auto | FillKernel::Portable => true,
            #[cfg(target_arch = "x86_64")]
            FillKernel::Avx2Fma => {
                std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
            }
            #[cfg(target_arch = "x86_64")]
            FillKernel::Avx512 | FillKernel::Avx512Gz => {
                std::is_x86_feature_detected!("avx512f") && std::is_x86_feature_detected!("fma")
            }
            #[cfg(not(target_arch = "x86_64"))]
            FillKernel::Avx2Fma | FillKernel::Avx512 | FillKernel::Avx512Gz => false,
        }
    }

    /// The kernel [`FillKernel::Auto`] stands for on this CPU (other kernels: themselves).
    ///
    /// ```
    /// use stance_topp::factored::FillKernel;
    /// assert_eq!(FillKernel::Portable.resolve(), FillKernel::Portable);
    /// ```
    pub fn resolve(self) -> FillKernel {
        match self {
            FillKernel::Auto => [FillKernel::Avx512Gz, FillKernel::Avx2Fma]
                .into_iter()
                .find(|k| k.is_available())
                .unwrap_or(FillKernel::Portable),
            k => k,
        }
    }

    /// A short name (`"auto"`, `"portable"`, `"avx2-fma"`, `"avx512"`, `"avx512-gz"`).
    ///
    /// ```
    /// use stance_topp::factored::FillKernel;
    /// assert_eq!(FillKernel::Avx512.name(), "avx512");
    /// assert_eq!(FillKernel::Avx512Gz.name(), "avx512-gz");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            FillKernel::Auto => "auto",
            FillKernel::Portable => "portable",
            FillKernel::Avx2Fma => "avx2-fma",
            FillKernel::Avx512 => "avx512",
            FillKernel::Avx512Gz => "avx512-gz",
        }
    }
}

/// The three 6-vectors of eq. 14 at one path point (see the module docs).
///
/// ```
/// use stance_topp::factored::eq14_vectors;
/// use stance_topp::path::PathPoint;
/// let q = PathPoint { p: [0.0, 0.0, 1.0], ps: [1.0, 0.0, 0.0], pss: [0.0; 3] };
/// let [wa, wb, wc] = eq14_vectors(&q, 2.0, [0.0, 0.0, -10.0], [0.0; 3], [0.0; 3]);
/// assert_eq!(wa, [-2.0, 0.0, 0.0, 0.0, -2.0, 0.0]); // -(m p_s, m p x p_s)
/// assert_eq!(wb, [0.0; 6]);
/// assert_eq!(wc, [0.0, 0.0, -20.0, 0.0, 0.0, 0.0]); // p x g = 0 for p on the z axis
/// ```
pub fn eq14_vectors(
    q: &PathPoint,
    mass: f64,
    gravity: [f64; 3],
    l1: [f64; 3],
    l2: [f64; 3],
) -> [[f64; 6]; 3] {
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let wrench = |v: [f64; 3], extra: [f64; 3], sign: f64| {
        let t = cross(q.p, v);
        [
            sign * mass * v[0],
            sign * mass * v[1],
            sign * mass * v[2],
            sign * (mass * t[0] + extra[0]),
            sign * (mass * t[1] + extra[1]),
            sign * (mass * t[2] + extra[2]),
        ]
    };
    [
        wrench(q.ps, l1, -1.0),
        wrench(q.pss, l2, -1.0),
        wrench(gravity, [0.0; 3], 1.0),
    ]
}

/// `U` stored by columns, and the three vectors of every grid point.
#[derive(Debug, Clone, PartialEq)]
pub struct FactoredRows {
    /// Columns of `U` (6 of length m), for vectorized sweeps over the rows.
    cols: [Vec<f64>; 6],
    s: Vec<f64>,
    w: Vec<[[f64; 6]; 3]>,
    /// `U_f w_c,f` per row when the force part of `w_c` is the same at every grid point (`m g`
    /// in eq. 14), so that `c = c_force + U_t w_c,t`.
    c_force: Option<Vec<f64>>,
    /// The last torque component of `w_c` is zero at every grid point (`p x g` for vertical `g`).
    c_tz_zero: bool,
    /// The constant force part of `w_c` is `(0, 0, f_z)` (vertical gravity): `c_force = U_z f_z`.
    c_force_vertical: bool,
    /// The columns again, once per load phase, for the AVX-512 kernel (`None` for `m < 8`,
    /// where that kernel computes rows one at a time, and on CPUs without AVX-512F).
    #[cfg(target_arch = "x86_64")]
    wide: Option<avx512::WideColumns>,
}

fn check_finite6(what: &'static str, v: &[[f64; 6]]) -> Result<(), ToppError> {
    for (i, r) in v.iter().enumerate() {
        if let Some((j, x)) = r.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(ToppError::NotFinite {
                what,
                point: i,
                row: j,
                value: *x,
            });
        }
    }
    Ok(())
}

/// `max |v_k|` with four independent accumulators (a single running maximum is a chain of
/// dependent operations, several times slower over the few thousand entries of `U` and `w`).
fn max_abs(v: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let mut chunks = v.chunks_exact(4);
    for c in &mut chunks {
        for k in 0..4 {
            acc[k] = acc[k].max(c[k].abs());
        }
    }
    for &x in chunks.remainder() {
        acc[0] = acc[0].max(x.abs());
    }
    acc[0].max(acc[1]).max(acc[2].max(acc[3]))
}

impl FactoredRows {
    /// From `U` (rows of 6) and per grid point `[w_a, w_b, w_c]`, with `a = U w_a`,
    /// `b = U w_b`, `c = U w_c` (in the notation `a_i = -U g_a_i`, `b_i = -U g_b_i`,
    /// `c_i = U g_c_i`: pass `w_a = -g_a`, `w_b = -g_b`, `w_c = g_c`; [`eq14_vectors`] does it).
    ///
    /// ```
    /// use stance_topp::factored::FactoredRows;
    /// let u = vec![[1.0, 0.0, 0.0, 0.0, 0.0, 0.0]];
    /// let w = vec![[[1.0; 6], [2.0; 6], [-3.0; 6]]; 2];
    /// let f = FactoredRows::new(&u, vec![0.0, 1.0], w).unwrap();
    /// let k = f.to_constraints();
    /// assert_eq!(k.rows_at(1)[0], stance_topp::Row { a: 1.0, b: 2.0, c: -3.0 });
    /// ```
    pub fn new(u: &[[f64; 6]], s: Vec<f64>, w: Vec<[[f64; 6]; 3]>) -> Result<Self, ToppError> {
        check_finite6("U", u)?;
        if w.len() != s.len() {
            return Err(ToppError::Shape {
                what: "factored vectors (one triple per grid point)".into(),
                expected: s.len(),
                got: w.len(),
            });
        }
        for (i, t) in w.iter().enumerate() {
            check_finite6("factored vector", &t[..]).map_err(|e| match e {
                ToppError::NotFinite {
                    what, row, value, ..
                } => ToppError::NotFinite {
                    what,
                    point: i,
                    row,
                    value,
                },
                e => e,
            })?;
        }
        // Grid validity is checked by CanonicalConstraints; check here too so errors come early.
        CanonicalConstraints::new(s.clone(), vec![0; s.len() + 1], vec![])?;
        // The fill writes rows that CanonicalConstraints never re-checks: bound the products.
        let u_max = max_abs(u.as_flattened());
        let w_max = max_abs(w.as_flattened().as_flattened());
        if 6.0 * u_max * w_max > crate::tol::MAX_ABS_COEFFICIENT {
            return Err(ToppError::InvalidValue {
                what: "factored rows",
                detail: format!(
                    "max |U| = {u_max:e} and max |w| = {w_max:e} give rows beyond {:e}; rescale \
                     U (its rows by positive factors) or the units of the wrenches",
                    crate::tol::MAX_ABS_COEFFICIENT
                ),
            });
        }
        let cols = std::array::from_fn(|k| u.iter().map(|r| r[k]).collect());
        // The grid check above guarantees at least two grid points.
        let force = &w[0][2][..3];
        let c_force = w.iter().all(|t| &t[2][..3] == force).then(|| {
            u.iter()
                .map(|r| {
                    madd::<false>(
                        r[2],
                        force[2],
                        madd::<false>(r[1], force[1], r[0] * force[0]),
                    )
                })
                .collect()
        });
        let c_tz_zero = w.iter().all(|t| t[2][5] == 0.0);
        let c_force_vertical = c_force.is_some() && force[0] == 0.0 && force[1] == 0.0;
        // Only where the AVX-512 kernel can run (8 copies of U, about 3 us for 172 rows).
        #[cfg(target_arch = "x86_64")]
        let wide = FillKernel::Avx512
            .is_available()
            .then(|| avx512::WideColumns::new(&cols, c_force.as_deref().unwrap_or(&[])))
            .flatten();
        Ok(Self {
            cols,
            s,
            w,
            c_force,
            c_tz_zero,
            c_force_vertical,
            #[cfg(target_arch = "x86_64")]
            wide,
        })
    }

    /// Eq. 14 along a sampled CoM path (point-mass model when `l1`, `l2` are `None`).
    ///
    /// ```
    /// use stance_topp::factored::FactoredRows;
    /// use stance_topp::path::PathPoint;
    /// let u = vec![[0.0, 0.0, 1.0, 0.0, 0.0, 0.0]]; // f_z <= 0 for w_GI: the weight points down
    /// let q = PathPoint { p: [0.0; 3], ps: [0.0, 0.0, 1.0], pss: [0.0; 3] };
    /// let f = FactoredRows::from_samples(&u, vec![0.0, 1.0], &[q, q], 1.0, [0.0, 0.0, -9.81], None)
    ///     .unwrap();
    /// let r = f.to_constraints().rows_at(0)[0];
    /// assert_eq!((r.a, r.b, r.c), (-1.0, 0.0, -9.81)); // u <= ... : s'' >= -9.81 (free fall)
    /// ```
    pub fn from_samples(
        u: &[[f64; 6]],
        s: Vec<f64>,
        samples: &[PathPoint],
        mass: f64,
        gravity: [f64; 3],
        angular: Option<&[[[f64; 3]; 2]]>,
    ) -> Result<Self, ToppError> {
        if !(mass.is_finite() && mass > 0.0) {
            return Err(ToppError::InvalidValue {
                what: "mass",
                detail: format!("{mass} kg; give a finite positive mass"),
            });
        }
        if let Some(v) = gravity.iter().find(|v| !v.is_finite()) {
            return Err(ToppError::NotFinite {
                what: "gravity",
                point: 0,
                row: 0,
                value: *v,
            });
        }
        if samples.len() != s.len() {
            return Err(ToppError::Shape {
                what: "path samples (one per grid point)".into(),
                expected: s.len(),
                got: samples.len(),
            });
        }
        if let Some(l) = angular {
            if l.len() != s.len() {
                return Err(ToppError::Shape {
                    what: "angular-momentum terms [l1, l2] (one pair per grid point)".into(),
                    expected: s.len(),
                    got: l.len(),
                });
            }
        }
        let w = samples
            .iter()
            .enumerate()
            .map(|(i, q)| {
                let [l1, l2] = angular.map_or([[0.0; 3]; 2], |l| l[i]);
                eq14_vectors(q, mass, gravity, l1, l2)
            })
            .collect();
        Self::new(u, s, w)
    }

    /// Eq. 14 along a CoM path evaluated at the grid `s` (point-mass model).
    ///
    /// ```
    /// use stance_topp::factored::FactoredRows;
    /// use stance_topp::path::Polyline;
    /// let path = Polyline::new(vec![0.0, 1.0], vec![[0.0; 3], [0.1, 0.0, 0.0]]).unwrap();
    /// let u = vec![[0.0, 0.0, 1.0, 0.0, 0.0, 0.0]];
    /// let f = FactoredRows::from_path(&u, vec![0.0, 0.5, 1.0], &path, 30.0, [0.0, 0.0, -9.81])
    ///     .unwrap();
    /// assert_eq!(f.to_constraints().num_points(), 3);
    /// ```
    pub fn from_path(
        u: &[[f64; 6]],
        s: Vec<f64>,
        path: &impl PathCurve,
        mass: f64,
        gravity: [f64; 3],
    ) -> Result<Self, ToppError> {
        let samples: Vec<PathPoint> = s.iter().map(|&si| path.eval(si)).collect();
        Self::from_samples(u, s, &samples, mass, gravity, None)
    }

    /// Number of rows per grid point (rows of `U`).
    ///
    /// ```
    /// use stance_topp::factored::FactoredRows;
    /// let f = FactoredRows::new(&[[0.0; 6]; 3], vec![0.0, 1.0], vec![[[0.0; 6]; 3]; 2]).unwrap();
    /// assert_eq!(f.num_rows(), 3);
    /// ```
    pub fn num_rows(&self) -> usize {
        self.cols[0].len()
    }

    /// New canonical constraints holding the rows (allocates once).
    ///
    /// ```
    /// use stance_topp::factored::FactoredRows;
    /// let f = FactoredRows::new(&[[1.0; 6]; 2], vec![0.0, 1.0], vec![[[1.0; 6]; 3]; 2]).unwrap();
    /// assert_eq!(f.to_constraints().rows().len(), 4);
    /// ```
    pub fn to_constraints(&self) -> CanonicalConstraints {
        let m = self.num_rows();
        let n = self.s.len();
        let offsets = (0..=n).map(|i| i * m).collect();
        let mut k = CanonicalConstraints::new(self.s.clone(), offsets, vec![Row::default(); n * m])
            .expect("grid validated at construction");
        self.fill(k.rows_mut()).expect("shape built just above");
        k
    }

    /// Rewrites the rows of constraints made by [`Self::to_constraints`] of a factored form with
    /// the same grid and number of rows (for example after `U` changed), without allocating.
    ///
    /// # Errors
    ///
    /// [`ToppError::InvalidValue`] when `k`'s grid or row counts differ.
    ///
    /// ```
    /// use stance_topp::factored::FactoredRows;
    /// let w = vec![[[1.0; 6], [0.0; 6], [-1.0; 6]]; 2];
    /// let f = FactoredRows::new(&[[1.0, 0.0, 0.0, 0.0, 0.0, 0.0]], vec![0.0, 1.0], w.clone())
    ///     .unwrap();
    /// let mut k = f.to_constraints();
    /// let g = FactoredRows::new(&[[3.0, 0.0, 0.0, 0.0, 0.0, 0.0]], vec![0.0, 1.0], w).unwrap();
    /// g.refill(&mut k).unwrap();
    /// assert_eq!(k.rows_at(1)[0].a, 3.0);
    /// let other = FactoredRows::new(&[[1.0; 6]], vec![0.0, 2.0], vec![[[0.0; 6]; 3]; 2]).unwrap();
    /// assert!(other.refill(&mut k).is_err());
    /// ```
    pub fn refill(&self, k: &mut CanonicalConstraints) -> Result<(), ToppError> {
        let m = self.num_rows();
        if k.grid() != self.s.as_slice() || k.offsets().iter().enumerate().any(|(i, &o)| o != i * m)
        {
            return Err(ToppError::InvalidValue {
                what: "constraints to refill",
                detail: format!(
                    "their grid or rows per point differ from this factored form ({} points, {m} \
                     rows each); build them with to_constraints",
                    self.s.len()
                ),
            });
        }
        self.fill(k.rows_mut())
    }

    /// Writes the rows of every grid point into `out` (`N + 1` times `m` rows, grid point after
    /// grid point): the hot path, no allocation.
    ///
    /// # Errors
    ///
    /// [`ToppError::Shape`] when `out` does not hold `(N + 1) m` rows.
    ///
    /// ```
    /// use stance_topp::factored::FactoredRows;
    /// use stance_topp::Row;
    /// let f = FactoredRows::new(&[[1.0, 2.0, 0.0, 0.0, 0.0, 0.0]], vec![0.0, 1.0],
    ///     vec![[[1.0; 6], [0.0; 6], [-1.0; 6]]; 2]).unwrap();
    /// let mut out = vec![Row::default(); 2];
    /// f.fill(&mut out).unwrap();
    /// assert_eq!(out[0].a, 3.0);
    /// assert_eq!(out[0].c, -3.0);
    /// assert!(f.fill(&mut out[..1]).is_err());
    /// ```
    pub fn fill(&self, out: &mut [Row]) -> Result<(), ToppError> {
        self.fill_with(out, FillKernel::Auto)
    }

    /// [`Self::fill`] with a chosen kernel (for comparisons and tests; [`FillKernel::Auto`] is
    /// what [`Self::fill`] runs).
    ///
    /// # Errors
    ///
    /// [`ToppError::Shape`] as [`Self::fill`]; [`ToppError::InvalidValue`] when this CPU cannot
    /// run `kernel` ([`FillKernel::is_available`]).
    ///
    /// ```
    /// use stance_topp::factored::{FactoredRows, FillKernel};
    /// use stance_topp::Row;
    /// let u: Vec<[f64; 6]> = (0..11).map(|j| [j as f64, 1.0, 0.0, 0.0, 0.0, 0.0]).collect();
    /// let f = FactoredRows::new(&u, vec![0.0, 1.0], vec![[[1.0; 6], [0.0; 6], [-1.0; 6]]; 2])
    ///     .unwrap();
    /// let mut fast = vec![Row::default(); 22];
    /// let mut portable = fast.clone();
    /// f.fill_with(&mut fast, FillKernel::Auto).unwrap();
    /// f.fill_with(&mut portable, FillKernel::Portable).unwrap();
    /// assert_eq!(fast, portable); // small integers: no round-off on either path
    /// assert_eq!(fast[11 + 10].a, 11.0);
    /// ```
    pub fn fill_with(&self, out: &mut [Row], which: FillKernel) -> Result<(), ToppError> {
        let m = self.num_rows();
        if out.len() != m * self.s.len() {
            return Err(ToppError::Shape {
                what: "output rows (grid points times rows of U)".into(),
                expected: m * self.s.len(),
                got: out.len(),
            });
        }
        let which = which.resolve();
        if !which.is_available() {
            return Err(ToppError::InvalidValue {
                what: "fill kernel",
                detail: format!(
                    "this CPU cannot run the {} kernel; use FillKernel::Auto",
                    which.name()
                ),
            });
        }
        let mode = match (&self.c_force, self.c_tz_zero) {
            (None, _) => CMode::Full,
            (Some(_), false) => CMode::ConstForce,
            (Some(_), true) if self.c_force_vertical && which == FillKernel::Avx512Gz => {
                CMode::VerticalForceNoTz
            }
            (Some(_), true) => CMode::ConstForceNoTz,
        };
        let c_force = self.c_force.as_deref().unwrap_or(&[]);
        match which {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: AVX-512F and FMA checked above; `out` has `w.len() m` rows; `c_force`
            // has `m` entries when `mode` uses it; `wide` was built from `cols` and `c_force`.
            FillKernel::Avx512 | FillKernel::Avx512Gz => unsafe {
                avx512::fill_avx512(&self.cols, c_force, self.wide.as_ref(), mode, &self.w, out)
            },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: AVX2 and FMA checked above.
            FillKernel::Avx2Fma => unsafe {
                kernel::fill_avx2(&self.cols, c_force, mode, &self.w, out)
            },
            _ => kernel::fill_portable(&self.cols, c_force, mode, &self.w, out),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Round-off allowed between a kernel and the naive sum, relative to `sum |u_q v_q|`: each
    /// side makes at most 6 roundings of about `EPSILON / 2` relative to that sum (a sum of
    /// six products, or a precomputed part plus three); 8 `EPSILON` bounds their difference.
    const KERNEL_ROUNDOFF: f64 = 8.0 * f64::EPSILON;

    /// Every kernel this CPU runs, each writing into slices at 8 different offsets of a larger
    /// buffer (so the AVX-512 kernel meets every alignment of its output), against a naive dot
    /// product per row; the fused kernels must agree bit for bit.
    fn check_against_naive(u: &[[f64; 6]], w: &[[[f64; 6]; 3]]) -> Result<(), TestCaseError> {
        let s: Vec<f64> = (0..w.len()).map(|i| i as f64).collect();
        let f = FactoredRows::new(u, s, w.to_vec()).unwrap();
        let total = u.len() * w.len();
        let mut fused: Option<Vec<Row>> = None;
        for which in [
            FillKernel::Portable,
            FillKernel::Avx2Fma,
            FillKernel::Avx512,
            FillKernel::Avx512Gz,
        ] {
            if !which.is_available() {
                prop_assert!(f
                    .fill_with(&mut vec![Row::default(); total], which)
                    .is_err());
                continue;
            }
            let mut buf = vec![Row::default(); total + 8];
            for off in 0..8 {
                buf.fill(Row {
                    a: f64::NAN,
                    b: f64::NAN,
                    c: f64::NAN,
                });
                f.fill_with(&mut buf[off..off + total], which).unwrap();
                prop_assert!(buf[..off]
                    .iter()
                    .chain(&buf[off + total..])
                    .all(|r| r.a.is_nan()));
                let got = &buf[off..off + total];
                for (i, wi) in w.iter().enumerate() {
                    for (j, uj) in u.iter().enumerate() {
                        let dot = |v: &[f64; 6]| (0..6).map(|q| uj[q] * v[q]).sum::<f64>();
                        let mag = |v: &[f64; 6]| (0..6).map(|q| (uj[q] * v[q]).abs()).sum::<f64>();
                        let want = [dot(&wi[0]), dot(&wi[1]), dot(&wi[2])];
                        let scale = [mag(&wi[0]), mag(&wi[1]), mag(&wi[2])];
                        let r = got[i * u.len() + j];
                        for ((g, e), sc) in [r.a, r.b, r.c].iter().zip(want).zip(scale) {
                            prop_assert!(
                                (g - e).abs() <= KERNEL_ROUNDOFF * sc,
                                "{g} vs {e} (scale {sc}, kernel {}, point {i}, row {j})",
                                which.name()
                            );
                        }
                    }
                }
                if which != FillKernel::Portable {
                    match &fused {
                        None => fused = Some(got.to_vec()),
                        Some(first) => prop_assert!(
                            first.as_slice() == got,
                            "{} differs from the other fused kernel (offset {off})",
                            which.name()
                        ),
                    }
                }
            }
        }
        let mut auto = vec![Row::default(); total];
        f.fill(&mut auto).unwrap();
        if let Some(first) = &fused {
            prop_assert!(first == &auto);
        }
        Ok(())
    }

    /// Large `U` (the AVX-512 kernel then sweeps the grid in several chunks, with load-phase
    /// periods 2, 8 and 1), deterministic pseudo-random entries.
    #[test]
    fn fill_matches_naive_products_for_large_u() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for (m, n) in [(1100, 21), (1099, 19), (1096, 17)] {
            let u: Vec<[f64; 6]> = (0..m).map(|_| std::array::from_fn(|_| next())).collect();
            let w: Vec<[[f64; 6]; 3]> = (0..n)
                .map(|_| std::array::from_fn(|_| std::array::from_fn(|_| 100.0 * next())))
                .collect();
            check_against_naive(&u, &w).unwrap();
        }
    }

    /// Eq. 14 with vertical gravity on large `U` (the path [`FillKernel::Avx512Gz`] speeds up:
    /// `c_force = U_z m g_z` recomputed), with load-phase periods 2, 8, 1 and 4, and on the
    /// sizes of the benchmark instances (137 and 172 rows, 101 grid points).
    #[test]
    fn fill_with_vertical_gravity_matches_naive_products_for_large_u() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for (m, n) in [
            (1100, 9),
            (1099, 9),
            (1096, 9),
            (172, 101),
            (137, 101),
            (60, 7),
        ] {
            let u: Vec<[f64; 6]> = (0..m).map(|_| std::array::from_fn(|_| next())).collect();
            let w: Vec<[[f64; 6]; 3]> = (0..n)
                .map(|_| {
                    let mut v = || [2.0 * next(), 2.0 * next(), 2.0 * next()];
                    let q = PathPoint {
                        p: v(),
                        ps: v(),
                        pss: v(),
                    };
                    eq14_vectors(&q, 38.0, [0.0, 0.0, -9.81], [0.0; 3], [0.0; 3])
                })
                .collect();
            let s: Vec<f64> = (0..n).map(|i| i as f64).collect();
            let f = FactoredRows::new(&u, s, w.clone()).unwrap();
            assert!(f.c_force_vertical && f.c_tz_zero);
            check_against_naive(&u, &w).unwrap();
        }
    }

    proptest! {
        /// General `w_c` (full 6-term product for `c`).
        #[test]
        fn fill_matches_naive_products(
            u in prop::collection::vec(prop::array::uniform6(-1.0f64..1.0), 1..60),
            w in prop::collection::vec(prop::array::uniform3(prop::array::uniform6(-100.0f64..100.0)), 2..6),
        ) {
            check_against_naive(&u, &w)?;
        }

        /// Eq. 14 along random CoM samples, with vertical and with tilted gravity: the constant
        /// force part of `w_c` (and, for vertical `g`, its zero last torque component) is
        /// detected and the shortened products agree with the naive ones.
        #[test]
        fn fill_with_eq14_structure_matches_naive_products(
            u in prop::collection::vec(prop::array::uniform6(-1.0f64..1.0), 1..60),
            p in prop::collection::vec(prop::array::uniform3(prop::array::uniform3(-2.0f64..2.0)), 2..6),
            tilt in prop::array::uniform2(-0.3f64..0.3),
            vertical in any::<bool>(),
        ) {
            let g = if vertical { [0.0, 0.0, -9.81] } else { [tilt[0], tilt[1], -9.81] };
            let w: Vec<[[f64; 6]; 3]> = p
                .iter()
                .map(|q| {
                    let q = PathPoint { p: q[0], ps: q[1], pss: q[2] };
                    eq14_vectors(&q, 38.0, g, [0.0; 3], [0.0; 3])
                })
                .collect();
            let s: Vec<f64> = (0..w.len()).map(|i| i as f64).collect();
            let f = FactoredRows::new(&u, s, w.clone()).unwrap();
            prop_assert!(f.c_force.is_some());
            prop_assert_eq!(f.c_tz_zero, vertical || w.iter().all(|t| t[2][5] == 0.0));
            prop_assert_eq!(f.c_force_vertical, vertical || tilt == [0.0; 2]);
            check_against_naive(&u, &w)?;
        }
    }
}
