//! The two conversions, span -> face and face -> span, and their reusable [`Workspace`].
//!
//! # Math
//!
//! **span -> face.** For `C = span(V)`: precondition (see [`crate::precondition`]) to whitened
//! unit generators `w_i` in `R^r`, `r = dim span(V)`; the equations are the complement of
//! `span(V)`. In `R^r` the cone is full-dimensional, and its facets are the extreme rays of the
//! **polar** `C° = {u : w_i . u <= 0 for all i}`, a pointed cone (the `w_i` span `R^r`), computed
//! by the double description method ([`crate::dd`]). The lineality space of `C` is the orthogonal
//! complement of `span(C°)`, i.e. the null space of the facet matrix.
//!
//! **face -> span.** For `C = {x : U x <= 0, E x = 0}` the polar is
//! `C° = span([U; E; -E])`, and `(C°)° = C`: the extreme rays of `C` are the facets of `C°`, the
//! lineality space of `C` is the equation space of `C°`. So face -> span is span -> face on the
//! polar, with the same preconditioning and certificate.

use nalgebra::DMatrix;

use crate::certificate::{certify_whitened, CertScratch, Certificate, CheckOptions, Claim};
use crate::dd::DdCore;
use crate::exact::exact_span_to_face;
use crate::forms::check_dimension;
use crate::linalg::{normalize, numerical_rank, orthonormal_rows, sorted_svd};
use crate::merge::merge_fallback_rows;
use crate::precondition::{scale_rows_pow2, whiten, whiten_into, WhitenScratch, Whitened};
use crate::wrench::{check_options as check_wrench_options, sorted_rows, WrenchFrame};
use crate::{Arithmetic, ConeError, DdOptions, FaceForm, SpanForm};

/// The last step of both wrench routes: the answer's rows mapped back to the input's
/// coordinates (`back`, in the order of `p.facets`, with `basis` their equations or lineality
/// there), an exact fallback's slivers merged with every drop certified both there and in the
/// frame (`p`'s own rows), sorted, and the frame recorded in the certificate.
fn finish_wrench(
    mut back: DMatrix<f64>,
    basis: &DMatrix<f64>,
    p: &mut Polar,
    frame: WrenchFrame,
    opts: &DdOptions,
) -> DMatrix<f64> {
    let delta = opts.tol.certificate;
    let computed = Some((&p.facets, &p.equations));
    merge_fallback_rows(&mut back, basis, computed, &mut p.certificate, delta);
    p.certificate.wrench_frame = Some(frame);
    sorted_rows(&back)
}

/// The result of [`span_to_face`].
#[derive(Clone, Debug, PartialEq)]
pub struct SpanToFace {
    /// `{x : facets x <= 0, equations x = 0}`; unit rows, facets orthogonal to the equations
    /// and to the lineality space, in lexicographic order.
    pub face: FaceForm,
    /// Orthonormal basis (rows) of the lineality space of the cone.
    pub lineality: DMatrix<f64>,
    /// Indices of input rows that are extreme rays (modulo the lineality space), one per extreme
    /// ray (the first input row among positively parallel ones), increasing.
    pub extreme_generators: Vec<usize>,
    /// What was verified.
    pub certificate: Certificate,
}

/// The result of [`face_to_span`].
#[derive(Clone, Debug, PartialEq)]
pub struct FaceToSpan {
    /// `{generators^T z + lineality^T y : z >= 0}`: unit extreme rays (orthogonal to the
    /// lineality space) and an orthonormal basis of the lineality space.
    pub span: SpanForm,
    /// Indices of input facet rows that are irredundant (facets of the cone), increasing.
    pub irredundant_facets: Vec<usize>,
    /// What was verified (on the polar conversion, which implies this one).
    pub certificate: Certificate,
}

