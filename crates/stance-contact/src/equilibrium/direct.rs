//! The static-equilibrium polygon straight from the contacts, without `U_stance`.
//!
//! # Math
//!
//! Static equilibrium of the CoM `p` holds iff `w_GI = (m g, m p x g)` is in the GIWC, i.e.
//! iff some `lambda >= 0` combines its generators `-(e_j, q_j x e_j)` (pyramid edge `e_j` at
//! contact vertex `q_j`, [`crate::Stance::giwc_span`]):
//!
//! ```text
//! sum_j lambda_j e_j = -g,        sum_j lambda_j q_j x e_j = g x p        (m factored out).
//! ```
//!
//! Write `tau = sum_j lambda_j q_j x e_j`. The second equation has a solution `p` iff
//! `g . tau = 0`, and then the CoMs are the line `p = tau x g / |g|^2 + t g`. So the set of
//! static CoMs is the image of the polytope
//!
//! ```text
//! Q = { lambda >= 0 : sum_j lambda_j e_j = -g,  g . sum_j lambda_j (q_j x e_j) = 0 }
//! ```
//!
//! (four equality rows) under a linear map, swept along `g`; its cross-section at height `z`
//! is `P = { L lambda + o : lambda in Q }` with `L_j = (kappa_x - r_x kappa_z,
//! kappa_y - r_y kappa_z)`, `kappa_j = (q_j x e_j) x g / |g|^2`, `r = (g_x, g_y) / g_z` and
//! `o = r z` (everything relative to the contacts' centroid and divided by their extent, so
//! the numbers are of order 1 whatever the units and the world origin).
//!
//! The polygon is computed by support-function expansion (Bretl and Lall 2008): solve
//! `max u . v, v in P` (an LP with four rows, solved by the crate's small dense simplex, warm-started from the
//! neighbouring vertex) for three directions, then for the outward normal of every edge of the
//! current polygon; a new vertex is inserted when it lies more than `dist_tol` beyond the edge,
//! otherwise the edge is final.
//!
//! # Certificate
//!
//! The LPs are not trusted; the result is checked from the data:
//!
//! - **Inner:** each vertex is `L lambda + o` for a `lambda >= 0` whose force and moment
//!   balance residual `|A lambda - b|` is at most `lp_feas` (relative to `|g|`).
//! - **Outer:** each edge's LP dual `y` bounds the whole polygon: for every feasible `lambda`,
//!   `n . L lambda = y . b + sum_j lambda_j r_j <= y . b + max(0, max_j r_j) Lambda` with the
//!   reduced costs `r_j = n . L_j - y . A_j` recomputed from the data and `Lambda >= sum_j
//!   lambda_j` proven by the dual `y_1` of `max sum_j lambda_j` (`y_1 . A_j >= s > 0` for all
//!   `j` gives `sum_j lambda_j <= y_1 . b / s`). When the forces are unbounded (an internal
//!   force, e.g. two hands squeezing along the line between them) there is no such bound: the
//!   dual must then be feasible within the face-form band, `max_j r_j <= face_tol (|L|_1 +
//!   |y|_1)`, the contract of `U_stance`'s own rows, and the offset is `y . b`.
//! - **Gap:** every corner of the outer polygon (consecutive edge lines intersected) is within
//!   `dist_tol` of the inner polygon, so the returned polygon is within `dist_tol` (Hausdorff)
//!   of the true one.
//!
//! When any of this fails, or the polygon is empty, unbounded or not 2-D
//! (e.g. two point contacts), the polygon is computed through `U_stance`
//! ([`super::StaticEquilibrium::polygon`]) and the route says why ([`PolygonRoute`]).

// `!(x <= tol)` is meant: a NaN must fail the certificate. Index loops over parallel arrays
// read like the math.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::needless_range_loop)]

use polycone::polytope::RegionStatus;

use super::simplex::{Lp4, LpStop, M};
use super::statics::{StaticEquilibrium, StaticPolygon};
use super::{seg_dist, EquilibriumOptions};
use crate::{ContactError, GiwcOptions, Stance};

