//! Continuing a span -> face conversion when generators are added.
//!
//! # Math
//!
//! For `C = span(V)` the facets are the extreme rays of the polar
//! `C° = {u : v_i . u <= 0 for every generator v_i}` (computed in whitened coordinates, see
//! [`crate::precondition`]). Adding generators `V'` gives
//!
//! ```text
//! span([V; V'])° = C° ∩ {u : v'_j . u <= 0 for every new generator v'_j}:
//! ```
//!
//! **appending generators appends constraint rows to the polar**, which is exactly one step of
//! the double description per new row. So a conversion that keeps its final state (the extreme
//! rays of `C°` and their zero sets, [`crate::dd`]) can continue with the new rows instead of
//! starting over: the double description work is that of the new rows only.
//!
//! # Coordinates
//!
//! The state lives in the whitened coordinates `y = S^{-1} Q x` of the last conversion from
//! scratch (the *frame*). Any invertible linear map of `span(V)` preserves the cone's
//! combinatorics, so the new generators are mapped into the frame as they are (`S^{-1} Q v'`,
//! then normalized), provided they lie in the same linear span. Everything a conversion from
//! scratch decides from its preconditioning is decided here without a new SVD:
//!
//! - **rank**: with `E` the frame's equations (the complement of `span(V)`), `M = [V; V']` has
//!   `sigma_{r+1}(M) <= |V' E^T|_F` (drop the component off the span: a rank-`r` matrix at that
//!   distance) and `sigma_r(M) >= sigma_r(V)` (adding rows does not decrease singular values),
//!   `sigma_1(V) <= sigma_1(M) <= sqrt(sigma_1(V)^2 + |V'|_F^2)`. If
//!   `|V' E^T|_F <= rank sigma_1(V)` and `sigma_r(V) > rank sqrt(sigma_1(V)^2 + |V'|_F^2)`
//!   ([`crate::tol::Tolerances::rank`]), a conversion from scratch finds rank `r` as well;
//!   otherwise the continuation starts over (the span grows, or the decision is close);
//! - **zero and duplicate generators**: the same rules as [`crate::precondition`] (the rows
//!   are scaled by powers of two first, so only a zero row is a zero generator; duplicates
//!   compared in the frame);
//! - **conditioning**: the frame is whitened for `V` (`Y^T Y = I` over its generators), so for
//!   all the generators `G = Y^T Y = I + sum y y^T` over the added ones (`y` not normalized),
//!   and the map from the frame to a fresh whitening has condition number
//!   `kappa = sqrt(cond G) <= sqrt(1 + sum |y|^2)`. Above
//!   [`crate::tol::Tolerances::continuation_condition`] the continuation **moves its state**
//!   to fresh whitened coordinates of all the generators (one SVD, and each polar ray mapped
//!   as a facet normal, `S' Q' Q^T S^{-1}` up to normalization; zero sets unchanged) before
//!   adding the new rows: that step ([`Step::Reframed`]) runs in the coordinates of a
//!   conversion from scratch. (Combining nearly parallel rays in badly conditioned
//!   coordinates loses accuracy: on a random stance with 5 mm patches, `kappa = 59` gave facet
//!   normals 9e-9 rad away from those from scratch, `kappa <= 45` less than 6e-11.)
//!
//! **Accuracy.** A continued ray comes from a longer chain of combinations than a ray
//! computed from scratch (each contact's rows combine rays made by the previous ones), and
//! combining nearly parallel rays amplifies rounding. After the new rows, every ray whose
//! largest slack on its tight rows exceeds [`crate::tol::Tolerances::polish`] is recomputed as
//! the projection of itself on the orthogonal complement of those rows (modified Gram-Schmidt),
//! which brings it back to rounding level.
//!
//! The result then gets the full [`crate::Certificate`], in the frame: soundness, support,
//! lineality and completeness are checked exactly as for a conversion from scratch, with the
//! tolerances applied to cosines in the frame, which differ from cosines in fresh whitened
//! coordinates by a factor at most `kappa` either way. The facets are mapped to world
//! coordinates and sorted by the same rule as from scratch.
//!
//! **Same answer as from scratch, up to merging.** The double description merges structure
//! that is degenerate within [`crate::tol::Tolerances::incidence`], and which near-degenerate
//! pieces end up merged depends on its path: the initial basis, the order of the rows and the
//! coordinates (cosines in the frame are within a factor `kappa` of fresh ones). On stances
//! degenerate at that scale, a continued answer and the answer from scratch can therefore
//! differ by such pieces, both certified, or one path's floating-point answer can fail its
//! certificate and come from the exact fallback while the other's passes. The random-stance
//! property test (`tests/continuation.rs`, 1 to 4 rectangles with patches down to 5 mm) saw
//! this on 5 stances out of about 27,000; its saved regressions replay the two below. In one, six
//! generators lie within `2.4e-9` (unit cosines in world coordinates) of one hyperplane: the
//! continuation returns one facet through all six; from scratch the same facet comes with two
//! more, through five of them each, `5.8e-7` and `5.3e-6` rad away from it (380 facets
//! against 382 on the shrunk case). The rays of each face form are within `7.9e-9` and
//! `5.1e-11` (relative distance) of the span of the generators. In the other, the answer from
//! scratch is exact, with 494 facets against 293. Apart from such cases the answers are the
//! same facets to `1e-9` rad, with the same equations, lineality and extreme generators. The
//! test checks that, and where the facets differ it checks both answers against a membership
//! oracle at the points where they differ most.
//!
//! # When a continuation starts over
//!
//! The continuation converts `[V; V']` from scratch (and says so in [`Continuation::last_step`],
//! with the [`Restart`] reason) when continuing is not the same problem:
//!
//! - the new generators may raise the dimension of the linear span (the cone was
//!   lower-dimensional: its equations change and the polar gains dimensions), or the rank
//!   decision is within the bounds above;
//! - exact arithmetic ([`crate::Arithmetic::Exact`]): the exact engine does not keep a state;
//! - the previous result came from the exact fallback (no floating-point state to resume);
//! - the resumed double description fails, or the certificate of the continued result fails
//!   (then the conversion from scratch runs, with its own exact fallback).
//!
//! A change of lineality within the same linear span needs no restart (the polar, pointed in
//! the frame, only loses dimensions, which the double description handles).