/// Reusable buffers of the conversions. Repeated conversions through the same workspace reuse
/// its arenas: the preconditioning (for `d <= 8`) and the double description loop (the hot
/// loop: one iteration per generator, pairs of rays inside) do not allocate once they are
/// large enough. The steps around them (certificate bookkeeping, the returned matrices) still
/// allocate a few small buffers per conversion.
#[derive(Clone, Debug)]
pub struct Workspace {
    /// The double description state (a [`crate::Continuation`] resumes it).
    pub(crate) core: DdCore,
    check: CertScratch,
    rows: Vec<f64>,
    scratch: Vec<f64>,
    /// Sort keys of the facets (their first coordinates as integers).
    keys: Vec<i64>,
    /// The map of whitened facets back to the input's coordinates (`d x r`).
    to_world: Vec<f64>,
    /// The whitening of the last conversion.
    pub(crate) wh: Whitened,
    wh_scratch: WhitenScratch,
    /// The input rows scaled by powers of two ([`scale_rows_pow2`]).
    scaled: Vec<f64>,
    /// Relative singular value up to which a dropped direction is rounding noise
    /// ([`crate::tol::RANK_NOISE`], raised by the wrench preconditioning to the rounding of its
    /// re-centring).
    rank_noise: f64,
}

fn check_finite(what: &'static str, m: &DMatrix<f64>) -> Result<(), ConeError> {
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            let v = m[(i, j)];
            if !v.is_finite() {
                return Err(ConeError::NonFinite {
                    what,
                    row: i,
                    col: j,
                    value: v,
                });
            }
        }
    }
    Ok(())
}

/// Everything span -> face computes, in whitened and world coordinates.
pub(crate) struct Polar {
    pub(crate) equations: DMatrix<f64>,
    pub(crate) facets: DMatrix<f64>,
    pub(crate) lineality: DMatrix<f64>,
    pub(crate) extreme: Vec<usize>,
    pub(crate) certificate: Certificate,
}

impl Default for Workspace {
    fn default() -> Self {
        Self {
            core: DdCore::default(),
            check: CertScratch::default(),
            rows: Vec::new(),
            scratch: Vec::new(),
            keys: Vec::new(),
            to_world: Vec::new(),
            wh: Whitened::default(),
            wh_scratch: WhitenScratch::default(),
            scaled: Vec::new(),
            rank_noise: crate::tol::RANK_NOISE,
        }
    }
}

impl Workspace {
    /// A new, empty workspace.
    ///
    /// ```
    /// let mut ws = polycone::Workspace::new();
    /// let v = polycone::nalgebra::DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 1.0]);
    /// let r = ws.span_to_face(&v, &Default::default()).unwrap();
    /// assert_eq!(r.face.facets.nrows(), 2);
    /// ```
    pub fn new() -> Self {
        Self::default()
    }

