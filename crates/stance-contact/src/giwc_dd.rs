//! `U_stance` through polycone's double description (span -> face).
//!
//! The conversion runs on the wrenches taken at the origin `c` of the first contact, not at
//! the world origin: `w_c = X w_GI` with `X = [I 0; -[c]x I]` (the same cone, moved), then the
//! face form comes back exactly, `U_stance = U_c X` (rows `(u_f + c x u_t, u_t)`, renormalized),
//! the equations likewise, and the lineality as `X^-1 l = (l_f, l_t + c x l_f)`. Reason: at the
//! world origin a stance `|c|` metres away has torques `|c|` times its forces, and the
//! conversion's relative rank decisions then lose the stance's own size (measured: a 50 cm
//! double support 30 km from the origin came back as a certified 38-facet cone with two
//! equations instead of 176 facets).

use nalgebra::DMatrix;

use crate::{ContactError, Giwc, Stance};

/// The point (world, m) at which the conversion runs: the origin of the first contact.
pub(crate) fn conversion_point(stance: &Stance) -> [f64; 3] {
    stance.contacts()[0].position()
}

/// Span rows (wrenches at the world origin) moved to the point `c`: `(f, tau - c x f)`.
pub(crate) fn span_at(span: &DMatrix<f64>, c: [f64; 3]) -> DMatrix<f64> {
    let mut out = span.clone();
    for i in 0..span.nrows() {
        let t = crate::cross(c, [span[(i, 0)], span[(i, 1)], span[(i, 2)]]);
        for k in 0..3 {
            out[(i, 3 + k)] -= t[k];
        }
    }
    out
}

/// Orthonormal rows spanning the rows of `m` (its row space; `m` has full row rank).
fn orthonormal_rows(m: DMatrix<f64>) -> DMatrix<f64> {
    if m.nrows() == 0 {
        return m;
    }
    let k = m.nrows();
    let q = m.transpose().qr().q();
    q.columns(0, k).transpose()
}

/// A face form computed at the point `c` moved back to the world origin (module doc).
pub(crate) fn giwc_at_origin(out: &polycone::SpanToFace, c: [f64; 3]) -> Giwc {
    let back = |m: &DMatrix<f64>| {
        let mut r = m.clone();
        for i in 0..m.nrows() {
            let t = crate::cross(c, [m[(i, 3)], m[(i, 4)], m[(i, 5)]]);
            for k in 0..3 {
                r[(i, k)] += t[k];
            }
            let n = r.row(i).norm();
            if n > 0.0 {
                r.row_mut(i).unscale_mut(n);
            }
        }
        r
    };
    let mut lineality = out.lineality.clone();
    for i in 0..lineality.nrows() {
        let t = crate::cross(c, [lineality[(i, 0)], lineality[(i, 1)], lineality[(i, 2)]]);
        for k in 0..3 {
            lineality[(i, 3 + k)] += t[k];
        }
    }
    Giwc {
        facets: back(&out.face.facets),
        equations: orthonormal_rows(back(&out.face.equations)),
        lineality: orthonormal_rows(lineality),
        certified: out.certificate.certified,
        certificate: Some(out.certificate.clone()),
    }
}

/// Options of the GIWC conversion: polycone's double-description options (arithmetic,
/// tolerances). The default tolerance mode merges structure degenerate within polycone's
/// epsilon (the intended geometry); `Arithmetic::Exact` certifies the cone of the generators
/// *as computed in floating point*, where rounding of rotated or translated contacts splits
/// facets of the intended geometry (e.g. 302 facets instead of 176 for the stair stance, as
/// cddlib's GMP mode does on rounded inputs).
#[derive(Debug, Clone, Default)]
pub struct GiwcOptions {
    /// Passed to `polycone::span_to_face`.
    pub dd: polycone::DdOptions,
}

impl Stance {
    /// `U_stance` (paper eq. 11): the face form of `span(A_stance V_all)` with its equations
    /// and lineality, in the paper's convention (`U_stance w_GI <= 0`, world origin).
    ///
    /// ```
    /// # use stance_contact::examples;
    /// let giwc = examples::single_support_flat().stance().unwrap().u_stance(&Default::default()).unwrap();
    /// assert_eq!(giwc.facets.nrows(), 16);
    /// assert_eq!(giwc.equations.nrows(), 0);
    /// assert!(giwc.certified);
    /// ```
    pub fn u_stance(&self, opts: &GiwcOptions) -> Result<Giwc, ContactError> {
        self.u_stance_with(&mut polycone::Workspace::new(), opts)
    }

    /// [`Stance::u_stance`] with a reusable polycone workspace (for many stances in a loop).
    ///
    /// ```
    /// # use stance_contact::examples;
    /// let mut ws = polycone::Workspace::new();
    /// for name in examples::NAMES {
    ///     let stance = examples::by_name(name).unwrap().stance().unwrap();
    ///     assert!(stance.u_stance_with(&mut ws, &Default::default()).unwrap().certified);
    /// }
    /// ```
    pub fn u_stance_with(
        &self,
        ws: &mut polycone::Workspace,
        opts: &GiwcOptions,
    ) -> Result<Giwc, ContactError> {
        let c = conversion_point(self);
        let span = span_at(&self.giwc_span(), c);
        let out = ws
            .span_to_face(&span, &opts.dd)
            .map_err(ContactError::Cone)?;
        Ok(giwc_at_origin(&out, c))
    }
}