use nalgebra::DMatrix;

use crate::convert::{exact_polar, Polar, SpanToFace, Workspace};
use crate::linalg::normalize;
use crate::precondition::{scale_rows_pow2, whiten, Whitened};
use crate::{Arithmetic, ConeError, DdOptions, FaceForm};

/// Why a [`Continuation`] converted from scratch instead of continuing.
#[derive(Clone, Debug, PartialEq)]
pub enum Restart {
    /// The first conversion.
    Initial,
    /// The dimension of the linear span of the generators changed (`from` -> `to`).
    RankChanged {
        /// Before the new generators.
        from: usize,
        /// With them.
        to: usize,
    },
    /// The new generators are within the rank tolerance of leaving the linear span (the
    /// bounds of the module docs cannot decide the rank); from scratch found it unchanged.
    RankUndecided,
    /// Exact arithmetic was asked for: every step is an exact conversion from scratch.
    ExactArithmetic,
    /// The previous result did not leave a floating-point state to resume (it came from the
    /// exact fallback, or an earlier step failed).
    NotResumable,
    /// The resumed double description failed (numerical cancellation).
    DdFailed,
    /// The continued result failed its certificate (the reason); the conversion from scratch
    /// replaced it.
    Uncertified(String),
}

/// How the current result of a [`Continuation`] was obtained.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// By continuing the previous double description with `rows_added` new polar rows (the new
    /// generators left after dropping zero and duplicate ones).
    Continued {
        /// New constraint rows of the polar processed.
        rows_added: usize,
    },
    /// By continuing the previous double description with `rows_added` new polar rows, after
    /// moving its state to the whitened coordinates of all the generators, because the
    /// condition bound `kappa` of the previous coordinates exceeded
    /// [`crate::tol::Tolerances::continuation_condition`].
    Reframed {
        /// New constraint rows of the polar processed.
        rows_added: usize,
        /// The condition bound that triggered the move.
        kappa: f64,
    },
    /// By a conversion from scratch, for this reason.
    FromScratch(Restart),
}

/// Running quantities of the generators since the frame (input units), for the decisions of
/// the module docs.
#[derive(Clone, Debug, Default)]
struct Track {
    /// Largest generator norm so far.
    maxn: f64,
    /// Largest `|e . v|` over equations `e` of the frame and kept generators `v`.
    max_eq_abs: f64,
    /// Over the generators added since the frame: `sum |y|^2` (frame coordinates, not
    /// normalized), `sum |E v|^2`, `sum |v|^2`.
    sum_y2: f64,
    sum_out2: f64,
    sum_v2: f64,
}

/// Why continuing stopped, before the conversion from scratch.
enum Stop {
    Restart(Restart),
    /// The rank bounds failed: the reason depends on what the conversion from scratch finds.
    Span,
}

/// A span -> face conversion that can continue when generators are added (see the
/// [module docs](self) for the math and the cases that start over).
///
/// ```
/// use polycone::{nalgebra::DMatrix, Continuation, DdOptions, Step};
/// // The positive orthant of R^3, then a fourth extreme ray.
/// let v = DMatrix::from_row_slice(3, 3, &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
/// let mut c = Continuation::new(&v, &DdOptions::default()).unwrap();
/// assert_eq!(c.result().face.facets.nrows(), 3);
/// let more = DMatrix::from_row_slice(1, 3, &[-1.0, 1.0, 1.0]);
/// let r = c.add_generators(&more).unwrap();
/// assert_eq!(r.face.facets.nrows(), 4);
/// assert!(r.certificate.certified);
/// assert_eq!(c.last_step(), &Step::Continued { rows_added: 1 });
/// assert_eq!(c.generators().nrows(), 4);
/// ```
#[derive(Clone, Debug)]
pub struct Continuation {
    opts: DdOptions,
    /// Every generator so far, in the order given (input rows).
    generators: DMatrix<f64>,
    /// The same rows scaled by powers of two ([`scale_rows_pow2`]): what every decision is
    /// made on, so that none depends on the scale of a generator.
    scaled: DMatrix<f64>,
    /// Buffers; `ws.core` holds the double description state when `resumable`.
    ws: Workspace,
    /// The whitening of the last conversion from scratch: the coordinates of the state.
    frame: Whitened,
    /// All generators so far in the frame's coordinates (kept, unit rows, distinct): the
    /// problem the current certificate was checked on.
    current: Whitened,
    track: Track,
    resumable: bool,
    result: SpanToFace,
    step: Step,
    /// Scratch for the new polar rows.
    new_rows: Vec<f64>,
    /// The input generator of each row of the double description state, in row order.
    dd_rows: Vec<usize>,
    /// Scratch for the polishing of the rays.
    basis: Vec<f64>,
}

