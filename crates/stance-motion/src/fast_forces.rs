//! The force check's fast path: supporting forces in the pyramids' span form, by the dense
//! active-set solver, warm-started from the previous sample.
//!
//! # Math
//!
//! The force at vertex `j` of contact `i` (contact frame) is a non-negative combination of the
//! `k` edges `e_l` of the contact's pyramid, `f_ij = sum_l lambda_ijl e_l`, so the pyramids are
//! the bounds `lambda >= 0`. With the wrench written at the centroid `c` of the contact points
//! and divided by its norm, as [`stance_contact::supporting_forces`] does,
//!
//! ```text
//! minimize    1/2 sum_ij |f_ij|^2 + eps/2 |lambda|^2
//! subject to  sum_ijl lambda_ijl (R_i e_l, (q_ij - c) x R_i e_l) = -w_GI(c) / |w_GI(c)|
//!             lambda >= 0
//! ```
//!
//! Its Hessian is block diagonal (one `k x k` block `E^T E + eps I` per vertex), its only
//! inequalities are bounds: the dense solver of the IK ([`stance_robot::ik::dense_qp`]) solves
//! it with its own KKT certificate, and consecutive samples share their active bounds. `eps`
//! ([`crate::tol::FAST_FORCES_REGULARIZATION`]) makes the Hessian definite where `k > 3` edges
//! span three directions; it moves the forces from the minimum-norm ones by a relative
//! `O(eps)`. A certified answer (bounds exact, equations within the tolerance of the slow path)
//! proves that forces exist; anything else (an infeasible sample, an iteration cap) goes to the
//! slow path, the two-phase Clarabel solve of [`stance_contact::supporting_forces`], which also
//! certifies infeasibility. The tests compare the two at every sample of the built-in motions,
//! played as retimed and faster.

use nalgebra::{DMatrix, DVector};
use stance_contact::Stance;
use stance_robot::ik::{DenseQpOptions, DenseQpStatus, DenseQpWorkspace};

/// Reusable buffers of the fast path (one per thread): the QP and the solver's working set.
#[derive(Debug, Clone, Default)]
pub struct FastForces {
    qp: DenseQpWorkspace,
    p: DMatrix<f64>,
    c: DVector<f64>,
    a: DMatrix<f64>,
    b: DVector<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// Block sizes of `P` (edges per vertex).
    blocks: Vec<usize>,
    /// KKT solves of the dense solver so far, over every call (its work).
    pub kkt_solves: usize,
}

impl FastForces {
    /// Empty buffers.
    pub fn new() -> Self {
        Self::default()
    }

