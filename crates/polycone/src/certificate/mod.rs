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

use crate::dd::{DdCore, DdFailure, Scan, SmallDd};
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
    /// After an exact fallback in the default mode: how many output rows were merged into a
    /// kept row closer than [`Tolerances::certificate`] (unit rows, input coordinates). The
    /// exact answer of the rounded input keeps slivers of the intended geometry as separate,
    /// nearly parallel rows; a merged row `u` within distance `delta` of a kept row `k` is
    /// violated by at most `delta` by any unit vector the kept rows admit (`u . x = k . x +
    /// (u - k) . x <= delta`): the merged answer is the exact one within the tolerance
    /// contract. 0 when nothing was merged.
    pub merged_rows: usize,
    /// The largest distance between a merged row and the kept row it was merged into (the
    /// bound above; 0 when nothing was merged).
    pub merge_distance: f64,
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
    /// The same, for the small per-facet conversions.
    tiny: SmallDd,
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

/// Most rays the fixed-size double description of a facet keeps before handing over to the
/// general one (facets of the paper's cones need about ten).
const TINY_MAX_RAYS: usize = 256;

/// Lanes of the slack loop: generators are processed in blocks of this many, so that the
/// products, the running maximum and the incidence flags vectorize.
const LANES: usize = 8;

/// Slacks `s = u . g` of `nf` unit facets `fw` (`nf x r`) against `ng` generators given
/// transposed in `gt` (`r x ng`), into `slack` (`nf x ng`, row-major). Returns the largest slack
/// (at least 0). When `inc` is `Some((inc, gw, eps))`, also sets bit `i` of facet `f`'s `gw`-word
/// row of `inc` for every `|s| <= eps`.
fn slacks(
    fw: &[f64],
    gt: &[f64],
    r: usize,
    ng: usize,
    slack: &mut Vec<f64>,
    inc: Option<(&mut [u64], usize, f64)>,
) -> f64 {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            // SAFETY: the CPU has AVX2 and FMA, checked just above.
            return unsafe { slacks_avx2(fw, gt, r, ng, slack, inc) };
        }
    }
    slacks_body(fw, gt, r, ng, slack, inc)
}

/// [`slacks_body`] compiled for AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn slacks_avx2(
    fw: &[f64],
    gt: &[f64],
    r: usize,
    ng: usize,
    slack: &mut Vec<f64>,
    inc: Option<(&mut [u64], usize, f64)>,
) -> f64 {
    slacks_body(fw, gt, r, ng, slack, inc)
}

#[inline(always)]
fn slacks_body(
    fw: &[f64],
    gt: &[f64],
    r: usize,
    ng: usize,
    slack: &mut Vec<f64>,
    mut inc: Option<(&mut [u64], usize, f64)>,
) -> f64 {
    let nf = fw.len().checked_div(r).unwrap_or(0);
    slack.clear();
    slack.resize(nf * ng, 0.0);
    let mut lane_max = [0.0f64; LANES];
    for (f, (u, s_row)) in fw
        .chunks_exact(r.max(1))
        .zip(slack.chunks_exact_mut(ng.max(1)))
        .enumerate()
    {
        if r == 0 || ng == 0 {
            break;
        }
        // Blocks of LANES generators: the sums stay in registers across the r coordinates.
        let full = ng / LANES * LANES;
        for b in (0..full).step_by(LANES) {
            let mut acc = [0.0f64; LANES];
            for (c, &uc) in u.iter().enumerate() {
                let g = &gt[c * ng + b..c * ng + b + LANES];
                for (a, &gv) in acc.iter_mut().zip(g) {
                    *a += uc * gv;
                }
            }
            s_row[b..b + LANES].copy_from_slice(&acc);
            for (m, &s) in lane_max.iter_mut().zip(&acc) {
                *m = if s > *m { s } else { *m };
            }
        }
        for i in full..ng {
            let s: f64 = u
                .iter()
                .enumerate()
                .map(|(c, &uc)| uc * gt[c * ng + i])
                .sum();
            s_row[i] = s;
            lane_max[0] = if s > lane_max[0] { s } else { lane_max[0] };
        }
        if let Some((inc, gw, eps)) = inc.as_mut() {
            let row = &mut inc[f * *gw..(f + 1) * *gw];
            for (wi, chunk) in s_row.chunks(64).enumerate() {
                let mut w = 0u64;
                for (b, &s) in chunk.iter().enumerate() {
                    w |= ((s.abs() <= *eps) as u64) << b;
                }
                row[wi] = w;
            }
        }
    }
    lane_max.iter().copied().fold(0.0, f64::max)
}