/// Why the direct route gave way to `U_stance`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fallback {
    /// No contact forces balance gravity (the polygon may be empty).
    Infeasible,
    /// The contact forces can grow without bound (a non-pointed GIWC: opposing contacts).
    Unbounded,
    /// The polygon is not a 2-D polygon (a segment or a point, e.g. one or two point contacts).
    Degenerate,
    /// The balance equations are dependent within the pivot tolerance.
    RankDeficient,
    /// An LP stopped on its iteration cap or a singular basis.
    Numerical,
    /// The certificate failed (a residual, a dual bound or the gap above its tolerance).
    Uncertified,
}

/// How a polygon was computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PolygonRoute {
    /// Support-function expansion over the contact forces, certified.
    Direct,
    /// Through `U_stance` and half-plane intersection, for the reason given.
    ViaUStance(Fallback),
}

/// A static-equilibrium polygon and how it was obtained.
#[derive(Debug, Clone, PartialEq)]
pub struct DirectPolygon {
    /// The polygon (same conventions as [`StaticEquilibrium::polygon`]).
    pub polygon: StaticPolygon,
    /// Direct, or through `U_stance` (and why).
    pub route: PolygonRoute,
    /// Certified Hausdorff distance bound (m) between the returned and the true polygon on the
    /// direct route (`NaN` through `U_stance`, whose own tolerance contract applies).
    pub gap: f64,
    /// LPs solved and simplex pivots done (direct route).
    pub lps: usize,
    /// See `lps`.
    pub pivots: usize,
}

/// A vertex of the current polygon and the edge that leaves it (to the next vertex).
#[derive(Debug, Clone, Copy)]
struct Vertex {
    /// Scaled coordinates.
    v: [f64; 2],
    /// Optimal basis and basic values of the LP that found it.
    basis: [usize; M],
    xb: [f64; M],
    /// The edge to the next vertex is final; its outward normal and LP dual.
    done: bool,
    normal: [f64; 2],
    y: [f64; M],
}

/// Reusable buffers of the direct polygon (no allocation in the LPs after the first call).
#[derive(Debug, Clone, Default)]
pub struct PolygonWorkspace {
    /// Options of the `U_stance` route (used only when the direct route gives way).
    pub giwc: GiwcOptions,
    lp: Lp4,
    l: Vec<[f64; 2]>,
    verts: Vec<Vertex>,
    offs: Vec<f64>,
    /// Contact vertices (world) with the range of their contact's edges in `edges`.
    points: Vec<([f64; 3], usize, usize)>,
    edges: Vec<[f64; 3]>,
    lps: usize,
}

/// Scaled problem data: centroid, extent, gravity ratios and height.
struct Frame {
    c0: [f64; 3],
    ell: f64,
    r: [f64; 2],
    z: f64,
}

impl PolygonWorkspace {
    /// An empty workspace.
    ///
    /// ```
    /// let ws = stance_contact::equilibrium::PolygonWorkspace::new();
    /// # let _ = ws;
    /// ```
    pub fn new() -> Self {
        Self::default()
    }

