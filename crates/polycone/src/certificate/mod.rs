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
//! 4. **completeness** (no facet of `C` is missing): in `L^perp`, where `C` is pointed of
//!    dimension `t`, every ridge (facet of a facet) of a polyhedral cone lies in exactly two
//!    facets. For each claimed facet `F`, its ridges are computed from the generators tight on
//!    it (all `(t-2)`-subsets when `F` is simplicial, a closed form when it has one tight
//!    generator more, below, otherwise a small double description in the hyperplane of `F`),
//!    and each ridge must be contained (as a set of generators) in
//!    exactly two claimed facets. By 1 and 2 every claimed facet is a facet of `C`; if a facet
//!    `F*` of `C` were missing, the facet graph of `C` being connected, some claimed facet `F`
//!    would be adjacent to a missing one, and the ridge `F ∩ F*` would lie in one claimed facet
//!    only. (`t = 1`: exactly one facet; `t = 2`: exactly two.)
//!
//!    A facet with more than `t` tight generators is first tried from the other side: its
//!    claimed neighbours cut its hyperplane into a cone `Q_F` that contains `cone(T_F)`, and
//!    when `Q_F` has `t - 1` or `t` constraints its extreme rays come in closed form and must
//!    each be matched by a tight generator (the `neighbours` module, which proves the same
//!    thing: no facet adjacent to `F` is missing). Only when that does not decide does the
//!    facet get its double description.
//!
//!    **Balinski's theorem** (the graph of a `k`-polytope is `k`-connected) saves up to
//!    `t - 2` of those double descriptions: the facets of `C` are the vertices of a
//!    `(t - 1)`-polytope (a section of the polar), so if facets `M` are missing, the claimed
//!    facets adjacent to `M` separate `M` from the other claimed facets (or are all of them,
//!    at least `t`): there are at least `t - 1` of them. If at most `t - 2` claimed facets are
//!    not checked, one of those adjacent to `M` is, and fails. The unchecked facets still get
//!    the support check (a missing facet must be detected by genuine facets).
//!
//! # Near-simplicial facets
//!
//! Let `F` have `k + 1` tight generators `g_1..g_{k+1}` spanning its hyperplane (`k = t - 1`),
//! in coordinates of that hyperplane: vectors of `R^k` of rank `k`, with a one-dimensional
//! dependency `sum_i lambda_i g_i = 0` (`lambda` spans the null space of the `k x (k + 1)`
//! matrix `[g_1 .. g_{k+1}]`). A set `S` of generators is a face of `cone(g)` iff some `y`
//! has `y . g_i = 0` on `S` and `y . g_i < 0` off `S`. The vectors `s = (y . g_i)_i` are exactly
//! the vectors orthogonal to `lambda` (the row space of the matrix), so `S` is a face iff some
//! `s` with `s_i = 0` on `S`, `s_i < 0` on the complement `N` has `sum_{i in N} lambda_i s_i = 0`:
//! iff `lambda` vanishes on `N` or takes both signs on `N`. Ridges (facets of `F`) are the
//! maximal proper faces, i.e. the minimal non-empty such `N`: `N = {i}` with `lambda_i = 0`, and
//! `N = {i, j}` with `lambda_i lambda_j < 0`. (Each is of dimension `k - 1`: removing a `g_i`
//! with `lambda_i != 0` leaves a basis, removing one more leaves rank `k - 1`; if
//! `lambda_i = 0`, the other `k` vectors carry the dependency and have rank `k - 1`.) If the
//! non-zero `lambda_i` all have one sign, `cone(g)` contains a line: no pointed facet, the
//! check fails. A generator in the interior of `F` has the sign opposite to all others: it is
//! in every ridge but no ridge drops only it, as expected.
//!
//! Signs are decided with the incidence tolerances, with a margin of ten (the ratio
//! `certificate / incidence`) on each side of the double description's threshold. By Cramer,
//! `lambda_q = ± det(G \ {g_q}) / c` with `c = sqrt(sum_q det(G \ {g_q})^2)`. For a ridge
//! `R = G \ {i, j}` with unit normal `y`, `|det(G \ {g_i})| = vol(R) |y . g_j|` and the
//! `k - 1` unit vectors of `R` have `vol(R) <= 1` (Hadamard), so `|y . g_j| >= c |lambda_i|`
//! and, from `lambda_i (y . g_i) + lambda_j (y . g_j) = 0`, `|y . g_i| >= c |lambda_j|`: every
//! generator off a ridge has slack at least `c min |lambda|` over the non-zero entries (for
//! `R = G \ {i}`, `lambda_i = 0`, likewise `|y . g_i| >= c |lambda_j|` for any `j`). So
//! `lambda_i` is non-zero when `c |lambda_i| >= certificate` (all such slacks are at least ten
//! times `incidence`). Conversely, if `lambda_i` is tiny but not zero, the ridges `G \ {i, j}`
//! it creates leave `g_j` a slack `|lambda_i| |y . g_i| / |lambda_j| <= |lambda_i| / |lambda_j|`,
//! which the double description merges: `lambda_i` counts as zero when
//! `|lambda_i| <= (incidence / 10) min |lambda_j|` (written `incidence^2 / certificate`). Any
//! entry between the two, or a rank deficiency, defers the facet to the double description
//! (never a guess). The unit tests check the closed form against the double description ridge
//! by ridge on random configurations (generic, redundant interior generator, generator on a
//! 2-face, entries of `lambda` moved by `1e-12` and `1e-8`, not pointed) and bit for bit on
//! whole conversions of the golden and stress cones, counting how many facets each path
//! decided. (A first version that called `|lambda_i| > support_rank` non-zero, without the
//! factor `c`, disagreed with the double description on a `1e-8` case.)
//!
//! A face form missing facets (the failure of cddlib's float mode described in the crate docs)
//! passes 1 and 2 but fails 4. Equations are checked separately: every generator satisfies them and their number
//! is `d - r`.

