//! Wrench preconditioning ([`crate::DdOptions::wrench`]): re-centre 6-D wrench cones on their own
//! contacts and measure torques in their own length unit before the conversion, so that the
//! answer does not depend on the reference point or on the unit of length.
//!
//! # Math
//!
//! Rows are wrenches `w = (f, tau)` (`f` the force, `tau` the moment about the reference point,
//! in that order). For a point `o` and a length `L > 0` let
//!
//! ```text
//! M (f, tau)       = (f, (tau - o x f) / L)          wrenches (vectors) forward
//! M^{-1} (f', t')  = (f', o x f' + L t')             wrenches back
//! M^{-T} (u_f, u_t) = (u_f - o x u_t, L u_t)          covectors (facet normals) forward
//! M^T (u_f', u_t') = (u_f' + o x u_t' / L, u_t' / L)  covectors back
//! ```
//!
//! `M` is invertible for every `o` and `L > 0`, so `span(M V) = M span(V)`: the conversion of
//! `M V` gives facets `u'` (`u' . M x <= 0`, i.e. `u = M^T u'` for `x`), equations likewise,
//! lineality directions `x = M^{-1} x'`, and the same extreme generators (a row is extreme in
//! `V` iff it is in `M V`).
//!
//! **The centre.** Each row with a force is read as a unit force direction `d_i = f_i / |f_i|`
//! and a moment per unit force `m_i = tau_i / |f_i|` (a positive scale of a row does not change
//! the cone, so it must not change the fit); `|m_i - o x d_i|` is its lever arm about `o`.
//! `o` minimizes `sum_i w_i |m_i - o x d_i|^2`: the normal equations are `A o = b` with
//! `A = sum_i w_i (I - d_i d_i^T)` (symmetric, positive semi-definite) and
//! `b = sum_i w_i d_i x m_i`. For wrenches of forces applied at one point `p`
//! (`tau_i = p x f_i`), `o = p`. The fit runs twice: first with `w_i = |f_i|^2 / |(f_i, tau_i)|^2`
//! (the rows normalized, so that rows with almost no force - lever arms near infinity, like
//! facet normals without torque part in face -> span - weigh little), then with `w_i = 1` on the
//! rows whose lever arm about the first centre is at most
//! [`crate::tol::Tolerances::wrench_outlier`] times the median. `A` is singular exactly when
//! every force is parallel to a line; along such null directions `n` (eigenvalues at most
//! [`crate::tol::Tolerances::wrench_center`] times the largest) the lever arms do not depend on
//! `o` (`n x d_i = 0`), and `o` takes the minimum-norm solution (component 0). Moving the
//! reference point by `s` (`tau_i -> tau_i - s x f_i`) moves `o` by `s` (up to the null
//! directions, which do not change `o x f_i`), so the re-centred torques `tau_i - o x f_i` do
//! not depend on where the reference point was, up to rounding (`|s| u` relative to the
//! torques at the contacts, `u` the unit roundoff: `~3e-11` for 30 km and 0.1 m feet) - and
//! up to the first fit's weights, which change with the reference point when the rows' lever
//! arms differ (they only select the rows of the second fit).
//! The fit is computed on the rows scaled by a power of two (exact) so that its sums neither
//! overflow nor underflow.
//!
//! **The length.** `L` is the median lever arm `|m_i - o x d_i|` over the rows with a force: the
//! size of the contact set seen from `o` (a median, so that a few rows at "infinity" do not
//! set it). Measuring lengths in another unit (`tau -> c tau`) gives `o -> c o` and `L -> c L`,
//! so the re-centred generators `(f, (tau - o x f) / L)` do not change: the conversion no longer
//! sees the unit. When no row has a force (norm above
//! [`crate::tol::Tolerances::zero_generator`] times the row's), `o = 0` and `L = 1` (the cone
//! then does not mix forces and torques, and the unit does not matter).
//!
//! **Rounding.** Where `tau_i - o x f_i` cancels (the torque of a force through `o`), it is
//! computed with an error of about `u |o| |f_i|` (`u` the unit roundoff; `|o|` is about the
//! distance from the reference point to the contacts, and the caller's torques were already
//! rounded at that scale). When every re-centred torque cancels (a point contact: all forces
//! through `o`), dividing that noise by an `L` made of it would blow it up to the size of the
//! forces and invent a 6-D cone; so `L` is at least
//! [`crate::tol::Tolerances::wrench_length`] times `|o|`, which keeps the noise at most
//! `u / wrench_length` (`1.1e-11`) relative to the forces, below the rank threshold. The floor
//! depends on the reference point; it is active only when the contacts are smaller than
//! `wrench_length` times their distance to it (`0.3 m` at 30 km), where it only scales the
//! torques (the whitening undoes any scaling; the rank decision sees it, with a margin of
//! `L / size` far above its threshold).
//!
//! Together: the same stance written about any reference point and in any unit of length gives
//! the same re-centred generators up to rounding, so the rank decision
//! ([`crate::tol::Tolerances::rank`]) - the one step of the conversion the whitening of
//! [`crate::precondition`] does not make invariant - is taken on the same numbers.
//!
//! **face -> span.** The input rows are covectors `u = (u_f, u_t)`; the same fit with the roles
//! swapped (`u_t` plays the force, `u_f` the moment: moving the reference point by `s` maps
//! `u_f -> u_f + s x u_t`) gives `o` and `L`, hence `M`, from the facets; the conversion runs
//! on the rows `M^{-T} u = (u_f - o x u_t, L u_t)`, the facets of the re-centred cone `M C`
//! (not necessarily the `M` the generators of `C` would give: any invertible `M` is exact,
//! this one is computed from what the caller gave; facets computed far from the contacts carry
//! the rounding of that frame amplified in their torque-free part, so this frame is less
//! invariant than the one of the generators: 0.1 m apart for the stairs about a point 30 km
//! away). The extreme rays `x'` and lineality of
//! `M C` map back by `M^{-1}`; the indices of irredundant facets are unchanged.
//!
//! # What is and is not guaranteed
//!
//! - The answer is mapped back exactly (up to rounding) to the caller's coordinates: facets and
//!   equations by `M^T` (facets then projected orthogonally to the equations and normalized;
//!   equations and lineality re-orthonormalized, keeping their count). Facets stay in
//!   lexicographic order.
//! - The certificate is the one of the re-centred problem `M V`: its angles and residuals are
//!   measured in the re-centred, whitened coordinates, not in the caller's.
//! - Invariance is up to rounding of `tau - o x f`, and of the input itself: wrenches written
//!   about a point `s` away from the contacts carry torque errors of `|s| u |f|` from the
//!   start, which no re-centring removes. Structure degenerate within
//!   [`crate::tol::Tolerances::incidence`] of the re-centred problem may then be merged
//!   differently for different reference points: the stairs stance gives its 176 facets in
//!   floating point up to 100 km away, but written about `(1e6, 1e6, 1e6)` m its rounded input
//!   fails the float certificate and the exact fallback returns 353 facets (the slivers of the
//!   rounding; 339 without the option). Smaller patches break much sooner: in the property
//!   test `shifted_rescaled_stances` of `tests/wrench.rs` (two rectangles with sides of 1 to
//!   20 cm, reference points up to 1.7 km away, lengths in units from 1 mm to 1 km), 7 of
//!   10,000 random stances came back from the exact fallback with twice the facets or more
//!   (three of them printed: 744 to 1281 m away, smallest sides 1.1 to 3.1 cm; another run
//!   printed one 721 m away with a smallest side of 8.7 cm). Where their
//!   facets differ from those at the stance's own origin, both answers agree with the
//!   membership oracle (the test checks it).
//! - face -> span is far more sensitive to the frame than span -> face: facets written in a
//!   far frame carry that frame's rounding in their torque-free part, and the re-centred,
//!   whitened facets of the stairs stance about a point 10 km away differ from the exact ones
//!   by `1e-10` to `1e-9`, at [`crate::tol::Tolerances::incidence`]. Measured on the stairs
//!   (176 facets from span -> face with the option, then face -> span with it, facets as
//!   returned and with every entry moved by one unit in the last place, 6 runs per point, 3
//!   directions): the 32 extreme rays every time up to 3 km; from 10 km (and at 30 km) the
//!   float certificate fails almost every time (a review's rerun had 1 of 6 runs pass at
//!   10 km in one direction) and the exact fallback returns 3300 to 4000 rays, the exact
//!   answer for the rounded facets (slow: `bench/peers/cones.md`). `tests/wrench.rs` checks
//!   1 km, with the one-ulp perturbations.
//! - Only for `d = 6` with rows `(f_x, f_y, f_z, tau_x, tau_y, tau_z)`; with
//!   [`crate::Arithmetic::Exact`] the option is refused (the map rounds the input, and exact
//!   mode already decides ranks exactly). The exact fallback of tolerance mode runs on the
//!   re-centred (rounded) input. [`crate::Continuation`] refuses the option.
//!
//! # Cost
//!
//! Two least-squares fits and a median over the input, the map, copies of the input and of
//! the answer, and one small SVD per non-empty equation or lineality basis: linear in the
//! number of generators and facets, small against the double description and the
//! certificate, so a stance at its own origin converts only slightly slower with the option
//! than without it. Far from the origin the option keeps the conversion in floating point where
//! without it the cone loses dimensions (30 km, 100 km) or fails its float certificate and
//! falls back to exact arithmetic (50 km along `x`), far slower. The figures, and the command
//! that measures them, are in `bench/peers/cones.md`.
//!
use nalgebra::{DMatrix, Matrix3, SymmetricEigen, Vector3};