    /// The static-equilibrium polygon of `stance` under `gravity` (m/s^2, with a vertical
    /// component), cut at height `z = height` (m): directly from the contact forces when the
    /// certificate holds, otherwise through `U_stance` (module doc).
    ///
    /// ```
    /// use stance_contact::{examples, equilibrium::{PolygonRoute, PolygonWorkspace}};
    /// let scene = examples::single_support_flat();
    /// let stance = scene.stance().unwrap();
    /// let out = PolygonWorkspace::new()
    ///     .static_polygon(&stance, scene.gravity, 0.0, &Default::default())
    ///     .unwrap();
    /// assert_eq!(out.route, PolygonRoute::Direct);
    /// assert_eq!(out.polygon.vertices.len(), 4); // the foot rectangle
    /// assert!((out.polygon.margin([0.0, 0.0]) - 0.065).abs() < 1e-9);
    /// ```
    pub fn static_polygon(
        &mut self,
        stance: &Stance,
        gravity: [f64; 3],
        height: f64,
        opts: &EquilibriumOptions,
    ) -> Result<DirectPolygon, ContactError> {
        check_inputs(gravity, height, opts)?;
        // Computed near the origin and at unit size, mapped back (`super::frame`): the answer
        // does not depend on the world origin or the unit of length.
        if let Some(frame) = super::frame::LengthFrame::of(stance) {
            let local = frame.local(stance);
            let mut out = self.static_polygon_here(&local, gravity, frame.height(height), opts)?;
            out.polygon = frame.polygon_to_world(out.polygon, height);
            out.gap *= frame.length;
            return Ok(out);
        }
        self.static_polygon_here(stance, gravity, height, opts)
    }

    /// The static-equilibrium polygon through `U_stance` only (the half-plane intersection of
    /// its rows), in the same length frame as [`Self::static_polygon`].
    ///
    /// ```
    /// use stance_contact::{examples, equilibrium::PolygonWorkspace};
    /// let scene = examples::single_support_flat();
    /// let stance = scene.stance().unwrap();
    /// let p = PolygonWorkspace::new()
    ///     .static_polygon_via_u_stance(&stance, scene.gravity, 0.0, &Default::default())
    ///     .unwrap();
    /// assert_eq!(p.vertices.len(), 4);
    /// ```
    pub fn static_polygon_via_u_stance(
        &mut self,
        stance: &Stance,
        gravity: [f64; 3],
        height: f64,
        opts: &EquilibriumOptions,
    ) -> Result<StaticPolygon, ContactError> {
        check_inputs(gravity, height, opts)?;
        match super::frame::LengthFrame::of(stance) {
            Some(f) => {
                let local =
                    self.u_stance_polygon(&f.local(stance), gravity, f.height(height), opts)?;
                Ok(f.polygon_to_world(local, height))
            }
            None => self.u_stance_polygon(stance, gravity, height, opts),
        }
    }

    /// The polygon through `U_stance` in the stance's own coordinates (both public routes).
    fn u_stance_polygon(
        &self,
        stance: &Stance,
        gravity: [f64; 3],
        height: f64,
        opts: &EquilibriumOptions,
    ) -> Result<StaticPolygon, ContactError> {
        let giwc = stance.u_stance(&self.giwc)?;
        StaticEquilibrium::new(&giwc, gravity, opts)?.polygon(height)
    }

    /// [`Self::static_polygon`] in the stance's own coordinates.
    fn static_polygon_here(
        &mut self,
        stance: &Stance,
        gravity: [f64; 3],
        height: f64,
        opts: &EquilibriumOptions,
    ) -> Result<DirectPolygon, ContactError> {
        self.lps = 0;
        self.lp.pivots = 0;
        // The polygon does not depend on |g| (no overflow for any magnitude).
        let g = super::scaled_gravity(gravity);
        match self.direct(stance, g, height, opts) {
            Ok((polygon, gap)) => Ok(DirectPolygon {
                polygon,
                route: PolygonRoute::Direct,
                gap,
                lps: self.lps,
                pivots: self.lp.pivots,
            }),
            Err(why) => {
                let polygon = self.u_stance_polygon(stance, gravity, height, opts)?;
                Ok(DirectPolygon {
                    polygon,
                    route: PolygonRoute::ViaUStance(why),
                    gap: f64::NAN,
                    lps: self.lps,
                    pivots: self.lp.pivots,
                })
            }
        }
    }