/// Certifies whitened facets `fw` (`nf x r`, unit rows) against the whitened generators.
/// `perp` (`t x r`, orthonormal rows) spans the facets, `lin` (`(r - t) x r`, orthonormal rows)
/// its complement, the claimed lineality space.
/// Returns the certificate and the extreme generators (indices into `wh.kept`, see
/// [`Incidence::extreme`]).
#[allow(clippy::too_many_arguments)]
pub(crate) fn certify_whitened(
    wh: &Whitened,
    fw: &[f64],
    perp: &[f64],
    lin: &[f64],
    tol: &Tolerances,
    arithmetic: Arithmetic,
    check_completeness: bool,
    cs: &mut CertScratch,
) -> (Certificate, Vec<usize>) {
    let r = wh.r;
    let nf = fw.len().checked_div(r).unwrap_or(0);
    let t = perp.len().checked_div(r).unwrap_or(0);
    let l = lin.len().checked_div(r).unwrap_or(0);
    let ng = wh.kept.len();
    let pointed = t == r;
    let gw = ng.div_ceil(64).max(1);
    let fwd = nf.div_ceil(64).max(1);

    // Slacks of every generator on every facet (unit vectors), and for a pointed cone the
    // incidence in the same sweep.
    cs.gt.clear();
    cs.gt.resize(r * ng, 0.0);
    for i in 0..ng {
        for (c, &g) in wh.gen(i).iter().enumerate() {
            cs.gt[c * ng + i] = g;
        }
    }
    cs.inc.clear();
    cs.inc.resize(nf * gw, 0);
    let max_violation = slacks(
        fw,
        &cs.gt,
        r,
        ng,
        &mut cs.slack,
        pointed.then_some((&mut cs.inc[..], gw, tol.incidence)),
    );

    // 1. Soundness.
    let soundness = max_violation <= tol.certificate && wh.equation_residual <= tol.certificate;

    // 2. Support: tight generators, projected on the facet's hyperplane, have rank r - 1.
    // When the ridge check runs (below), it decides support on the way (same projection, in
    // L^perp), so the loop here only runs without it.
    let merged_support = check_completeness && t >= 3 && ok_dims(t, nf);
    let mut unsupported_facets = Vec::new();
    if !merged_support {
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
                unsupported_facets.push(f);
            }
        }
        cs.rows = proj;
    }

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
        lineality = match cs.small.run(&rows, m, l, tol.incidence, tol.support_rank) {
            Ok(()) => cs.small.n == 0,
            Err(_) => false,
        };
    }

    // 4. Completeness: every ridge of every claimed facet lies in exactly two claimed facets.
    if !pointed {
        project_incidence(wh, fw, perp, t, tol, cs);
    }
    cs.by_gen.clear();
    cs.by_gen.resize(ng * fwd, 0);
    for f in 0..nf {
        for wi in 0..gw {
            let mut w = cs.inc[f * gw + wi];
            while w != 0 {
                let i = wi * 64 + w.trailing_zeros() as usize;
                w &= w - 1;
                cs.by_gen[i * fwd + f / 64] |= 1 << (f % 64);
            }
        }
    }
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
        tiny: &mut cs.tiny,
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
    };
    (cert, extreme)
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

