//! Completeness of one facet from its claimed neighbours (the dual of the per-facet ridge
//! enumeration).
//!
//! # Math
//!
//! Let `F` be a claimed facet with unit normal `u_F` and tight generators `T_F`, and let
//! `K_F = cone(T_F)`, a pointed cone of dimension `k = t - 1` in the hyperplane
//! `H_F = u_F^perp`. For any set `N` of other claimed facets, soundness gives
//! `u_G . x <= 0` on `K_F`, and on `H_F` this reads `y_G . x <= 0` with `y_G` the projection of
//! `u_G` on `H_F`. So `K_F ⊆ Q_F = {x in H_F : y_G . x <= 0, G in N}`.
//!
//! **Claim.** If every claimed facet `F` has `Q_F ⊆ K_F` for some such `N`, no facet is
//! missing. Indeed, if a facet `F*` of `C` is missing, the facet graph of `C` being connected,
//! some claimed `F` is adjacent to a missing `F*`; near the relative interior of their ridge
//! `R = F ∩ F*`, every facet of `C` other than `F` and `F*` is strictly satisfied (a ridge lies
//! in exactly two facets), and so is every claimed facet other than `F` (claimed facets are
//! facets of `C`, by support). Points of `H_F` just across `R` are then in `Q_F` but not in
//! `K_F`.
//!
//! **The check.** `N` is taken as the claimed facets whose tight sets meet `T_F` in inclusion-
//! maximal sets of at least `t - 2` generators (for a complete answer these are exactly the
//! ridges of `F`, one neighbour each). `Q_F ⊆ K_F` holds iff every extreme ray of `Q_F` lies
//! in `K_F`. The extreme rays of `Q_F = cone(Y)°` (`Y` the unit `y_G`) are the facet normals of
//! `cone(Y)`; with `|N| = k` (a basis) they are the normals of the `k` subsets that drop one
//! `y_a`, with `|N| = k + 1` they come from the closed form of near-simplicial cones (signs of
//! the dependency `lambda` of `Y`, see the parent module: drop `{a, b}` with
//! `lambda_a lambda_b < 0`, or `{a}` with `lambda_a = 0`). Other sizes are left to the double
//! description of `T_F`. Each ray `q` is tight on a set `S ⊆ Y`; it must be matched by a
//! generator `g` in `T_F` tight on every facet of `S`, and that match is checked
//! geometrically, not only by incidence:
//!
//! - A subset `S' ⊆ S` of `k - 1` vectors spans `q^perp` with volume at least `v` (below), so
//!   its smallest singular value is at least `v / P` with `P = ((k-1)/(k-2))^((k-2)/2)` (the
//!   largest product of `k - 2` singular values of `k - 1` unit rows). The unit projection `ĝ`
//!   of `g` is then within `sin(angle) <= beta = sqrt(k - 1) max_{S'} |y . ĝ| / (v / P)` of the
//!   line of `q`, and `beta <= support_rank` is required.
//! - Each dropped `y_a` must have `y_a . ĝ < -beta`: since `y_a . q < 0`, this puts `ĝ` on the
//!   side of `+q`.
//! - Volumes: for a basis `Y`, dropping `a` leaves `S' = Y \ {y_a}` with
//!   `vol(S') >= |det Y|`; for the near-simplicial case, `S' = Y \ {y_a, y_b}` with
//!   `vol(S') >= c max(|lambda_a|, |lambda_b|)` (`|det(Y \ {y_b})| = c |lambda_b|` is
//!   `vol(S')` times the distance of the unit `y_a` to `span(S')`); for `lambda_a = 0`,
//!   `S' = Y \ {y_a, y_b}` with the largest `|lambda_b|`.
//!
//! Then `Q_F` is within `asin(support_rank)` of `K_F` ray by ray, and `F` is a facet: the
//! matched generators must have rank `k` (the support check of the parent module, on a
//! subset). Two neighbours with the same intersection, or one whose intersection is all of
//! `T_F` (a duplicate of `F`), send the facet to the double description, whose ridge counts
//! reject them.