/// The input generators of the double description rows of a conversion from scratch.
fn dd_rows_of(wh: &Whitened) -> Vec<usize> {
    wh.distinct.iter().map(|&t| wh.kept[t]).collect()
}

/// Recomputes each ray of `core` (coordinates of `wh`) whose largest slack on its tight rows
/// (its zero set) exceeds `polish` as its orthogonal projection on the complement of those
/// rows: `x <- x - P_T x`, normalized. Continued rays
/// come from longer chains of combinations than rays from scratch, and combining nearly
/// parallel rays amplifies rounding (measured: tight residuals of 3e-11 instead of 2e-15 on a
/// stance with 5 mm patches); the projection brings them back to rounding level. Tight rows
/// whose Gram-Schmidt residual is at most `rank_eps` add no direction; a ray whose tight rows
/// do not reach rank `r - 1` is left as it is.
fn polish_rays(
    core: &mut crate::dd::DdCore,
    dd_rows: &[usize],
    wh: &Whitened,
    [polish, rank_eps]: [f64; 2],
    basis: &mut Vec<f64>,
) {
    let (r, words, n) = (wh.r, core.words, core.n);
    if r < 2 {
        return;
    }
    for i in 0..n {
        // The largest slack of the ray on its tight rows: below `polish`, nothing to do.
        let x = &core.x[i * r..(i + 1) * r];
        let mut worst: f64 = 0.0;
        for (wi, &w0) in core.z[i * words..(i + 1) * words].iter().enumerate() {
            let mut w = w0;
            while w != 0 {
                let b = w.trailing_zeros() as usize;
                w &= w - 1;
                if let Some(t) = dd_rows
                    .get(wi * 64 + b)
                    .and_then(|g| wh.kept.binary_search(g).ok())
                {
                    let s: f64 = wh.gen(t).iter().zip(x).map(|(a, b)| a * b).sum();
                    worst = worst.max(s.abs());
                }
            }
        }
        if worst <= polish {
            continue;
        }
        basis.clear();
        let mut nb = 0;
        for (wi, &w0) in core.z[i * words..(i + 1) * words].iter().enumerate() {
            let mut w = w0;
            while w != 0 && nb + 1 < r {
                let b = w.trailing_zeros() as usize;
                w &= w - 1;
                let Some(&g) = dd_rows.get(wi * 64 + b) else {
                    continue;
                };
                let Ok(t) = wh.kept.binary_search(&g) else {
                    continue;
                };
                let start = basis.len();
                basis.extend_from_slice(wh.gen(t));
                for _ in 0..2 {
                    for q in 0..nb {
                        let (head, tail) = basis.split_at_mut(start);
                        let qv = &head[q * r..(q + 1) * r];
                        let c: f64 = qv.iter().zip(tail.iter()).map(|(a, b)| a * b).sum();
                        for (x, y) in tail.iter_mut().zip(qv) {
                            *x -= c * y;
                        }
                    }
                }
                if normalize(&mut basis[start..]) > rank_eps {
                    nb += 1;
                } else {
                    basis.truncate(start);
                }
            }
        }
        if nb + 1 != r {
            continue;
        }
        let x = &mut core.x[i * r..(i + 1) * r];
        for _ in 0..2 {
            for q in basis.chunks_exact(r) {
                let c: f64 = q.iter().zip(x.iter()).map(|(a, b)| a * b).sum();
                for (xv, qv) in x.iter_mut().zip(q) {
                    *xv -= c * qv;
                }
            }
        }
        normalize(x);
    }
}

fn polar_into_result(p: Polar, d: usize) -> SpanToFace {
    SpanToFace {
        face: FaceForm {
            dim: d,
            facets: p.facets,
            equations: p.equations,
        },
        lineality: p.lineality,
        extreme_generators: p.extreme,
        certificate: p.certificate,
    }
}

fn check_generators(v: &DMatrix<f64>, d: Option<usize>) -> Result<(), ConeError> {
    crate::forms::check_dimension(v.ncols())?;
    if let Some(d) = d {
        if v.ncols() != d {
            return Err(ConeError::DimensionMismatch {
                what: "new generators",
                got: v.ncols(),
                expected: d,
            });
        }
    }
    for j in 0..v.ncols() {
        for i in 0..v.nrows() {
            let x = v[(i, j)];
            if !x.is_finite() {
                return Err(ConeError::NonFinite {
                    what: "generators",
                    row: i,
                    col: j,
                    value: x,
                });
            }
        }
    }
    Ok(())
}

