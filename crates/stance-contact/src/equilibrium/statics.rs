//! Static equilibrium for one gravity vector: the CoM test, the polygon, the margin.

use polycone::polytope::{polygon_from_halfplanes, RegionStatus};

use super::halfspaces::{com_halfspaces, ComHalfspaces, Tester};
use super::EquilibriumOptions;
use crate::{ContactError, Giwc};

/// The static-equilibrium CoM set `{p : U_stance (g, p x g) <= 0}` of a stance for one gravity
/// vector: a prism along `g` (module doc of [`crate::equilibrium`]).
#[derive(Debug, Clone, PartialEq)]
pub struct StaticEquilibrium {
    gravity: [f64; 3],
    halfspaces: ComHalfspaces,
    tester: Tester,
    opts: EquilibriumOptions,
    /// The cross-section at height 0, computed once (reused by [`Self::polygon`]).
    section0: Option<StaticPolygon>,
    /// The rows of `halfspaces` that bound the prism (all of them when unknown).
    irredundant: ComHalfspaces,
}

/// Cross-section of the static-equilibrium prism by the horizontal plane `z = height`.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticPolygon {
    /// Empty (no static CoM), bounded, or unbounded (clipped to the far box; e.g. a
    /// non-pointed GIWC).
    pub status: RegionStatus,
    /// 2 for a proper polygon, 1 or 0 for a degenerate one.
    pub dim: usize,
    /// Vertices `[x, y]`, counter-clockwise.
    pub vertices: Vec<[f64; 2]>,
    /// Irredundant half-planes `(a, b)`, `a . (x, y) <= b`, unit `a`, one per edge.
    pub halfplanes: Vec<([f64; 2], f64)>,
    /// The height `z` of the cross-section (m).
    pub height: f64,
}

impl StaticPolygon {
    /// Signed distance (m) from `(x, y)` to the polygon boundary: positive inside (distance to
    /// the nearest edge line), negative outside (minus the distance to the polygon).
    ///
    /// ```
    /// # use stance_contact::{examples, equilibrium::StaticEquilibrium};
    /// let scene = examples::single_support_flat();
    /// let giwc = scene.stance().unwrap().u_stance(&Default::default()).unwrap();
    /// let poly = StaticEquilibrium::new(&giwc, scene.gravity, &Default::default()).unwrap()
    ///     .polygon(0.0).unwrap();
    /// assert!((poly.margin([0.0, 0.0]) - 0.065).abs() < 1e-9); // the foot's half width
    /// assert!((poly.margin([0.2, 0.0]) + 0.09).abs() < 1e-9);
    /// ```
    pub fn margin(&self, p: [f64; 2]) -> f64 {
        if self.status == RegionStatus::Empty || self.vertices.is_empty() {
            return f64::NEG_INFINITY;
        }
        let inside = self.dim == 2
            && self
                .halfplanes
                .iter()
                .all(|(a, b)| a[0] * p[0] + a[1] * p[1] <= *b);
        if inside {
            return self
                .halfplanes
                .iter()
                .map(|(a, b)| b - a[0] * p[0] - a[1] * p[1])
                .fold(f64::INFINITY, f64::min);
        }
        // Outside: distance to the nearest boundary segment (or vertex).
        let n = self.vertices.len();
        let best = (0..n)
            .map(|i| super::seg_dist(p, self.vertices[i], self.vertices[(i + 1) % n]))
            .fold(f64::INFINITY, f64::min);
        -best
    }
}

