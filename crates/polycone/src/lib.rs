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
//! the reference point, up to the rank decision: see [`DdOptions::wrench`] for wrench cones),
//! reduces to the full-dimensional case in `span(V)`, and computes the
//! extreme rays of the pointed polar by double description (the [`dd`] module docs);
//! [`face_to_span`] is [`span_to_face`] applied to the polar `span([U; E; -E])`.
//!
//! Adding generators to a converted cone adds constraint rows to its polar: a [`Continuation`]
//! keeps the double description state of a conversion and continues it with the new rows
//! instead of starting over (the same answer as from scratch up to how structure degenerate
//! within the tolerances is merged, with a full certificate; the [`continuation`] module docs
//! say when answers differ and list the cases that start over).
//!
//! Edge cases: the zero cone (no or only zero generators) has `E = I`; the whole space has no
//! facet and `L = I`; a half-space has one facet and `d - 1` lineality directions.
//!
//! # The tolerance contract ([`Arithmetic::Tolerance`], the default)
//!
//! In whitened coordinates every generator `w_i` and facet normal `u` is a unit vector, so
//! slacks `u . w_i` are cosines, independent of units. Signs are decided with
//! `eps = `[`tol::Tolerances::incidence`] (`|u . w_i| <= eps`: incident): structure that is
//! degenerate within `eps` (a foot `1e-12` m out of plane) is merged. Every answer is then
//! verified by the [`Certificate`], in whitened unit coordinates:
//!
//! 1. **soundness**: every generator satisfies every facet up to
//!    [`tol::Tolerances::certificate`] (the true cone lies in the returned one, up to that
//!    angle), and the equations annihilate the generators;
//! 2. **support**: every facet is incident to generators spanning a hyperplane (no facet is
//!    spurious: each is, within `eps`, a facet of the true cone);
//! 3. **lineality**: the generators lying in the returned lineality space positively span it;
//! 4. **completeness**: every ridge of every returned facet (computed from the generators
//!    incident to it) lies in exactly two returned facets, or, equivalently for this proof,
//!    the returned facets next to a facet cut its hyperplane down to exactly the cone of its
//!    incident generators (checked ray by ray with a proven angle bound); with 1 and 2 this
//!    proves that no facet is missing (the facet graph of a cone is connected), which is what
//!    cddlib's float mode gets wrong on near-degenerate stances while passing 1 and 2. Up to
//!    `t - 2` facets of a `t`-dimensional pointed part need not be checked (Balinski's
//!    theorem: the facet graph is `(t - 1)`-connected); the certificate module docs give the
//!    arguments.
//!
//! So a certified answer is the face form of `span(V)` up to merging structure degenerate
//! within `eps`. What is not proven: a bound on the distance between the returned and the true
//! cone as a function of `eps` (incidences are tolerance decisions); the tests check membership
//! against an independent oracle (non-negative least squares over the generators) outside a
//! `1e-6` band. When the certificate fails, the conversion falls back to exact arithmetic
//! ([`DdOptions::exact_fallback`], on by default), and returns [`ConeError::Uncertified`] if
//! that fails too: a wrong cone is never returned as certified. The exact answer of the
//! rounded input keeps the slivers rounding split off the intended geometry; rows of it closer
//! than [`tol::Tolerances::certificate`] to a kept row, then rows whose removal enlarges the
//! cone by at most that tolerance, are dropped, each with a certificate (non-negative weights
//! on the kept rows whose residual bounds the enlargement; the `merge` module docs): no unit
//! vector the answer admits violates a row of the exact answer by more than the recorded
//! [`Certificate::merge_distance`] ([`Certificate::merged_rows`]). The tests check it against
//! the exact answer's face -> span, and check, with the intended (unrounded) geometry written in
//! integers and converted exactly, that the merged answer has at most its facets: two feet 1e-9
//! to 1e-5 m apart in height (42 intended; 16 to 38 kept, the coplanar 16 at 1e-9 m), the
//! stairs stance with patches of 10 to 100 um (168 intended, 239 to 270 exact rows of the
//! rounded input, 160 kept) and three contacts, one rolled by 0.01 degree (218 intended, 326
//! exact, 190 kept); and that every answer of the stress corpus (remote origins, tiny
//! patches, raised and rolled feet), certified in floating point or not, on both routes, has
//! at most the intended facets and stays within the tolerance of the exact cone.
//!
//! # Exact semantics ([`Arithmetic::Exact`])
//!
//! Every `f64` is a dyadic rational, so the input as given is converted to integers and the
//! double description, the equations, the lineality space and the certificate are computed
//! with big integers (see the `exact` module source): certified exact combinatorics for the
//! input as given, facet normals rounded to `f64` at the end. Rounding of the input usually
//! breaks the degeneracies of the intended geometry: the exact answer for a rounded flat
//! double support has 32 facets where the intended geometry has 16 (the same as cddlib's GMP
//! mode on the same input).
//!
//! # Limitations
//!
//! - Speed: the certified tolerance mode is faster than cddlib's float mode on 6-D wrench
//!   cones, but short of the ten times (16 generators) and thirty times (32) aimed at
//!   (`bench/peers/cones.md` has the figures and how to measure them). The checks are what
//!   cost: the certificate is most of a conversion, and everything but the certificate
//!   already stands about at those targets. Every facet but `t - 2` needs its ridges: from its
//!   claimed neighbours in closed form (the cheapest), by closed forms of its tight
//!   generators, or by a double description of them (the dearest), and every facet its
//!   support. Without the completeness part (`DdOptions::check_completeness`, uncertified)
//!   the targets are still not met.
//! - Above `d = 8` the preconditioning and the lineality split use nalgebra's SVD, which can
//!   return wrong singular values on rank-deficient inputs (its issue 1172; a review found
//!   227 defective decompositions among 3000 random rank-1 to rank-4 matrices with 9 to 12
//!   columns, without a wrong cone end to end on 13 of them). Up to `d = 8`, the paper's
//!   dimensions, the project's own QR and one-sided Jacobi are used.
//! - The hot bitset scans of the double description use AVX-512 (with `vpopcntq`) or AVX2
//!   when the CPU has them, chosen at run time; every variant gives the same answers (unit
//!   tests compare them), only the speed differs.
//! - [`Arithmetic::Exact`] uses big integers without a floating-point filter: as fast as
//!   cddlib's GMP mode or faster (`bench/peers/cones.md`), but far slower than the
//!   floating-point path; its cost grows with the size of the integers, hence with the
//!   number of exact facets.
//! - [`face_to_span`] runs the double description on the polar, whose constraints are the
//!   facets: with hundreds of facets it is much slower than [`span_to_face`] of the same cone.
//! - Inputs degenerate at the scale of the tolerances may need the exact fallback (slow) or
//!   fail certification (an error, never a wrong certified cone). The fallback's slivers are
//!   merged (see above) at a cost: least-squares fits over the exact rows, which the
//!   shallow-row pass adds to the fallback (`bench/peers/cones.md`). The merge keeps the first row
//!   of a near-parallel pair and drops shallow rows in increasing distance: a greedy choice, so
//!   it may keep more rows than the fewest a tolerance of `1e-8` allows, never more than the
//!   exact answer, and it is certified whatever the choice. Its distances are measured in the
//!   input's coordinates (on the wrench route, in the frame as well): invariant to the scale
//!   of a row, not to a change of units per coordinate.
//! - In tolerance mode, rank decisions (equations, lineality) use a relative singular-value
//!   threshold ([`tol::Tolerances::rank`]); exact mode computes exact ranks. "Relative" means
//!   relative to the input as given (after each row is scaled by a power of two: no decision
//!   depends on the scale of a row): the whitening that makes the conversion independent of the
//!   reference point and the units comes after the rank decision. A wrench cone written about a
//!   point far from its contacts has its sixth direction near 1e-10 of its largest: the stairs
//!   stance (176 facets at its contacts) written about a point 30 km away horizontally came
//!   back certified as a 5-D cone with 116 facets. A singular value that is dropped by the
//!   tolerance but stands above the rounding level ([`tol::RANK_NOISE`]) now leaves the rank
//!   undecided: [`ConeError::RankUndecided`], never a cone with a lost direction. For 6-D wrench
//!   cones, [`DdOptions::wrench`] (the [`wrench`] module) decides it: the generators are
//!   re-centred on their least-squares centre and scaled by their lever arm before the rank
//!   decision, and the far stances give the 176 facets in floating point (pulled back to the
//!   contacts within `4e-9` rad; `tests/wrench.rs`). What stays: the input itself is rounded
//!   in the far frame (`|s| u` of lever arm, `u` the unit roundoff), so from about 1000 km the
//!   rounding breaks the stance's degeneracies at the scale of
//!   [`tol::Tolerances::incidence`] even with the option (the stairs at `(1e6, 1e6, 1e6)` m:
//!   353 facets from the exact fallback); other dimensions, [`Arithmetic::Exact`] and
//!   [`Continuation`] do not take the option. Without it, write wrenches about a point near
//!   the generators (`stance-contact` does) or use [`Arithmetic::Exact`].
//! - [`Continuation`] saves only the double description of the generators already converted
//!   (and the SVD of the preconditioning while its coordinates stay well-conditioned): each
//!   step runs the full certificate (most of a conversion of a 6-D wrench cone) on the
//!   result, as no incremental certificate is done, and the double description of the new rows
//!   usually dominates the rest. Against a conversion from scratch when the second contact of
//!   the paper's stances is added, that saves about nothing (a little is lost on the box
//!   climbing, whose hand moves the state to fresh coordinates); the gain is large only when
//!   the new rows cut no ray (`bench/peers/contact.md`). A step that may enlarge the linear
//!   span of the generators (a lower-dimensional cone) is a conversion from scratch; continued
//!   steps allocate their results and some bookkeeping.
//! - The 2-D and 3-D polygon/polyhedron routines live in a separate module (`polytope`).