    /// Fills the LP columns; returns the frame.
    fn setup(&mut self, stance: &Stance, gravity: [f64; 3], height: f64) -> Option<Frame> {
        let gn = norm3(gravity);
        let gh = [gravity[0] / gn, gravity[1] / gn, gravity[2] / gn];
        // Contact vertices (world) and the pyramid edges (world) of each contact.
        self.points.clear();
        self.edges.clear();
        let model = stance.friction_model();
        for c in stance.contacts() {
            let rot = c.rotation();
            let first_edge = self.edges.len();
            for e in model.edges(c.friction()) {
                let w = rot * nalgebra::Vector3::from(e);
                self.edges.push([w[0], w[1], w[2]]);
            }
            for q in c.vertices_world() {
                self.points.push((q, first_edge, self.edges.len()));
            }
        }
        // Centroid and extent of the contact vertices.
        let count = self.points.len() as f64;
        let mut c0 = [0.0; 3];
        for (q, _, _) in &self.points {
            for k in 0..3 {
                c0[k] += q[k] / count;
            }
        }
        let ell = self
            .points
            .iter()
            .map(|(q, _, _)| norm3(sub3(*q, c0)))
            .fold(0.0, f64::max);
        if !(ell > 0.0 && ell.is_finite()) {
            return None;
        }
        let r = [gh[0] / gh[2], gh[1] / gh[2]];
        self.lp.a.clear();
        self.l.clear();
        for &(q, e0, e1) in &self.points {
            let qs = sub3(q, c0).map(|x| x / ell);
            for e in &self.edges[e0..e1] {
                let m = crate::cross(qs, *e);
                let a = [e[0], e[1], e[2], dot3(gh, m)];
                let kappa = crate::cross(m, gh);
                let l = [kappa[0] - r[0] * kappa[2], kappa[1] - r[1] * kappa[2]];
                let s = 1.0 / (a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + a[3] * a[3]).sqrt();
                self.lp.a.push(a.map(|x| x * s));
                self.l.push(l.map(|x| x * s));
            }
        }
        Some(Frame {
            c0,
            ell,
            r,
            z: (height - c0[2]) / ell,
        })
    }

    /// Maximizes `u . L lambda` from the current basis.
    fn support(&mut self, u: [f64; 2], max_iter: usize) -> Result<Vertex, Fallback> {
        self.lps += 1;
        let Self { lp, l, .. } = self;
        lp.maximize(|j| u[0] * l[j][0] + u[1] * l[j][1], max_iter)
            .map_err(stop)?;
        Ok(Vertex {
            v: self.image(&self.lp.basis, &self.lp.xb),
            basis: self.lp.basis,
            xb: self.lp.xb,
            done: false,
            normal: u,
            y: self.lp.y,
        })
    }

    /// `L lambda` for a basic solution (negative basic values clamped to 0).
    fn image(&self, basis: &[usize; M], xb: &[f64; M]) -> [f64; 2] {
        let mut v = [0.0; 2];
        for i in 0..M {
            let x = xb[i].max(0.0);
            v[0] += self.l[basis[i]][0] * x;
            v[1] += self.l[basis[i]][1] * x;
        }
        v
    }

