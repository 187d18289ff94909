//! Preconditioning: a change of coordinates that makes the conversion independent of units and
//! of the reference point.
//!
//! # Math
//!
//! Let `V` (`n x d`, one generator per row) have the thin SVD `V = Y S Q` with `S = diag(s_1 >=
//! ... >= s_r > 0)` (singular values above [`crate::tol::Tolerances::rank`] times `s_1`), `Q`
//! (`r x d`) orthonormal rows. Then
//!
//! - `span(V)` is the row space of `Q` and the **equations** of the cone are an orthonormal basis
//!   `E` of its complement (`E v = 0` for every generator);
//! - the **whitened coordinates** of `x in span(V)` are `y = S^{-1} Q x`, and the whitened
//!   generators are the rows of `W = V Q^T S^{-1} = Y`, which has orthonormal columns.
//!
//! For any invertible linear map `M` of `R^d` (a change of reference point of wrenches, a change
//! of units), `V M^T` has whitened generators `Y O` with `O` orthogonal: the problem the double
//! description solves is the same up to a rotation, so its combinatorics and conditioning do
//! not depend on where the world origin is or on the units. A facet `u_w . y <= 0` in whitened
//! coordinates is `u . x <= 0` with `u = Q^T S^{-1} u_w` (then normalized).
//!
//! Zero generators (norm at most [`crate::tol::Tolerances::zero_generator`] times the largest) are
//! dropped; whitened generators are normalized to unit rows, and positively parallel duplicates
//! (distance at most [`crate::tol::Tolerances::duplicate`]) are merged.

use nalgebra::DMatrix;

use crate::linalg::{normalize, numerical_rank, sorted_svd};
use crate::tol::Tolerances;

/// A span-form problem in whitened coordinates.
#[derive(Clone, Debug, Default)]
pub(crate) struct Whitened {
    /// Dimension of `span(V)`.
    pub r: usize,
    /// Dimension of the input space.
    pub d: usize,
    /// `r x d`, orthonormal rows spanning `span(V)`, row-major.
    pub q: Vec<f64>,
    /// The `r` singular values kept.
    pub sv: Vec<f64>,
    /// `(d - r) x d`, orthonormal rows: the equations.
    pub equations: DMatrix<f64>,
    /// Input indices of the nonzero generators.
    pub kept: Vec<usize>,
    /// Whitened unit generators, `kept.len() x r`, row-major.
    pub w: Vec<f64>,
    /// Indices into `kept` of the generators left after merging duplicates.
    pub distinct: Vec<usize>,
    /// Largest `|E v| / max |v|` over the generators (how far they are from `span(V)`).
    pub equation_residual: f64,
    /// The exact power of two the input was multiplied by before the SVD (so that `sv` are the
    /// singular values of `scale * V`); 1 when no scaling was needed.
    pub scale: f64,
}

impl Whitened {
    /// Whitened generator `i` (index into `kept`).
    #[inline]
    pub fn gen(&self, i: usize) -> &[f64] {
        &self.w[i * self.r..(i + 1) * self.r]
    }

    /// Maps a whitened facet normal back: `u = Q^T S^{-1} u_w`, normalized.
    pub fn facet_to_world(&self, u_w: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for ((&u, &s), q) in u_w.iter().zip(&self.sv).zip(self.q.chunks_exact(self.d)) {
            let f = u / s;
            for (o, qv) in out.iter_mut().zip(q) {
                *o += f * qv;
            }
        }
        normalize(out);
    }

    /// Maps a facet normal `u` to whitened coordinates: `u_w = S Q u`, normalized.
    pub fn facet_from_world(&self, u: &[f64], out: &mut [f64]) {
        for ((o, &s), q) in out
            .iter_mut()
            .zip(&self.sv)
            .zip(self.q.chunks_exact(self.d))
        {
            let qu: f64 = q.iter().zip(u).map(|(a, b)| a * b).sum();
            *o = s * qu;
        }
        normalize(out);
    }

    /// Maps a whitened point back: `x = Q^T S y` (not normalized).
    pub fn point_to_world(&self, y: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for ((&y, &s), q) in y.iter().zip(&self.sv).zip(self.q.chunks_exact(self.d)) {
            let f = y * s;
            for (o, qv) in out.iter_mut().zip(q) {
                *o += f * qv;
            }
        }
    }
}

