//! Incidence of facets and generators: projection on `L^perp` for cones with lineality, and
//! the bitsets both ways that the support and ridge checks read.

use super::*;

/// For a cone with lineality, generators and facets projected on `L^perp` (`t` orthonormal
/// rows `perp`) and normalized, into `cs.gp`, `cs.fp`, with the generators lying in `L`
/// flagged in `cs.in_l`, and the incidence recomputed there into `cs.inc`.
pub(super) fn project_incidence(
    wh: &Whitened,
    fw: &[f64],
    perp: &[f64],
    t: usize,
    tol: &Tolerances,
    cs: &mut CertScratch,
) {
    let r = wh.r;
    let ng = wh.kept.len();
    let nf = fw.len().checked_div(r).unwrap_or(0);
    let gw = ng.div_ceil(64).max(1);
    cs.gp.clear();
    cs.gp.resize(ng * t, 0.0);
    cs.in_l.clear();
    cs.in_l.resize(ng, false);
    for i in 0..ng {
        let g = wh.gen(i);
        for b in 0..t {
            cs.gp[i * t + b] = dot(&perp[b * r..(b + 1) * r], g);
        }
        if normalize(&mut cs.gp[i * t..(i + 1) * t]) <= tol.certificate {
            cs.in_l[i] = true;
        }
    }
    cs.fp.clear();
    cs.fp.resize(nf * t, 0.0);
    for f in 0..nf {
        for b in 0..t {
            cs.fp[f * t + b] = dot(&perp[b * r..(b + 1) * r], &fw[f * r..(f + 1) * r]);
        }
        normalize(&mut cs.fp[f * t..(f + 1) * t]);
    }
    cs.inc.clear();
    cs.inc.resize(nf * gw, 0);
    for f in 0..nf {
        let u = &cs.fp[f * t..(f + 1) * t];
        for i in 0..ng {
            if !cs.in_l[i] && dot(u, &cs.gp[i * t..(i + 1) * t]).abs() <= tol.incidence {
                cs.inc[f * gw + i / 64] |= 1 << (i % 64);
            }
        }
    }
}

/// Generator-facet incidence in `L^perp` coordinates (dimension `t`), as bitsets both ways.
pub(crate) struct Incidence<'a> {
    pub(super) t: usize,
    pub(super) nf: usize,
    /// Generators (unit, `ng x t`), facets (unit, `nf x t`).
    pub(super) gp: &'a [f64],
    pub(super) fp: &'a [f64],
    /// Generator lies in the lineality space (projection ~ 0); empty when pointed (none does).
    pub(super) in_l: &'a [bool],
    pub(super) gw: usize,
    pub(super) fwd: usize,
    /// `nf x gw`: generators tight on each facet.
    pub(super) inc: &'a [u64],
    /// `ng x fwd`: facets tight on each generator.
    pub(super) by_gen: &'a [u64],
}

impl Incidence<'_> {
    /// Generator `i` lies in the lineality space.
    #[inline]
    pub(super) fn in_l(&self, i: usize) -> bool {
        self.in_l.get(i).copied().unwrap_or(false)
    }

    /// Extreme generators among `candidates` (indices into `kept`), one per extreme ray: `g` is
    /// extreme iff it is not in `L` and no generator is tight on a strict superset of the
    /// facets `g` is tight on (for a complete face form, those generators lie in the smallest
    /// face containing `g`, which is a ray iff `g` is extreme); among generators tight on the
    /// same facets (the same ray), the first is kept.
    pub(super) fn extreme(&self, candidates: &[usize]) -> Vec<usize> {
        if self.t == 0 {
            return Vec::new();
        }
        let fwd = self.fwd;
        let mut out: Vec<usize> = Vec::new();
        if fwd == 1 {
            // One word per facet set (at most 64 facets): the same test on `u64`s.
            let set = |i: usize| self.by_gen[i];
            for &g in candidates {
                if self.in_l(g) {
                    continue;
                }
                let sg = set(g);
                let dominated = candidates
                    .iter()
                    .any(|&h| sg & !set(h) == 0 && sg != set(h) && !self.in_l(h));
                if dominated || out.iter().any(|&o| set(o) == sg) {
                    continue;
                }
                out.push(g);
            }
            return out;
        }
        let set = |i: usize| &self.by_gen[i * fwd..(i + 1) * fwd];
        for &g in candidates {
            if self.in_l(g) {
                continue;
            }
            let sg = set(g);
            let dominated = candidates.iter().any(|&h| {
                h != g
                    && !self.in_l(h)
                    && sg.iter().zip(set(h)).all(|(a, b)| a & !b == 0)
                    && sg != set(h)
            });
            if dominated || out.iter().any(|&o| set(o) == sg) {
                continue;
            }
            out.push(g);
        }
        out
    }
}