mod neighbours;

use crate::dd::{DdCore, DdFailure, Scan};
use crate::linalg::{dot, normalize, rank_of, spans};
use crate::precondition::Whitened;
use crate::tol::Tolerances;
use crate::Arithmetic;
use neighbours::{neighbours_prove_facet, Hyperplane, NeighbourScratch};

/// Counts a facet in the test-only [`RidgeStats`] (no code outside test builds).
macro_rules! record {
    ($field:ident) => {
        #[cfg(test)]
        STATS.with(|c| {
            let mut s = c.get();
            s.$field += 1;
            c.set(s);
        });
    };
}

mod incidence;
mod ridges;
mod simplicial;
mod slacks;

use incidence::*;
use ridges::*;
use simplicial::*;
use slacks::*;

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
    /// Completeness: no facet is missing (module docs: the ridges of the claimed facets, all
    /// but at most `t - 2` of them, are covered, as counted from the facet's tight generators
    /// or proven from its claimed neighbours).
    pub completeness: bool,
    /// Number of ridges not covered by exactly two claimed facets, among the facets checked
    /// ridge by ridge (a facet its neighbours do not prove complete is checked that way, so a
    /// failed completeness check always counts at least one; a facet with too few tight
    /// generators counts one) (`usize::MAX` when the facet count is
    /// impossible for the dimension, or when the check was not run:
    /// [`crate::DdOptions::check_completeness`]).
    pub open_ridges: usize,
    /// When the answer comes from the exact fallback ([`crate::DdOptions::exact_fallback`]):
    /// why the floating-point answer was not kept (its failed certificate). `None` when the
    /// arithmetic of [`Self::arithmetic`] was the one asked for.
    pub fallback: Option<String>,
    /// After an exact fallback in the default mode: how many rows of the exact answer were
    /// dropped as slivers of the rounded input (module `merge` in the source): rows closer than
    /// [`Tolerances::certificate`] to a kept row (unit rows), then rows whose removal enlarges
    /// the cone by at most that tolerance (each proven by non-negative weights on the kept rows
    /// whose residual bounds the enlargement). Distances are measured in the input's
    /// coordinates and, on the wrench route, also in the frame's ([`Self::wrench_frame`]):
    /// a row is dropped only when both are within the tolerance, so no two kept rows are within
    /// it of each other in both. Only rows are dropped, so the answer contains the exact cone,
    /// and no unit vector the answer admits violates a row of the exact answer by more than
    /// [`Self::merge_distance`]: the merged answer is the exact one within the tolerance
    /// contract. 0 when nothing was merged.
    pub merged_rows: usize,
    /// The proven bound of [`Self::merged_rows`]: the largest violation of a row of the exact
    /// answer (unit, in the input's coordinates) by a unit vector of the merged cone (0 when
    /// nothing was merged).
    pub merge_distance: f64,
    /// The frame the wrench preconditioning ([`crate::DdOptions::wrench`]) computed in, rows
    /// `(f, tau)` mapped to `(f, (tau - o x f) / L)` and facet rows `(u_f, u_t)` to
    /// `(u_f - o x u_t, L u_t)`; `None` on the other routes.
    pub wrench_frame: Option<crate::wrench::WrenchFrame>,
}