    fn direct(
        &mut self,
        stance: &Stance,
        gravity: [f64; 3],
        height: f64,
        opts: &EquilibriumOptions,
    ) -> Result<(StaticPolygon, f64), Fallback> {
        let frame = self
            .setup(stance, gravity, height)
            .ok_or(Fallback::Degenerate)?;
        let gh = norm3(gravity);
        let b = [-gravity[0] / gh, -gravity[1] / gh, -gravity[2] / gh, 0.0];
        let n = self.lp.a.len();
        let tol = &opts.tol;
        self.lp.reset(n, b, tol.lp_opt, tol.lp_pivot);
        let max_iter = 50 + 10 * n;
        self.lp.phase1(tol.lp_feas, max_iter).map_err(stop)?;

        // Lambda >= sum lambda_j, proven by the dual of max sum lambda_j; infinite when the
        // contact forces can grow without bound (internal forces between opposing contacts).
        self.lps += 1;
        let lambda = match self.lp.maximize(|_| 1.0, max_iter) {
            Ok(()) => {
                let y1 = self.lp.y;
                let s = self
                    .lp
                    .a
                    .iter()
                    .map(|a| dot4(&y1, a))
                    .fold(f64::INFINITY, f64::min);
                // Rounding of the dot products (unit columns, |b| = 1): within 8 eps |y_1|_1.
                let err = 8.0 * f64::EPSILON * y1.iter().map(|v| v.abs()).sum::<f64>();
                let s = s - err;
                if !(s > 0.0) {
                    return Err(Fallback::Uncertified);
                }
                let lambda = (dot4(&y1, &b) + err) / s * (1.0 + 4.0 * f64::EPSILON);
                if !lambda.is_finite() {
                    return Err(Fallback::Numerical);
                }
                lambda
            }
            // The basis is still feasible: the ratio test stopped before any pivot.
            Err(LpStop::Unbounded) => f64::INFINITY,
            Err(other) => return Err(stop(other)),
        };

        // Three directions, then expansion.
        let dist = opts.polytope.dist_tol / frame.ell;
        let merge = opts.polytope.merge_tol / frame.ell;
        self.verts.clear();
        for k in 0..3 {
            let ang = std::f64::consts::FRAC_PI_2 + k as f64 * 2.0 * std::f64::consts::FRAC_PI_3;
            let w = self.support([ang.cos(), ang.sin()], max_iter)?;
            let distinct = self.verts.iter().all(|p| dist2(p.v, w.v) > merge);
            if distinct {
                self.verts.push(w);
            }
        }
        if self.verts.len() < 2 {
            return Err(Fallback::Degenerate);
        }
        let cap = 20 + 4 * n;
        // Expand until every edge is final; merged edges (flat vertices dropped) are solved
        // again.
        loop {
            let mut i = 0;
            while i < self.verts.len() {
                if self.verts[i].done {
                    i += 1;
                    continue;
                }
                if self.lps > cap {
                    return Err(Fallback::Numerical);
                }
                let len = self.verts.len();
                let (a, bv) = (self.verts[i].v, self.verts[(i + 1) % len].v);
                let e = [bv[0] - a[0], bv[1] - a[1]];
                let le = (e[0] * e[0] + e[1] * e[1]).sqrt();
                if le <= merge {
                    if len <= 2 {
                        return Err(Fallback::Degenerate);
                    }
                    let drop = (i + 1) % len;
                    self.verts.remove(drop);
                    if drop < i {
                        i -= 1;
                    }
                    continue;
                }
                let nrm = [e[1] / le, -e[0] / le];
                // Warm start from the current basis (the last LP's, for a nearby direction).
                let w = self.support(nrm, max_iter)?;
                let h_edge = dot2(nrm, a).max(dot2(nrm, bv));
                if dot2(nrm, w.v) - h_edge <= dist {
                    let vi = &mut self.verts[i];
                    vi.done = true;
                    vi.normal = nrm;
                    vi.y = w.y;
                    i += 1;
                } else {
                    self.verts.insert(i + 1, w);
                }
            }
            if !self.drop_flat_vertices(dist) {
                break;
            }
        }
        if self.verts.len() < 3 {
            return Err(Fallback::Degenerate);
        }
        let gap = self.certify(&b, lambda, dist, tol.lp_feas, tol.face)?;
        Ok((self.to_world(&frame, height), gap * frame.ell))
    }

    /// Removes boundary points that are not corners (within `dist` of the segment joining their
    /// neighbours): an LP's optimal basis maps to a point of the optimal edge, not always to one
    /// of its ends. The merged edge is marked for a new LP along its own normal. Returns
    /// whether anything was removed.
    fn drop_flat_vertices(&mut self, dist: f64) -> bool {
        let mut dropped = false;
        let mut k = 0;
        while k < self.verts.len() && self.verts.len() > 3 {
            let n = self.verts.len();
            let (p, q, r) = (
                self.verts[(k + n - 1) % n].v,
                self.verts[k].v,
                self.verts[(k + 1) % n].v,
            );
            let d = [r[0] - p[0], r[1] - p[1]];
            let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
            let off_line = ((q[0] - p[0]) * d[1] - (q[1] - p[1]) * d[0]).abs() / len;
            if len > 0.0 && off_line <= dist && seg_dist(q, p, r) <= dist {
                self.verts.remove(k);
                let prev = (k + n - 1) % n;
                let prev = if prev > k { prev - 1 } else { prev };
                self.verts[prev].done = false;
                dropped = true;
                k = k.saturating_sub(1);
            } else {
                k += 1;
            }
        }
        dropped
    }