/// For a cone with lineality, generators and facets projected on `L^perp` (`t` orthonormal
/// rows `perp`) and normalized, into `cs.gp`, `cs.fp`, with the generators lying in `L`
/// flagged in `cs.in_l`, and the incidence recomputed there into `cs.inc`.
fn project_incidence(
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
    t: usize,
    nf: usize,
    /// Generators (unit, `ng x t`), facets (unit, `nf x t`).
    gp: &'a [f64],
    fp: &'a [f64],
    /// Generator lies in the lineality space (projection ~ 0); empty when pointed (none does).
    in_l: &'a [bool],
    gw: usize,
    fwd: usize,
    /// `nf x gw`: generators tight on each facet.
    inc: &'a [u64],
    /// `ng x fwd`: facets tight on each generator.
    by_gen: &'a [u64],
}

impl Incidence<'_> {
    /// Generator `i` lies in the lineality space.
    #[inline]
    fn in_l(&self, i: usize) -> bool {
        self.in_l.get(i).copied().unwrap_or(false)
    }

    /// Extreme generators among `candidates` (indices into `kept`), one per extreme ray: `g` is
    /// extreme iff it is not in `L` and no generator is tight on a strict superset of the
    /// facets `g` is tight on (for a complete face form, those generators lie in the smallest
    /// face containing `g`, which is a ray iff `g` is extreme); among generators tight on the
    /// same facets (the same ray), the first is kept.
    fn extreme(&self, candidates: &[usize]) -> Vec<usize> {
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

/// Buffers of [`count_open_ridges`], borrowed from [`CertScratch`].
struct RidgeWork<'a> {
    small: &'a mut DdCore,
    tiny: &'a mut SmallDd,
    members: &'a mut Vec<usize>,
    rows: &'a mut Vec<f64>,
    ridge: &'a mut Vec<usize>,
    neighbours: &'a mut Vec<u64>,
    cand: &'a mut Vec<u32>,
    acc: &'a mut Vec<u64>,
    drops: &'a mut Vec<(usize, usize)>,
    lambda: &'a mut Vec<f64>,
    vbuf: &'a mut Vec<f64>,
    nb: &'a mut NeighbourScratch,
    skip: &'a mut Vec<usize>,
    buf: &'a mut Vec<f64>,
}

/// The number of claimed facets containing `ridge` (generator indices, a subset of facet `f`'s
/// tight generators; 2 expected). With one-word incidence rows (`ng <= 64`), `neighbours` holds
/// the tight sets of the other facets sharing at least `t - 2` generators with `f`, which are
/// the only ones that can contain a ridge of `f` (a ridge has rank `t - 2`, so at least `t - 2`
/// generators); otherwise every facet is tested through the per-generator bitsets.
#[inline]
fn covered(
    incd: &Incidence,
    t: usize,
    ridge: &[usize],
    neighbours: &[u64],
    acc: &mut Vec<u64>,
    scan: Scan,
) -> usize {
    let (nf, fwd) = (incd.nf, incd.fwd);
    if incd.gw == 1 && ridge.len() + 2 >= t {
        let mask = ridge.iter().fold(0u64, |m, &i| m | 1 << i);
        return 1 + scan.count_supersets(mask, neighbours);
    }
    let by_gen = incd.by_gen;
    acc.clear();
    acc.resize(fwd, u64::MAX);
    for &i in ridge {
        for (a, b) in acc.iter_mut().zip(&by_gen[i * fwd..(i + 1) * fwd]) {
            *a &= b;
        }
    }
    let extra = fwd * 64 - nf;
    (acc.iter().map(|w| w.count_ones()).sum::<u32>()
        - if ridge.is_empty() { extra as u32 } else { 0 }) as usize
}