use super::{ridges_from_dependency, Incidence};
use crate::linalg::{abs_det, dot, spans};
use crate::tol::Tolerances;

/// Buffers of [`neighbours_prove_facet`].
#[derive(Clone, Debug, Default)]
pub(crate) struct NeighbourScratch {
    /// `(T_F ∩ T_G, G)` for the candidate neighbours, then the maximal ones.
    meet: Vec<(u64, u32)>,
    drops: Vec<(usize, usize)>,
    /// Rank scratch (the rare case where a determinant does not decide support).
    buf: Vec<f64>,
    rows: Vec<f64>,
}

/// Householder coordinates of the hyperplane of a facet: `H = I - 2 v v^T / (v . v)` maps
/// the facet normal to `± e_j`; the other coordinates of `H x` are orthonormal coordinates of
/// the projection of `x` on the hyperplane.
pub(crate) struct Hyperplane<'a> {
    pub(crate) v: &'a [f64],
    pub(crate) vv: f64,
    pub(crate) j: usize,
}

impl Hyperplane<'_> {
    /// [`Self::project`] with the dimension `K` of the hyperplane fixed at compile time.
    #[inline(always)]
    fn project_k<const K: usize>(&self, x: &[f64]) -> [f64; K] {
        let (x, v) = (&x[..K + 1], &self.v[..K + 1]);
        let c = 2.0 * x.iter().zip(v).map(|(a, b)| a * b).sum::<f64>() / self.vv;
        let mut out = [0.0f64; K];
        for (q, o) in out.iter_mut().enumerate() {
            let src = q + (q >= self.j) as usize;
            *o = x[src] - c * v[src];
        }
        out
    }

    /// The `t - 1` coordinates of the projection of `x` (length `t`) into `out`.
    #[inline]
    pub(crate) fn project(&self, x: &[f64], out: &mut [f64]) {
        let c = 2.0 * dot(self.v, x) / self.vv;
        for (q, o) in out.iter_mut().enumerate() {
            let src = q + (q >= self.j) as usize;
            *o = x[src] - c * self.v[src];
        }
    }
}

/// `P(k)`: the largest product of the `k - 2` largest singular values of `k - 1` unit rows.
fn volume_factor(k: usize) -> f64 {
    if k <= 2 {
        1.0
    } else {
        let (a, b) = ((k - 1) as f64, (k - 2) as f64);
        (a / b).powf(b / 2.0)
    }
}

/// The unit linear dependency `lambda` of `K + 1` vectors `y` of `R^K` of rank `K`, and
/// `c = sqrt(sum_q det(Y \ {y_q})^2)`, as the parent module's `dependency` (Gaussian
/// elimination with partial pivoting on the `K x (K + 1)` matrix whose columns are the vectors;
/// `None` when a pivot is at most `eps` twice, i.e. rank below `K`).
pub(crate) fn dependency_k<const K: usize>(y: &[[f64; K]], eps: f64) -> Option<(Vec1<K>, f64)> {
    let n = K + 1;
    // m[r][i] = y[i][r]: rows are coordinates, columns the vectors (n <= K + 1 <= 9).
    let mut m = [[0.0f64; 9]; K];
    for (i, yi) in y.iter().enumerate().take(n) {
        for r in 0..K {
            m[r][i] = yi[r];
        }
    }
    let mut det = 1.0;
    let mut piv_col = [usize::MAX; K];
    let mut row = 0;
    let mut free = usize::MAX;
    for c in 0..n {
        if row == K {
            if free == usize::MAX {
                free = c;
            }
            continue;
        }
        let mut p = row;
        for r in row + 1..K {
            if m[r][c].abs() > m[p][c].abs() {
                p = r;
            }
        }
        if m[p][c].abs() <= eps {
            if free != usize::MAX {
                return None;
            }
            free = c;
            continue;
        }
        m.swap(p, row);
        det *= m[row][c].abs();
        let inv = 1.0 / m[row][c];
        for x in m[row][..n].iter_mut() {
            *x *= inv;
        }
        let pivot = m[row];
        for (r, mr) in m.iter_mut().enumerate() {
            if r != row {
                let f = mr[c];
                if f != 0.0 {
                    for q in 0..n {
                        mr[q] -= f * pivot[q];
                    }
                }
            }
        }
        piv_col[row] = c;
        row += 1;
    }
    if row < K || free == usize::MAX {
        return None;
    }
    let mut lambda = Vec1::<K>::default();
    lambda.0[free] = 1.0;
    for r in 0..K {
        lambda.0[piv_col[r]] = -m[r][free];
    }
    let norm = crate::linalg::normalize(&mut lambda.0[..n]);
    Some((lambda, norm * det))
}