impl StaticEquilibrium {
    /// Prepares the static-equilibrium test of `giwc` under `gravity` (m/s^2, any direction).
    ///
    /// ```
    /// # use stance_contact::{examples, equilibrium::StaticEquilibrium};
    /// let scene = examples::single_support_flat();
    /// let giwc = scene.stance().unwrap().u_stance(&Default::default()).unwrap();
    /// let eq = StaticEquilibrium::new(&giwc, [0.0, 0.0, -9.81], &Default::default()).unwrap();
    /// assert!(eq.contains([0.0, 0.0, 0.8]));
    /// assert!(!eq.contains([0.2, 0.0, 0.8]));
    /// ```
    pub fn new(
        giwc: &Giwc,
        gravity: [f64; 3],
        opts: &EquilibriumOptions,
    ) -> Result<Self, ContactError> {
        let halfspaces = com_halfspaces(giwc, gravity, opts.tol.zero_normal, opts.tol.face)?;
        let mut out = Self {
            gravity,
            tester: Tester::new(&halfspaces, opts.tol.region),
            halfspaces,
            opts: *opts,
            section0: None,
            irredundant: ComHalfspaces {
                normals: vec![],
                offsets: vec![],
                infeasible: false,
            },
        };
        out.irredundant = out.halfspaces.clone();
        // Test loop on the irredundant rows only (the polygon's edges), when they are known.
        let gs = super::scaled_gravity(gravity);
        let gn = gs.iter().map(|x| x * x).sum::<f64>().sqrt();
        if gs[2].abs() > opts.tol.zero_normal * gn {
            let poly = out.section(0.0)?;
            if poly.status == RegionStatus::Bounded && poly.dim == 2 {
                let keep = out.active_rows(&poly);
                let reduced = ComHalfspaces {
                    normals: keep.iter().map(|&i| out.halfspaces.normals[i]).collect(),
                    offsets: keep.iter().map(|&i| out.halfspaces.offsets[i]).collect(),
                    infeasible: out.halfspaces.infeasible,
                };
                out.tester = Tester::new(&reduced, opts.tol.region);
                out.irredundant = reduced;
            }
            out.section0 = Some(poly);
        }
        Ok(out)
    }

    fn active_rows(&self, poly: &StaticPolygon) -> Vec<usize> {
        // Rows tight on both ends of some edge.
        let n = poly.vertices.len();
        let mut keep = Vec::new();
        for i in 0..n {
            let (s, e) = (poly.vertices[i], poly.vertices[(i + 1) % n]);
            let z = poly.height;
            let best = self
                .halfspaces
                .normals
                .iter()
                .zip(&self.halfspaces.offsets)
                .enumerate()
                .map(|(k, (a, d))| {
                    let r1 = (a[0] * s[0] + a[1] * s[1] + a[2] * z - d).abs();
                    let r2 = (a[0] * e[0] + a[1] * e[1] + a[2] * z - d).abs();
                    (k, r1.max(r2))
                })
                .min_by(|x, y| x.1.total_cmp(&y.1));
            if let Some((k, _)) = best {
                keep.push(k);
            }
        }
        keep.sort_unstable();
        keep.dedup();
        keep
    }

    /// The half-spaces `a . p <= d` of the prism (unit `a`, metres), all rows of `U_stance`.
    ///
    /// ```
    /// # use stance_contact::{examples, equilibrium::StaticEquilibrium};
    /// let scene = examples::single_support_flat();
    /// let giwc = scene.stance().unwrap().u_stance(&Default::default()).unwrap();
    /// let eq = StaticEquilibrium::new(&giwc, scene.gravity, &Default::default()).unwrap();
    /// assert!(eq.halfspaces().normals.len() <= 16);
    /// ```
    pub fn halfspaces(&self) -> &ComHalfspaces {
        &self.halfspaces
    }

    /// The half-spaces that bound the prism: the rows of the polygon's edges when the polygon
    /// is a bounded 2-D polygon (every other row is redundant, at every height, since all rows
    /// are parallel to `g`), otherwise all rows.
    ///
    /// ```
    /// # use stance_contact::{examples, equilibrium::StaticEquilibrium};
    /// let scene = examples::single_support_flat();
    /// let giwc = scene.stance().unwrap().u_stance(&Default::default()).unwrap();
    /// let eq = StaticEquilibrium::new(&giwc, scene.gravity, &Default::default()).unwrap();
    /// assert_eq!(eq.irredundant_halfspaces().normals.len(), 4); // the foot's 4 edges
    /// ```
    pub fn irredundant_halfspaces(&self) -> &ComHalfspaces {
        &self.irredundant
    }