    /// [`span_to_face`] with this workspace's buffers.
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, Workspace, DdOptions};
    /// let mut ws = Workspace::new();
    /// // The quadrant of R^2 plus a redundant generator.
    /// let v = DMatrix::from_row_slice(3, 2, &[1.0, 0.0, 1.0, 1.0, 0.0, 2.0]);
    /// let r = ws.span_to_face(&v, &DdOptions::default()).unwrap();
    /// assert_eq!(r.extreme_generators, vec![0, 2]);
    /// assert!(r.certificate.certified);
    /// ```
    pub fn span_to_face(
        &mut self,
        generators: &DMatrix<f64>,
        opts: &DdOptions,
    ) -> Result<SpanToFace, ConeError> {
        let d = generators.ncols();
        check_dimension(d)?;
        check_finite("generators", generators)?;
        // Every decision below is independent of a positive scaling of any generator.
        let scaled = self.rows_scaled(generators);
        let result = if opts.wrench {
            self.span_to_face_wrench(&scaled, opts)
        } else {
            self.polar_merged(&scaled, opts).map(|p| SpanToFace {
                face: FaceForm {
                    dim: d,
                    facets: p.facets,
                    equations: p.equations,
                },
                lineality: p.lineality,
                extreme_generators: p.extreme,
                certificate: p.certificate,
            })
        };
        self.scaled = scaled.data.into();
        result
    }

    /// `m` with each row scaled by a power of two ([`scale_rows_pow2`]), in this workspace's
    /// buffer (give it back with `self.scaled = m.data.into()`).
    fn rows_scaled(&mut self, m: &DMatrix<f64>) -> DMatrix<f64> {
        let mut buf = std::mem::take(&mut self.scaled);
        buf.clear();
        buf.extend_from_slice(m.as_slice());
        let mut scaled = DMatrix::from_vec(m.nrows(), m.ncols(), buf);
        scale_rows_pow2(&mut scaled);
        scaled
    }

    /// [`face_to_span`] with this workspace's buffers.
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, Workspace, DdOptions, FaceForm};
    /// let mut ws = Workspace::new();
    /// // The half-plane y >= 0: lineality along x, one generator (0, 1).
    /// let face = FaceForm::new(DMatrix::from_row_slice(1, 2, &[0.0, -1.0]), DMatrix::zeros(0, 2)).unwrap();
    /// let r = ws.face_to_span(&face, &DdOptions::default()).unwrap();
    /// assert_eq!(r.span.generators.nrows(), 1);
    /// assert!((r.span.generators[(0, 1)] - 1.0).abs() < 1e-12);
    /// assert_eq!(r.span.lineality.nrows(), 1);
    /// ```
    pub fn face_to_span(
        &mut self,
        face: &FaceForm,
        opts: &DdOptions,
    ) -> Result<FaceToSpan, ConeError> {
        face.validate()?;
        let d = face.dim;
        let (nu, ne) = (face.facets.nrows(), face.equations.nrows());
        let mut g = DMatrix::zeros(nu + 2 * ne, d);
        if nu > 0 {
            g.view_mut((0, 0), (nu, d)).copy_from(&face.facets);
        }
        if ne > 0 {
            g.view_mut((nu, 0), (ne, d)).copy_from(&face.equations);
            g.view_mut((nu + ne, 0), (ne, d))
                .copy_from(&(-&face.equations));
        }
        // Every decision below is independent of a positive scaling of any facet or equation.
        scale_rows_pow2(&mut g);
        if opts.wrench {
            return self.face_to_span_wrench(&g, nu, opts);
        }
        let p = self.polar_merged(&g, opts)?;
        let irredundant_facets = p.extreme.iter().copied().filter(|&i| i < nu).collect();
        Ok(FaceToSpan {
            span: SpanForm {
                dim: d,
                generators: p.facets,
                lineality: p.equations,
            },
            irredundant_facets,
            certificate: p.certificate,
        })
    }

    /// [`Self::span_to_face`] with the wrench preconditioning: convert `M V`, map back.
    fn span_to_face_wrench(
        &mut self,
        generators: &DMatrix<f64>,
        opts: &DdOptions,
    ) -> Result<SpanToFace, ConeError> {
        check_wrench_options(generators.ncols(), opts)?;
        opts.tol.validate()?;
        let frame = WrenchFrame::of_wrenches(generators, &opts.tol)?;
        let v_centred = frame.vectors_forward(generators);
        check_finite("re-centred generators", &v_centred)?;
        let inner = DdOptions {
            wrench: false,
            ..opts.clone()
        };
        let mut p = self.polar_recentred(&v_centred, &inner, &frame)?;
        let equations = frame.basis_back(&p.equations, false);
        let lineality = frame.basis_back(&p.lineality, true);
        let back = frame.rays_back(&p.facets, false, &[&equations, &lineality]);
        let facets = finish_wrench(back, &equations, &mut p, frame, opts);
        Ok(SpanToFace {
            face: FaceForm {
                dim: generators.ncols(),
                facets,
                equations,
            },
            lineality,
            extreme_generators: p.extreme,
            certificate: p.certificate,
        })
    }

    /// [`Self::face_to_span`] with the wrench preconditioning on the polar's generators `g`
    /// (`[U; E; -E]`, the first `nu` rows facets): convert `M^{-T} g`, map back.
    fn face_to_span_wrench(
        &mut self,
        g: &DMatrix<f64>,
        nu: usize,
        opts: &DdOptions,
    ) -> Result<FaceToSpan, ConeError> {
        check_wrench_options(g.ncols(), opts)?;
        opts.tol.validate()?;
        let frame = WrenchFrame::of_covectors(g, &opts.tol)?;
        let g_centred = frame.covectors_forward(g);
        check_finite("re-centred facets", &g_centred)?;
        let inner = DdOptions {
            wrench: false,
            ..opts.clone()
        };
        let mut p = self.polar_recentred(&g_centred, &inner, &frame)?;
        let lineality = frame.basis_back(&p.equations, true);
        let back = frame.rays_back(&p.facets, true, &[&lineality]);
        let generators = finish_wrench(back, &lineality, &mut p, frame, opts);
        Ok(FaceToSpan {
            span: SpanForm {
                dim: g.ncols(),
                generators,
                lineality,
            },
            irredundant_facets: p.extreme.iter().copied().filter(|&i| i < nu).collect(),
            certificate: p.certificate,
        })
    }

    /// [`Self::polar`] on rows re-centred by `frame`: the re-centring `tau - o x f` rounds at
    /// about `u |o| / L` relative (`u` the unit roundoff), so directions below that are noise.
    fn polar_recentred(
        &mut self,
        v: &DMatrix<f64>,
        opts: &DdOptions,
        frame: &WrenchFrame,
    ) -> Result<Polar, ConeError> {
        let o = frame.center;
        let reach = (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt() / frame.length;
        self.rank_noise = crate::tol::RANK_NOISE * reach.max(1.0);
        let p = self.polar(v, opts);
        self.rank_noise = crate::tol::RANK_NOISE;
        p
    }

    /// [`Self::polar`] with an exact fallback's slivers merged, in the coordinates of `v` (the
    /// input's; the wrench routes merge after mapping back instead).
    fn polar_merged(&mut self, v: &DMatrix<f64>, opts: &DdOptions) -> Result<Polar, ConeError> {
        let mut p = self.polar(v, opts)?;
        let delta = opts.tol.certificate;
        merge_fallback_rows(&mut p.facets, &p.equations, None, &mut p.certificate, delta);
        Ok(p)
    }

    /// span -> face on `v` (finite, `d >= 1` columns): the common engine of both directions.
    fn polar(&mut self, v: &DMatrix<f64>, opts: &DdOptions) -> Result<Polar, ConeError> {
        opts.tol.validate()?;
        if opts.arithmetic == Arithmetic::Exact {
            return exact_polar(v, opts);
        }
        match self.polar_tolerance(v, opts) {
            Err(ConeError::Uncertified(reason)) if opts.exact_fallback => {
                // Repair: the exact answer for the input as given.
                let mut p = exact_polar(v, opts).map_err(|e| {
                    ConeError::Uncertified(format!("{reason}; exact fallback: {e}"))
                })?;
                p.certificate.fallback = Some(reason);
                Ok(p)
            }
            other => other,
        }
    }

    /// The floating-point conversion with the tolerance contract.
    fn polar_tolerance(&mut self, v: &DMatrix<f64>, opts: &DdOptions) -> Result<Polar, ConeError> {
        self.whiten_and_run(v, opts)?;
        // Moved out for the call and back (no allocation: the default is empty).
        let wh = std::mem::take(&mut self.wh);
        let fw = self.rays_whitened(wh.r);
        let polar = self.finish_polar(&wh, fw, opts);
        self.wh = wh;
        polar
    }

    /// Preconditioning into `self.wh` and the double description on the polar, in whitened
    /// coordinates: the extreme rays are left in `self.core` (none when `r = 0`).
    pub(crate) fn whiten_and_run(
        &mut self,
        v: &DMatrix<f64>,
        opts: &DdOptions,
    ) -> Result<(), ConeError> {
        let tol = &opts.tol;
        whiten_into(v, tol, &mut self.wh, &mut self.wh_scratch);
        let wh = &self.wh;
        if let Some(ratio) = wh.rank_undecided.filter(|&x| x > self.rank_noise) {
            return Err(ConeError::RankUndecided {
                ratio,
                noise: self.rank_noise,
                rank: tol.rank,
            });
        }
        let r = wh.r;
        // Double description on the polar, in whitened coordinates.
        self.rows.clear();
        for &i in &wh.distinct {
            self.rows.extend_from_slice(wh.gen(i));
        }
        let m = wh.distinct.len();
        if r > 0 {
            self.core
                .run(&self.rows, m, r, tol.incidence, tol.rank)
                .map_err(|e| ConeError::Uncertified(format!("double description failed: {e:?}")))?;
        } else {
            self.core.n = 0;
        }
        Ok(())
    }

    /// The rays left in `self.core` by [`Self::whiten_and_run`] (dimension `r`), flat.
    fn rays_whitened(&self, r: usize) -> Vec<f64> {
        let nf = if r > 0 { self.core.n } else { 0 };
        let mut fw: Vec<f64> = Vec::with_capacity(nf * r);
        for f in 0..nf {
            fw.extend_from_slice(self.core.ray(f));
        }
        fw
    }

    /// From the extreme rays `fw` of the polar (whitened coordinates of `wh`, unit rows): the
    /// lineality space, the certificate, and everything mapped back to world coordinates in
    /// the deterministic order.
    pub(crate) fn finish_polar(
        &mut self,
        wh: &Whitened,
        fw: Vec<f64>,
        opts: &DdOptions,
    ) -> Result<Polar, ConeError> {
        let tol = &opts.tol;
        let (d, r) = (wh.d, wh.r);
        let nf = fw.len().checked_div(r).unwrap_or(0);
        // Lineality: the null space of the facet matrix, in whitened coordinates.
        let (perp, lin) = split_lineality(&fw, nf, r, tol.rank);
        let t = perp.len().checked_div(r).unwrap_or(0);
        let l = r - t;
        let (certificate, extreme_kept) = certify_whitened(
            Claim {
                wh,
                fw: &fw,
                perp: &perp,
                lin: &lin,
            },
            CheckOptions {
                tol,
                arithmetic: opts.arithmetic,
                check_completeness: opts.check_completeness,
            },
            &mut self.check,
        );
        if !certificate.certified && !opts.allow_uncertified && opts.check_completeness {
            return Err(ConeError::Uncertified(certificate.failure_reason()));
        }
        // Facets in world coordinates, sorted lexicographically.
        let facets = &mut self.scratch;
        facets.clear();
        facets.resize(nf * d, 0.0);
        wh.facets_to_world(&fw, facets, &mut self.to_world);
        let mut order: Vec<usize> = (0..nf).collect();
        // The first coordinate as an integer of the same total order (`f64::total_cmp`)
        // decides most comparisons.
        let key = |x: f64| {
            let b = x.to_bits() as i64;
            b ^ ((((b >> 63) as u64) >> 1) as i64)
        };
        let first = &mut self.keys;
        first.clear();
        first.extend((0..nf).map(|f| key(facets[f * d])));
        order.sort_unstable_by(|&a, &b| {
            let o = first[a].cmp(&first[b]);
            if o.is_ne() {
                return o;
            }
            let (ra, rb) = (&facets[a * d..(a + 1) * d], &facets[b * d..(b + 1) * d]);
            for (x, y) in ra.iter().zip(rb) {
                let o = x.total_cmp(y);
                if o.is_ne() {
                    return o;
                }
            }
            // Equal rows are interchangeable; the index keeps the order total.
            a.cmp(&b)
        });
        let facets_m = DMatrix::from_fn(nf, d, |i, j| facets[order[i] * d + j]);
        // Lineality in world coordinates.
        let mut lw = DMatrix::zeros(l, d);
        let mut x = vec![0.0; d];
        for b in 0..l {
            wh.point_to_world(&lin[b * r..(b + 1) * r], &mut x);
            normalize(&mut x);
            lw.row_mut(b).copy_from_slice(&x);
        }
        let lineality = orthonormal_rows(&lw, tol.rank);
        // Extreme generators (a by-product of the certificate's incidence), as input rows.
        let mut extreme: Vec<usize> = extreme_kept.iter().map(|&i| wh.kept[i]).collect();
        extreme.sort_unstable();
        Ok(Polar {
            equations: wh.equations.clone(),
            facets: facets_m,
            lineality,
            extreme,
            certificate,
        })
    }
}