/// `K + 1` numbers (at most 9), on the stack.
#[derive(Clone, Copy)]
pub(crate) struct Vec1<const K: usize>(pub(crate) [f64; 9]);

impl<const K: usize> Default for Vec1<K> {
    fn default() -> Self {
        Self([0.0; 9])
    }
}

/// Tries to prove that facet `f` has no missing neighbour (module docs). `cand` lists the
/// claimed facets sharing at least `t - 2` tight generators with `f` (it may include `f`),
/// `hp` the coordinates of its hyperplane. `true`: proven, and the facet is supported.
/// `false`: undecided (decide with the double description of its tight generators).
/// One-word incidence rows, and `t` from 3 to 9.
pub(crate) fn neighbours_prove_facet(
    incd: &Incidence,
    f: usize,
    cand: &[u32],
    hp: &Hyperplane,
    tol: &Tolerances,
    s: &mut NeighbourScratch,
) -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("popcnt") {
            // SAFETY: the CPU supports `popcnt`, checked just above.
            return unsafe { prove_facet_popcnt(incd, f, cand, hp, tol, s) };
        }
    }
    prove_facet(incd, f, cand, hp, tol, s)
}

/// [`prove_facet`] compiled with the `popcnt` instruction (the intersections are counted in
/// its first loop).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "popcnt")]
unsafe fn prove_facet_popcnt(
    incd: &Incidence,
    f: usize,
    cand: &[u32],
    hp: &Hyperplane,
    tol: &Tolerances,
    s: &mut NeighbourScratch,
) -> bool {
    prove_facet(incd, f, cand, hp, tol, s)
}

/// The body of [`neighbours_prove_facet`].
#[inline(always)]
fn prove_facet(
    incd: &Incidence,
    f: usize,
    cand: &[u32],
    hp: &Hyperplane,
    tol: &Tolerances,
    s: &mut NeighbourScratch,
) -> bool {
    debug_assert_eq!(incd.gw, 1);
    let t = incd.t;
    let inc = incd.inc;
    let tf = inc[f];
    let need = (t - 2) as u32;
    // Candidate neighbours and their intersections with T_F.
    s.meet.clear();
    for &g in cand {
        if g as usize == f {
            continue;
        }
        let m = tf & inc[g as usize];
        if m == tf {
            // A duplicate of F (or a facet containing its generators): not for this check.
            return false;
        }
        if m.count_ones() >= need {
            s.meet.push((m, g));
        }
    }
    // Keep the inclusion-maximal intersections; equal ones send the facet to the DD.
    let n = s.meet.len();
    let mut keep = 0usize;
    for a in 0..n {
        let ma = s.meet[a].0;
        let mut maximal = true;
        let mut twin = false;
        for b in 0..n {
            let mb = s.meet[b].0;
            if ma & !mb == 0 && a != b {
                if ma != mb {
                    maximal = false;
                    break;
                }
                twin = true;
            }
        }
        if maximal {
            if twin {
                // Two neighbours through one maximal face: a ridge in three facets if it is
                // one (the ridge counts of the DD path say so), or a missing facet.
                return false;
            }
            s.meet[keep] = s.meet[a];
            keep += 1;
            if keep > t {
                // More than `t` = k + 1 neighbours: no closed form (the DD decides).
                return false;
            }
        }
    }
    s.meet.truncate(keep);
    match t - 1 {
        2 => prove_k::<2>(incd, f, hp, tol, s),
        3 => prove_k::<3>(incd, f, hp, tol, s),
        4 => prove_k::<4>(incd, f, hp, tol, s),
        5 => prove_k::<5>(incd, f, hp, tol, s),
        6 => prove_k::<6>(incd, f, hp, tol, s),
        7 => prove_k::<7>(incd, f, hp, tol, s),
        8 => prove_k::<8>(incd, f, hp, tol, s),
        _ => false,
    }
}