/// A conversion from scratch that keeps its state: `(result, frame, resumable)`.
fn from_scratch(
    ws: &mut Workspace,
    v: &DMatrix<f64>,
    opts: &DdOptions,
) -> Result<(SpanToFace, Whitened, bool), ConeError> {
    let d = v.ncols();
    opts.tol.validate()?;
    if opts.arithmetic == Arithmetic::Exact {
        let p = exact_polar(v, opts)?;
        return Ok((polar_into_result(p, d), Whitened::default(), false));
    }
    let attempt = ws.whiten_and_run(v, opts).and_then(|()| {
        // The continuation keeps the whitening (its frame).
        let wh = std::mem::take(&mut ws.wh);
        let fw = rays_of(ws, wh.r);
        ws.finish_polar(&wh, fw, opts).map(|p| (p, wh))
    });
    match attempt {
        Ok((p, wh)) => {
            // The continuation needs the input scale of the singular values.
            let resumable = wh.scale.is_finite() && wh.scale > 0.0;
            Ok((polar_into_result(p, d), wh, resumable))
        }
        Err(ConeError::Uncertified(reason)) if opts.exact_fallback => {
            let mut p = exact_polar(v, opts)
                .map_err(|e| ConeError::Uncertified(format!("{reason}; exact fallback: {e}")))?;
            p.certificate.fallback = Some(reason);
            // As a conversion from scratch does: the rounded input's slivers merged.
            crate::merge::merge_fallback_rows(
                &mut p.facets,
                &p.equations,
                None,
                &mut p.certificate,
                opts.tol.certificate,
            );
            Ok((polar_into_result(p, d), Whitened::default(), false))
        }
        Err(e) => Err(e),
    }
}

/// The running quantities right after a conversion from scratch of `v` with whitening `wh`.
fn track_of(v: &DMatrix<f64>, wh: &Whitened) -> Track {
    let norms: Vec<f64> = (0..v.nrows()).map(|i| v.row(i).norm()).collect();
    let maxn = norms.iter().copied().fold(0.0, f64::max);
    Track {
        maxn,
        max_eq_abs: wh.equation_residual * maxn,
        sum_y2: 0.0,
        sum_out2: 0.0,
        sum_v2: 0.0,
    }
}

/// The rays of the workspace's double description state (dimension `r`), flat.
fn rays_of(ws: &Workspace, r: usize) -> Vec<f64> {
    let nf = if r > 0 { ws.core.n } else { 0 };
    let mut fw = Vec::with_capacity(nf * r);
    for f in 0..nf {
        fw.extend_from_slice(ws.core.ray(f));
    }
    fw
}