/// The exact conversion; an uncertified exact answer is an error unless allowed.
pub(crate) fn exact_polar(v: &DMatrix<f64>, opts: &DdOptions) -> Result<Polar, ConeError> {
    let e = exact_span_to_face(v, &opts.tol)?;
    if !e.certificate.certified && !opts.allow_uncertified {
        return Err(ConeError::Uncertified(format!(
            "exact: {}",
            e.certificate.failure_reason()
        )));
    }
    Ok(Polar {
        equations: e.equations,
        facets: e.facets,
        lineality: e.lineality,
        extreme: e.extreme,
        certificate: e.certificate,
    })
}

/// The row space of the facet matrix `fw` (`nf x r`) and its complement, the lineality space,
/// as flat row-major orthonormal rows.
fn split_lineality(fw: &[f64], nf: usize, r: usize, rank_tol: f64) -> (Vec<f64>, Vec<f64>) {
    if r == 0 {
        (Vec::new(), Vec::new())
    } else if nf == 0 {
        (
            Vec::new(),
            DMatrix::<f64>::identity(r, r).as_slice().to_vec(),
        )
    } else if crate::linalg::spans(fw, nf, r, rank_tol, &mut Vec::new()) {
        // Facets span R^r (a pointed cone): no lineality, any orthonormal basis is L^perp.
        (
            DMatrix::<f64>::identity(r, r).as_slice().to_vec(),
            Vec::new(),
        )
    } else {
        let fm = DMatrix::from_row_slice(nf, r, fw);
        let (sv, vt) = sorted_svd(&fm);
        let t = numerical_rank(&sv, rank_tol);
        let mut perp = Vec::with_capacity(t * r);
        for b in 0..t {
            perp.extend(vt.row(b).iter());
        }
        let mut lin = Vec::with_capacity((r - t) * r);
        for b in t..r {
            lin.extend(vt.row(b).iter());
        }
        (perp, lin)
    }
}