/// The geometric part of [`neighbours_prove_facet`] in the hyperplane of dimension `K`, on
/// the maximal neighbours left in `s.meet`: the extreme rays of `Q_F` from the neighbours'
/// projected normals ([`NeighbourNormals`]), each matched by a tight generator within the
/// angle of the module doc ([`RayBounds::matches`]), and the matched generators spanning the
/// hyperplane ([`Matched::span`]).
fn prove_k<const K: usize>(
    incd: &Incidence,
    f: usize,
    hp: &Hyperplane,
    tol: &Tolerances,
    s: &mut NeighbourScratch,
) -> bool {
    let t = K + 1;
    let inc = incd.inc;
    let tf = inc[f];
    let p = s.meet.len();
    if p != K && p != K + 1 {
        return false;
    }
    let mut nb = NeighbourNormals::<K> {
        y: [[0.0f64; K]; 9],
        ny: [0.0f64; 9],
        vol: [0.0f64; 9],
        p,
    };
    if !nb.project(incd, &s.meet, hp, tol) || !nb.extreme_rays(tol, &mut s.drops) {
        return false;
    }
    let bounds = RayBounds::new::<K>(tol, &nb);
    // Tight generators of each neighbour.
    let mut gmask = [0u64; 9];
    for (q, &(_, g)) in s.meet.iter().enumerate() {
        gmask[q] = inc[g as usize];
    }
    let mut matched = Matched::<K>::new();
    for &(a, b) in &s.drops {
        // The generators tight on the facets the ray is tight on: all but the dropped ones.
        let mut tight = tf;
        for (q, &gm) in gmask[..p].iter().enumerate() {
            if q != a && q != b {
                tight &= gm;
            }
        }
        if tight == 0 {
            return false;
        }
        let i = tight.trailing_zeros() as usize;
        let Some(slot) = matched.slot(i, || hp.project_k::<K>(&incd.gp[i * t..(i + 1) * t])) else {
            return false;
        };
        if !bounds.matches(&nb, a, b, &matched.gh[slot], tol) {
            return false;
        }
    }
    matched.span(tol, &mut s.rows, &mut s.buf)
}

/// The `p` (`K` or `K + 1`) neighbours of a facet seen in its hyperplane: the unit
/// projections `y_G` of their normals, the norms of those projections before normalization,
/// and per vector the volume bound of the module doc (`|det Y|` for a basis, `c |lambda_q|`
/// for `K + 1` vectors).
struct NeighbourNormals<const K: usize> {
    y: [[f64; K]; 9],
    ny: [f64; 9],
    vol: [f64; 9],
    p: usize,
}

impl<const K: usize> NeighbourNormals<K> {
    /// The unit projections of the normals of the neighbours `meet` (`p` of them) on the
    /// hyperplane `hp`, and their norms; `false` when one is at most
    /// [`Tolerances::support_rank`] long (a neighbour nearly parallel to the facet).
    #[inline(always)]
    fn project(
        &mut self,
        incd: &Incidence,
        meet: &[(u64, u32)],
        hp: &Hyperplane,
        tol: &Tolerances,
    ) -> bool {
        let t = K + 1;
        let (y, ny) = (&mut self.y, &mut self.ny);
        for (q, &(_, g)) in meet.iter().enumerate() {
            let g = g as usize;
            y[q] = hp.project_k::<K>(&incd.fp[g * t..(g + 1) * t]);
            let norm = y[q].iter().map(|x| x * x).sum::<f64>().sqrt();
            if norm <= tol.support_rank {
                return false;
            }
            let inv = 1.0 / norm;
            for x in y[q].iter_mut() {
                *x *= inv;
            }
            ny[q] = norm;
        }
        true
    }