    /// The certificate of the module doc; returns the gap (scaled units) and leaves the
    /// verified offsets of the edge lines in `self.offs`.
    fn certify(
        &mut self,
        b: &[f64; M],
        lambda: f64,
        dist: f64,
        feas: f64,
        face_tol: f64,
    ) -> Result<f64, Fallback> {
        let nv = self.verts.len();
        // Inner: residuals of the vertices' contact forces, and their images.
        for k in 0..nv {
            let (basis, xb) = (self.verts[k].basis, self.verts[k].xb);
            let mut res = [-b[0], -b[1], -b[2], -b[3]];
            for i in 0..M {
                if xb[i] < -feas {
                    return Err(Fallback::Uncertified);
                }
                let x = xb[i].max(0.0);
                let a = &self.lp.a[basis[i]];
                for r in 0..M {
                    res[r] += a[r] * x;
                }
            }
            if res.iter().any(|r| !(r.abs() <= feas)) {
                return Err(Fallback::Uncertified);
            }
            self.verts[k].v = self.image(&basis, &xb);
        }
        // Outer: verified offsets of the edge lines.
        let mut offs = std::mem::take(&mut self.offs);
        offs.clear();
        offs.resize(nv, 0.0);
        let out = self.certify_outer(&mut offs, b, lambda, dist, face_tol);
        self.offs = offs;
        out
    }

    fn certify_outer(
        &mut self,
        offs: &mut [f64],
        b: &[f64; M],
        lambda: f64,
        dist: f64,
        face_tol: f64,
    ) -> Result<f64, Fallback> {
        let nv = self.verts.len();
        for k in 0..nv {
            let (nrm, y) = (self.verts[k].normal, self.verts[k].y);
            let mut rmax: f64 = 0.0;
            let mut lmax: f64 = 0.0;
            for (a, l) in self.lp.a.iter().zip(&self.l) {
                rmax = rmax.max(dot2(nrm, *l) - dot4(&y, a));
                lmax = lmax.max(l[0].abs() + l[1].abs());
            }
            let yb = dot4(&y, b);
            let y1: f64 = y.iter().map(|v| v.abs()).sum();
            offs[k] = if lambda.is_finite() {
                // Rounding: each computed r_j is within 8 eps (|L_j|_1 + |y|_1) of the exact
                // one (unit columns A_j), and sum_j lambda_j r_j <= max_j r_j Lambda; y . b
                // within 8 eps |y|_1 (|b| = 1).
                let guard = 8.0 * f64::EPSILON * ((lmax + y1) * (1.0 + lambda) + y1);
                yb + rmax * lambda + guard
            } else {
                // Unbounded forces: no bound on sum lambda_j, so the dual must be feasible
                // within the face-form band, the contract of U_stance's own rows (the edge is
                // then a face of the GIWC of generators moved by at most that much).
                if !(rmax <= face_tol * (lmax + y1)) {
                    return Err(Fallback::Uncertified);
                }
                yb + 8.0 * f64::EPSILON * y1
            };
            if !offs[k].is_finite() {
                return Err(Fallback::Numerical);
            }
        }
        // Soundness of the inner polygon against the outer lines.
        for k in 0..nv {
            for j in 0..nv {
                if dot2(self.verts[k].normal, self.verts[j].v) > offs[k] + dist {
                    return Err(Fallback::Uncertified);
                }
            }
        }
        // Gap: corners of the outer polygon against the inner polygon.
        let mut gap: f64 = 0.0;
        let mut turn = 0.0;
        for k in 0..nv {
            let km = (k + nv - 1) % nv;
            let (n1, n2) = (self.verts[km].normal, self.verts[k].normal);
            let det = n1[0] * n2[1] - n1[1] * n2[0];
            if !(det > 0.0) {
                return Err(Fallback::Uncertified);
            }
            turn += det.atan2(dot2(n1, n2));
            let o = [
                (offs[km] * n2[1] - offs[k] * n1[1]) / det,
                (n1[0] * offs[k] - n2[0] * offs[km]) / det,
            ];
            if !(o[0].is_finite() && o[1].is_finite()) {
                return Err(Fallback::Uncertified);
            }
            for j in 0..nv {
                if dot2(self.verts[j].normal, o) > offs[j] + dist {
                    return Err(Fallback::Uncertified);
                }
            }
            let d = (0..nv)
                .map(|j| seg_dist(o, self.verts[j].v, self.verts[(j + 1) % nv].v))
                .fold(f64::INFINITY, f64::min);
            gap = gap.max(d);
        }
        if (turn - 2.0 * std::f64::consts::PI).abs() > 1e-6 || !(gap <= dist) {
            return Err(Fallback::Uncertified);
        }
        Ok(gap)
    }

