//! Robust static equilibrium (eq. 12, sign fixed for `g` pointing down): the 3-D region `M`.

use polycone::polytope::{polyhedron_from_halfspaces, Polyhedron, RegionStatus};

use super::halfspaces::{com_halfspaces, ComHalfspaces, Tester};
use super::EquilibriumOptions;
use super::StaticEquilibrium;
use crate::{ContactError, Giwc};

/// The robust static-equilibrium region `M = {p : U_stance (g_k, p x g_k) <= 0, k = 1..K}` as
/// an explicit polyhedron (vertices, faces, irredundant half-spaces), with a fast CoM test.
#[derive(Debug, Clone, PartialEq)]
pub struct RobustRegion {
    /// The gravity-like vectors `g_k` (m/s^2).
    pub gravities: Vec<[f64; 3]>,
    /// `M` itself: status (empty / bounded / unbounded), vertices, faces (counter-clockwise
    /// from outside), and the plane `(n, d)` (`n . p <= d`, unit `n`, metres) of each face.
    pub polyhedron: Polyhedron,
    /// Irredundant half-spaces of `M` (the face planes) when `M` is a bounded solid; otherwise
    /// the irredundant rows of the K prisms.
    pub halfspaces: ComHalfspaces,
    tester: Tester,
}

impl RobustRegion {
    /// Computes `M` for the gravity-like vectors `gravities` (at least one).
    ///
    /// ```
    /// # use stance_contact::{examples, equilibrium::RobustRegion};
    /// use polycone::polytope::RegionStatus;
    /// let scene = examples::single_support_flat();
    /// let giwc = scene.stance().unwrap().u_stance(&Default::default()).unwrap();
    /// let gs = [[0.15, 0.0, -9.81], [-0.15, 0.0, -9.81], [0.0, 0.15, -9.81], [0.0, -0.15, -9.81]];
    /// let m = RobustRegion::new(&giwc, &gs, &Default::default()).unwrap();
    /// assert_eq!(m.polyhedron.status, RegionStatus::Bounded);
    /// assert!(m.contains([0.0, 0.0, 0.8]));
    /// assert!(!m.contains([0.2, 0.0, 0.8]));
    /// ```
    pub fn new(
        giwc: &Giwc,
        gravities: &[[f64; 3]],
        opts: &EquilibriumOptions,
    ) -> Result<Self, ContactError> {
        if gravities.is_empty() {
            return Err(ContactError::BadGravity {
                gravity: [0.0; 3],
                reason: "no gravity vector given: give at least one (e.g. [0, 0, -9.81])".into(),
            });
        }
        let mut all = ComHalfspaces {
            normals: vec![],
            offsets: vec![],
            infeasible: false,
        };
        // Each prism contributes only its irredundant rows (M is inside every prism, so a row
        // redundant for one prism is redundant for M): about 10x fewer planes to clip.
        for &g in gravities {
            let g = super::scaled_gravity(g);
            let gn = g.iter().map(|x| x * x).sum::<f64>().sqrt();
            if g.iter().all(|x| x.is_finite()) && g[2].abs() > opts.tol.zero_normal * gn {
                let eq = StaticEquilibrium::new(giwc, g, opts)?;
                all.extend(eq.irredundant_halfspaces().clone());
            } else {
                all.extend(com_halfspaces(
                    giwc,
                    g,
                    opts.tol.zero_normal,
                    opts.tol.face,
                )?);
            }
        }
        let polyhedron = if all.infeasible {
            Polyhedron {
                status: RegionStatus::Empty,
                dim: 0,
                vertices: vec![],
                faces: vec![],
                active: vec![],
                planes: vec![],
            }
        } else {
            polyhedron_from_halfspaces(&all.normals, &all.offsets, &opts.polytope)?
        };
        let halfspaces = if polyhedron.status == RegionStatus::Bounded && polyhedron.dim == 3 {
            ComHalfspaces {
                normals: polyhedron.planes.iter().map(|p| p.0).collect(),
                offsets: polyhedron.planes.iter().map(|p| p.1).collect(),
                infeasible: false,
            }
        } else {
            all
        };
        Ok(Self {
            gravities: gravities.to_vec(),
            tester: Tester::new(&halfspaces, opts.tol.region),
            polyhedron,
            halfspaces,
        })
    }

    /// Whether the CoM `p` (world, m) is robustly statically stable (within the region band).
    ///
    /// ```
    /// # use stance_contact::{examples, equilibrium::RobustRegion};
    /// let scene = examples::double_support_flat();
    /// let giwc = scene.stance().unwrap().u_stance(&Default::default()).unwrap();
    /// let m = RobustRegion::new(&giwc, &[[0.0, 0.0, -9.81]], &Default::default()).unwrap();
    /// assert!(m.contains([0.0, 0.0, 0.8]));
    /// ```
    #[inline]
    pub fn contains(&self, p: [f64; 3]) -> bool {
        self.tester.contains(p)
    }

    /// Tests many CoMs in parallel (rayon) into `out`; no allocation per point. Slices of
    /// different lengths are an error.
    ///
    /// ```
    /// # use stance_contact::{examples, equilibrium::RobustRegion};
    /// let scene = examples::single_support_flat();
    /// let giwc = scene.stance().unwrap().u_stance(&Default::default()).unwrap();
    /// let m = RobustRegion::new(&giwc, &[[0.1, 0.0, -9.81], [-0.1, 0.0, -9.81]], &Default::default()).unwrap();
    /// let mut out = [false; 2];
    /// m.contains_batch(&[[0.0, 0.0, 0.8], [0.0, 0.3, 0.8]], &mut out).unwrap();
    /// assert_eq!(out, [true, false]);
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

    /// Signed margin (m): for a CoM inside a bounded `M`, its distance to the boundary (the
    /// smallest distance to a face plane); outside, minus the largest plane violation (a lower
    /// bound on the distance to `M`).
    ///
    /// ```
    /// # use stance_contact::{examples, equilibrium::RobustRegion};
    /// let scene = examples::single_support_flat();
    /// let giwc = scene.stance().unwrap().u_stance(&Default::default()).unwrap();
    /// let m = RobustRegion::new(&giwc, &[[0.0, 0.0, -9.81]], &Default::default()).unwrap();
    /// assert!((m.margin([0.0, 0.0, 0.8]) - 0.065).abs() < 1e-9);
    /// ```
    pub fn margin(&self, p: [f64; 3]) -> f64 {
        -self.halfspaces.max_residual(p)
    }
}
