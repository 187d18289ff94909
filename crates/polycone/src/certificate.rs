//! The certificate attached to every conversion.
//!
//! # Math
//!
//! Let `C = span(V)` (generators `V`, in whitened coordinates, full-dimensional in `R^r`) and let
//! the claimed answer be `C' = {y : U y <= 0}` with lineality space `L` (the null space of `U`)
//! of dimension `l = r - rank(U)`. Then `C = C'` iff
//!
//! 1. **soundness** (`C ⊆ C'`): `u . v <= 0` for every facet `u` and generator `v`;
//! 2. **support**: every facet is tight on generators spanning a hyperplane (rank `r - 1`), so it
//!    is a facet of `C` and not merely a valid inequality;
//! 3. **lineality** (`L ⊆ C`): the generators lying in `L` positively span `L`, i.e. they have
//!    rank `l` and the dual cone `{y in L : g . y <= 0 for those g}` is `{0}` (checked by a double
//!    description run in `L`, which must return no ray);
//! 4. **completeness** (`C' ⊆ C`): a dual conversion of `U` (in `L^perp`) returns the extreme rays
//!    of `C' ∩ L^perp`; each must be positively parallel to the projection onto `L^perp` of some
//!    generator (which lies in `C` because `L ⊆ C`). Then `C' = L + cone(rays) ⊆ C`.
//!
//! A face form missing facets (the failure of cddlib's float mode described in the crate docs)
//! passes 1 and 2 but fails 4: the missing facets leave `C'` an extreme ray that is no
//! generator. Equations are checked separately: every generator satisfies them and their number
//! is `d - r`.

use crate::dd::DdCore;
use crate::linalg::{dot, normalize, rank_of};
use crate::precondition::Whitened;
use crate::tol::Tolerances;
use crate::Arithmetic;

/// What was verified about a conversion, and how well. `certified` is the conjunction of the
/// checks; a wrong cone is never certified (see the crate docs for the exact guarantee).
#[derive(Clone, Debug, PartialEq)]
pub struct Certificate {
    /// All checks passed.
    pub certified: bool,
    /// The arithmetic the certified combinatorics were decided with.
    pub arithmetic: Arithmetic,
    /// Largest `u . v` over facets `u` and generators `v`, both unit in whitened coordinates,
    /// clamped below at 0 (soundness holds iff at most [`Tolerances::certificate`]).
    pub max_violation: f64,
    /// Largest `|e . v| / max_i |v_i|` over equations `e` and generators `v` (input units).
    pub max_equation_residual: f64,
    /// Soundness: `max_violation` and `max_equation_residual` within the tolerance.
    pub soundness: bool,
    /// Support: every facet is tight on generators of rank `r - 1`.
    pub support: bool,
    /// Indices of the facets that failed the support check.
    pub unsupported_facets: Vec<usize>,
    /// The lineality space is positively spanned by generators.
    pub lineality: bool,
    /// Completeness: every extreme ray of the claimed cone is a generator.
    pub completeness: bool,
    /// Number of extreme rays of the claimed cone that match no generator.
    pub unmatched_rays: usize,
}

impl Certificate {
    /// A short explanation of the failed checks (empty when certified).
    pub fn failure_reason(&self) -> String {
        let mut r = Vec::new();
        if !self.soundness {
            r.push(format!(
                "soundness: violation {:.3e}, equation residual {:.3e}",
                self.max_violation, self.max_equation_residual
            ));
        }
        if !self.support {
            r.push(format!(
                "support: {} facet(s) not tight on a hyperplane of generators",
                self.unsupported_facets.len()
            ));
        }
        if !self.lineality {
            r.push("lineality: the lineality space is not spanned by generators".into());
        }
        if !self.completeness {
            r.push(format!(
                "completeness: {} extreme ray(s) of the face form are not generators",
                self.unmatched_rays
            ));
        }
        r.join("; ")
    }
}