impl Certificate {
    /// Which arithmetic and route gave the answer: `"tolerance"`, `"exact"` (asked for) or
    /// `"exact_fallback"` (the floating-point answer failed its certificate; see
    /// [`Certificate::fallback`]).
    ///
    /// ```
    /// use polycone::{DdOptions, Workspace};
    /// use nalgebra::DMatrix;
    /// let v = DMatrix::<f64>::identity(3, 3);
    /// let r = Workspace::new().span_to_face(&v, &DdOptions::default()).unwrap();
    /// assert_eq!(r.certificate.route(), "tolerance");
    /// ```
    pub fn route(&self) -> &'static str {
        match (self.arithmetic, &self.fallback) {
            (Arithmetic::Tolerance, _) => "tolerance",
            (Arithmetic::Exact, None) => "exact",
            (Arithmetic::Exact, Some(_)) => "exact_fallback",
        }
    }

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
                "completeness: {} ridge(s) not shared by exactly two facets",
                self.open_ridges
            ));
        }
        r.join("; ")
    }
}

/// Reusable buffers of the certificate (part of [`crate::Workspace`]): once warm, certifying a
/// cone of the same size does not allocate, apart from the returned lists.
#[derive(Clone, Debug, Default)]
pub(crate) struct CertScratch {
    /// The double description of facets that have neither closed form, and of the lineality
    /// check.
    pub(crate) small: DdCore,
    /// Generators transposed (`r x ng`): the slack loop runs along contiguous generators.
    gt: Vec<f64>,
    /// Slacks `u . g` (`nf x ng`, row-major), whitened coordinates.
    slack: Vec<f64>,
    /// Generators and facets in `L^perp` coordinates (non-pointed cones only).
    gp: Vec<f64>,
    fp: Vec<f64>,
    in_l: Vec<bool>,
    /// Incidence bitsets, both ways (see [`Incidence`]).
    inc: Vec<u64>,
    by_gen: Vec<u64>,
    /// Per-facet work of the ridge check.
    members: Vec<usize>,
    rows: Vec<f64>,
    ridge: Vec<usize>,
    neighbours: Vec<u64>,
    cand: Vec<u32>,
    acc: Vec<u64>,
    drops: Vec<(usize, usize)>,
    lambda: Vec<f64>,
    vbuf: Vec<f64>,
    /// The neighbour check of facets (`neighbours` module).
    nb: NeighbourScratch,
    /// Facets left unchecked by Balinski's theorem (at most `t - 2`).
    skip: Vec<usize>,
    /// Linear algebra scratch.
    buf: Vec<f64>,
}

/// What a conversion claims, in whitened coordinates: the generators (`wh`), the facets `fw`
/// (`nf x r`, unit rows), and the split of the space into `perp` (`t x r`, orthonormal rows,
/// spanned by the facets) and `lin` (`(r - t) x r`, the claimed lineality space).
#[derive(Clone, Copy)]
pub(crate) struct Claim<'a> {
    pub wh: &'a Whitened,
    pub fw: &'a [f64],
    pub perp: &'a [f64],
    pub lin: &'a [f64],
}

/// How a claim is checked: the tolerances, the arithmetic of the conversion, and whether the
/// completeness part (ridges) runs.
#[derive(Clone, Copy)]
pub(crate) struct CheckOptions<'a> {
    pub tol: &'a Tolerances,
    pub arithmetic: Arithmetic,
    pub check_completeness: bool,
}