    /// Whether the CoM `p` (world, m) is in static equilibrium (within the region band).
    ///
    /// ```
    /// # use stance_contact::{examples, equilibrium::StaticEquilibrium};
    /// let scene = examples::double_support_flat();
    /// let giwc = scene.stance().unwrap().u_stance(&Default::default()).unwrap();
    /// let eq = StaticEquilibrium::new(&giwc, scene.gravity, &Default::default()).unwrap();
    /// assert!(eq.contains([0.0, 0.0, 0.8]));
    /// ```
    #[inline]
    pub fn contains(&self, p: [f64; 3]) -> bool {
        self.tester.contains(p)
    }

    /// Tests many CoMs in parallel (rayon), writing `out[i]` for `points[i]`; no allocation per
    /// point. Slices of different lengths are an error.
    ///
    /// ```
    /// # use stance_contact::{examples, equilibrium::StaticEquilibrium};
    /// let scene = examples::single_support_flat();
    /// let giwc = scene.stance().unwrap().u_stance(&Default::default()).unwrap();
    /// let eq = StaticEquilibrium::new(&giwc, scene.gravity, &Default::default()).unwrap();
    /// let pts = [[0.0, 0.0, 0.8], [0.2, 0.0, 0.8]];
    /// let mut out = [false; 2];
    /// eq.contains_batch(&pts, &mut out).unwrap();
    /// assert_eq!(out, [true, false]);
    /// assert!(eq.contains_batch(&pts, &mut [false; 3]).is_err());
    /// ```
    pub fn contains_batch(
        &self,
        points: &[[f64; 3]],
        out: &mut [bool],
    ) -> Result<(), ContactError> {
        super::halfspaces::same_length(points.len(), out.len())?;
        self.tester.contains_batch(points, out);
        Ok(())
    }

    /// The cross-section of the static-equilibrium prism at height `z = height` (m): the
    /// static-equilibrium polygon (independent of the height for vertical gravity).
    /// Gravity without vertical component is an error (the prism is horizontal).
    ///
    /// ```
    /// # use stance_contact::{examples, equilibrium::StaticEquilibrium};
    /// let scene = examples::single_support_flat();
    /// let giwc = scene.stance().unwrap().u_stance(&Default::default()).unwrap();
    /// let poly = StaticEquilibrium::new(&giwc, scene.gravity, &Default::default()).unwrap()
    ///     .polygon(0.0).unwrap();
    /// assert_eq!(poly.vertices.len(), 4); // the foot rectangle
    /// ```
    pub fn polygon(&self, height: f64) -> Result<StaticPolygon, ContactError> {
        match &self.section0 {
            // Vertical gravity: every cross-section is the same polygon.
            Some(p) if height == 0.0 || (self.gravity[0] == 0.0 && self.gravity[1] == 0.0) => {
                Ok(StaticPolygon {
                    height,
                    ..p.clone()
                })
            }
            _ => self.section(height),
        }
    }

    fn section(&self, height: f64) -> Result<StaticPolygon, ContactError> {
        let g = super::scaled_gravity(self.gravity);
        let gn = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
        if g[2].abs() <= self.opts.tol.zero_normal * gn {
            return Err(ContactError::BadGravity {
                gravity: self.gravity,
                reason: "no vertical component: the static-equilibrium set is a horizontal prism without a horizontal cross-section".into(),
            });
        }
        if !height.is_finite() {
            return Err(ContactError::NonFinite {
                what: "polygon height".into(),
            });
        }
        let h = &self.halfspaces;
        let empty = StaticPolygon {
            status: RegionStatus::Empty,
            dim: 0,
            vertices: vec![],
            halfplanes: vec![],
            height,
        };
        if h.infeasible {
            return Ok(empty);
        }
        let a2: Vec<[f64; 2]> = h.normals.iter().map(|a| [a[0], a[1]]).collect();
        let b2: Vec<f64> = h
            .normals
            .iter()
            .zip(&h.offsets)
            .map(|(a, d)| d - a[2] * height)
            .collect();
        let poly = polygon_from_halfplanes(&a2, &b2, &self.opts.polytope)?;
        let halfplanes = if poly.status == RegionStatus::Bounded {
            poly.halfplanes()
        } else {
            Vec::new()
        };
        Ok(StaticPolygon {
            status: poly.status,
            dim: poly.dim,
            halfplanes,
            vertices: poly.vertices,
            height,
        })
    }
}