/// The ridge check of completeness (see the module doc), for `t >= 3` (smaller `t` are decided by
/// [`ok_dims`]). Returns the number of ridges not covered by exactly two facets.
fn count_open_ridges(
    incd: &Incidence,
    tol: &Tolerances,
    w: &mut RidgeWork,
    unsupported: &mut Vec<usize>,
) -> usize {
    let t = incd.t;
    if t < 3 {
        return 0;
    }
    let Incidence { nf, gw, .. } = *incd;
    let (gp, fp, inc) = (incd.gp, incd.fp, incd.inc);
    let scan = Scan::detect();
    let mut open = 0;
    // The `t - 2` facets with the most tight generators beyond `t` (ties: the first).
    w.skip.clear();
    let mut sizes = [0usize; 64];
    for f in 0..nf {
        let m = (0..gw).map(|wi| inc[f * gw + wi].count_ones()).sum::<u32>() as usize;
        if m <= t {
            continue;
        }
        if w.skip.len() < (t - 2).min(sizes.len()) {
            sizes[w.skip.len()] = m;
            w.skip.push(f);
        } else if let Some(low) = (0..w.skip.len()).min_by_key(|&q| sizes[q]) {
            if m > sizes[low] {
                sizes[low] = m;
                w.skip[low] = f;
            }
        }
    }
    w.vbuf.clear();
    w.vbuf.resize(t, 0.0);
    w.lambda.clear();
    w.lambda.resize(t, 0.0);
    for f in 0..nf {
        let members = &mut *w.members;
        members.clear();
        for wi in 0..gw {
            let mut word = inc[f * gw + wi];
            while word != 0 {
                members.push(wi * 64 + word.trailing_zeros() as usize);
                word &= word - 1;
            }
        }
        if members.len() < t - 1 {
            unsupported.push(f);
            open += 1;
            continue;
        }
        // Coordinates in the hyperplane u^perp: a Householder reflection H = I - 2 v v^T / v.v
        // with v = u + sign(u_j) e_j maps u to -sign(u_j) e_j; the other coordinates of H g
        // are orthonormal coordinates of g in u^perp.
        let u = &fp[f * t..(f + 1) * t];
        let j = (0..t)
            .max_by(|&a, &b| u[a].abs().total_cmp(&u[b].abs()))
            .unwrap_or(0);
        let v = &mut w.vbuf[..];
        v.copy_from_slice(u);
        v[j] += if u[j] >= 0.0 { 1.0 } else { -1.0 };
        let vv = dot(v, v);
        let k = t - 1;
        let hp = Hyperplane {
            v: &w.vbuf[..],
            vv,
            j,
        };
        // The other facets that may share a ridge with this one (one-word rows only).
        // Balinski's theorem (module doc): up to `t - 2` facets need only support; those with
        // the most tight generators (beyond `t`) are the expensive ones.
        let skip = !force_dd() && w.skip.contains(&f);
        if gw == 1 && !skip {
            w.cand.clear();
            scan.candidates(inc[f], inc, (t - 2) as u32, w.cand);
            if members.len() > t
                && !force_dd()
                && neighbours_prove_facet(incd, f, w.cand, &hp, tol, w.nb)
            {
                // Completeness (and support) from the claimed neighbours (`neighbours`).
                record!(neighbours);
                continue;
            }
        }
        w.neighbours.clear();
        if gw == 1 && !skip {
            w.neighbours.extend(
                w.cand
                    .iter()
                    .filter(|&&g| g as usize != f)
                    .map(|&g| inc[g as usize]),
            );
        }
        let rows = &mut *w.rows;
        rows.clear();
        rows.resize(members.len() * k, 0.0);
        for (&i, out) in members.iter().zip(rows.chunks_exact_mut(k)) {
            hp.project(&gp[i * t..(i + 1) * t], out);
            // No normalization needed: H is orthogonal and the dropped coordinate is
            // `±u . g`, at most `incidence` for a tight generator, so the row's norm is 1 to
            // within `incidence^2 / 2` (1e-18 by default), far below every threshold.
        }
        if skip {
            if !spans(rows, members.len(), k, tol.support_rank, w.buf) {
                unsupported.push(f);
                open += 1;
            }
            record!(skipped);
            continue;
        }
        let ridge = &mut *w.ridge;
        if members.len() == t - 1 {
            // Simplicial facet (when its generators are independent: support): its ridges drop
            // one generator each.
            if !spans(&rows[..k * k], k, k, tol.support_rank, w.buf) {
                unsupported.push(f);
                open += 1;
                continue;
            }
            record!(simplicial);
            for drop in 0..members.len() {
                ridge.clear();
                ridge.extend(
                    members
                        .iter()
                        .enumerate()
                        .filter(|&(k, _)| k != drop)
                        .map(|(_, &i)| i),
                );
                if covered(incd, t, ridge, w.neighbours, w.acc, scan) != 2 {
                    open += 1;
                }
            }
            continue;
        }
        if members.len() == t && !force_dd() {
            // One generator more than simplicial: closed form (module doc, "Near-simplicial
            // facets"), unless the dependency has an entry near zero: then the DD below decides.
            let m = members.len();
            match near_simplicial_ridges(rows, k, tol, w.lambda, w.buf, w.drops) {
                Some(true) => {
                    record!(closed_form);
                    for &(a, b) in w.drops.iter() {
                        ridge.clear();
                        ridge.extend((0..m).filter(|&q| q != a && q != b).map(|q| members[q]));
                        if covered(incd, t, ridge, w.neighbours, w.acc, scan) != 2 {
                            open += 1;
                        }
                    }
                    continue;
                }
                Some(false) => {
                    // The facet's generators positively span its hyperplane: not a face of a
                    // pointed cone, so the claimed form is wrong.
                    record!(closed_form);
                    open += 1;
                    continue;
                }
                None => {}
            }
        }
        record!(dd);
        // The facet's ridges: the zero sets of the extreme rays of the polar of cone(rows),
        // by the fixed-size double description, or the general one beyond its range.
        let m = members.len();
        let tiny = &mut *w.tiny;
        let small = &mut *w.small;
        let (result, used_tiny) =
            match tiny.run(rows, m, k, tol.incidence, tol.support_rank, TINY_MAX_RAYS) {
                Some(r) => (r, true),
                None => (
                    small.run(rows, m, k, tol.incidence, tol.support_rank),
                    false,
                ),
            };
        match result {
            Ok(()) => {}
            Err(DdFailure::RankDeficient) => {
                unsupported.push(f);
                open += 1;
                continue;
            }
            Err(_) => {
                open += 1;
                continue;
            }
        }
        let nr = if used_tiny { tiny.n() } else { small.n };
        for q in 0..nr {
            let z_hi = |loc: usize| -> bool {
                if used_tiny {
                    tiny.z[q] >> loc & 1 == 1
                } else {
                    small.z[q * small.words + loc / 64] >> (loc % 64) & 1 == 1
                }
            };
            ridge.clear();
            for (loc, &i) in members.iter().enumerate() {
                if z_hi(loc) {
                    ridge.push(i);
                }
            }
            if covered(incd, t, ridge, w.neighbours, w.acc, scan) != 2 {
                open += 1;
            }
        }
    }
    open
}