// Index loops over several parallel arrays read like the math here.
#![allow(clippy::needless_range_loop)]

pub use nalgebra;

mod certificate;
pub mod continuation;
mod convert;
pub mod dd;
mod error;
mod exact;
mod forms;
mod linalg;
mod merge;
pub mod polytope;
pub mod precondition;
pub mod tol;
pub mod wrench;

pub use certificate::Certificate;
pub use continuation::{Continuation, Restart, Step};
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
    /// [`Arithmetic::Exact`] and why, and how many near-parallel rows were merged). Default
    /// `true`.
    pub exact_fallback: bool,
    /// Run the completeness check of the certificate (the ridge check, about half of the
    /// instructions of a small conversion). When `false`, soundness and support are still checked but the
    /// result is never `certified` (and an uncertified result is returned, not an error, as
    /// if `allow_uncertified` were set). Default `true`.
    pub check_completeness: bool,
    /// Return the answer even when its certificate fails (with `certified == false`) instead of
    /// [`ConeError::Uncertified`]; the exact fallback is then not attempted. For diagnosis
    /// only: such an answer may be a wrong cone. Default `false`.
    pub allow_uncertified: bool,
    /// The wrench preconditioning ([`wrench`] module): for 6-D cones of wrenches
    /// `(f_x, f_y, f_z, tau_x, tau_y, tau_z)` only, re-centre the torques on the least-squares
    /// centre of the generators and divide them by their median lever arm before the conversion,
    /// then map the answer back, so that the rank decision, hence the answer, does not depend
    /// on the reference point or the unit of length. The certificate is that of the
    /// re-centred problem. Refused ([`ConeError::NotAWrench`]) for other dimensions, and
    /// ([`ConeError::IncompatibleOptions`]) with [`Arithmetic::Exact`] and by
    /// [`Continuation`]. Default `false`.
    pub wrench: bool,
}

impl Default for DdOptions {
    fn default() -> Self {
        Self {
            arithmetic: Arithmetic::Tolerance,
            tol: tol::Tolerances::default(),
            exact_fallback: true,
            check_completeness: true,
            allow_uncertified: false,
            wrench: false,
        }
    }
}