/// Certifies whitened facets `fw` (`nf x r`, unit rows) against the whitened generators.
/// `perp` (`t x r`, orthonormal rows) spans the facets, `lin` (`(r - t) x r`, orthonormal rows)
/// its complement, the claimed lineality space.
#[allow(clippy::too_many_arguments)]
pub(crate) fn certify_whitened(
    wh: &Whitened,
    fw: &[f64],
    perp: &[f64],
    lin: &[f64],
    tol: &Tolerances,
    arithmetic: Arithmetic,
    check: &mut DdCore,
    scratch: &mut Vec<f64>,
) -> Certificate {
    let r = wh.r;
    let nf = fw.len().checked_div(r).unwrap_or(0);
    let t = perp.len().checked_div(r).unwrap_or(0);
    let l = lin.len().checked_div(r).unwrap_or(0);
    let ng = wh.kept.len();

    // 1. Soundness.
    let mut max_violation: f64 = 0.0;
    for f in 0..nf {
        let u = &fw[f * r..(f + 1) * r];
        for i in 0..ng {
            max_violation = max_violation.max(dot(u, wh.gen(i)));
        }
    }
    let soundness = max_violation <= tol.certificate && wh.equation_residual <= tol.certificate;

    // 2. Support: tight generators, projected on the facet's hyperplane, have rank r - 1.
    let mut unsupported_facets = Vec::new();
    let mut proj = Vec::new();
    for f in 0..nf {
        let u = &fw[f * r..(f + 1) * r];
        proj.clear();
        let mut cnt = 0;
        for i in 0..ng {
            let g = wh.gen(i);
            let s = dot(u, g);
            if s.abs() <= tol.incidence {
                for c in 0..r {
                    proj.push(g[c] - s * u[c]);
                }
                cnt += 1;
            }
        }
        let rank = rank_of(
            (0..cnt).map(|i| &proj[i * r..(i + 1) * r]),
            r,
            tol.support_rank,
            scratch,
        );
        if rank + 1 != r {
            unsupported_facets.push(f);
        }
    }
    let support = unsupported_facets.is_empty();

    // 3. Lineality: generators in L positively span L.
    let mut lineality = true;
    if l > 0 {
        let mut rows = Vec::new();
        let mut m = 0;
        for i in 0..ng {
            let g = wh.gen(i);
            let out: f64 = (0..t)
                .map(|b| dot(&perp[b * r..(b + 1) * r], g).powi(2))
                .sum();
            if out.sqrt() <= tol.certificate {
                let start = rows.len();
                for b in 0..l {
                    rows.push(dot(&lin[b * r..(b + 1) * r], g));
                }
                normalize(&mut rows[start..]);
                m += 1;
            }
        }
        lineality = match check.run(&rows, m, l, tol.incidence, tol.support_rank) {
            Ok(()) => check.n == 0,
            Err(_) => false,
        };
    }

    // 4. Completeness: the rays of the dual conversion of the facets are generators.
    let mut unmatched_rays = 0;
    let mut completeness = true;
    if t > 0 {
        let mut rows = vec![0.0; nf * t];
        for f in 0..nf {
            let u = &fw[f * r..(f + 1) * r];
            for b in 0..t {
                rows[f * t + b] = dot(&perp[b * r..(b + 1) * r], u);
            }
            normalize(&mut rows[f * t..(f + 1) * t]);
        }
        // Projected generators, in `perp` coordinates, unit (those not in L).
        let mut gens = Vec::new();
        for i in 0..ng {
            let g = wh.gen(i);
            let start = gens.len();
            for b in 0..t {
                gens.push(dot(&perp[b * r..(b + 1) * r], g));
            }
            if normalize(&mut gens[start..]) <= tol.certificate {
                gens.truncate(start);
            }
        }
        let ngp = gens.len() / t;
        match check.run(&rows, nf, t, tol.incidence, tol.support_rank) {
            Ok(()) => {
                for k in 0..check.n {
                    let ray = check.ray(k);
                    let matched = (0..ngp).any(|i| {
                        let g = &gens[i * t..(i + 1) * t];
                        let d2: f64 = ray.iter().zip(g).map(|(a, b)| (a - b) * (a - b)).sum();
                        d2.sqrt() <= tol.parallel
                    });
                    if !matched {
                        unmatched_rays += 1;
                    }
                }
                completeness = unmatched_rays == 0;
            }
            Err(_) => completeness = false,
        }
    }

    Certificate {
        certified: soundness && support && lineality && completeness,
        arithmetic,
        max_violation,
        max_equation_residual: wh.equation_residual,
        soundness,
        support,
        unsupported_facets,
        lineality,
        completeness,
        unmatched_rays,
    }
}
