//! The completeness check (item 4 of the module docs): every ridge of every facet is shared by
//! exactly two facets, found per facet by the simplicial rule, the near-simplicial closed form
//! (`simplicial`), the claimed neighbours (`neighbours`) or a double description in the
//! facet's hyperplane; and the test-only counters of which rule decided.

use super::*;

/// Buffers of [`count_open_ridges`], borrowed from [`CertScratch`].
pub(super) struct RidgeWork<'a> {
    pub(super) small: &'a mut DdCore,
    pub(super) members: &'a mut Vec<usize>,
    pub(super) rows: &'a mut Vec<f64>,
    pub(super) ridge: &'a mut Vec<usize>,
    pub(super) neighbours: &'a mut Vec<u64>,
    pub(super) cand: &'a mut Vec<u32>,
    pub(super) acc: &'a mut Vec<u64>,
    pub(super) drops: &'a mut Vec<(usize, usize)>,
    pub(super) lambda: &'a mut Vec<f64>,
    pub(super) vbuf: &'a mut Vec<f64>,
    pub(super) nb: &'a mut NeighbourScratch,
    pub(super) skip: &'a mut Vec<usize>,
    pub(super) buf: &'a mut Vec<f64>,
}

/// The number of claimed facets containing `ridge` (generator indices, a subset of facet `f`'s
/// tight generators; 2 expected). With one-word incidence rows (`ng <= 64`), `neighbours` holds
/// the tight sets of the other facets sharing at least `t - 2` generators with `f`, which are
/// the only ones that can contain a ridge of `f` (a ridge has rank `t - 2`, so at least `t - 2`
/// generators); otherwise every facet is tested through the per-generator bitsets.
#[inline]
pub(super) fn covered(
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
/// [`ok_dims`]). Returns the number of ridges not covered by exactly two facets; facets that
/// fail support are added to `unsupported`.
pub(super) fn count_open_ridges(
    incd: &Incidence,
    tol: &Tolerances,
    w: &mut RidgeWork,
    unsupported: &mut Vec<usize>,
) -> usize {
    let t = incd.t;
    if t < 3 {
        return 0;
    }
    let scan = Scan::detect();
    most_incident_facets(incd, w.skip);
    w.vbuf.clear();
    w.vbuf.resize(t, 0.0);
    w.lambda.clear();
    w.lambda.resize(t, 0.0);
    let mut open = 0;
    for f in 0..incd.nf {
        let facet = facet_ridges(incd, f, tol, w, scan);
        open += facet.open;
        if facet.unsupported {
            unsupported.push(f);
        }
    }
    open
}

/// The `t - 2` facets with the most tight generators beyond `t` (ties: the first), into `skip`:
/// by Balinski's theorem (module doc) they need only support.
fn most_incident_facets(incd: &Incidence, skip: &mut Vec<usize>) {
    let Incidence { nf, gw, t, .. } = *incd;
    let inc = incd.inc;
    skip.clear();
    let mut sizes = [0usize; 64];
    for f in 0..nf {
        let m = (0..gw).map(|wi| inc[f * gw + wi].count_ones()).sum::<u32>() as usize;
        if m <= t {
            continue;
        }
        if skip.len() < (t - 2).min(sizes.len()) {
            sizes[skip.len()] = m;
            skip.push(f);
        } else if let Some(low) = (0..skip.len()).min_by_key(|&q| sizes[q]) {
            if m > sizes[low] {
                sizes[low] = m;
                skip[low] = f;
            }
        }
    }
}

/// What the ridge check found on one facet.
struct FacetRidges {
    /// Ridges of the facet not covered by exactly two facets (1 for a facet that fails).
    open: usize,
    /// The facet's tight generators do not span its hyperplane.
    unsupported: bool,
}

impl FacetRidges {
    const CLOSED: FacetRidges = FacetRidges {
        open: 0,
        unsupported: false,
    };
    const UNSUPPORTED: FacetRidges = FacetRidges {
        open: 1,
        unsupported: true,
    };
    const WRONG: FacetRidges = FacetRidges {
        open: 1,
        unsupported: false,
    };
}

/// The ridge check of facet `f`: its ridges found by the first rule that applies (claimed
/// neighbours, Balinski skip, simplicial, near-simplicial closed form, double description in
/// its hyperplane), each counted open unless exactly two facets cover it.
///
/// The facet's `m` tight generators are taken in orthonormal coordinates of its hyperplane
/// (`t - 1` of them, [`hyperplane_coordinates`]); then `m = t - 1` is the simplicial rule
/// ([`simplicial_ridges`]), `m = t` the closed form ([`near_simplicial_facet_ridges`]), and
/// anything else, or a closed form that defers, the double description ([`dd_ridges`]).
fn facet_ridges(
    incd: &Incidence,
    f: usize,
    tol: &Tolerances,
    w: &mut RidgeWork,
    scan: Scan,
) -> FacetRidges {
    let Incidence { gw, t, .. } = *incd;
    let inc = incd.inc;
    tight_generators(inc, gw, f, w.members);
    let members = &*w.members;
    if members.len() < t - 1 {
        return FacetRidges::UNSUPPORTED;
    }
    let hp = hyperplane_coordinates(&incd.fp[f * t..(f + 1) * t], w.vbuf);
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
            return FacetRidges::CLOSED;
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
    let k = t - 1;
    let rows = &mut *w.rows;
    rows.clear();
    rows.resize(members.len() * k, 0.0);
    for (&i, out) in members.iter().zip(rows.chunks_exact_mut(k)) {
        hp.project(&incd.gp[i * t..(i + 1) * t], out);
        // No normalization needed: H is orthogonal and the dropped coordinate is
        // `±u . g`, at most `incidence` for a tight generator, so the row's norm is 1 to
        // within `incidence^2 / 2` (1e-18 by default), far below every threshold.
    }
    if skip {
        record!(skipped);
        return if spans(rows, members.len(), k, tol.support_rank, w.buf) {
            FacetRidges::CLOSED
        } else {
            FacetRidges::UNSUPPORTED
        };
    }
    if members.len() == t - 1 {
        return simplicial_ridges(incd, tol, w, scan);
    }
    if members.len() == t && !force_dd() {
        if let Some(found) = near_simplicial_facet_ridges(incd, tol, w, scan) {
            return found;
        }
    }
    dd_ridges(incd, tol, w, scan)
}

/// The tight generators of facet `f` (the set bits of its `gw`-word incidence row), into
/// `members`, in increasing order.
#[inline(always)]
fn tight_generators(inc: &[u64], gw: usize, f: usize, members: &mut Vec<usize>) {
    members.clear();
    for wi in 0..gw {
        let mut word = inc[f * gw + wi];
        while word != 0 {
            members.push(wi * 64 + word.trailing_zeros() as usize);
            word &= word - 1;
        }
    }
}

/// Coordinates in the hyperplane `u^perp` of the unit facet normal `u` (length `t`): a
/// Householder reflection `H = I - 2 v v^T / v.v` with `v = u + sign(u_j) e_j` (`j` the
/// largest `|u_j|`, so that `v.v >= 1`) maps `u` to `-sign(u_j) e_j`; the other coordinates of
/// `H g` are orthonormal coordinates of `g` in `u^perp`. `v` is written into `vbuf` (length
/// `t`).
#[inline(always)]
fn hyperplane_coordinates<'b>(u: &[f64], vbuf: &'b mut [f64]) -> Hyperplane<'b> {
    let t = u.len();
    let j = (0..t)
        .max_by(|&a, &b| u[a].abs().total_cmp(&u[b].abs()))
        .unwrap_or(0);
    vbuf.copy_from_slice(u);
    vbuf[j] += if u[j] >= 0.0 { 1.0 } else { -1.0 };
    let vv = dot(vbuf, vbuf);
    Hyperplane { v: vbuf, vv, j }
}