/// Ridges of a near-simplicial facet: `rows` holds `k + 1` unit vectors `g_i` of `R^k` (the
/// facet's tight generators in coordinates of its hyperplane). On success, `drops` lists the
/// pairs `(i, j)` (`i <= j`, indices into `rows`) such that the ridges of `cone(g)` are exactly
/// `G \ {g_i, g_j}` (module doc, "Near-simplicial facets"): `i < j` with
/// `lambda_i lambda_j < 0`, and `i = j` with `lambda_i = 0`. Returns `Some(false)` when the
/// non-zero `lambda_i` all have one sign (the cone contains a line: not pointed). Entries
/// with `c |lambda_i| >= certificate` are non-zero, entries with
/// `|lambda_i| <= (incidence^2 / certificate) min |lambda_j|` (over the non-zero ones) are
/// zero (module doc: margins of ten around the double description's `incidence`). `None`
/// (decide with a double description instead) when the vectors have rank below `k` or an
/// entry lies between the two.
fn near_simplicial_ridges(
    rows: &[f64],
    k: usize,
    tol: &Tolerances,
    lambda: &mut [f64],
    scratch: &mut Vec<f64>,
    drops: &mut Vec<(usize, usize)>,
) -> Option<bool> {
    near_simplicial(rows, k, tol, lambda, scratch, drops).map(|(pointed, _)| pointed)
}