/// Certifies a claimed face form of `span(generators)` independently of how it was computed:
/// soundness, support, lineality and completeness (see [`Certificate`]), plus the equations
/// (they must annihilate every generator and number `d - dim span(V)`) and the claimed
/// lineality space (its dimension must be that of the null space of the facets within
/// `span(V)`, and the facets and equations must vanish on it).
///
/// ```
/// use polycone::{nalgebra::DMatrix, span_to_face, certify_span_to_face, DdOptions, FaceForm};
/// let v = DMatrix::from_row_slice(3, 3, &[1.0, 0.0, 1.0, 0.0, 1.0, 1.0, -1.0, -1.0, 1.0]);
/// let opts = DdOptions::default();
/// let r = span_to_face(&v, &opts).unwrap();
/// let ok = certify_span_to_face(&v, &r.face, &r.lineality, &opts).unwrap();
/// assert!(ok.certified);
/// // Drop a facet: the face form is now too large, and the certificate says so.
/// let partial = FaceForm::new(r.face.facets.rows(0, 2).into_owned(), r.face.equations.clone()).unwrap();
/// let bad = certify_span_to_face(&v, &partial, &r.lineality, &opts).unwrap();
/// assert!(!bad.certified);
/// ```
pub fn certify_span_to_face(
    generators: &DMatrix<f64>,
    face: &FaceForm,
    lineality: &DMatrix<f64>,
    opts: &DdOptions,
) -> Result<Certificate, ConeError> {
    let d = generators.ncols();
    check_dimension(d)?;
    check_finite("generators", generators)?;
    face.validate()?;
    if face.dim != d {
        return Err(ConeError::DimensionMismatch {
            what: "face form",
            got: face.dim,
            expected: d,
        });
    }
    if lineality.nrows() > 0 && lineality.ncols() != d {
        return Err(ConeError::DimensionMismatch {
            what: "lineality",
            got: lineality.ncols(),
            expected: d,
        });
    }
    check_finite("lineality", lineality)?;
    opts.tol.validate()?;
    // The same normalization as the conversions: no decision depends on a row's scale.
    let mut generators = generators.clone();
    scale_rows_pow2(&mut generators);
    let generators = &generators;
    if opts.wrench {
        // Certify the re-centred problem: generators by `M`, facets and equations by `M^{-T}`,
        // lineality by `M`.
        check_wrench_options(d, opts)?;
        let frame = WrenchFrame::of_wrenches(generators, &opts.tol)?;
        let v_centred = frame.vectors_forward(generators);
        check_finite("re-centred generators", &v_centred)?;
        let face_centred = FaceForm {
            dim: d,
            facets: frame.covectors_forward(&face.facets),
            equations: frame.covectors_forward(&face.equations),
        };
        let lineality_centred = frame.vectors_forward(lineality);
        let inner = DdOptions {
            wrench: false,
            ..opts.clone()
        };
        return certify_span_to_face(&v_centred, &face_centred, &lineality_centred, &inner);
    }
    let tol = &opts.tol;
    let wh = whiten(generators, tol);
    let r = wh.r;
    // Facets in whitened coordinates (their components along the equations do not matter).
    let nf = face.facets.nrows();
    let mut fw = vec![0.0; nf * r];
    let mut u = vec![0.0; d];
    for f in 0..nf {
        for j in 0..d {
            u[j] = face.facets[(f, j)];
        }
        wh.facet_from_world(&u, &mut fw[f * r..(f + 1) * r]);
    }
    let (perp, lin) = split_lineality(&fw, nf, r, tol.rank);
    let mut check = CertScratch::default();
    let (mut cert, _) = certify_whitened(
        Claim {
            wh: &wh,
            fw: &fw,
            perp: &perp,
            lin: &lin,
        },
        CheckOptions {
            tol,
            arithmetic: opts.arithmetic,
            check_completeness: true,
        },
        &mut check,
    );
    // Equations: annihilate the generators, and as many as the complement of span(V).
    let maxn = (0..generators.nrows())
        .map(|i| generators.row(i).norm())
        .fold(0.0, f64::max);
    let mut eq_res: f64 = 0.0;
    for e in 0..face.equations.nrows() {
        let row = face.equations.row(e);
        let rn = row.norm();
        for i in 0..generators.nrows() {
            if maxn > 0.0 && rn > 0.0 {
                eq_res = eq_res.max(row.dot(&generators.row(i)).abs() / (rn * maxn));
            }
        }
    }
    let eq_rank = {
        let (sv, _) = if face.equations.nrows() > 0 {
            sorted_svd(&face.equations)
        } else {
            (Vec::new(), DMatrix::zeros(0, 0))
        };
        numerical_rank(&sv, tol.rank)
    };
    cert.max_equation_residual = cert.max_equation_residual.max(eq_res);
    if eq_res > tol.certificate || eq_rank + r != d {
        cert.soundness = false;
    }
    // Claimed lineality: right dimension, and in the claimed cone's lineality space.
    let l = r - perp.len().checked_div(r).unwrap_or(0);
    let mut lin_ok = lineality.nrows() == l;
    for b in 0..lineality.nrows() {
        let x = lineality.row(b).transpose();
        let n = x.norm();
        // Cosines: the facet and equation rows may have any positive scale.
        let off = |row: nalgebra::RowDVector<f64>| {
            (&row * &x)[0].abs() > tol.certificate * n * row.norm()
        };
        let bad_f = (0..nf).any(|f| off(face.facets.row(f).into_owned()));
        let bad_e = (0..face.equations.nrows()).any(|e| off(face.equations.row(e).into_owned()));
        if n == 0.0 || bad_f || bad_e {
            lin_ok = false;
        }
    }
    cert.lineality &= lin_ok;
    cert.certified = cert.soundness && cert.support && cert.lineality && cert.completeness;
    Ok(cert)
}