/// A simplicial facet (`t - 1` tight generators, their hyperplane coordinates in `w.rows`):
/// supported iff they are independent, and then its ridges drop one generator each.
#[inline(always)]
fn simplicial_ridges(
    incd: &Incidence,
    tol: &Tolerances,
    w: &mut RidgeWork,
    scan: Scan,
) -> FacetRidges {
    let t = incd.t;
    let k = t - 1;
    let members = &*w.members;
    if !spans(&w.rows[..k * k], k, k, tol.support_rank, w.buf) {
        return FacetRidges::UNSUPPORTED;
    }
    record!(simplicial);
    let ridge = &mut *w.ridge;
    let mut open = 0;
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
    FacetRidges {
        open,
        unsupported: false,
    }
}

/// A facet with one tight generator more than simplicial (`t`, hyperplane coordinates in
/// `w.rows`): its ridges by the closed form (module doc, "Near-simplicial facets"), or `None`
/// when the dependency has an entry near zero (the double description decides then).
#[inline(always)]
fn near_simplicial_facet_ridges(
    incd: &Incidence,
    tol: &Tolerances,
    w: &mut RidgeWork,
    scan: Scan,
) -> Option<FacetRidges> {
    let t = incd.t;
    let k = t - 1;
    let members = &*w.members;
    let m = members.len();
    match near_simplicial_ridges(w.rows, k, tol, w.lambda, w.buf, w.drops) {
        Some(true) => {
            record!(closed_form);
            let ridge = &mut *w.ridge;
            let mut open = 0;
            for &(a, b) in w.drops.iter() {
                ridge.clear();
                ridge.extend((0..m).filter(|&q| q != a && q != b).map(|q| members[q]));
                if covered(incd, t, ridge, w.neighbours, w.acc, scan) != 2 {
                    open += 1;
                }
            }
            Some(FacetRidges {
                open,
                unsupported: false,
            })
        }
        Some(false) => {
            // The facet's generators positively span its hyperplane: not a face of a
            // pointed cone, so the claimed form is wrong.
            record!(closed_form);
            Some(FacetRidges::WRONG)
        }
        None => None,
    }
}

/// The facet's ridges by a double description in its hyperplane: the zero sets of the
/// extreme rays of the polar of `cone(rows)` (`w.rows`, the tight generators' hyperplane
/// coordinates). A rank deficiency fails support; any other failure of the double
/// description fails the facet.
#[inline(always)]
fn dd_ridges(incd: &Incidence, tol: &Tolerances, w: &mut RidgeWork, scan: Scan) -> FacetRidges {
    record!(dd);
    let t = incd.t;
    let k = t - 1;
    let members = &*w.members;
    let m = members.len();
    let small = &mut *w.small;
    match small.run(w.rows, m, k, tol.incidence, tol.support_rank) {
        Ok(()) => {}
        Err(DdFailure::RankDeficient) => return FacetRidges::UNSUPPORTED,
        Err(_) => return FacetRidges::WRONG,
    }
    let ridge = &mut *w.ridge;
    let mut open = 0;
    for q in 0..small.n {
        let z_hi = |loc: usize| small.z[q * small.words + loc / 64] >> (loc % 64) & 1 == 1;
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
    FacetRidges {
        open,
        unsupported: false,
    }
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
pub(super) fn force_dd() -> bool {
    FORCE_DD.with(|c| c.get())
}

#[cfg(not(test))]
#[inline(always)]
pub(super) fn force_dd() -> bool {
    false
}