    fn to_world(&self, f: &Frame, height: f64) -> StaticPolygon {
        let shift = [f.r[0] * f.z, f.r[1] * f.z];
        let vertices = self
            .verts
            .iter()
            .map(|p| {
                [
                    f.c0[0] + f.ell * (p.v[0] + shift[0]),
                    f.c0[1] + f.ell * (p.v[1] + shift[1]),
                ]
            })
            .collect();
        let halfplanes = self
            .verts
            .iter()
            .zip(&self.offs)
            .map(|(p, off)| {
                // (+ 0.0 turns a -0.0 into 0.0 in the output)
                let n = [p.normal[0] + 0.0, p.normal[1] + 0.0];
                let h = f.ell * (off + dot2(n, shift)) + n[0] * f.c0[0] + n[1] * f.c0[1];
                (n, h)
            })
            .collect();
        StaticPolygon {
            status: RegionStatus::Bounded,
            dim: 2,
            vertices,
            halfplanes,
            height,
        }
    }
}

fn check_inputs(
    gravity: [f64; 3],
    height: f64,
    opts: &EquilibriumOptions,
) -> Result<(), ContactError> {
    if gravity.iter().any(|x| !x.is_finite()) {
        return Err(ContactError::NonFinite {
            what: "gravity".into(),
        });
    }
    if !height.is_finite() {
        return Err(ContactError::NonFinite {
            what: "polygon height".into(),
        });
    }
    let g = super::scaled_gravity(gravity);
    let gn = norm3(g);
    if gn == 0.0 {
        return Err(ContactError::BadGravity {
            gravity,
            reason: "the zero vector: give a non-zero gravity (e.g. [0, 0, -9.81])".into(),
        });
    }
    if g[2].abs() <= opts.tol.zero_normal * gn {
        return Err(ContactError::BadGravity {
            gravity,
            reason: "no vertical component: the static-equilibrium set is a horizontal prism without a horizontal cross-section".into(),
        });
    }
    Ok(())
}

fn stop(s: LpStop) -> Fallback {
    match s {
        LpStop::Unbounded => Fallback::Unbounded,
        LpStop::Infeasible => Fallback::Infeasible,
        LpStop::RankDeficient => Fallback::RankDeficient,
        LpStop::IterationCap | LpStop::Singular => Fallback::Numerical,
    }
}

fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm3(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn dot4(a: &[f64; M], b: &[f64; M]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}

fn dot2(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn dist2(a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [a[0] - b[0], a[1] - b[1]];
    (d[0] * d[0] + d[1] * d[1]).sqrt()
}