/// Converts a cone from span form to face form: `span(V) = {x : U x <= 0, E x = 0}`.
///
/// `generators` is `n x d`, one generator per row (`n = 0` gives the zero cone, whose
/// equations are the identity). See the crate docs for the tolerance contract; the result is
/// certified or an error is returned (unless [`DdOptions::allow_uncertified`]).
///
/// ```
/// use polycone::{nalgebra::DMatrix, span_to_face, DdOptions};
/// // The positive orthant of R^3.
/// let v = DMatrix::<f64>::identity(3, 3);
/// let r = span_to_face(&v, &DdOptions::default()).unwrap();
/// assert_eq!(r.face.facets.nrows(), 3);
/// assert_eq!(r.face.equations.nrows(), 0);
/// assert_eq!(r.extreme_generators, vec![0, 1, 2]);
/// assert!(r.certificate.certified);
/// ```
pub fn span_to_face(generators: &DMatrix<f64>, opts: &DdOptions) -> Result<SpanToFace, ConeError> {
    Workspace::new().span_to_face(generators, opts)
}

/// Converts a cone from face form to span form: `{x : U x <= 0, E x = 0} = span(V) + span(L)`
/// with `L` the lineality space.
///
/// ```
/// use polycone::{nalgebra::DMatrix, face_to_span, DdOptions, FaceForm};
/// // x >= 0, y >= 0 in R^2 is generated by (1, 0) and (0, 1).
/// let face = FaceForm::new(DMatrix::from_row_slice(2, 2, &[-1.0, 0.0, 0.0, -1.0]), DMatrix::zeros(0, 2)).unwrap();
/// let r = face_to_span(&face, &DdOptions::default()).unwrap();
/// assert_eq!(r.span.generators.nrows(), 2);
/// assert_eq!(r.span.lineality.nrows(), 0);
/// assert!(r.certificate.certified);
/// ```
pub fn face_to_span(face: &FaceForm, opts: &DdOptions) -> Result<FaceToSpan, ConeError> {
    Workspace::new().face_to_span(face, opts)
}