/// Certifies a [`Claim`] (whitened facets against the whitened generators, and the claimed
/// lineality split) as `how` says. Returns the certificate and the extreme generators (indices into `wh.kept`, see
/// [`Incidence::extreme`]).
///
/// The four checks of the module doc in order: the slacks `u . g` of every generator on every
/// facet give soundness (and, for a pointed cone, the incidence); support is the rank of each
/// facet's tight generators, unless the ridge check decides it on the way; lineality is a
/// double description in `L`; completeness counts the open ridges.
pub(crate) fn certify_whitened(
    claim: Claim,
    how: CheckOptions,
    cs: &mut CertScratch,
) -> (Certificate, Vec<usize>) {
    let Claim { wh, fw, perp, lin } = claim;
    let CheckOptions {
        tol,
        arithmetic,
        check_completeness,
    } = how;
    let r = wh.r;
    let nf = fw.len().checked_div(r).unwrap_or(0);
    let t = perp.len().checked_div(r).unwrap_or(0);
    let ng = wh.kept.len();
    let pointed = t == r;

    // 1. Soundness.
    let max_violation = slacks_and_incidence(wh, fw, nf, pointed, tol, cs);
    let soundness = max_violation <= tol.certificate && wh.equation_residual <= tol.certificate;

    // 2. Support: tight generators, projected on the facet's hyperplane, have rank r - 1.
    // When the ridge check runs (below), it decides support on the way (same projection, in
    // L^perp), so the loop here only runs without it.
    let merged_support = check_completeness && t >= 3 && ok_dims(t, nf);
    let mut unsupported_facets = Vec::new();
    if !merged_support {
        unsupported_by_rank(wh, fw, nf, tol, cs, &mut unsupported_facets);
    }

    // 3. Lineality: generators in L positively span L.
    let lineality = lineality_spanned(wh, perp, lin, tol, &mut cs.small);

    // 4. Completeness: every ridge of every claimed facet lies in exactly two claimed facets.
    if !pointed {
        project_incidence(wh, fw, perp, t, tol, cs);
    }
    let gw = ng.div_ceil(64).max(1);
    let fwd = nf.div_ceil(64).max(1);
    transpose_incidence(&cs.inc, nf, ng, gw, fwd, &mut cs.by_gen);
    let (gp, fp): (&[f64], &[f64]) = if pointed {
        (&wh.w, fw)
    } else {
        (&cs.gp, &cs.fp)
    };
    let in_l: &[bool] = if pointed { &[] } else { &cs.in_l };
    let inc = Incidence {
        t,
        nf,
        gp,
        fp,
        in_l,
        gw,
        fwd,
        inc: &cs.inc,
        by_gen: &cs.by_gen,
    };
    let mut work = RidgeWork {
        small: &mut cs.small,
        members: &mut cs.members,
        rows: &mut cs.rows,
        ridge: &mut cs.ridge,
        neighbours: &mut cs.neighbours,
        cand: &mut cs.cand,
        acc: &mut cs.acc,
        drops: &mut cs.drops,
        lambda: &mut cs.lambda,
        vbuf: &mut cs.vbuf,
        nb: &mut cs.nb,
        skip: &mut cs.skip,
        buf: &mut cs.buf,
    };
    let open_ridges = if !check_completeness {
        usize::MAX
    } else if ok_dims(t, nf) {
        count_open_ridges(&inc, tol, &mut work, &mut unsupported_facets)
    } else {
        usize::MAX
    };
    let completeness = open_ridges == 0;
    unsupported_facets.sort_unstable();
    unsupported_facets.dedup();
    let support = unsupported_facets.is_empty();
    let extreme = inc.extreme(&wh.distinct);

    let cert = Certificate {
        certified: soundness && support && lineality && completeness,
        arithmetic,
        max_violation,
        max_equation_residual: wh.equation_residual,
        soundness,
        support,
        unsupported_facets,
        lineality,
        completeness,
        open_ridges,
        fallback: None,
        merged_rows: 0,
        merge_distance: 0.0,
        wrench_frame: None,
    };
    (cert, extreme)
}

