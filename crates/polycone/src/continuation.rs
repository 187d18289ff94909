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
//! starting over: the work is the iterations of the new rows only.
//!
//! Coordinates: the double description state lives in the whitened coordinates of the
//! conversion it started from (the *frame*, `y = S^{-1} Q x`). Any invertible linear map of
//! `span(V)` preserves the cone's combinatorics, so the new generators are mapped into the frame
//! as they are (`S^{-1} Q v'`, normalized), as long as they lie in the same linear span. The
//! result is then certified exactly as a conversion from scratch is: the generators `[V; V']`
//! are preconditioned afresh (this decides the rank, the zero and duplicate generators, the
//! equations), the facets are mapped into those fresh coordinates and the full
//! [`crate::Certificate`] runs there. The tolerance contract of a continued result is therefore
//! the same as that of a conversion from scratch, on the same coordinates.
//!
//! # When a continuation starts over
//!
//! The continuation converts `[V; V']` from scratch (and says so in [`Continuation::last_step`],
//! with the [`Restart`] reason) when continuing is not the same problem:
//!
//! - the new generators raise the dimension of the linear span (the cone was lower-dimensional:
//!   its equations change and the polar gains dimensions) or the rank decision changes;
//! - a generator kept before is now a zero generator relative to the larger new ones;
//! - exact arithmetic ([`crate::Arithmetic::Exact`]): the exact engine does not keep a state;
//! - the previous result came from the exact fallback (no floating-point state to resume);
//! - the resumed double description fails, or the certificate of the continued result fails
//!   (then the conversion from scratch runs, with its own exact fallback).
//!
//! Duplicate and zero generators among the new ones are dropped as in a conversion from
//! scratch; a change of lineality with the same linear span needs no restart (the polar, still
//! pointed in the frame, only loses dimensions, which the double description handles).

use nalgebra::DMatrix;

use crate::convert::{exact_polar, Polar, SpanToFace, Workspace};
use crate::linalg::normalize;
use crate::precondition::{whiten, Whitened};
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
    /// A generator kept before is now negligible next to the new ones
    /// ([`crate::tol::Tolerances::zero_generator`]).
    ZeroGeneratorsChanged,
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
    /// By a conversion from scratch, for this reason.
    FromScratch(Restart),
}

