//! CoM half-spaces `a . p <= d` of one gravity vector, and the tight test loop over them.

use crate::{ContactError, Giwc};

/// Half-spaces `normals[i] . p <= offsets[i]` (unit normals, offsets in metres) on the CoM.
#[derive(Debug, Clone, PartialEq)]
pub struct ComHalfspaces {
    /// Unit normals `a_i`.
    pub normals: Vec<[f64; 3]>,
    /// Offsets `d_i` (m).
    pub offsets: Vec<f64>,
    /// True when a CoM-independent row is violated: no CoM is stable.
    pub infeasible: bool,
}

impl ComHalfspaces {
    /// Appends the rows of `other` (intersection of the two sets).
    pub(crate) fn extend(&mut self, other: ComHalfspaces) {
        self.normals.extend(other.normals);
        self.offsets.extend(other.offsets);
        self.infeasible |= other.infeasible;
    }

    /// Largest residual `max_i (a_i . p - d_i)` (m; `-inf` without rows, `+inf` when
    /// infeasible); `<= 0` inside.
    ///
    /// ```
    /// use stance_contact::ComHalfspaces;
    /// let h = ComHalfspaces { normals: vec![[1.0, 0.0, 0.0]], offsets: vec![0.5], infeasible: false };
    /// assert_eq!(h.max_residual([1.0, 0.0, 0.0]), 0.5);
    /// ```
    pub fn max_residual(&self, p: [f64; 3]) -> f64 {
        if self.infeasible {
            return f64::INFINITY;
        }
        self.normals
            .iter()
            .zip(&self.offsets)
            .map(|(a, d)| a[0] * p[0] + a[1] * p[1] + a[2] * p[2] - d)
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// The static-equilibrium half-spaces of the CoM for one gravity vector `g` (m/s^2):
/// `a = g x u_t`, `d = -u_f . g` per row of `U_stance`, two per equation, normalized; rows with
/// `|a| <= zero_normal |g|` are checked as `0 <= d` (within `face_tol |g|`) and dropped.
///
/// ```
/// use stance_contact::{com_halfspaces, examples};
/// let giwc = examples::single_support_flat().stance().unwrap().u_stance(&Default::default()).unwrap();
/// let h = com_halfspaces(&giwc, [0.0, 0.0, -9.81], 1e-12, 1e-9).unwrap();
/// assert!(!h.infeasible);
/// assert!(h.normals.iter().all(|a| a[2].abs() < 1e-12)); // vertical gravity: a vertical prism
/// ```
pub fn com_halfspaces(
    giwc: &Giwc,
    gravity: [f64; 3],
    zero_normal: f64,
    face_tol: f64,
) -> Result<ComHalfspaces, ContactError> {
    if gravity.iter().any(|x| !x.is_finite()) {
        return Err(ContactError::NonFinite {
            what: "gravity".into(),
        });
    }
    for (m, what) in [(&giwc.facets, "facets"), (&giwc.equations, "equations")] {
        if m.nrows() > 0 && m.ncols() != 6 {
            return Err(ContactError::BadShape(format!(
                "GIWC {what} must have 6 columns (force, torque), got {}",
                m.ncols()
            )));
        }
    }
    if gravity.iter().all(|&x| x == 0.0) {
        return Err(ContactError::BadGravity {
            gravity,
            reason: "the zero vector: give a non-zero gravity (e.g. [0, 0, -9.81])".into(),
        });
    }
    // The half-spaces do not depend on |g|: work with g scaled to a largest component of 1.
    let g = super::scaled_gravity(gravity);
    let gn = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    let mut out = ComHalfspaces {
        normals: Vec::with_capacity(giwc.facets.nrows() + 2 * giwc.equations.nrows()),
        offsets: Vec::with_capacity(giwc.facets.nrows() + 2 * giwc.equations.nrows()),
        infeasible: false,
    };
    let push = |u: [f64; 6], out: &mut ComHalfspaces| {
        let a = crate::cross(g, [u[3], u[4], u[5]]);
        let d = -(u[0] * g[0] + u[1] * g[1] + u[2] * g[2]);
        let an = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        if an <= zero_normal * gn {
            if d < -face_tol * gn {
                out.infeasible = true;
            }
            return;
        }
        out.normals.push([a[0] / an, a[1] / an, a[2] / an]);
        out.offsets.push(d / an);
    };
    let row = |m: &nalgebra::DMatrix<f64>, i: usize| {
        let mut u = [0.0; 6];
        for (k, x) in u.iter_mut().enumerate() {
            *x = m[(i, k)];
        }
        u
    };
    for i in 0..giwc.facets.nrows() {
        push(row(&giwc.facets, i), &mut out);
    }
    for i in 0..giwc.equations.nrows() {
        let e = row(&giwc.equations, i);
        push(e, &mut out);
        push(e.map(|x| -x), &mut out);
    }
    Ok(out)
}

/// Batch outputs must match the points one to one.
pub(crate) fn same_length(points: usize, out: usize) -> Result<(), ContactError> {
    if points == out {
        Ok(())
    } else {
        Err(ContactError::BadShape(format!(
            "{points} points but {out} output slots: give one output per point"
        )))
    }
}

/// Structure-of-arrays copy of half-spaces for the batch test loop (no allocation per point).
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct Tester {
    ax: Vec<f64>,
    ay: Vec<f64>,
    az: Vec<f64>,
    d: Vec<f64>,
    infeasible: bool,
}

impl Tester {
    pub(crate) fn new(h: &ComHalfspaces, tol: f64) -> Self {
        Self {
            ax: h.normals.iter().map(|a| a[0]).collect(),
            ay: h.normals.iter().map(|a| a[1]).collect(),
            az: h.normals.iter().map(|a| a[2]).collect(),
            // The band is folded into the offsets once.
            d: h.offsets.iter().map(|d| d + tol).collect(),
            infeasible: h.infeasible,
        }
    }

    #[inline]
    pub(crate) fn contains(&self, p: [f64; 3]) -> bool {
        if self.infeasible {
            return false;
        }
        let n = self.d.len();
        let (ax, ay, az, d) = (&self.ax[..n], &self.ay[..n], &self.az[..n], &self.d[..n]);
        let mut ok = true;
        for i in 0..n {
            ok &= ax[i] * p[0] + ay[i] * p[1] + az[i] * p[2] <= d[i];
        }
        ok
    }

    pub(crate) fn contains_batch(&self, points: &[[f64; 3]], out: &mut [bool]) {
        use rayon::prelude::*;
        /// Points per rayon task: enough half-space tests that a task's work amortizes rayon's
        /// scheduling (`bench/peers/contact.md`).
        const CHUNK: usize = 4096;
        out.par_chunks_mut(CHUNK)
            .zip(points.par_chunks(CHUNK))
            .for_each(|(o, p)| {
                for (o, p) in o.iter_mut().zip(p) {
                    *o = self.contains(*p);
                }
            });
    }
}
