//! # polycone
//!
//! Polyhedral convex cones in any dimension: conversion between the **span form**
//! `span(V) = {V z : z >= 0}` (generators) and the **face form** `face(U) = {x : U x <= 0}`
//! (facet normals), by the double description method (Motzkin et al. 1953; Fukuda and Prodon
//! 1996), with the lineality space and the equations of general cones, preconditioning, and a
//! certificate on every result.
//!
//! # The math
//!
//! A polyhedral cone `C` in `R^d` has two complete descriptions:
//!
//! - face form `C = {x : U x <= 0, E x = 0}` ([`FaceForm`]): rows of `U` are unit outward facet
//!   normals, rows of `E` an orthonormal basis of the **equations** (the complement of the
//!   linear hull of `C`; present when `C` is not full-dimensional);
//! - span form `C = {V^T z + L^T y : z >= 0}` ([`SpanForm`]): rows of `V` generators, rows of `L`
//!   a basis of the **lineality space** (the largest linear subspace in `C`; present when `C`
//!   is not pointed).
//!
//! The **polar** `C° = {u : u . x <= 0 for all x in C}` swaps the two: the facets of `C` are the
//! extreme rays of `C°`, the equations of `C` span the lineality space of `C°`, and `C°° = C`.
//! [`span_to_face`] whitens the generators (so that the answer does not depend on units or on
//! the reference point), reduces to the full-dimensional case in `span(V)`, and computes the
//! extreme rays of the pointed polar by double description (the [`dd`] module docs);
//! [`face_to_span`] is [`span_to_face`] applied to the polar `span([U; E; -E])`.
//!
//! Edge cases: the zero cone (no or only zero generators) has `E = I`; the whole space has no
//! facet and `L = I`; a half-space has one facet and `d - 1` lineality directions.
//!
//! # The tolerance contract ([`Arithmetic::Tolerance`], the default)
//!
//! In whitened coordinates every generator `w_i` and facet `u` is a unit vector, and a
//! generator is **incident** to a facet when `|u . w_i| <= eps` with
//! `eps = `[`tol::Tolerances::incidence`]. The returned face form is exactly right for a
//! perturbation of the input in which every whitened generator moved by at most about `eps`
//! (a relative perturbation, independent of units): structure that is degenerate within `eps`
//! (a foot `1e-12` out of plane) is merged. What is certified (see [`Certificate`]), in whitened
//! unit coordinates: every generator satisfies every facet up to
//! [`tol::Tolerances::certificate`]; every facet is tight (within `eps`) on generators spanning a
//! hyperplane; the lineality space is positively spanned by generators; and every extreme ray
//! of the returned face form is (within [`tol::Tolerances::parallel`]) the projection of a
//! generator. So the returned cone is sandwiched: it contains every generator up to the
//! certificate tolerance and contains nothing outside `span(V)` beyond the parallel tolerance.
//! If any check fails, the conversion returns [`ConeError::Uncertified`] instead of a cone.
//!
//! # Limitations
//!
//! - [`Arithmetic::Exact`] uses big integers without a floating-point filter: it is one to three
//!   orders of magnitude slower than the tolerance mode, and its answer is exact for the
//!   rounded input (near-degenerate stances get many tiny facets).
//! - The double description runs in `f64` with a tolerance on signs; inputs degenerate at the
//!   scale of the tolerances may fail certification (an error, never a wrong certified cone).
//! - The completeness check costs a second double description run (of the result).
//! - Rank decisions (equations, lineality) use a relative singular-value threshold
//!   ([`tol::Tolerances::rank`]).

// Index loops over several parallel arrays read like the math here.
#![allow(clippy::needless_range_loop)]

pub use nalgebra;

mod certificate;
mod convert;
pub mod dd;
mod error;
mod exact;
mod forms;
mod linalg;
pub mod precondition;
pub mod tol;

pub use certificate::Certificate;
pub use convert::{
    certify_span_to_face, face_to_span, span_to_face, FaceToSpan, SpanToFace, Workspace,
};
pub use error::ConeError;
pub use forms::{FaceForm, SpanForm};

/// The two semantics of a conversion.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Arithmetic {
    /// Floating point with the tolerance contract of the crate docs (the default).
    #[default]
    Tolerance,
    /// Certified exact combinatorics for the input as given.
    Exact,
}

/// Options of a conversion.
#[derive(Clone, Debug)]
pub struct DdOptions {
    /// Tolerance (default) or exact semantics.
    pub arithmetic: Arithmetic,
    /// Thresholds, see [`tol::Tolerances`].
    pub tol: tol::Tolerances,
    /// In tolerance mode, when the floating-point answer cannot be certified, compute the exact
    /// answer for the input as given instead (slower; its certificate says
    /// [`Arithmetic::Exact`]). Default `true`.
    pub exact_fallback: bool,
    /// Run the completeness check of the certificate (the ridge check, about two thirds of the
    /// time of a conversion). When `false`, soundness and support are still checked but the
    /// result is never `certified` (and an uncertified result is returned, not an error, as
    /// if `allow_uncertified` were set). Default `true`.
    pub check_completeness: bool,
    /// Return the answer even when its certificate fails (with `certified == false`) instead of
    /// [`ConeError::Uncertified`]. Default `false`.
    pub allow_uncertified: bool,
}

impl Default for DdOptions {
    fn default() -> Self {
        Self {
            arithmetic: Arithmetic::Tolerance,
            tol: tol::Tolerances::default(),
            exact_fallback: true,
            check_completeness: true,
            allow_uncertified: false,
        }
    }
}