/// Slacks `u . g` of every generator `g` on every facet `u` (unit vectors, whitened
/// coordinates) into `cs.slack`, with the generators transposed first (`cs.gt`, `r x ng`) so
/// that the loop runs along contiguous generators; for a pointed cone, the incidence
/// (`|u . g| <= incidence`) in the same sweep into `cs.inc` (`nf x gw` words). Returns the
/// largest slack, at least 0 (soundness: at most [`Tolerances::certificate`]).
fn slacks_and_incidence(
    wh: &Whitened,
    fw: &[f64],
    nf: usize,
    pointed: bool,
    tol: &Tolerances,
    cs: &mut CertScratch,
) -> f64 {
    let (r, ng) = (wh.r, wh.kept.len());
    let gw = ng.div_ceil(64).max(1);
    cs.gt.clear();
    cs.gt.resize(r * ng, 0.0);
    for i in 0..ng {
        for (c, &g) in wh.gen(i).iter().enumerate() {
            cs.gt[c * ng + i] = g;
        }
    }
    cs.inc.clear();
    cs.inc.resize(nf * gw, 0);
    slacks(
        fw,
        &cs.gt,
        r,
        ng,
        &mut cs.slack,
        pointed.then_some((&mut cs.inc[..], gw, tol.incidence)),
    )
}

/// The support check alone (item 2 of the module doc), for when the ridge check does not
/// decide it: each facet `u`'s tight generators `g` (`|u . g| <= incidence`, from the slacks
/// in `cs.slack`), projected on its hyperplane (`g - (u . g) u`), must have rank `r - 1`.
/// Facets that fail are pushed to `unsupported`.
fn unsupported_by_rank(
    wh: &Whitened,
    fw: &[f64],
    nf: usize,
    tol: &Tolerances,
    cs: &mut CertScratch,
    unsupported: &mut Vec<usize>,
) {
    let (r, ng) = (wh.r, wh.kept.len());
    let mut proj = std::mem::take(&mut cs.rows);
    for f in 0..nf {
        let u = &fw[f * r..(f + 1) * r];
        proj.clear();
        let mut cnt = 0;
        for i in 0..ng {
            let s = cs.slack[f * ng + i];
            if s.abs() <= tol.incidence {
                let g = wh.gen(i);
                for c in 0..r {
                    proj.push(g[c] - s * u[c]);
                }
                cnt += 1;
            }
        }
        let rank = rank_of(
            (0..cnt).map(|i| &proj[i * r..(i + 1) * r]),
            r,
            r - 1,
            tol.support_rank,
            &mut cs.buf,
        );
        if rank + 1 != r {
            unsupported.push(f);
        }
    }
    cs.rows = proj;
}