/// [`near_simplicial_ridges`], also returning `c = sqrt(sum_q det(G \ {g_q})^2)` (so that
/// `|det(G \ {g_q})| = c |lambda_q|`).
pub(crate) fn near_simplicial(
    rows: &[f64],
    k: usize,
    tol: &Tolerances,
    lambda: &mut [f64],
    scratch: &mut Vec<f64>,
    drops: &mut Vec<(usize, usize)>,
) -> Option<(bool, f64)> {
    drops.clear();
    let c = dependency(rows, k, tol.support_rank, lambda, scratch)?;
    ridges_from_dependency(&lambda[..k + 1], c, tol, drops).map(|pointed| (pointed, c))
}

/// The sign logic of [`near_simplicial_ridges`], given the unit dependency `lambda` (`k + 1`
/// entries) and `c`. Fills `drops`; `None` when a sign is not clear.
pub(crate) fn ridges_from_dependency(
    lambda: &[f64],
    c: f64,
    tol: &Tolerances,
    drops: &mut Vec<(usize, usize)>,
) -> Option<bool> {
    drops.clear();
    let m = lambda.len();
    // Non-zero: every slack it implies off a ridge is at least `certificate` (ten times
    // `incidence`); zero: the slacks it implies are at most `incidence^2 / certificate` (a
    // tenth of `incidence`). Margins of ten either way, so that the double description,
    // deciding at `incidence`, takes the same decisions despite rounding.
    let min_nonzero = lambda
        .iter()
        .map(|x| x.abs())
        .filter(|&x| c * x >= tol.certificate)
        .fold(f64::INFINITY, f64::min);
    let zero_cut = tol.incidence * (tol.incidence / tol.certificate) * min_nonzero;
    let sign = |x: f64| -> Option<i8> {
        if c * x.abs() >= tol.certificate {
            Some(if x > 0.0 { 1 } else { -1 })
        } else if x.abs() <= zero_cut {
            Some(0)
        } else {
            None
        }
    };
    for &x in lambda {
        sign(x)?;
    }
    let mut pointed = false;
    for a in 0..m {
        let sa = sign(lambda[a])?;
        if sa == 0 {
            drops.push((a, a));
            continue;
        }
        for b in a + 1..m {
            let sb = sign(lambda[b])?;
            if sa * sb < 0 {
                drops.push((a, b));
                pointed = true;
            }
        }
    }
    if !pointed {
        drops.clear();
    }
    Some(pointed)
}

/// How the ridges of each facet were found in one certificate (test builds only).
#[cfg(test)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct RidgeStats {
    /// Simplicial facets (`t - 1` tight generators): all `(t - 2)`-subsets.
    pub simplicial: usize,
    /// Near-simplicial facets (`t` tight generators) decided by the closed form.
    pub closed_form: usize,
    /// Facets decided from their claimed neighbours (`neighbours` module).
    pub neighbours: usize,
    /// Facets decided by a double description in their hyperplane.
    pub dd: usize,
    /// Facets whose ridges were not enumerated (support only; Balinski's theorem).
    pub skipped: usize,
}

#[cfg(test)]
thread_local! {
    /// Test switch: decide every non-simplicial facet with the double description.
    pub(crate) static FORCE_DD: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    /// Test counters, accumulated over the certificates of this thread.
    pub(crate) static STATS: std::cell::Cell<RidgeStats> =
        const { std::cell::Cell::new(RidgeStats { simplicial: 0, closed_form: 0, neighbours: 0, dd: 0, skipped: 0 }) };
}

#[cfg(test)]
fn force_dd() -> bool {
    FORCE_DD.with(|c| c.get())
}