    /// The extreme rays of `Q_F`, as dropped pairs `(a, b)` into `drops` (`a == b`: one
    /// dropped vector), and the volume bounds: with `K` vectors (a basis, `|det Y|` at least
    /// [`Tolerances::certificate`]) every ray drops one; with `K + 1`, the rays of the
    /// near-simplicial closed form on their dependency. `false` when neither decides.
    #[inline(always)]
    fn extreme_rays(&mut self, tol: &Tolerances, drops: &mut Vec<(usize, usize)>) -> bool {
        drops.clear();
        if self.p == K {
            let mut m = [[0.0f64; K]; K];
            m.copy_from_slice(&self.y[..K]);
            let det = abs_det(m);
            if det < tol.certificate {
                return false;
            }
            drops.extend((0..K).map(|a| (a, a)));
            self.vol[..K].fill(det);
        } else {
            let Some((lambda, c)) = dependency_k::<K>(&self.y[..K + 1], tol.support_rank) else {
                return false;
            };
            if ridges_from_dependency(&lambda.0[..K + 1], c, tol, drops) != Some(true) {
                return false;
            }
            for q in 0..=K {
                self.vol[q] = c * lambda.0[q].abs();
            }
        }
        true
    }
}

/// The constants of the match of a ray by a generator (module doc): the volume factor `P`,
/// `sqrt(K - 1)`, the cosine a tight generator may keep with a unit `u_G` tight on it, and the
/// smallest norm of a projected neighbour normal.
struct RayBounds {
    pk: f64,
    root: f64,
    tight_cos: f64,
    min_ny: f64,
}

impl RayBounds {
    #[inline(always)]
    fn new<const K: usize>(tol: &Tolerances, nb: &NeighbourNormals<K>) -> Self {
        Self {
            pk: volume_factor(K),
            root: ((K - 1) as f64).sqrt(),
            // A tight generator's projection is within `2 incidence` of orthogonal to a unit
            // `u_G` tight on it (`y_G . g = u_G . g - (u_G . u_F)(u_F . g)`), i.e.
            // `2 incidence / |y_G|` to the unit `y_G`; the factor covers the rounding of that
            // bound.
            tight_cos: 2.0 * tol.incidence * (1.0 + 1e-6),
            // The smallest norm before normalization: the a priori bound below uses it for
            // every S'.
            min_ny: nb.ny[..nb.p].iter().copied().fold(f64::INFINITY, f64::min),
        }
    }

    /// Whether the projected generator `g` matches the ray that drops `a` and `b`: within
    /// `beta <= support_rank` of its line (through `S'`, all but `a` and one more vector, and
    /// its volume bound), on the side of `+q` (each dropped vector has `y . g < -beta`).
    #[inline(always)]
    fn matches<const K: usize>(
        &self,
        nb: &NeighbourNormals<K>,
        a: usize,
        b: usize,
        g: &[f64; K],
        tol: &Tolerances,
    ) -> bool {
        let (p, y, vol) = (nb.p, &nb.y, &nb.vol);
        // S' (all but `a` and `skip`) and its volume bound.
        let (skip, v) = if p == K {
            (a, vol[a])
        } else if a != b {
            (b, vol[a].max(vol[b]))
        } else {
            // lambda_a = 0: drop also the vector with the largest |lambda|.
            let mut bb = if a == 0 { 1 } else { 0 };
            for q in 0..p {
                if q != a && vol[q] > vol[bb] {
                    bb = q;
                }
            }
            (bb, vol[bb])
        };
        let sigma = v / self.pk;
        if sigma.is_nan() || sigma <= 0.0 {
            return false;
        }
        let mut beta = self.root * self.tight_cos / self.min_ny / sigma;
        if beta > tol.support_rank {
            // The a priori bound is too coarse: measure the cosines.
            let mut err: f64 = 0.0;
            for q in 0..p {
                if q != a && q != skip {
                    err = err.max(dot(&y[q], g).abs());
                }
            }
            beta = self.root * err / sigma;
            if beta > tol.support_rank {
                return false;
            }
        }
        // The dropped vectors cut the ray strictly: ĝ is on the side of +q.
        !(dot(&y[a], g) >= -beta || (b != a && dot(&y[b], g) >= -beta))
    }
}