/// A span -> face conversion that can continue when generators are added (see the module
/// docs of `continuation` for the math and the cases that start over).
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
    /// Buffers; `ws.core` holds the double description state when `resumable`.
    ws: Workspace,
    /// Coordinates of the state in `ws.core` (the whitening of the last conversion from scratch).
    frame: Whitened,
    /// The fresh preconditioning of `generators` (the coordinates of the current certificate).
    current: Whitened,
    resumable: bool,
    result: SpanToFace,
    step: Step,
    /// Scratch for the new polar rows, in the frame.
    new_rows: Vec<f64>,
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
    if v.ncols() == 0 {
        return Err(ConeError::ZeroDimension);
    }
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
    let attempt = ws.whiten_and_run(v, opts).and_then(|wh| {
        let fw = rays_of(ws, wh.r);
        ws.finish_polar(&wh, fw, opts).map(|p| (p, wh))
    });
    match attempt {
        Ok((p, wh)) => Ok((polar_into_result(p, d), wh, true)),
        Err(ConeError::Uncertified(reason)) if opts.exact_fallback => {
            let p = exact_polar(v, opts)
                .map_err(|e| ConeError::Uncertified(format!("{reason}; exact fallback: {e}")))?;
            Ok((polar_into_result(p, d), Whitened::default(), false))
        }
        Err(e) => Err(e),
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
    /// let ws: Workspace = c.into_workspace();
    /// # let _ = ws;
    /// ```
    pub fn with_workspace(
        mut ws: Workspace,
        generators: &DMatrix<f64>,
        opts: &DdOptions,
    ) -> Result<Self, ConeError> {
        check_generators(generators, None)?;
        let (result, frame, resumable) = from_scratch(&mut ws, generators, opts)?;
        Ok(Self {
            opts: opts.clone(),
            generators: generators.clone(),
            ws,
            current: frame.clone(),
            frame,
            resumable,
            result,
            step: Step::FromScratch(Restart::Initial),
            new_rows: Vec::new(),
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
    /// all of them: the same answer as [`crate::span_to_face`] on the stacked generators (same
    /// facets up to rounding, same order rule, equations, lineality, extreme generators as
    /// indices into [`Continuation::generators`], a full certificate), obtained by continuing
    /// the double description when possible ([`Continuation::last_step`]).
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
        let mut all = self
            .generators
            .clone()
            .resize_vertically(n_old + new.nrows(), 0.0);
        all.rows_mut(n_old, new.nrows()).copy_from(new);
        let outcome = match self.continue_with(&all, n_old) {
            Ok((result, wh, rows_added)) => {
                self.current = wh;
                Ok((result, Step::Continued { rows_added }))
            }
            Err(reason) => self.restart(&all, reason),
        };
        match outcome {
            Ok((result, step)) => {
                self.generators = all;
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
        self.current = frame.clone();
        self.frame = frame;
        self.resumable = resumable;
        Ok((result, Step::FromScratch(reason)))
    }

    /// Continues the state with the generators of `all` past row `n_old`; `Err(reason)` when
    /// it cannot (the caller restarts). On success: the result, its fresh preconditioning and
    /// the number of polar rows added.
    fn continue_with(
        &mut self,
        all: &DMatrix<f64>,
        n_old: usize,
    ) -> Result<(SpanToFace, Whitened, usize), Restart> {
        let opts = self.opts.clone();
        if opts.arithmetic == Arithmetic::Exact {
            return Err(Restart::ExactArithmetic);
        }
        if !self.resumable {
            return Err(Restart::NotResumable);
        }
        // Fresh preconditioning of all the generators: the rank, zero and duplicate decisions
        // and the coordinates of the certificate, exactly as from scratch.
        let wh = whiten(all, &opts.tol);
        let r = self.frame.r;
        if wh.r != r {
            return Err(Restart::RankChanged { from: r, to: wh.r });
        }
        let old_kept = wh.kept.iter().take_while(|&&i| i < n_old).count();
        if wh.kept[..old_kept] != self.current.kept[..] {
            return Err(Restart::ZeroGeneratorsChanged);
        }
        // New polar rows: the new distinct generators, mapped into the frame (S^-1 Q v).
        self.new_rows.clear();
        let mut rows_added = 0;
        for &t in &wh.distinct {
            let i = wh.kept[t];
            if i < n_old {
                continue;
            }
            let start = self.new_rows.len();
            for (q, &s) in self.frame.q.chunks_exact(self.frame.d).zip(&self.frame.sv) {
                let y: f64 = q.iter().zip(all.row(i).iter()).map(|(a, b)| a * b).sum();
                self.new_rows.push(y / s);
            }
            let norm = normalize(&mut self.new_rows[start..]);
            if !(norm.is_finite() && norm > 0.0) {
                return Err(Restart::DdFailed);
            }
            rows_added += 1;
        }
        if r > 0 {
            self.ws
                .core
                .add_rows(&self.new_rows, rows_added, opts.tol.incidence)
                .map_err(|_| Restart::DdFailed)?;
        }
        // The polar rays, frame -> world -> fresh coordinates.
        let fw_frame = rays_of(&self.ws, r);
        let nf = fw_frame.len().checked_div(r).unwrap_or(0);
        let mut fw = vec![0.0; nf * r];
        let mut u = vec![0.0; wh.d];
        for (src, dst) in fw_frame
            .chunks_exact(r.max(1))
            .zip(fw.chunks_exact_mut(r.max(1)))
        {
            self.frame.facet_to_world(src, &mut u);
            wh.facet_from_world(&u, dst);
        }
        let p = self
            .ws
            .finish_polar(&wh, fw, &opts)
            .map_err(|e| Restart::Uncertified(e.to_string()))?;
        if opts.check_completeness && !p.certificate.certified {
            // Returned uncertified only because `allow_uncertified` is set: from scratch may
            // certify what the continuation could not.
            return Err(Restart::Uncertified(p.certificate.failure_reason()));
        }
        Ok((polar_into_result(p, wh.d), wh, rows_added))
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
