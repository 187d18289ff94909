//! `U_stance` through polycone's double description (span -> face).

use crate::{ContactError, Giwc, Stance};

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
        let span = self.giwc_span();
        let out = ws
            .span_to_face(&span, &opts.dd)
            .map_err(|e| ContactError::Cone(e.to_string()))?;
        Ok(Giwc {
            facets: out.face.facets,
            equations: out.face.equations,
            lineality: out.lineality,
            certified: out.certificate.certified,
        })
    }
}
