//! Contact stability of legged robots: contact wrench cones, the gravito-inertial wrench cone
//! (GIWC) computed once per stance, static and robust static equilibrium, and supporting
//! contact forces. Implements Sections II-IV of Caron, Pham and Nakamura, "Leveraging Cone
//! Double Description for Multi-contact Stability of Humanoids with Applications to Statics
//! and Dynamics" (RSS 2015), "the paper" below.
//!
//! # Math, in the paper's notation
//!
//! - Contact `i`: pose `world_from_contact = (R_i, p_i)` (z axis = surface normal into the
//!   robot), a convex shape with vertices `v_j`, friction `mu_i` approximated by a k-sided
//!   pyramid ([`FrictionModel`]; default the paper's outer 4-sided pyramid
//!   `|f_x|, |f_y| <= mu f_z`).
//! - Surface contact wrench cone (Proposition 1): `V_surf = A_surf V_point`
//!   ([`Contact::v_surf`]).
//! - `w_GI = A_stance w_all` (eq. 8-9, [`Stance::a_stance`]); `GIWC = span(A_stance V_all)`
//!   ([`Stance::giwc_span`]); `U_stance = (A_stance V_all)^F` through polycone's double
//!   description ([`Stance::u_stance`], [`Giwc`]), with equations and lineality; updated
//!   by continuing the conversion when a contact is added ([`GiwcBuilder`]: the GIWC is the
//!   Minkowski sum of the contacts' wrench cones, so a new contact appends polar rows). Convention:
//!   `U_stance w_GI <= 0`, wrench at the world origin; the net contact wrench `w_c = -w_GI`
//!   is in `-GIWC` ([`Giwc::net_contact_wrench_face`]).
//! - Static equilibrium: `U_stance (m g, m p x g) <= 0`, half-spaces linear in the CoM `p`
//!   ([`equilibrium`]); the static-equilibrium polygon also straight from the contact forces,
//!   without `U_stance`, by certified support-function LPs
//!   ([`equilibrium::PolygonWorkspace::static_polygon`]); robust static equilibrium (eq. 12 with the sign fixed for `g` pointing
//!   down) as an explicit 3-D polyhedron ([`equilibrium::RobustRegion`]).
//! - Supporting forces: a QP over the vertex forces ([`supporting_forces`]), independent of the
//!   double description; the check of every face-form test.
//!
//! Rows are `(force, torque)` everywhere. Thresholds live in [`tol`].
//!
//! # Example
//!
//! ```
//! use stance_contact::{examples, equilibrium::StaticEquilibrium};
//! let scene = examples::double_support_flat();
//! let giwc = scene.stance().unwrap().u_stance(&Default::default()).unwrap();
//! let eq = StaticEquilibrium::new(&giwc, scene.gravity, &Default::default()).unwrap();
//! assert!(eq.contains([0.0, 0.0, 0.8]));
//! let polygon = eq.polygon(0.0).unwrap();
//! assert_eq!(polygon.vertices.len(), 4); // both feet's outer corners
//! ```
//!
//! # Limitations
//!
//! - Friction cones are polyhedral (k-sided pyramids); the exact second-order cone is not used.
//! - Friction coefficients above [`tol::MAX_FRICTION`] (1e6) are refused: the pyramid's normal
//!   component would fall below the cone conversion's rank threshold.
//! - Far from the world origin: `U_stance` is computed about the first contact's origin and
//!   moved back exactly, and the supporting-forces QP is solved about the contacts' centroid,
//!   so both stay accurate kilometres away; the face-form test `U w <= tol |w|` of a wrench at
//!   the world origin is relative to `|w|`, whose torque grows with the distance (about 1 mm
//!   of CoM per 1e-9 at 1 km): test CoMs with the half-spaces in metres
//!   ([`equilibrium::StaticEquilibrium`], [`equilibrium::RobustRegion`]) instead.
//! - Adding a contact ([`GiwcBuilder::add_contact`]) continues the double description, but
//!   the certificate still runs on the whole result, so there is no gain to speak of on the
//!   paper's stances and a 4-contact one (`bench/peers/contact.md`). A contact
//!   that may enlarge the linear span of the GIWC (lower-dimensional stances, e.g. point
//!   contacts) is a conversion from scratch; so is removing a contact (not offered).
//! - Region computations are tolerance-based (metres, [`tol`]): a CoM within
//!   `DEFAULT_REGION_TOL` outside a half-space counts as stable, vertices within the polytope
//!   merge distance are one vertex, and regions reaching farther than the polytope `far`
//!   bound (1e6 m) are reported unbounded.
//! - The static-equilibrium polygon for a gravity without vertical component is an error (the
//!   prism is horizontal); for oblique gravity it is the cross-section at a chosen height.
//! - The direct polygon ([`equilibrium::PolygonWorkspace::static_polygon`]) computes
//!   `U_stance` instead, and says so ([`equilibrium::PolygonRoute`]), when the polygon is
//!   empty, unbounded or not 2-D (one or two point contacts), or when its certificate fails. On
//!   2000 random stances of the property tests (`route_statistics`, one in seven contacts
//!   frictionless): 1062 direct, 303 unbounded, 481 empty, 154 degenerate, no certificate
//!   failure (one in 2000 before frictionless contacts were drawn: near-parallel edges).
//! - The robust region margin outside `M` is a lower bound (largest plane violation), not the
//!   exact distance.
//! - The supporting-forces QP distributes forces on the shape vertices (the paper's model); it
//!   reports `Unknown` if the solver stops without a conclusion.

#![warn(missing_docs)]

pub mod contact;
pub mod equilibrium;
pub mod error;
pub mod examples;
pub mod forces;
pub mod friction;
pub mod giwc;
mod giwc_dd;
mod giwc_incremental;
pub mod scene;
pub mod stance;
pub mod tol;

pub use contact::{Contact, Shape};
pub use equilibrium::{com_halfspaces, ComHalfspaces, EquilibriumOptions};
pub use error::ContactError;
pub use forces::{supporting_forces, wrench_at, ContactForces, ForcesOutcome, SupportingForces};
pub use friction::{Approximation, FrictionModel};
pub use giwc::Giwc;
pub use giwc_dd::GiwcOptions;
pub use giwc_incremental::GiwcBuilder;
pub use nalgebra;
pub use scene::{ContactSpec, Scene};
pub use stance::{w_gi_static, Stance};

#[inline]
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