use crate::linalg::{normalize, sorted_svd};
use crate::tol::Tolerances;
use crate::ConeError;

/// The dimension of a wrench `(f, tau)`.
pub const WRENCH_DIM: usize = 6;

/// The frame of the wrench preconditioning: `M (f, tau) = (f, (tau - o x f) / L)` (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WrenchFrame {
    /// The centre `o` (in the caller's unit of length, coordinates about its reference point).
    pub center: [f64; 3],
    /// The length scale `L > 0`, the median lever arm about `center` (same unit).
    pub length: f64,
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm3(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// `|m - o x d|` for a unit force direction `d` and moment per unit force `m`.
fn lever(d: [f64; 3], m: [f64; 3], o: [f64; 3]) -> f64 {
    let od = cross(o, d);
    norm3([m[0] - od[0], m[1] - od[1], m[2] - od[2]])
}

/// The median of the lever arms about `o` (the upper one for an even count).
fn median_lever(levers: &[([f64; 3], [f64; 3], f64)], o: [f64; 3]) -> f64 {
    let mut r: Vec<f64> = levers.iter().map(|(d, m, _)| lever(*d, *m, o)).collect();
    r.sort_by(f64::total_cmp);
    r[r.len() / 2]
}

/// The weighted least-squares centre: minimizes `sum_i w_i |m_i - o x d_i|^2`, minimum-norm
/// along the eigenvectors of `A` at most `wrench_center` times its largest eigenvalue.
fn solve_center(levers: &[([f64; 3], [f64; 3], f64)], w: &[f64], tol: &Tolerances) -> [f64; 3] {
    let mut m_a = Matrix3::<f64>::zeros();
    let mut rhs = Vector3::<f64>::zeros();
    for ((d, m, _), &wi) in levers.iter().zip(w) {
        let dv = Vector3::from(*d);
        m_a += (Matrix3::identity() * dv.norm_squared() - dv * dv.transpose()) * wi;
        rhs += Vector3::from(cross(*d, *m)) * wi;
    }
    let eig = SymmetricEigen::new(m_a);
    let lmax = eig.eigenvalues.iter().fold(0.0f64, |m, &l| m.max(l));
    let mut o = Vector3::<f64>::zeros();
    if lmax > 0.0 {
        for k in 0..3 {
            let l = eig.eigenvalues[k];
            if l > tol.wrench_center * lmax {
                let q = eig.eigenvectors.column(k);
                o += q * (q.dot(&rhs) / l);
            }
        }
    }
    [o[0], o[1], o[2]]
}

fn check_dim(d: usize) -> Result<(), ConeError> {
    if d == WRENCH_DIM {
        Ok(())
    } else {
        Err(ConeError::NotAWrench { dim: d })
    }
}

/// Checks that the wrench preconditioning applies: `d = 6`, tolerance arithmetic.
pub(crate) fn check_options(d: usize, opts: &crate::DdOptions) -> Result<(), ConeError> {
    check_dim(d)?;
    if opts.arithmetic == crate::Arithmetic::Exact {
        return Err(ConeError::IncompatibleOptions(
            "`wrench` with exact arithmetic: the re-centring rounds the input, and exact mode \
             decides ranks exactly without it; drop one of the two",
        ));
    }
    Ok(())
}

impl WrenchFrame {
    /// The frame of wrench generators `v` (`n x 6`, rows `(f, tau)`, finite): `o` the least
    /// squares centre, `L` the median lever arm about it (module docs). The fit sees only the
    /// rows, not the cone, so duplicate generators count as given.
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, tol::Tolerances, wrench::WrenchFrame};
    /// // Forces (0, 0, 1) at (+-2, 0, 0) and (1, 0, 0) at (0, 0, +-2), about a reference point
    /// // such that the contacts are centred on c = (10, -20, 30): tau = p x f.
    /// let c = [10.0, -20.0, 30.0];
    /// let wrench = |p: [f64; 3], f: [f64; 3]| {
    ///     let p = [p[0] + c[0], p[1] + c[1], p[2] + c[2]];
    ///     [f[0], f[1], f[2], p[1] * f[2] - p[2] * f[1], p[2] * f[0] - p[0] * f[2], p[0] * f[1] - p[1] * f[0]]
    /// };
    /// let rows = [
    ///     wrench([2.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
    ///     wrench([-2.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
    ///     wrench([0.0, 0.0, 2.0], [1.0, 0.0, 0.0]),
    ///     wrench([0.0, 0.0, -2.0], [1.0, 0.0, 0.0]),
    /// ];
    /// let v = DMatrix::from_fn(4, 6, |i, j| rows[i][j]);
    /// let fr = WrenchFrame::of_wrenches(&v, &Tolerances::default()).unwrap();
    /// for k in 0..3 {
    ///     assert!((fr.center[k] - c[k]).abs() < 1e-12);
    /// }
    /// // Every lever arm is 2.
    /// assert!((fr.length - 2.0).abs() < 1e-12);
    /// // Not 6-D: an error, not a panic.
    /// assert!(WrenchFrame::of_wrenches(&DMatrix::zeros(1, 3), &Tolerances::default()).is_err());
    /// ```
    pub fn of_wrenches(v: &DMatrix<f64>, tol: &Tolerances) -> Result<Self, ConeError> {
        check_dim(v.ncols())?;
        Ok(Self::fit(v, 0, 3, tol))
    }

    /// The frame of covector rows `u` (`n x 6`, rows `(u_f, u_t)`: facets and equations of a
    /// wrench cone, finite), such that `M^{-T} u = (u_f - o x u_t, L u_t)` is re-centred
    /// (module docs, face -> span).
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, tol::Tolerances, wrench::WrenchFrame};
    /// // Facet normals (u_f, u_t), and the same facets for wrenches written about a reference
    /// // point moved by -s (u_f -> u_f + s x u_t): the centres differ by s, the lengths agree.
    /// let u0 = DMatrix::from_row_slice(3, 6, &[
    ///     0.1, 0.2, 0.0, 1.0, 0.0, 0.0,
    ///     0.0, -0.3, 0.1, 0.0, 1.0, 0.0,
    ///     0.2, 0.0, -0.1, 0.0, 0.5, 1.0,
    /// ]);
    /// let s = [1000.0, -700.0, 30.0];
    /// let mut u1 = u0.clone();
    /// for i in 0..3 {
    ///     let t = [u0[(i, 3)], u0[(i, 4)], u0[(i, 5)]];
    ///     u1[(i, 0)] += s[1] * t[2] - s[2] * t[1];
    ///     u1[(i, 1)] += s[2] * t[0] - s[0] * t[2];
    ///     u1[(i, 2)] += s[0] * t[1] - s[1] * t[0];
    /// }
    /// let tol = Tolerances::default();
    /// let (f0, f1) = (WrenchFrame::of_covectors(&u0, &tol).unwrap(), WrenchFrame::of_covectors(&u1, &tol).unwrap());
    /// for k in 0..3 {
    ///     assert!((f1.center[k] - f0.center[k] - s[k]).abs() < 1e-9);
    /// }
    /// assert!((f1.length - f0.length).abs() < 1e-9 * f0.length);
    /// ```
    pub fn of_covectors(u: &DMatrix<f64>, tol: &Tolerances) -> Result<Self, ConeError> {
        check_dim(u.ncols())?;
        Ok(Self::fit(u, 3, 0, tol))
    }

    /// The fit on rows whose "force" block starts at column `a` and "moment" block at `b`.
    fn fit(v: &DMatrix<f64>, a: usize, b: usize, tol: &Tolerances) -> Self {
        // A power of two (exact; o and L do not depend on a common scale of the rows) so that
        // the sums below neither overflow nor underflow.
        let amax = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let (s1, s2) = if amax > 0.0 {
            let e = amax.log2().floor() as i32;
            (2f64.powi(-(e / 2)), 2f64.powi(-(e - e / 2)))
        } else {
            (1.0, 1.0)
        };
        let rows: Vec<([f64; 3], [f64; 3])> = (0..v.nrows())
            .map(|i| {
                let g = |c: usize| v[(i, c)] * s1 * s2;
                ([g(a), g(a + 1), g(a + 2)], [g(b), g(b + 1), g(b + 2)])
            })
            .collect();
        // Per row: the force direction and the moment per unit force, `(a_i, b_i) / |a_i|`
        // (a positive scale of a row does not change the cone); rows without force are left out.
        let levers: Vec<([f64; 3], [f64; 3], f64)> = rows
            .iter()
            .filter_map(|(f, t)| {
                let nf = norm3(*f);
                let nrow = (nf * nf + norm3(*t).powi(2)).sqrt();
                (nf > 0.0 && nf > tol.zero_generator * nrow).then(|| {
                    let d = [f[0] / nf, f[1] / nf, f[2] / nf];
                    let m = [t[0] / nf, t[1] / nf, t[2] / nf];
                    // Weight of the first fit: the row normalized to unit norm.
                    (d, m, (nf / nrow).powi(2))
                })
            })
            .collect();
        if levers.is_empty() {
            return Self {
                center: [0.0; 3],
                length: 1.0,
            };
        }
        // First fit: unit rows (rows at "infinite" lever arm weigh little), then the rows whose
        // lever arm about it exceeds `wrench_outlier` times the median are left out of the
        // second fit, where every row weighs the same.
        let all: Vec<f64> = levers.iter().map(|l| l.2).collect();
        let o1 = solve_center(&levers, &all, tol);
        let l1 = median_lever(&levers, o1).max(tol.wrench_length * norm3(o1));
        let trimmed: Vec<f64> = levers
            .iter()
            .map(|(d, m, _)| {
                if lever(*d, *m, o1) <= tol.wrench_outlier * l1 {
                    1.0
                } else {
                    0.0
                }
            })
            .collect();
        let center = if trimmed.iter().any(|&w| w > 0.0) {
            solve_center(&levers, &trimmed, tol)
        } else {
            o1
        };
        let length = median_lever(&levers, center).max(tol.wrench_length * norm3(center));
        let length = if length.is_finite() && length > 0.0 {
            length
        } else {
            1.0
        };
        Self { center, length }
    }

    /// `M x` on every row (wrenches forward).
    pub(crate) fn vectors_forward(&self, v: &DMatrix<f64>) -> DMatrix<f64> {
        let mut out = v.clone();
        for i in 0..v.nrows() {
            let f = [v[(i, 0)], v[(i, 1)], v[(i, 2)]];
            let of = cross(self.center, f);
            for k in 0..3 {
                out[(i, 3 + k)] = (v[(i, 3 + k)] - of[k]) / self.length;
            }
        }
        out
    }

    /// `M^{-1} x'` on one row (wrenches back).
    fn vector_back(&self, x: &mut [f64]) {
        let of = cross(self.center, [x[0], x[1], x[2]]);
        for k in 0..3 {
            x[3 + k] = of[k] + self.length * x[3 + k];
        }
    }

    /// `M^{-T} u` on every row (covectors forward).
    pub(crate) fn covectors_forward(&self, u: &DMatrix<f64>) -> DMatrix<f64> {
        let mut out = u.clone();
        for i in 0..u.nrows() {
            let t = [u[(i, 3)], u[(i, 4)], u[(i, 5)]];
            let ot = cross(self.center, t);
            for k in 0..3 {
                out[(i, k)] = u[(i, k)] - ot[k];
                out[(i, 3 + k)] = self.length * t[k];
            }
        }
        out
    }

    /// `M^T u'` on one row (covectors back).
    fn covector_back(&self, u: &mut [f64]) {
        let t = [u[3] / self.length, u[4] / self.length, u[5] / self.length];
        let ot = cross(self.center, t);
        for (uk, ok) in u[..3].iter_mut().zip(ot) {
            *uk += ok;
        }
        u[3..].copy_from_slice(&t);
    }

    /// The maps back of the module docs on every row: `M^{-1}` on vectors (`vectors`), `M^T`
    /// on covectors (otherwise).
    fn rows_back(&self, m: &DMatrix<f64>, vectors: bool) -> Vec<Vec<f64>> {
        (0..m.nrows())
            .map(|i| {
                let mut x: Vec<f64> = m.row(i).iter().copied().collect();
                if vectors {
                    self.vector_back(&mut x);
                } else {
                    self.covector_back(&mut x);
                }
                x
            })
            .collect()
    }

    /// Maps an orthonormal basis of a subspace back (vectors by `M^{-1}`, covectors by `M^T`) and
    /// re-orthonormalizes it, keeping its dimension (the map is invertible).
    pub(crate) fn basis_back(&self, m: &DMatrix<f64>, vectors: bool) -> DMatrix<f64> {
        let k = m.nrows();
        if k == 0 {
            return m.clone();
        }
        let rows = self.rows_back(m, vectors);
        let mapped = DMatrix::from_fn(k, WRENCH_DIM, |i, j| rows[i][j]);
        let (_, vt) = sorted_svd(&mapped);
        vt.rows(0, k).into_owned()
    }

    /// Maps unit rays back (vectors by `M^{-1}`, covectors by `M^T`), removes their components
    /// along the orthonormal rows of `ortho` (the equations, or the lineality space: the rays
    /// are defined modulo those, or orthogonal to them) and normalizes them, in their order.
    /// [`sorted_rows`] then gives the answer's order.
    pub(crate) fn rays_back(
        &self,
        m: &DMatrix<f64>,
        vectors: bool,
        ortho: &[&DMatrix<f64>],
    ) -> DMatrix<f64> {
        let mut rows = self.rows_back(m, vectors);
        for x in rows.iter_mut() {
            for basis in ortho {
                for b in 0..basis.nrows() {
                    let c: f64 = basis.row(b).iter().zip(x.iter()).map(|(p, q)| p * q).sum();
                    for (xv, pv) in x.iter_mut().zip(basis.row(b).iter()) {
                        *xv -= c * pv;
                    }
                }
            }
            normalize(x);
        }
        DMatrix::from_fn(rows.len(), WRENCH_DIM, |i, j| rows[i][j])
    }
}

/// The rows of `m` sorted lexicographically (the order of the wrench route's answers).
pub(crate) fn sorted_rows(m: &DMatrix<f64>) -> DMatrix<f64> {
    let mut order: Vec<usize> = (0..m.nrows()).collect();
    order.sort_by(|&a, &b| {
        m.row(a)
            .iter()
            .zip(m.row(b).iter())
            .map(|(x, y)| x.total_cmp(y))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    m.select_rows(order.iter())
}