    /// Each contact's wrench (contact frame: force, then moment about the frame's origin; N and
    /// N m) of supporting forces that hold `w_gi`, when the fast path certifies them; `None`
    /// otherwise ([`Self::resultants`]).
    pub fn wrenches(
        &mut self,
        stance: &Stance,
        w_gi: &[f64; 6],
        max_residual: f64,
    ) -> Option<Vec<[f64; 6]>> {
        if w_gi.iter().any(|x| !x.is_finite()) {
            return None;
        }
        let model = stance.friction_model();
        let contacts = stance.contacts();
        let edges: Vec<Vec<[f64; 3]>> =
            contacts.iter().map(|c| model.edges(c.friction())).collect();
        let points: Vec<(usize, [f64; 3])> = contacts
            .iter()
            .enumerate()
            .flat_map(|(i, c)| c.vertices_world().into_iter().map(move |q| (i, q)))
            .collect();
        let nv = points.len();
        if nv == 0 {
            return None;
        }
        let n: usize = points.iter().map(|(i, _)| edges[*i].len()).sum();
        let mut centroid = [0.0; 3];
        for (_, q) in &points {
            for k in 0..3 {
                centroid[k] += q[k] / nv as f64;
            }
        }
        let w_c = stance_contact::wrench_at(w_gi, centroid);
        let scale = w_c.iter().map(|x| x * x).sum::<f64>().sqrt();
        let scale = if scale > 0.0 { scale } else { 1.0 };
        if self.p.nrows() != n {
            self.p = DMatrix::zeros(n, n);
            self.c = DVector::zeros(n);
            self.a = DMatrix::zeros(6, n);
            self.b = DVector::zeros(6);
            self.lo = vec![0.0; n];
            self.hi = vec![f64::INFINITY; n];
            self.qp.reset();
        }
        // P is block diagonal: one block per vertex
        self.blocks.clear();
        self.blocks
            .extend(points.iter().map(|(i, _)| edges[*i].len()));
        self.qp.set_blocks(&self.blocks);
        self.p.fill(0.0);
        for (b, w) in self.b.iter_mut().zip(&w_c) {
            *b = -w / scale;
        }
        let eps = crate::tol::FAST_FORCES_REGULARIZATION;
        let mut col = 0;
        for (i, q) in &points {
            let rot = contacts[*i].rotation();
            let lever = [q[0] - centroid[0], q[1] - centroid[1], q[2] - centroid[2]];
            let e = &edges[*i];
            for (u, eu) in e.iter().enumerate() {
                for (v, ev) in e.iter().enumerate() {
                    self.p[(col + u, col + v)] = eu[0] * ev[0]
                        + eu[1] * ev[1]
                        + eu[2] * ev[2]
                        + if u == v { eps } else { 0.0 };
                }
                let g = rot * nalgebra::Vector3::new(eu[0], eu[1], eu[2]);
                let t = [
                    lever[1] * g.z - lever[2] * g.y,
                    lever[2] * g.x - lever[0] * g.z,
                    lever[0] * g.y - lever[1] * g.x,
                ];
                for r in 0..3 {
                    self.a[(r, col + u)] = g[r];
                    self.a[(3 + r, col + u)] = t[r];
                }
            }
            col += e.len();
        }
        let opts = DenseQpOptions {
            max_iterations: crate::tol::FAST_FORCES_MAX_ITERATIONS,
            ..Default::default()
        };
        let mut rep = self.qp.solve(
            &self.p, &self.c, &self.a, &self.b, &self.lo, &self.hi, &opts,
        );
        self.kkt_solves += rep.iterations;
        if rep.status != DenseQpStatus::Optimal {
            // a working set carried from the previous sample may not suit this one: once more
            // from every weight free
            self.qp.reset();
            rep = self.qp.solve(
                &self.p, &self.c, &self.a, &self.b, &self.lo, &self.hi, &opts,
            );
            self.kkt_solves += rep.iterations;
        }
        if rep.status != DenseQpStatus::Optimal {
            self.qp.reset();
            return None;
        }
        let lambda = self.qp.solution();
        // the certificate of the slow path: the wrench rows within its residual, every force in
        // its pyramid within the same (held bounds sit on 0, free ones within the solver's
        // primal tolerance)
        let mut residual = 0.0;
        for r in 0..6 {
            let v: f64 = (0..n).map(|k| self.a[(r, k)] * lambda[k]).sum::<f64>() - self.b[r];
            residual += v * v;
        }
        if residual.sqrt() > max_residual || lambda.iter().any(|x| *x < -max_residual) {
            self.qp.reset();
            return None;
        }
        let mut out = vec![[0.0; 6]; contacts.len()];
        let mut col = 0;
        let mut vertex = vec![0usize; contacts.len()];
        for (i, _) in &points {
            let v = contacts[*i].vertices_local()[vertex[*i]];
            vertex[*i] += 1;
            let mut f = [0.0; 3];
            for (u, e) in edges[*i].iter().enumerate() {
                for k in 0..3 {
                    f[k] += lambda[col + u] * e[k] * scale;
                }
            }
            // force, and its moment about the contact frame's origin (vertex at (x, y, 0))
            let w = &mut out[*i];
            for k in 0..3 {
                w[k] += f[k];
            }
            w[3] += v[1] * f[2];
            w[4] -= v[0] * f[2];
            w[5] += v[0] * f[1] - v[1] * f[0];
            col += edges[*i].len();
        }
        Some(out)
    }

    /// Each contact's resultant force (contact frame, N) of supporting forces that hold
    /// `w_gi` (the gravito-inertial wrench at the world origin), when the fast path certifies
    /// them; `None` otherwise (infeasible, or not certified: use the slow path).
    pub fn resultants(
        &mut self,
        stance: &Stance,
        w_gi: &[f64; 6],
        max_residual: f64,
    ) -> Option<Vec<[f64; 3]>> {
        self.wrenches(stance, w_gi, max_residual)
            .map(|w| w.iter().map(|x| [x[0], x[1], x[2]]).collect())
    }
}

#[cfg(test)]
mod doc_examples {
    //! The examples that were in the docs of this private module.

    #[test]
    fn wrenches_example() {
        use crate::fast_forces::FastForces;
        use stance_contact::{examples, w_gi_static};
        let scene = examples::single_support_flat();
        let stance = scene.stance().unwrap();
        let w = FastForces::new()
            .wrenches(
                &stance,
                &w_gi_static(30.0, scene.gravity, [0.0, 0.0, 0.8]),
                1e-6,
            )
            .unwrap();
        // the CoM above the contact's origin: no moment about it
        assert!(w[0][3].abs() < 1e-6 && w[0][4].abs() < 1e-6);
    }

    #[test]
    fn resultants_example() {
        use crate::fast_forces::FastForces;
        use stance_contact::{examples, w_gi_static};
        let scene = examples::single_support_flat();
        let stance = scene.stance().unwrap();
        let mut fast = FastForces::new();
        let f = fast
            .resultants(
                &stance,
                &w_gi_static(30.0, scene.gravity, [0.0, 0.0, 0.8]),
                1e-6,
            )
            .unwrap();
        assert!((f[0][2] - 30.0 * 9.81).abs() < 1e-4);
        assert!(fast
            .resultants(
                &stance,
                &w_gi_static(30.0, scene.gravity, [0.2, 0.0, 0.8]),
                1e-6
            )
            .is_none());
    }
}
