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
//!    it (all `(t-2)`-subsets when `F` is simplicial, otherwise a small double description in
//!    the hyperplane of `F`), and each ridge must be contained (as a set of generators) in
//!    exactly two claimed facets. By 1 and 2 every claimed facet is a facet of `C`; if a facet
//!    `F*` of `C` were missing, the facet graph of `C` being connected, some claimed facet `F`
//!    would be adjacent to a missing one, and the ridge `F ∩ F*` would lie in one claimed facet
//!    only. (`t = 1`: exactly one facet; `t = 2`: exactly two.)
//!
//! A face form missing facets (the failure of cddlib's float mode described in the crate docs)
//! passes 1 and 2 but fails 4. Equations are checked separately: every generator satisfies them and their number
//! is `d - r`.

use crate::dd::{DdCore, DdFailure};
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
    /// Completeness: every ridge of every claimed facet lies in exactly two claimed facets.
    pub completeness: bool,
    /// Number of ridges (of claimed facets) not covered by exactly two claimed facets
    /// (`usize::MAX` when the facet count is impossible for the dimension, or when the check
    /// was not run: [`crate::DdOptions::check_completeness`]).
    pub open_ridges: usize,
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

/// Certifies whitened facets `fw` (`nf x r`, unit rows) against the whitened generators.
/// `perp` (`t x r`, orthonormal rows) spans the facets, `lin` (`(r - t) x r`, orthonormal rows)
/// its complement, the claimed lineality space.
#[allow(clippy::too_many_arguments)]
/// Returns the certificate and the extreme generators (indices into `wh.kept`, see
/// [`Incidence::extreme`]).
pub(crate) fn certify_whitened(
    wh: &Whitened,
    fw: &[f64],
    perp: &[f64],
    lin: &[f64],
    tol: &Tolerances,
    arithmetic: Arithmetic,
    check_completeness: bool,
    check: &mut DdCore,
    scratch: &mut Vec<f64>,
) -> (Certificate, Vec<usize>) {
    let r = wh.r;
    let nf = fw.len().checked_div(r).unwrap_or(0);
    let t = perp.len().checked_div(r).unwrap_or(0);
    let l = lin.len().checked_div(r).unwrap_or(0);
    let ng = wh.kept.len();

    // Slacks of every generator on every facet (unit vectors): S = F W^T, one matrix product.
    let slack = if nf > 0 && ng > 0 && r > 0 {
        let fm = nalgebra::DMatrix::from_row_slice(nf, r, fw);
        let wm = nalgebra::DMatrix::from_row_slice(ng, r, &wh.w);
        fm * wm.transpose()
    } else {
        nalgebra::DMatrix::zeros(nf, ng)
    };

    // 1. Soundness.
    let max_violation = slack.iter().copied().fold(0.0, f64::max);
    let soundness = max_violation <= tol.certificate && wh.equation_residual <= tol.certificate;

    // 2. Support: tight generators, projected on the facet's hyperplane, have rank r - 1.
    // When the ridge check runs (below), it decides support on the way (same projection, in
    // L^perp), so the loop here only runs without it.
    let merged_support = check_completeness && t >= 3 && ok_dims(t, nf);
    let mut unsupported_facets = Vec::new();
    let mut proj = Vec::new();
    for f in 0..nf {
        if merged_support {
            break;
        }
        let u = &fw[f * r..(f + 1) * r];
        proj.clear();
        let mut cnt = 0;
        for i in 0..ng {
            let s = slack[(f, i)];
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
            scratch,
        );
        if rank + 1 != r {
            unsupported_facets.push(f);
        }
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
        lineality = match check.run(&rows, m, l, tol.incidence, tol.support_rank) {
            Ok(()) => check.n == 0,
            Err(_) => false,
        };
    }

    // 4. Completeness: every ridge of every claimed facet lies in exactly two claimed facets.
    let inc = Incidence::new(wh, fw, perp, t, tol, &slack);
    let open_ridges = if !check_completeness {
        usize::MAX
    } else if ok_dims(t, nf) {
        count_open_ridges(&inc, t, tol, check, scratch, &mut unsupported_facets)
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

/// Generator-facet incidence in `L^perp` coordinates (dimension `t`), as bitsets both ways.
pub(crate) struct Incidence {
    t: usize,
    ng: usize,
    nf: usize,
    /// Generators (unit, `ng x t`), facets (unit, `nf x t`).
    gp: Vec<f64>,
    fp: Vec<f64>,
    /// Generator lies in the lineality space (projection ~ 0).
    in_l: Vec<bool>,
    gw: usize,
    fwd: usize,
    /// `nf x gw`: generators tight on each facet.
    inc: Vec<u64>,
    /// `ng x fwd`: facets tight on each generator.
    by_gen: Vec<u64>,
}

impl Incidence {
    fn new(
        wh: &Whitened,
        fw: &[f64],
        perp: &[f64],
        t: usize,
        tol: &Tolerances,
        slack: &nalgebra::DMatrix<f64>,
    ) -> Self {
        let r = wh.r;
        let ng = wh.kept.len();
        let nf = fw.len().checked_div(r).unwrap_or(0);
        let gw = ng.div_ceil(64).max(1);
        let fwd = nf.div_ceil(64).max(1);
        if t == r {
            // Pointed: L^perp is all of R^r; the whitened coordinates serve as they are.
            let mut inc = vec![0u64; nf * gw];
            let mut by_gen = vec![0u64; ng * fwd];
            // `slack` is column-major (`nf x ng`): walk it column by column.
            for i in 0..ng {
                for (f, s) in slack.column(i).iter().enumerate() {
                    if s.abs() <= tol.incidence {
                        inc[f * gw + i / 64] |= 1 << (i % 64);
                        by_gen[i * fwd + f / 64] |= 1 << (f % 64);
                    }
                }
            }
            return Self {
                t,
                ng,
                nf,
                gp: wh.w.clone(),
                fp: fw.to_vec(),
                in_l: vec![false; ng],
                gw,
                fwd,
                inc,
                by_gen,
            };
        }
        let mut gp = vec![0.0; ng * t];
        let mut in_l = vec![false; ng];
        for i in 0..ng {
            let g = wh.gen(i);
            for b in 0..t {
                gp[i * t + b] = dot(&perp[b * r..(b + 1) * r], g);
            }
            if normalize(&mut gp[i * t..(i + 1) * t]) <= tol.certificate {
                in_l[i] = true;
            }
        }
        let mut fp = vec![0.0; nf * t];
        for f in 0..nf {
            for b in 0..t {
                fp[f * t + b] = dot(&perp[b * r..(b + 1) * r], &fw[f * r..(f + 1) * r]);
            }
            normalize(&mut fp[f * t..(f + 1) * t]);
        }
        let mut inc = vec![0u64; nf * gw];
        let mut by_gen = vec![0u64; ng * fwd];
        for f in 0..nf {
            let u = &fp[f * t..(f + 1) * t];
            for i in 0..ng {
                if !in_l[i] && dot(u, &gp[i * t..(i + 1) * t]).abs() <= tol.incidence {
                    inc[f * gw + i / 64] |= 1 << (i % 64);
                    by_gen[i * fwd + f / 64] |= 1 << (f % 64);
                }
            }
        }
        Self {
            t,
            ng,
            nf,
            gp,
            fp,
            in_l,
            gw,
            fwd,
            inc,
            by_gen,
        }
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
        let set = |i: usize| &self.by_gen[i * fwd..(i + 1) * fwd];
        let mut out: Vec<usize> = Vec::new();
        for &g in candidates {
            if self.in_l[g] {
                continue;
            }
            let sg = set(g);
            let dominated = candidates.iter().any(|&h| {
                h != g
                    && !self.in_l[h]
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

/// The ridge check of completeness (see the module doc), for `t >= 3` (smaller `t` are decided by
/// [`ok_dims`]). Returns the number of ridges not covered by exactly two facets.
fn count_open_ridges(
    incd: &Incidence,
    t: usize,
    tol: &Tolerances,
    small: &mut DdCore,
    scratch: &mut Vec<f64>,
    unsupported: &mut Vec<usize>,
) -> usize {
    if t < 3 {
        return 0;
    }
    let Incidence {
        ng, nf, gw, fwd, ..
    } = *incd;
    let (gp, fp, inc, by_gen) = (&incd.gp, &incd.fp, &incd.inc, &incd.by_gen);
    let mut open = 0;
    let mut members: Vec<usize> = Vec::new();
    let mut rows: Vec<f64> = Vec::new();
    let mut acc = vec![0u64; fwd];
    let mut ridge: Vec<usize> = Vec::new();
    let mut vbuf = vec![0.0; t];
    let mut lambda = vec![0.0; t];
    // Counts the facets containing `ridge` (generator indices); 2 expected.
    let covered = |ridge: &[usize], acc: &mut [u64]| -> u32 {
        if fwd == 1 {
            // At most 64 facets: one register, starting from the set of all facets.
            let mut a = if nf == 64 { u64::MAX } else { (1u64 << nf) - 1 };
            for &i in ridge {
                a &= by_gen[i];
            }
            return a.count_ones();
        }
        acc.fill(u64::MAX);
        for &i in ridge {
            for (a, b) in acc.iter_mut().zip(&by_gen[i * fwd..(i + 1) * fwd]) {
                *a &= b;
            }
        }
        let extra = fwd * 64 - nf;
        acc.iter().map(|w| w.count_ones()).sum::<u32>()
            - if ridge.is_empty() { extra as u32 } else { 0 }
    };
    for f in 0..nf {
        members.clear();
        for i in 0..ng {
            if inc[f * gw + i / 64] >> (i % 64) & 1 == 1 {
                members.push(i);
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
        let v = &mut vbuf[..];
        v.copy_from_slice(u);
        v[j] += if u[j] >= 0.0 { 1.0 } else { -1.0 };
        let vv = dot(v, v);
        let k = t - 1;
        rows.clear();
        for &i in &members {
            let g = &gp[i * t..(i + 1) * t];
            let c = 2.0 * dot(v, g) / vv;
            let start = rows.len();
            for q in (0..t).filter(|&q| q != j) {
                rows.push(g[q] - c * v[q]);
            }
            normalize(&mut rows[start..]);
        }
        if members.len() == t - 1 {
            // Simplicial facet (when its generators are independent: support): its ridges drop
            // one generator each.
            if rank_of(
                (0..k).map(|q| &rows[q * k..(q + 1) * k]),
                k,
                k,
                tol.support_rank,
                scratch,
            ) < k
            {
                unsupported.push(f);
                open += 1;
                continue;
            }
            for drop in 0..members.len() {
                ridge.clear();
                ridge.extend(
                    members
                        .iter()
                        .enumerate()
                        .filter(|&(k, _)| k != drop)
                        .map(|(_, &i)| i),
                );
                if covered(&ridge, &mut acc) != 2 {
                    open += 1;
                }
            }
            continue;
        }
        if members.len() == t {
            // One generator more than simplicial: the facet is a cone of k + 1 vectors in R^k
            // with a single linear dependency `sum lambda_i g_i = 0`. Its facets are
            // `G \ {i, j}` for `lambda_i > 0 > lambda_j`, and `G \ {i}` for `lambda_i = 0`.
            match dependency(&rows, k, tol.support_rank, &mut lambda, scratch) {
                None => {
                    unsupported.push(f);
                    open += 1;
                }
                Some(()) => {
                    let m = members.len();
                    let sign = |i: usize| -> i32 {
                        if lambda[i] > tol.support_rank {
                            1
                        } else if lambda[i] < -tol.support_rank {
                            -1
                        } else {
                            0
                        }
                    };
                    let has_pos = (0..m).any(|i| sign(i) > 0);
                    let has_neg = (0..m).any(|i| sign(i) < 0);
                    if !(has_pos && has_neg) {
                        open += 1;
                        continue;
                    }
                    for a in 0..m {
                        for b in a..m {
                            let is_ridge = if a == b {
                                sign(a) == 0
                            } else {
                                sign(a) * sign(b) < 0
                            };
                            if !is_ridge {
                                continue;
                            }
                            ridge.clear();
                            ridge.extend((0..m).filter(|&q| q != a && q != b).map(|q| members[q]));
                            if covered(&ridge, &mut acc) != 2 {
                                open += 1;
                            }
                        }
                    }
                }
            }
            continue;
        }
        match small.run(&rows, members.len(), k, tol.incidence, tol.support_rank) {
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
        for q in 0..small.n {
            let z = &small.z[q * small.words..(q + 1) * small.words];
            ridge.clear();
            for (loc, &i) in members.iter().enumerate() {
                if z[loc / 64] >> (loc % 64) & 1 == 1 {
                    ridge.push(i);
                }
            }
            if covered(&ridge, &mut acc) != 2 {
                open += 1;
            }
        }
    }
    open
}

/// The linear dependency `lambda` (unit norm) of `k + 1` vectors of `R^k` (`rows`, row-major)
/// of rank `k`, by Gaussian elimination with partial pivoting on the `k x (k + 1)` matrix whose
/// columns are the vectors. `None` when the rank is below `k` (pivot at most `eps`).
fn dependency(
    rows: &[f64],
    k: usize,
    eps: f64,
    lambda: &mut [f64],
    m: &mut Vec<f64>,
) -> Option<()> {
    let n = k + 1;
    m.clear();
    m.resize(k * n, 0.0);
    for i in 0..n {
        for r in 0..k {
            m[r * n + i] = rows[i * k + r];
        }
    }
    // Row echelon with column pivots; the free column is the last non-pivot one.
    let mut piv_col = vec![usize::MAX; k];
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
    normalize(&mut lambda[..n]);
    Some(())
}