impl Continuation {
    /// Converts `generators` (`n x d`, one per row) like [`crate::span_to_face`], keeping the
    /// state to continue from.
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, Continuation, Restart, Step};
    /// let v = DMatrix::<f64>::identity(2, 2);
    /// let c = Continuation::new(&v, &Default::default()).unwrap();
    /// assert_eq!(c.result().face.facets.nrows(), 2);
    /// assert_eq!(c.last_step(), &Step::FromScratch(Restart::Initial));
    /// ```
    pub fn new(generators: &DMatrix<f64>, opts: &DdOptions) -> Result<Self, ConeError> {
        Self::with_workspace(Workspace::new(), generators, opts)
    }

    /// [`Continuation::new`] reusing the buffers of `ws` (taken over by the continuation; get
    /// them back with [`Continuation::into_workspace`]).
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, Continuation, Workspace};
    /// let v = DMatrix::<f64>::identity(3, 3);
    /// let c = Continuation::with_workspace(Workspace::new(), &v, &Default::default()).unwrap();
    /// assert_eq!(c.result().face.facets.nrows(), 3);
    /// ```
    pub fn with_workspace(
        mut ws: Workspace,
        generators: &DMatrix<f64>,
        opts: &DdOptions,
    ) -> Result<Self, ConeError> {
        check_generators(generators, None)?;
        if opts.wrench {
            return Err(ConeError::IncompatibleOptions(
                "`wrench` with a Continuation: convert each stance with `span_to_face`, or move \
                 the reference point near the contacts yourself",
            ));
        }
        let mut scaled = generators.clone();
        scale_rows_pow2(&mut scaled);
        let (result, frame, resumable) = from_scratch(&mut ws, &scaled, opts)?;
        let dd_rows = dd_rows_of(&frame);
        Ok(Self {
            opts: opts.clone(),
            generators: generators.clone(),
            track: track_of(&scaled, &frame),
            scaled,
            ws,
            current: frame.clone(),
            frame,
            resumable,
            result,
            step: Step::FromScratch(Restart::Initial),
            new_rows: Vec::new(),
            dd_rows,
            basis: Vec::new(),
        })
    }

    /// The face form of the span of every generator so far (certified like any conversion).
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, Continuation};
    /// let c = Continuation::new(&DMatrix::<f64>::identity(3, 3), &Default::default()).unwrap();
    /// assert!(c.result().certificate.certified);
    /// ```
    pub fn result(&self) -> &SpanToFace {
        &self.result
    }

    /// Every generator so far, in the order given (the indices of
    /// [`SpanToFace::extreme_generators`] refer to these rows).
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, Continuation};
    /// let c = Continuation::new(&DMatrix::<f64>::identity(3, 3), &Default::default()).unwrap();
    /// assert_eq!(c.generators().shape(), (3, 3));
    /// ```
    pub fn generators(&self) -> &DMatrix<f64> {
        &self.generators
    }

    /// How the current result was obtained: continued, or from scratch and why.
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, Continuation, Restart, Step};
    /// // A ray of the plane, then a generator off its line: the span grows, so from scratch.
    /// let mut c = Continuation::new(&DMatrix::from_row_slice(1, 2, &[1.0, 0.0]), &Default::default()).unwrap();
    /// c.add_generators(&DMatrix::from_row_slice(1, 2, &[0.0, 1.0])).unwrap();
    /// assert_eq!(c.last_step(), &Step::FromScratch(Restart::RankChanged { from: 1, to: 2 }));
    /// ```
    pub fn last_step(&self) -> &Step {
        &self.step
    }

    /// The bound `sqrt(1 + sum |y|^2)` on the condition number of the current coordinates
    /// relative to a fresh whitening (1 right after a conversion from scratch; see the module
    /// docs).
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, Continuation};
    /// let mut c = Continuation::new(&DMatrix::<f64>::identity(3, 3), &Default::default()).unwrap();
    /// assert_eq!(c.condition_bound(), 1.0);
    /// c.add_generators(&DMatrix::from_row_slice(1, 3, &[-1.0, 1.0, 1.0])).unwrap();
    /// assert!((c.condition_bound() - 2.0).abs() < 1e-12); // 1 + |(-1, 1, 1)|^2 = 4
    /// ```
    pub fn condition_bound(&self) -> f64 {
        (1.0 + self.track.sum_y2).sqrt()
    }

    /// The options the conversions use.
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, Continuation, DdOptions};
    /// let c = Continuation::new(&DMatrix::<f64>::identity(2, 2), &DdOptions::default()).unwrap();
    /// assert!(c.options().exact_fallback);
    /// ```
    pub fn options(&self) -> &DdOptions {
        &self.opts
    }

    /// Gives the buffers back.
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, Continuation};
    /// let c = Continuation::new(&DMatrix::<f64>::identity(2, 2), &Default::default()).unwrap();
    /// let mut ws = c.into_workspace();
    /// assert!(ws.span_to_face(&DMatrix::<f64>::identity(2, 2), &Default::default()).is_ok());
    /// ```
    pub fn into_workspace(self) -> Workspace {
        self.ws
    }

    /// Adds generators (`q x d`, one per row, finite) and returns the face form of the span of
    /// all of them: the same cone as [`crate::span_to_face`] on the stacked generators (same
    /// facets up to rounding, same order rule, equations, lineality, extreme generators as
    /// indices into [`Continuation::generators`], a full certificate; on stances degenerate at
    /// the scale of the tolerances, facets may be merged differently: module docs), obtained
    /// by continuing the double description when possible ([`Continuation::last_step`]).
    ///
    /// On error (bad input, or a cone that cannot be certified) the continuation still
    /// describes the previous generators and result; after an uncertified step the next call
    /// converts from scratch.
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, span_to_face, Continuation, DdOptions, Step};
    /// // A square-based pyramid in R^3, one edge at a time after the first three.
    /// let v = DMatrix::from_row_slice(3, 3, &[1.0, 1.0, 1.0, -1.0, 1.0, 1.0, -1.0, -1.0, 1.0]);
    /// let opts = DdOptions::default();
    /// let mut c = Continuation::new(&v, &opts).unwrap();
    /// let r = c.add_generators(&DMatrix::from_row_slice(1, 3, &[1.0, -1.0, 1.0])).unwrap().clone();
    /// assert_eq!(c.last_step(), &Step::Continued { rows_added: 1 });
    /// let scratch = span_to_face(c.generators(), &opts).unwrap();
    /// assert_eq!(r.face.facets.nrows(), 4);
    /// assert!((r.face.facets.clone() - scratch.face.facets).amax() < 1e-12);
    /// assert_eq!(r.extreme_generators, vec![0, 1, 2, 3]);
    /// // Wrong width: an error, and the continuation is unchanged.
    /// assert!(c.add_generators(&DMatrix::zeros(1, 2)).is_err());
    /// assert_eq!(c.generators().nrows(), 4);
    /// ```
    pub fn add_generators(&mut self, new: &DMatrix<f64>) -> Result<&SpanToFace, ConeError> {
        let d = self.generators.ncols();
        check_generators(new, Some(d))?;
        let n_old = self.generators.nrows();
        let stack = |old: &DMatrix<f64>, new: &DMatrix<f64>| {
            let mut all = old.clone().resize_vertically(n_old + new.nrows(), 0.0);
            all.rows_mut(n_old, new.nrows()).copy_from(new);
            all
        };
        let mut new_scaled = new.clone();
        scale_rows_pow2(&mut new_scaled);
        let all = stack(&self.scaled, &new_scaled);
        let outcome = match self.continue_with(&all, n_old) {
            Ok((result, wh, track, step)) => {
                if matches!(step, Step::Reframed { .. }) {
                    self.frame = wh.clone();
                }
                self.current = wh;
                self.track = track;
                Ok((result, step))
            }
            Err(Stop::Restart(reason)) => self.restart(&all, reason),
            Err(Stop::Span) => {
                let from = self.frame.r;
                self.restart(&all, Restart::RankUndecided)
                    .map(|(res, step)| match self.frame.r {
                        to if to != from && self.resumable => {
                            (res, Step::FromScratch(Restart::RankChanged { from, to }))
                        }
                        _ => (res, step),
                    })
            }
        };
        match outcome {
            Ok((result, step)) => {
                self.generators = stack(&self.generators, new);
                self.scaled = all;
                self.result = result;
                self.step = step;
                Ok(&self.result)
            }
            Err(e) => {
                self.resumable = false;
                Err(e)
            }
        }
    }

    /// A conversion of `all` from scratch, keeping its state.
    fn restart(
        &mut self,
        all: &DMatrix<f64>,
        reason: Restart,
    ) -> Result<(SpanToFace, Step), ConeError> {
        let (result, frame, resumable) = from_scratch(&mut self.ws, all, &self.opts)?;
        self.track = track_of(all, &frame);
        self.dd_rows = dd_rows_of(&frame);
        self.current = frame.clone();
        self.frame = frame;
        self.resumable = resumable;
        Ok((result, Step::FromScratch(reason)))
    }

    /// Continues the state with the generators of `all` past row `n_old`; `Err` when it cannot
    /// (the caller restarts). On success: the result, the generators in the coordinates of the
    /// state, the running quantities and the step taken.
    fn continue_with(
        &mut self,
        all: &DMatrix<f64>,
        n_old: usize,
    ) -> Result<(SpanToFace, Whitened, Track, Step), Stop> {
        let opts = &self.opts;
        let tol = &opts.tol;
        if opts.arithmetic == Arithmetic::Exact {
            return Err(Stop::Restart(Restart::ExactArithmetic));
        }
        if !self.resumable {
            return Err(Stop::Restart(Restart::NotResumable));
        }
        let frame = &self.frame;
        let (d, r) = (frame.d, frame.r);
        let n_new = all.nrows() - n_old;
        let mut t = self.track.clone();
        let norms: Vec<f64> = (n_old..all.nrows()).map(|i| all.row(i).norm()).collect();
        t.maxn = norms.iter().copied().fold(t.maxn, f64::max);
        // Singular values in input units.
        let sv_in: Vec<f64> = frame.sv.iter().map(|s| s / frame.scale).collect();
        let mut wh = self.current.clone();
        let first_new_distinct = wh.distinct.len();
        let mut y = vec![0.0; r];
        for (t_new, &norm) in norms.iter().enumerate() {
            // Rows are scaled by powers of two (the largest entry in [0.5, 1)): only a zero
            // row is a zero generator, whatever the other rows' sizes.
            if norm == 0.0 {
                continue;
            }
            let i = n_old + t_new;
            let v = all.row(i);
            if r == 0 {
                // A non-zero generator in a zero cone: the span grows.
                return Err(Stop::Span);
            }
            let mut out2 = 0.0;
            for e in 0..d - r {
                let ev: f64 = frame.equations.row(e).dot(&v);
                out2 += ev * ev;
                t.max_eq_abs = t.max_eq_abs.max(ev.abs());
            }
            t.sum_out2 += out2;
            t.sum_v2 += norm * norm;
            for ((yc, q), &s) in y.iter_mut().zip(frame.q.chunks_exact(d)).zip(&sv_in) {
                *yc = q.iter().zip(v.iter()).map(|(a, b)| a * b).sum::<f64>() / s;
            }
            t.sum_y2 += normalize(&mut y).powi(2);
            let kept_index = wh.kept.len();
            wh.kept.push(i);
            wh.w.extend_from_slice(&y);
            let duplicate = wh.distinct.iter().any(|&s| {
                let g = &wh.w[s * r..(s + 1) * r];
                let d2: f64 = g.iter().zip(&y).map(|(a, b)| (a - b) * (a - b)).sum();
                d2 <= tol.duplicate * tol.duplicate
            });
            if !duplicate {
                wh.distinct.push(kept_index);
            }
        }
        if n_new > 0 && r > 0 {
            // The rank bounds of the module docs.
            let (s1, sr) = (sv_in[0], sv_in[r - 1]);
            let stays_below = t.sum_out2.sqrt() <= tol.rank * s1;
            let stays_above = sr > tol.rank * (s1 * s1 + t.sum_v2).sqrt();
            if !(stays_below && stays_above) {
                return Err(Stop::Span);
            }
        }
        let kappa = (1.0 + t.sum_y2).sqrt();
        let reframed = kappa.is_nan() || kappa > tol.continuation_condition;
        let (wh, t, first_new_distinct) = if reframed {
            // Move the state to the whitened coordinates of all the generators (those of a
            // conversion from scratch): the polar rays are facet normals.
            let fresh = whiten(all, tol);
            if fresh.r != r {
                return Err(Stop::Span);
            }
            if fresh.kept != wh.kept {
                // (Both keep exactly the nonzero rows; should that ever differ, starting over
                // is the safe answer.)
                return Err(Stop::Span);
            }
            let mut u = vec![0.0; d];
            let n = self.ws.core.n;
            for ray in self.ws.core.x.chunks_exact_mut(r.max(1)).take(n) {
                frame.facet_to_world(ray, &mut u);
                fresh.facet_from_world(&u, ray);
            }
            // `distinct` follows the input order: the new generators are a suffix.
            let first = fresh
                .distinct
                .iter()
                .position(|&k| fresh.kept[k] >= n_old)
                .unwrap_or(fresh.distinct.len());
            let t = track_of(all, &fresh);
            (fresh, t, first)
        } else {
            wh.equation_residual = if t.maxn > 0.0 {
                t.max_eq_abs / t.maxn
            } else {
                0.0
            };
            (wh, t, first_new_distinct)
        };
        // New polar rows: the new distinct generators, in the coordinates of the state.
        self.new_rows.clear();
        for &k in &wh.distinct[first_new_distinct..] {
            self.new_rows.extend_from_slice(wh.gen(k));
        }
        let rows_added = wh.distinct.len() - first_new_distinct;
        if r > 0 {
            self.ws
                .core
                .add_rows(&self.new_rows, rows_added, tol.incidence)
                .map_err(|_| Stop::Restart(Restart::DdFailed))?;
            self.dd_rows.extend(
                wh.distinct[first_new_distinct..]
                    .iter()
                    .map(|&k| wh.kept[k]),
            );
            polish_rays(
                &mut self.ws.core,
                &self.dd_rows,
                &wh,
                [tol.polish, tol.support_rank],
                &mut self.basis,
            );
        }
        let fw = rays_of(&self.ws, r);
        let p = self
            .ws
            .finish_polar(&wh, fw, opts)
            .map_err(|e| Stop::Restart(Restart::Uncertified(e.to_string())))?;
        if opts.check_completeness && !p.certificate.certified {
            // Returned uncertified only because `allow_uncertified` is set: from scratch may
            // certify what the continuation could not.
            return Err(Stop::Restart(Restart::Uncertified(
                p.certificate.failure_reason(),
            )));
        }
        let step = if reframed {
            Step::Reframed { rows_added, kappa }
        } else {
            Step::Continued { rows_added }
        };
        Ok((polar_into_result(p, d), wh, t, step))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The generators of a flat 4-sided pyramid at the 4 corners of two rectangles (a flat
    /// double support), wrench `-(f, p x f)`.
    fn two_feet() -> DMatrix<f64> {
        let mut rows = Vec::new();
        for (cx, cy) in [(0.0, 0.1), (0.05, -0.12)] {
            for (sx, sy) in [(1.0, 1.0), (1.0, -1.0), (-1.0, -1.0), (-1.0, 1.0)] {
                let p = [cx + sx * 0.11, cy + sy * 0.065, 0.0];
                for (ex, ey) in [(0.7, 0.7), (0.7, -0.7), (-0.7, -0.7), (-0.7, 0.7)] {
                    let f = [ex, ey, 1.0];
                    let t = [
                        p[1] * f[2] - p[2] * f[1],
                        p[2] * f[0] - p[0] * f[2],
                        p[0] * f[1] - p[1] * f[0],
                    ];
                    rows.extend([-f[0], -f[1], -f[2], -t[0], -t[1], -t[2]]);
                }
            }
        }
        DMatrix::from_row_slice(32, 6, &rows)
    }

    /// A corrupted state (one polar ray lost, as a wrong continuation would lose a facet) is
    /// caught by the certificate of the continued result, and the conversion from scratch
    /// replaces it.
    #[test]
    fn certificate_catches_a_wrong_continuation() {
        let v = two_feet();
        let opts = DdOptions::default();
        let mut c = Continuation::new(&v.rows(0, 16).into_owned(), &opts).unwrap();
        // Drop the last ray of the state: the first foot's polar loses an extreme ray.
        c.ws.core.n -= 1;
        let words = c.ws.core.words;
        let k = c.ws.core.k;
        let n = c.ws.core.n;
        c.ws.core.x.truncate(n * k);
        c.ws.core.z.truncate(n * words);
        let r = c
            .add_generators(&v.rows(16, 16).into_owned())
            .unwrap()
            .clone();
        assert!(
            matches!(c.last_step(), Step::FromScratch(Restart::Uncertified(_))),
            "{:?}",
            c.last_step()
        );
        let scratch = crate::span_to_face(&v, &opts).unwrap();
        assert_eq!(r, scratch);
        assert!(r.certificate.certified);
        // The state is sound again: the next step continues.
        let more = DMatrix::from_row_slice(1, 6, &[0.0, 0.0, -1.0, -0.01, 0.02, 0.0]);
        c.add_generators(&more).unwrap();
        assert_eq!(c.last_step(), &Step::Continued { rows_added: 1 });
    }

    /// Without a floating-point state (after an exact fallback or a failed step), the next
    /// step converts from scratch and says why.
    #[test]
    fn not_resumable_restarts() {
        let v = two_feet();
        let opts = DdOptions::default();
        let mut c = Continuation::new(&v.rows(0, 16).into_owned(), &opts).unwrap();
        c.resumable = false;
        let r = c
            .add_generators(&v.rows(16, 16).into_owned())
            .unwrap()
            .clone();
        assert_eq!(c.last_step(), &Step::FromScratch(Restart::NotResumable));
        assert_eq!(r, crate::span_to_face(&v, &opts).unwrap());
        assert!(c.resumable);
    }
}

#[cfg(test)]
mod timing {
    use super::*;
    use crate::precondition::whiten;
    use std::time::Instant;

    fn med<F: FnMut()>(mut f: F) -> f64 {
        let mut v: Vec<f64> = (0..3000)
            .map(|_| {
                let t = Instant::now();
                f();
                t.elapsed().as_secs_f64() * 1e6
            })
            .collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    }

    pub(super) fn golden(case: &str) -> DMatrix<f64> {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../testdata/cones/");
        let text = std::fs::read_to_string(format!("{path}{case}.json")).unwrap();
        let j: serde_json::Value = serde_json::from_str(&text).unwrap();
        let rows: Vec<Vec<f64>> =
            serde_json::from_value(j["generators"]["float64"].clone()).unwrap();
        DMatrix::from_fn(rows.len(), 6, |i, k| rows[i][k])
    }

    /// Where the time goes, by phase, from scratch and continued (the last 16 generators
    /// added to the others), on the golden stances:
    /// `cargo test --release -p polycone --lib timing -- --ignored --nocapture`.
    #[test]
    #[ignore]
    fn breakdown() {
        for case in [
            "double_support_flat",
            "double_support_stairs",
            "tilted_foot_hand_ledge",
            "opposing_walls_frictionless",
        ] {
            let v = golden(case);
            let n = v.nrows();
            let first = v.rows(0, n - 16).into_owned();
            let last = v.rows(n - 16, 16).into_owned();
            let opts = DdOptions::default();
            let tol = opts.tol;
            let mut ws = Workspace::new();
            let t_whiten = med(|| {
                std::hint::black_box(whiten(&v, &tol));
            });
            let wh = whiten(&v, &tol);
            let mut a = Vec::new();
            for &i in &wh.distinct {
                a.extend_from_slice(wh.gen(i));
            }
            let m = wh.distinct.len();
            let t_dd = med(|| {
                ws.core.run(&a, m, wh.r, tol.incidence, tol.rank).unwrap();
            });
            let pairs_scratch = ws.core.pairs_tested;
            let fw = rays_of(&ws, wh.r);
            let t_finish = med(|| {
                std::hint::black_box(ws.finish_polar(&wh, fw.clone(), &opts).unwrap());
            });
            let t_total = med(|| {
                std::hint::black_box(ws.span_to_face(&v, &opts).unwrap());
            });
            let base = Continuation::new(&first, &opts).unwrap();
            let mut c = base.clone();
            c.add_generators(&last).unwrap();
            assert!(matches!(
                c.last_step(),
                Step::Continued { .. } | Step::Reframed { .. }
            ));
            let t_clone = med(|| {
                std::hint::black_box(base.clone());
            });
            let t_cont = med(|| {
                c.clone_from(&base);
                c.add_generators(&last).unwrap();
            });
            let t_clone_from = med(|| {
                c.clone_from(&base);
            });
            // The continued DD alone, and the certificate on its result.
            c.clone_from(&base);
            c.add_generators(&last).unwrap();
            let mut core = base.ws.core.clone();
            let rows_new = c.new_rows.clone();
            let cnt = rows_new.len() / wh.r;
            let t_dd_cont = med(|| {
                core.clone_from(&base.ws.core);
                core.add_rows(&rows_new, cnt, tol.incidence).unwrap();
            }) - med(|| core.clone_from(&base.ws.core));
            let fwc = rays_of(&c.ws, wh.r);
            let t_finish_cont = med(|| {
                std::hint::black_box(c.ws.finish_polar(&c.current, fwc.clone(), &opts).unwrap());
            });
            eprintln!(
                "{case}: {n} generators, {} facets; from scratch {t_total:.1} us = whiten {t_whiten:.1} + dd {t_dd:.1} ({pairs_scratch} pairs) + certificate and output {t_finish:.1}; \
                 continued {:.1} us (dd {t_dd_cont:.1}, certificate and output {t_finish_cont:.1}), clone {t_clone:.1}, kappa bound {:.2}",
                fw.len() / wh.r,
                t_cont - t_clone_from,
                c.condition_bound(),
            );
        }
    }
}

#[cfg(test)]
mod profile {
    use super::*;

    /// A loop of continued steps on the stairs stance, for a profiler:
    /// `cargo test --release -p polycone --lib profile_loop -- --ignored`.
    #[test]
    #[ignore]
    fn profile_loop() {
        let v = super::timing::golden("double_support_stairs");
        let base = Continuation::new(&v.rows(0, 16).into_owned(), &DdOptions::default()).unwrap();
        let last = v.rows(16, 16).into_owned();
        let mut c = base.clone();
        for _ in 0..20000 {
            c.clone_from(&base);
            std::hint::black_box(c.add_generators(&last).unwrap());
        }
    }
}