/// The generators matched to the rays so far: their projections on the hyperplane (`gh`) and
/// indices (`gi`), `ng` of them (at most 16).
struct Matched<const K: usize> {
    gh: [[f64; K]; 16],
    gi: [usize; 16],
    ng: usize,
}

impl<const K: usize> Matched<K> {
    #[inline(always)]
    fn new() -> Self {
        Self {
            gh: [[0.0f64; K]; 16],
            gi: [usize::MAX; 16],
            ng: 0,
        }
    }

    /// The slot of generator `i`, added with its projection `project()` when new; `None` when
    /// all 16 slots are taken.
    #[inline(always)]
    fn slot(&mut self, i: usize, project: impl FnOnce() -> [f64; K]) -> Option<usize> {
        match self.gi[..self.ng].iter().position(|&x| x == i) {
            Some(slot) => Some(slot),
            None => {
                if self.ng == self.gi.len() {
                    return None;
                }
                self.gh[self.ng] = project();
                self.gi[self.ng] = i;
                self.ng += 1;
                Some(self.ng - 1)
            }
        }
    }

    /// Support: the matched generators span the hyperplane (at least `K` of them; the
    /// determinant fast path of `spans` on the first `K`, then `spans` itself).
    #[inline(always)]
    fn span(&self, tol: &Tolerances, rows: &mut Vec<f64>, buf: &mut Vec<f64>) -> bool {
        let ng = self.ng;
        if ng < K {
            return false;
        }
        let mut m = [[0.0f64; K]; K];
        m.copy_from_slice(&self.gh[..K]);
        let bound = if ng == K { 1.0 } else { K as f64 } * tol.support_rank;
        if abs_det(m) > bound {
            return true;
        }
        rows.clear();
        for g in &self.gh[..ng] {
            rows.extend_from_slice(g);
        }
        spans(rows, ng, K, tol.support_rank, buf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(500))]
        /// The fixed-size dependency agrees with the parent module's general one, bit for bit.
        #[test]
        fn fixed_size_dependency_matches_the_general_one(
            raw in proptest::collection::vec(-1.0f64..1.0, 42),
        ) {
            const K: usize = 5;
            let mut y = [[0.0f64; K]; K + 1];
            for (q, row) in y.iter_mut().enumerate() {
                row.copy_from_slice(&raw[q * K..(q + 1) * K]);
                let n = dot(row, row).sqrt();
                prop_assume!(n > 1e-3);
                for x in row.iter_mut() {
                    *x /= n;
                }
            }
            let flat: Vec<f64> = y.iter().flatten().copied().collect();
            let (mut lambda, mut scratch) = (vec![0.0; K + 1], Vec::new());
            let general = super::super::dependency_dyn(&flat, K, 1e-7, &mut lambda, &mut scratch);
            let fixed = dependency_k::<K>(&y, 1e-7);
            match (general, fixed) {
                (None, None) => {}
                (Some(c), Some((l, c2))) => {
                    prop_assert_eq!(c.to_bits(), c2.to_bits());
                    for q in 0..=K {
                        prop_assert_eq!(lambda[q].to_bits(), l.0[q].to_bits());
                    }
                }
                (a, b) => prop_assert!(false, "{:?} vs {:?}", a, b.map(|x| x.1)),
            }
        }
    }

    /// The volume factor is the largest product of `k - 2` singular values of `k - 1` unit
    /// rows: 1 for `k = 2`, `sqrt 2` for `k = 3`, `(4/3)^(3/2)` for `k = 5`.
    #[test]
    fn volume_factor_values() {
        assert_eq!(volume_factor(2), 1.0);
        assert!((volume_factor(3) - 2f64.sqrt()).abs() < 1e-15);
        assert!((volume_factor(5) - (4.0f64 / 3.0).powf(1.5)).abs() < 1e-15);
    }
}
