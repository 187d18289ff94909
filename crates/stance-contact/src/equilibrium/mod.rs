//! Static and robust static equilibrium of the CoM (paper Section IV).
//!
//! Static equilibrium (`p'' = 0`, `L' = 0`): `U_stance (m g, m p x g) <= 0`; `m > 0` factors
//! out. With `u = (u_f, u_t)` a row of `U_stance` and the triple product
//! `u_t . (p x g) = p . (g x u_t)`, each row is a half-space **linear in the CoM** `p`:
//!
//! ```text
//! a . p <= d,   a = g x u_t,   d = -u_f . g.
//! ```
//!
//! (Equations `e . w_GI = 0` give two opposite half-spaces.) Since `a` is orthogonal to `g`, the
//! set of static CoMs is an infinite prism along `g`; for vertical `g` its cross-section is the
//! static-equilibrium polygon (Bretl and Lall 2008). For non-vertical `g` the prism is oblique:
//! [`StaticEquilibrium::polygon`] returns its cross-section by the horizontal plane at a given
//! height (the same polygon, translated, at every height).
//!
//! The same polygon can be computed without `U_stance`, straight from the contact forces that
//! balance gravity, by support-function LPs with a certificate ([`direct`]); it is the faster
//! route when `U_stance` is not needed otherwise.
//!
//! Robust static equilibrium for gravity-like vectors `g_1 .. g_K` (eq. 12, with the sign fixed
//! for `g` pointing down: `U (g_k, p x g_k) <= 0`): `M` is the intersection of the K prisms, a
//! 3-D polyhedron, bounded when the `g_k` are not all parallel ([`RobustRegion`]).
//!
//! Every half-space is normalized (`|a| = 1`), so residuals are distances in metres. Rows whose
//! `a` vanishes (`|a| <= zero_normal |g|`) do not depend on the CoM: they are checked once
//! (`0 <= d`), and if violated no CoM is stable.

pub mod direct;
mod frame;
mod halfspaces;
mod robust;
mod simplex;
mod statics;

pub use direct::{DirectPolygon, Fallback, PolygonRoute, PolygonWorkspace};
pub use halfspaces::{com_halfspaces, ComHalfspaces};
pub use robust::RobustRegion;
pub use statics::{StaticEquilibrium, StaticPolygon};

use crate::tol::ContactTolerances;
use polycone::polytope::PolytopeOptions;

/// Options of the equilibrium computations.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EquilibriumOptions {
    /// The crate's thresholds (membership band, zero normals).
    pub tol: ContactTolerances,
    /// Thresholds of the polygon/polyhedron routines (metres).
    pub polytope: PolytopeOptions,
}

/// `g` divided by its largest absolute component (unchanged when zero or not finite). Every set
/// here is invariant under positive scaling of `g`; this keeps `|g|` and `g x u` free of
/// overflow and underflow for gravities of any magnitude (e.g. 1e200 or 1e-200 m/s^2).
pub(crate) fn scaled_gravity(g: [f64; 3]) -> [f64; 3] {
    let m = g.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if m > 0.0 && m.is_finite() {
        g.map(|x| x / m)
    } else {
        g
    }
}

/// Distance from `p` to the segment `[s, e]` (a point when `s = e`).
pub(crate) fn seg_dist(p: [f64; 2], s: [f64; 2], e: [f64; 2]) -> f64 {
    let d = [e[0] - s[0], e[1] - s[1]];
    let l2 = d[0] * d[0] + d[1] * d[1];
    let t = if l2 > 0.0 {
        (((p[0] - s[0]) * d[0] + (p[1] - s[1]) * d[1]) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (x, y) = (p[0] - s[0] - t * d[0], p[1] - s[1] - t * d[1]);
    // (not hypot: this runs V^2 times in the direct polygon's gap check, and lengths here are
    // far from overflow: polygons stay within the polytope `far` bound)
    (x * x + y * y).sqrt()
}