/// The lineality check (item 3 of the module doc): the generators lying in the claimed
/// lineality space `L` (`l` orthonormal rows `lin`; a generator is in `L` when its component
/// along the `t` rows `perp` of `L^perp` is at most [`Tolerances::certificate`]) positively
/// span `L`, i.e. the double description of their coordinates in `L` (unit rows) finds no
/// ray. True when `l = 0`.
fn lineality_spanned(
    wh: &Whitened,
    perp: &[f64],
    lin: &[f64],
    tol: &Tolerances,
    small: &mut DdCore,
) -> bool {
    let r = wh.r;
    let t = perp.len().checked_div(r).unwrap_or(0);
    let l = lin.len().checked_div(r).unwrap_or(0);
    if l == 0 {
        return true;
    }
    let mut rows = Vec::new();
    let mut m = 0;
    for i in 0..wh.kept.len() {
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
    match small.run(&rows, m, l, tol.incidence, tol.support_rank) {
        Ok(()) => small.n == 0,
        Err(_) => false,
    }
}

/// The incidence by generator (`by_gen`, `ng x fwd` words: bit `f` of row `i` when generator
/// `i` is tight on facet `f`) from the incidence by facet (`inc`, `nf x gw` words).
fn transpose_incidence(
    inc: &[u64],
    nf: usize,
    ng: usize,
    gw: usize,
    fwd: usize,
    by_gen: &mut Vec<u64>,
) {
    by_gen.clear();
    by_gen.resize(ng * fwd, 0);
    for f in 0..nf {
        for wi in 0..gw {
            let mut w = inc[f * gw + wi];
            while w != 0 {
                let i = wi * 64 + w.trailing_zeros() as usize;
                w &= w - 1;
                by_gen[i * fwd + f / 64] |= 1 << (f % 64);
            }
        }
    }
}

/// Facet counts that are possible for a pointed cone of dimension `t` (with `t >= 1`, at least
/// `t` facets; `t = 1`: one; `t = 2`: two).
fn ok_dims(t: usize, nf: usize) -> bool {
    match t {
        0 => nf == 0,
        1 => nf == 1,
        2 => nf == 2,
        _ => nf >= t,
    }
}

#[cfg(test)]
mod tests {
    //! The closed form of near-simplicial facets against the double description it replaces:
    //! ridge by ridge on random configurations, and bit for bit on whole conversions.
    use super::*;
    use crate::{span_to_face, DdOptions, SpanToFace};
    use nalgebra::DMatrix;
    use proptest::prelude::*;

    /// Ridges (as sorted local index sets) of `cone(rows)` by the double description, `None`
    /// when it fails.
    fn ridges_by_dd(rows: &[f64], k: usize, tol: &Tolerances) -> Option<Vec<Vec<usize>>> {
        let mut dd = DdCore::default();
        dd.run(rows, k + 1, k, tol.incidence, tol.support_rank)
            .ok()?;
        let mut out: Vec<Vec<usize>> = (0..dd.n)
            .map(|q| {
                let z = &dd.z[q * dd.words..(q + 1) * dd.words];
                (0..=k)
                    .filter(|&i| z[i / 64] >> (i % 64) & 1 == 1)
                    .collect()
            })
            .collect();
        out.sort();
        Some(out)
    }

    /// Ridges by the closed form; `Err(())` when it defers to the double description.
    fn ridges_closed(rows: &[f64], k: usize, tol: &Tolerances) -> Result<Vec<Vec<usize>>, ()> {
        let (mut lambda, mut scratch, mut drops) = (vec![0.0; k + 1], Vec::new(), Vec::new());
        match near_simplicial_ridges(rows, k, tol, &mut lambda, &mut scratch, &mut drops) {
            None => Err(()),
            Some(_) => {
                let mut out: Vec<Vec<usize>> = drops
                    .iter()
                    .map(|&(a, b)| (0..=k).filter(|&q| q != a && q != b).collect())
                    .collect();
                out.sort();
                Ok(out)
            }
        }
    }

    fn unit_rows(v: &mut [f64], k: usize) {
        for r in v.chunks_exact_mut(k) {
            normalize(r);
        }
    }

    /// `k + 1` vectors of `R^k` of one of six kinds: 0 generic (any signs, possibly not
    /// pointed), 1 pointed (first coordinate positive), 2 pointed with the last vector a
    /// positive combination of the others (redundant, interior), 3 pointed with the last
    /// vector a positive combination of two others (it lies on a 2-face: `lambda` vanishes on
    /// the other `k - 2`), 4 and 5: kind 3 with the last vector moved by `1e-12` (zeros merged)
    /// and `1e-8` (between the two thresholds, or clear) in a pseudo-random direction.
    fn config(kind: u8, k: usize, raw: &[f64], w: &[f64]) -> Vec<f64> {
        let mut v: Vec<f64> = raw[..(k + 1) * k].to_vec();
        if kind >= 1 {
            for r in v.chunks_exact_mut(k) {
                r[0] = r[0].abs() + 0.05;
            }
        }
        unit_rows(&mut v, k);
        let combine = |v: &mut Vec<f64>, n: usize| {
            for c in 0..k {
                v[k * k + c] = (0..n).map(|i| w[i] * v[i * k + c]).sum();
            }
        };
        match kind {
            2 => combine(&mut v, k),
            3..=5 => combine(&mut v, 2),
            _ => {}
        }
        unit_rows(&mut v, k);
        if kind >= 4 {
            let size = if kind == 4 { 1e-12 } else { 1e-8 };
            for c in 0..k {
                v[k * k + c] += size * raw[41 - c];
            }
            unit_rows(&mut v, k);
        }
        v
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]
        /// Wherever the closed form decides, it finds exactly the ridges of the double
        /// description; it defers on a zero entry of `lambda`.
        #[test]
        fn closed_form_ridges_match_the_double_description(
            k in 2usize..=6,
            kind in 0u8..6,
            raw in proptest::collection::vec(-1.0f64..1.0, 42),
            w in proptest::collection::vec(0.05f64..1.0, 6),
        ) {
            let tol = Tolerances::default();
            let rows = config(kind, k, &raw, &w);
            let by_dd = ridges_by_dd(&rows, k, &tol);
            match ridges_closed(&rows, k, &tol) {
                Ok(closed) => {
                    let dd = by_dd.expect("the double description succeeds where the closed form does");
                    prop_assert_eq!(closed, dd);
                }
                Err(()) => {
                    // Deferred: only on a sign that is not clear or a rank deficiency.
                    prop_assert!(by_dd.is_none() || rank_deficient_or_small_lambda(&rows, k, &tol));
                }
            }
        }
    }

    /// A generator on a ridge of the facet (`lambda_i = 0`): its ridges by hand.
    #[test]
    fn zero_entry_of_the_dependency_gives_a_ridge_with_three_generators() {
        let tol = Tolerances::default();
        // a, b, c = a + b (on the face spanned by a and b), e.
        let mut rows = vec![1.0, 0.0, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 2.0, -1.0, 0.0, 1.0];
        unit_rows(&mut rows, 3);
        let closed = ridges_closed(&rows, 3, &tol).expect("clear signs");
        assert_eq!(closed, vec![vec![0, 1, 2], vec![0, 3], vec![1, 3]]);
        assert_eq!(Some(closed), ridges_by_dd(&rows, 3, &tol));
        // Not pointed: a + b + e' = 0 with e' = -(a + b): no ridge, `Some(false)`.
        let mut rows = vec![
            1.0, 0.0, 1.0, 0.0, 1.0, 1.0, -1.0, -1.0, -2.0, 0.0, 1.0, 0.0,
        ];
        unit_rows(&mut rows, 3);
        let (mut lambda, mut scratch, mut drops) = (vec![0.0; 4], Vec::new(), Vec::new());
        let r = near_simplicial_ridges(&rows, 3, &tol, &mut lambda, &mut scratch, &mut drops);
        assert_eq!(r, Some(false));
    }

    fn rank_deficient_or_small_lambda(rows: &[f64], k: usize, tol: &Tolerances) -> bool {
        let (mut lambda, mut scratch) = (vec![0.0; k + 1], Vec::new());
        match dependency(rows, k, tol.support_rank, &mut lambda, &mut scratch) {
            None => true,
            Some(c) => lambda.iter().any(|x| c * x.abs() <= 1e3 * tol.certificate),
        }
    }

    /// Generators of the gravito-inertial wrench cone (world frame, `(f, p x f)`) of
    /// rectangular contacts: friction pyramid edges (4, mu) at the 4 corners of each contact.
    fn giwc(contacts: &[([f64; 3], f64, [f64; 2])], mu: f64) -> DMatrix<f64> {
        let mut rows = Vec::new();
        for &(p0, roll, half) in contacts {
            let (s, c) = roll.sin_cos();
            // Rotation about x by `roll`: contact frame axes in the world.
            let rot = |v: [f64; 3]| [v[0], c * v[1] - s * v[2], s * v[1] + c * v[2]];
            for (sx, sy) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                let q = rot([sx * half[0], sy * half[1], 0.0]);
                let p = [p0[0] + q[0], p0[1] + q[1], p0[2] + q[2]];
                for (fx, fy) in [(mu, 0.0), (-mu, 0.0), (0.0, mu), (0.0, -mu)] {
                    let f = rot([fx, fy, 1.0]);
                    let m = [
                        p[1] * f[2] - p[2] * f[1],
                        p[2] * f[0] - p[0] * f[2],
                        p[0] * f[1] - p[1] * f[0],
                    ];
                    rows.push([f[0], f[1], f[2], m[0], m[1], m[2]]);
                }
            }
        }
        DMatrix::from_fn(rows.len(), 6, |i, j| rows[i][j])
    }

    /// The golden cones of the repository's fixtures and a stress corpus like the
    /// integration tests' (remote origin, tiny patches, feet slightly out of plane or rolled).
    fn inputs() -> Vec<(String, DMatrix<f64>)> {
        let mut out = Vec::new();
        let dir = format!("{}/../../testdata/cones", env!("CARGO_MANIFEST_DIR"));
        let mut names: Vec<_> = std::fs::read_dir(&dir)
            .expect("fixtures")
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "json"))
            .collect();
        names.sort();
        for path in names {
            let j: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(&path).expect("read")).expect("json");
            let d = j["dim"].as_u64().expect("dim") as usize;
            let v = stance_test_support::hex::matrix(&j["generators"]["float64_hex"], d);
            out.push((path.file_stem().unwrap().to_string_lossy().into_owned(), v));
        }
        let foot = [0.11, 0.065];
        let two = |o: [f64; 3], dz: f64, roll_deg: f64, half: [f64; 2]| {
            giwc(
                &[
                    ([o[0], o[1] + 0.1, o[2]], 0.0, half),
                    (
                        [o[0] + 0.05, o[1] - 0.1, o[2] + dz],
                        roll_deg.to_radians(),
                        half,
                    ),
                ],
                0.7,
            )
        };
        out.push(("flat".into(), two([0.0; 3], 0.0, 0.0, foot)));
        out.push((
            "origin_1km".into(),
            two([1000.0, -700.0, 30.0], 0.0, 0.0, foot),
        ));
        out.push(("patch_10um".into(), two([0.0; 3], 0.0, 0.0, [5e-6, 5e-6])));
        for dz in [1e-5, 1e-7, 1e-9] {
            out.push((format!("out_of_plane_{dz:e}"), two([0.0; 3], dz, 0.0, foot)));
        }
        for roll in [1.0, 0.1] {
            out.push((format!("rolled_{roll}deg"), two([0.0; 3], 0.0, roll, foot)));
        }
        // Random stances: 2 to 4 contacts at pseudo-random positions and rolls (xorshift).
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for case in 0..12 {
            let contacts: Vec<_> = (0..2 + case % 3)
                .map(|_| {
                    let p = [0.5 * next(), 0.5 * next(), 0.2 * next()];
                    (
                        p,
                        0.6 * next(),
                        [0.05 + 0.05 * next().abs(), 0.03 + 0.03 * next().abs()],
                    )
                })
                .collect();
            out.push((
                format!("random_{case}"),
                giwc(&contacts, 0.5 + 0.3 * next().abs()),
            ));
        }
        out
    }

    fn run(v: &DMatrix<f64>, dd_only: bool) -> (Result<SpanToFace, String>, RidgeStats) {
        FORCE_DD.with(|c| c.set(dd_only));
        STATS.with(|c| c.set(RidgeStats::default()));
        let r = span_to_face(v, &DdOptions::default()).map_err(|e| e.to_string());
        FORCE_DD.with(|c| c.set(false));
        (r, STATS.with(|c| c.get()))
    }

    /// On every golden and stress input, the closed form gives the same result, bit for bit,
    /// as the double description on every facet, and it is actually used.
    #[test]
    fn closed_form_equals_double_description_on_golden_and_stress_cones() {
        let mut total = RidgeStats::default();
        for (name, v) in inputs() {
            let (fast, s_fast) = run(&v, false);
            let (slow, s_slow) = run(&v, true);
            assert_eq!(fast, slow, "{name}");
            assert_eq!(s_slow.closed_form, 0, "{name}");
            assert_eq!(s_fast.simplicial, s_slow.simplicial, "{name}");
            assert_eq!(
                s_fast.closed_form + s_fast.neighbours + s_fast.dd + s_fast.skipped,
                s_slow.dd,
                "{name}"
            );
            eprintln!("{name}: {s_fast:?}");
            total.simplicial += s_fast.simplicial;
            total.closed_form += s_fast.closed_form;
            total.neighbours += s_fast.neighbours;
            total.dd += s_fast.dd;
            total.skipped += s_fast.skipped;
        }
        eprintln!("total: {total:?}");
        assert!(total.closed_form > 0, "{total:?}");
        assert!(total.neighbours > 0, "{total:?}");
    }
}