/// Whitens the generators `v` (rows), assumed finite with `v.ncols() >= 1`.
pub(crate) fn whiten(v: &DMatrix<f64>, tol: &Tolerances) -> Whitened {
    // Scale by a power of two (exact, and the cone does not change) so that the largest entry
    // is about 1: norms of rows with entries near 1e300 or 1e-300 neither overflow nor vanish.
    let amax = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if amax > 0.0 && !(0.5..=1.0).contains(&amax) {
        let e = amax.log2().floor() as i32;
        // Two steps: 2^-e alone may not be representable for subnormal inputs.
        let (e1, e2) = (e / 2, e - e / 2);
        let scaled = v * 2f64.powi(-e1) * 2f64.powi(-e2);
        let mut wh = whiten_scaled(&scaled, tol);
        // (May overflow to infinity for subnormal inputs; users of `scale` check.)
        wh.scale = 2f64.powi(-e1) * 2f64.powi(-e2);
        return wh;
    }
    whiten_scaled(v, tol)
}

/// [`whiten`] on an input whose largest entry is about 1 (or zero).
fn whiten_scaled(v: &DMatrix<f64>, tol: &Tolerances) -> Whitened {
    let (n, d) = v.shape();
    let norms: Vec<f64> = (0..n).map(|i| v.row(i).norm()).collect();
    let maxn = norms.iter().copied().fold(0.0, f64::max);
    let kept: Vec<usize> = (0..n)
        .filter(|&i| norms[i] > 0.0 && norms[i] > tol.zero_generator * maxn)
        .collect();
    if kept.is_empty() {
        return Whitened {
            r: 0,
            d,
            q: Vec::new(),
            sv: Vec::new(),
            equations: DMatrix::identity(d, d),
            kept,
            w: Vec::new(),
            distinct: Vec::new(),
            equation_residual: 0.0,
            scale: 1.0,
        };
    }
    let mut vk = DMatrix::zeros(kept.len(), d);
    for (r, &i) in kept.iter().enumerate() {
        vk.row_mut(r).copy_from(&v.row(i));
    }
    let (sv_all, vt) = sorted_svd(&vk);
    let r = numerical_rank(&sv_all, tol.rank);
    let mut q = Vec::with_capacity(r * d);
    for c in 0..r {
        q.extend(vt.row(c).iter());
    }
    let equations = vt.rows(r, d - r).into_owned();
    let sv = sv_all[..r].to_vec();
    let mut w = vec![0.0; kept.len() * r];
    let mut equation_residual: f64 = 0.0;
    let mut row = vec![0.0; d];
    for (t, &i) in kept.iter().enumerate() {
        for (x, y) in row.iter_mut().zip(v.row(i).iter()) {
            *x = *y;
        }
        let wt = &mut w[t * r..(t + 1) * r];
        for ((o, qc), &s) in wt.iter_mut().zip(q.chunks_exact(d)).zip(&sv) {
            *o = qc.iter().zip(&row).map(|(a, b)| a * b).sum::<f64>() / s;
        }
        normalize(wt);
        for e in 0..d - r {
            let ev = equations.row(e);
            let dot: f64 = ev.iter().zip(&row).map(|(a, b)| a * b).sum();
            equation_residual = equation_residual.max(dot.abs() / maxn);
        }
    }
    let mut distinct: Vec<usize> = Vec::with_capacity(kept.len());
    'outer: for t in 0..kept.len() {
        let gt = &w[t * r..(t + 1) * r];
        for &s in &distinct {
            let gs = &w[s * r..(s + 1) * r];
            // Most pairs differ in the first coordinate already.
            if (gt[0] - gs[0]).abs() > tol.duplicate {
                continue;
            }
            let d2: f64 = gt.iter().zip(gs).map(|(a, b)| (a - b) * (a - b)).sum();
            if d2 <= tol.duplicate * tol.duplicate {
                continue 'outer;
            }
        }
        distinct.push(t);
    }
    Whitened {
        r,
        d,
        q,
        sv,
        equations,
        kept,
        w,
        distinct,
        equation_residual,
        scale: 1.0,
    }
}