#[cfg(not(test))]
#[inline(always)]
fn force_dd() -> bool {
    false
}

/// The linear dependency `lambda` (unit norm) of `k + 1` vectors of `R^k` (`rows`, row-major)
/// of rank `k`, by Gaussian elimination with partial pivoting on the `k x (k + 1)` matrix whose
/// columns are the vectors. Also returns `c = sqrt(sum_q det(G \ {g_q})^2)` (so that
/// `|det(G \ {g_q})| = c |lambda_q|`: `lambda` is the vector of signed cofactors divided by
/// `c`), from the product of the pivots. `None` when the rank is below `k` (pivot at most
/// `eps`).
fn dependency(
    rows: &[f64],
    k: usize,
    eps: f64,
    lambda: &mut [f64],
    m: &mut Vec<f64>,
) -> Option<f64> {
    // Fixed-size elimination for the usual dimensions (same operations, stack arrays).
    macro_rules! fixed {
        ($k:literal) => {{
            let mut y = [[0.0f64; $k]; $k + 1];
            for (yi, r) in y.iter_mut().zip(rows.chunks_exact($k)) {
                yi.copy_from_slice(r);
            }
            let (l, c) = neighbours::dependency_k::<$k>(&y, eps)?;
            lambda[..$k + 1].copy_from_slice(&l.0[..$k + 1]);
            Some(c)
        }};
    }
    match k {
        2 => fixed!(2),
        3 => fixed!(3),
        4 => fixed!(4),
        5 => fixed!(5),
        6 => fixed!(6),
        7 => fixed!(7),
        8 => fixed!(8),
        _ => dependency_dyn(rows, k, eps, lambda, m),
    }
}

/// [`dependency`] for any `k` (heap scratch `m`); the reference the fixed-size version is
/// tested against.
fn dependency_dyn(
    rows: &[f64],
    k: usize,
    eps: f64,
    lambda: &mut [f64],
    m: &mut Vec<f64>,
) -> Option<f64> {
    let n = k + 1;
    let mut det = 1.0;
    m.clear();
    m.resize(k * n, 0.0);
    for i in 0..n {
        for r in 0..k {
            m[r * n + i] = rows[i * k + r];
        }
    }
    // Row echelon with column pivots; the free column is the last non-pivot one.
    // Pivot columns: on the stack for the dimensions of wrench cones and far beyond.
    let mut piv_small = [usize::MAX; 16];
    let mut piv_big = Vec::new();
    let piv_col: &mut [usize] = if k <= piv_small.len() {
        &mut piv_small[..k]
    } else {
        piv_big.resize(k, usize::MAX);
        &mut piv_big
    };
    let mut row = 0;
    let mut free = usize::MAX;
    for c in 0..n {
        if row == k {
            if free == usize::MAX {
                free = c;
            }
            continue;
        }
        let mut p = row;
        for r in row + 1..k {
            if m[r * n + c].abs() > m[p * n + c].abs() {
                p = r;
            }
        }
        if m[p * n + c].abs() <= eps {
            if free != usize::MAX {
                return None;
            }
            free = c;
            continue;
        }
        for t in 0..n {
            m.swap(p * n + t, row * n + t);
        }
        det *= m[row * n + c].abs();
        let inv = 1.0 / m[row * n + c];
        for t in 0..n {
            m[row * n + t] *= inv;
        }
        for r in 0..k {
            if r != row {
                let f = m[r * n + c];
                if f != 0.0 {
                    for t in 0..n {
                        m[r * n + t] -= f * m[row * n + t];
                    }
                }
            }
        }
        piv_col[row] = c;
        row += 1;
    }
    if row < k || free == usize::MAX {
        return None;
    }
    lambda[..n].fill(0.0);
    lambda[free] = 1.0;
    for r in 0..k {
        lambda[piv_col[r]] = -m[r * n + free];
    }
    // With `lambda_free = 1`, `lambda` is the cofactor vector divided by `det(G \ {g_free})`.
    Some(normalize(&mut lambda[..n]) * det)
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
