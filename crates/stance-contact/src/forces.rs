//! Supporting contact forces (wrench distribution): forces at the contact vertices that realize
//! a given gravito-inertial wrench, or a certificate that none exist.
//!
//! With `f_ij` the force (contact frame of contact `i`) at vertex `q_ij` (world), the QP is
//!
//! ```text
//! minimize    1/2 sum |f_ij|^2
//! subject to  sum_ij (R_i f_ij, (q_ij - c) x R_i f_ij) = -w_GI(c)   (Newton-Euler at c)
//!             G f_ij <= 0                                     (friction pyramid, face form)
//! ```
//!
//! with `w_GI(c) = (f_GI, tau_GI - c x f_GI)` the gravito-inertial wrench moved from the world
//! origin to the centroid `c` of the contact points (the same equations, exactly). Written at
//! the world origin, a stance 1 km away would let a force error of 1 mN stand for a torque
//! error of 1 N m, and the relative tolerances below would accept a CoM a metre outside the
//! support; at `c` they mean the same thing wherever the origin is.
//!
//! solved by Clarabel (an interior-point solver) in two phases. Phase 1 is an always-feasible
//! LP: minimize `|s|_1` subject to `sum_ij (...) + s = -w_GI` and the pyramids; its optimum is
//! the L1 distance (in wrench space, relative to `|w_GI|`) from the target to the reachable
//! cone, and a positive optimum is the certificate that no forces exist (`distance` in the
//! result). Phase 2, when the distance is zero, finds the minimum-norm forces. (Asking the
//! solver to detect infeasibility of the QP directly is less reliable: interior-point methods
//! may stop with "insufficient progress" on infeasible problems.) It uses the pyramids in **face** form and the forces directly,
//! so it is independent of the span construction and of the double description: it is the
//! check of every face-form test in the tests. The problem is scaled by `|w_GI(c)|`.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};

use crate::tol::ContactTolerances;
use crate::{ContactError, Stance};

/// Outcome of [`supporting_forces`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ForcesOutcome {
    /// Forces were found (residual below `qp_max_residual`).
    Feasible,
    /// The solver certified that no forces exist.
    Infeasible,
    /// The solver stopped without a conclusion (see `solver_status`).
    Unknown,
}

/// Forces of one contact.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactForces {
    /// Contact name.
    pub contact: String,
    /// Application points (contact vertices), world coordinates (m).
    pub points: Vec<[f64; 3]>,
    /// Forces (N) in world coordinates, one per point.
    pub forces_world: Vec<[f64; 3]>,
    /// The same forces in the contact frame.
    pub forces_local: Vec<[f64; 3]>,
}

/// Result of [`supporting_forces`].
#[derive(Debug, Clone, PartialEq)]
pub struct SupportingForces {
    /// Feasible, infeasible or unknown.
    pub outcome: ForcesOutcome,
    /// Per-contact forces (meaningful when `outcome` is `Feasible`).
    pub contacts: Vec<ContactForces>,
    /// `|sum of contact wrenches + w_GI| / |w_GI|` of the returned forces, wrenches taken at
    /// the centroid of the contact points (module doc).
    pub residual: f64,
    /// Largest friction-pyramid violation `max(G f) / |w_GI|` of the returned forces (`w_GI`
    /// at the centroid of the contact points).
    pub friction_violation: f64,
    /// Phase-1 optimum: L1 distance from `-w_GI` to the wrenches the contacts can produce,
    /// relative to `|w_GI|`, at the centroid of the contact points (0 when feasible; the
    /// infeasibility certificate otherwise).
    pub distance: f64,
    /// Clarabel's status of the last phase run, for the record.
    pub solver_status: String,
}

fn csc_from_dense(rows: usize, cols: usize, a: &[f64]) -> CscMatrix<f64> {
    let mut colptr = Vec::with_capacity(cols + 1);
    let mut rowval = Vec::new();
    let mut nzval = Vec::new();
    colptr.push(0);
    for c in 0..cols {
        for r in 0..rows {
            let v = a[r * cols + c];
            if v != 0.0 {
                rowval.push(r);
                nzval.push(v);
            }
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(rows, cols, colptr, rowval, nzval)
}

/// A wrench `(f, tau)` given at the world origin, moved to the point `c`: `(f, tau - c x f)`.
///
/// ```
/// let w = stance_contact::wrench_at(&[0.0, 0.0, -10.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
/// assert_eq!(w, [0.0, 0.0, -10.0, 0.0, -10.0, 0.0]);
/// ```
pub fn wrench_at(w: &[f64; 6], c: [f64; 3]) -> [f64; 6] {
    let c_x_f = crate::cross(c, [w[0], w[1], w[2]]);
    [
        w[0],
        w[1],
        w[2],
        w[3] - c_x_f[0],
        w[4] - c_x_f[1],
        w[5] - c_x_f[2],
    ]
}

/// Finds contact forces realizing `w_gi` (gravito-inertial wrench at the world origin, paper
/// convention) with minimal sum of squared norms, or a certificate that none exist.
///
/// ```
/// use stance_contact::{examples, supporting_forces, w_gi_static, ForcesOutcome};
/// let scene = examples::single_support_flat();
/// let stance = scene.stance().unwrap();
/// let tol = Default::default();
/// let ok = supporting_forces(&stance, &w_gi_static(30.0, scene.gravity, [0.0, 0.0, 0.8]), &tol).unwrap();
/// assert_eq!(ok.outcome, ForcesOutcome::Feasible);
/// let total_fz: f64 = ok.contacts[0].forces_world.iter().map(|f| f[2]).sum();
/// assert!((total_fz - 30.0 * 9.81).abs() < 1e-4);
/// let no = supporting_forces(&stance, &w_gi_static(30.0, scene.gravity, [0.2, 0.0, 0.8]), &tol).unwrap();
/// assert_eq!(no.outcome, ForcesOutcome::Infeasible);
/// ```
pub fn supporting_forces(
    stance: &Stance,
    w_gi: &[f64; 6],
    tol: &ContactTolerances,
) -> Result<SupportingForces, ContactError> {
    if w_gi.iter().any(|x| !x.is_finite()) {
        return Err(ContactError::NonFinite {
            what: "the gravito-inertial wrench".into(),
        });
    }
    let lp = ForceProblem::new(stance, w_gi);
    let (x, status, distance, solved1) = solve_forces(&lp, tol)?;
    let (residual, friction_violation) = lp.residuals(&x);
    let outcome = if !solved1 {
        ForcesOutcome::Unknown
    } else if distance > tol.qp_max_residual {
        ForcesOutcome::Infeasible
    } else if residual <= tol.qp_max_residual && friction_violation <= tol.qp_max_residual {
        ForcesOutcome::Feasible
    } else {
        ForcesOutcome::Unknown
    };
    let contacts = per_contact(stance, &lp, &x);
    Ok(SupportingForces {
        outcome,
        contacts,
        residual,
        friction_violation,
        distance,
        solver_status: format!("{status:?}"),
    })
}

/// The force problem in the scaled variables: `A f = b` for the six wrench rows (about the
/// contact points' centroid, divided by the wrench's norm) and `G f <= 0` for the friction rows,
/// `f` the local force at every contact vertex.
struct ForceProblem {
    /// Contact index and world position of every vertex (3 variables each).
    points: Vec<(usize, [f64; 3])>,
    /// `m x n` rows, row-major: 6 wrench rows, then `nf` friction rows.
    a: Vec<f64>,
    b: Vec<f64>,
    n: usize,
    m: usize,
    nf: usize,
    /// The wrench's norm the rows were divided by.
    scale: f64,
}

impl ForceProblem {
    fn new(stance: &Stance, w_gi: &[f64; 6]) -> Self {
        let model = stance.friction_model();
        // Face rows of each contact's pyramid (k sides, plus `f_z >= 0` when mu = 0).
        let faces: Vec<Vec<[f64; 3]>> = stance
            .contacts()
            .iter()
            .map(|c| model.faces(c.friction()))
            .collect();
        // Variables: 3 per contact vertex.
        let mut points: Vec<(usize, [f64; 3])> = Vec::new();
        for (i, c) in stance.contacts().iter().enumerate() {
            for q in c.vertices_world() {
                points.push((i, q));
            }
        }
        let nv = points.len();
        let n = 3 * nv;
        // Friction rows, all vertices.
        let nf: usize = points.iter().map(|(i, _)| faces[*i].len()).sum();
        let m = 6 + nf;
        // Reference point: the centroid c of the contact points; w_GI(c) = (f, tau - c x f).
        let mut centroid = [0.0; 3];
        for (_, q) in &points {
            for k in 0..3 {
                centroid[k] += q[k] / nv as f64;
            }
        }
        let w_c = wrench_at(w_gi, centroid);
        let scale = w_c.iter().map(|x| x * x).sum::<f64>().sqrt();
        let scale = if scale > 0.0 { scale } else { 1.0 };
        let mut a = vec![0.0; m * n];
        let mut b = vec![0.0; m];
        for r in 0..6 {
            b[r] = -w_c[r] / scale;
        }
        let mut row = 6;
        for (j, (i, q)) in points.iter().enumerate() {
            let rot = stance.contacts()[*i].rotation();
            let qr =
                crate::stance::skew([q[0] - centroid[0], q[1] - centroid[1], q[2] - centroid[2]])
                    * rot;
            for r in 0..3 {
                for c in 0..3 {
                    a[r * n + 3 * j + c] = rot[(r, c)];
                    a[(3 + r) * n + 3 * j + c] = qr[(r, c)];
                }
            }
            for g in &faces[*i] {
                for c in 0..3 {
                    a[row * n + 3 * j + c] = g[c];
                }
                row += 1;
            }
        }
        ForceProblem {
            points,
            a,
            b,
            n,
            m,
            nf,
            scale,
        }
    }

    /// The wrench residual (2-norm over the six rows) and the largest friction row of `x`.
    fn residuals(&self, x: &[f64]) -> (f64, f64) {
        let (a, b, n, m) = (&self.a, &self.b, self.n, self.m);
        let mut residual = 0.0;
        for r in 0..6 {
            let v: f64 = (0..n).map(|c| a[r * n + c] * x[c]).sum::<f64>() - b[r];
            residual += v * v;
        }
        let residual = residual.sqrt();
        let friction_violation = (6..m)
            .map(|r| (0..n).map(|c| a[r * n + c] * x[c]).sum::<f64>())
            .fold(0.0, f64::max);
        (residual, friction_violation)
    }
}

/// Phase 1 (distance of the wrench to what the contacts can produce), then, when it is zero,
/// phase 2 (minimum-norm forces). Returns the forces, the solver status, the phase-1 distance,
/// and whether phase 1 solved.
fn solve_forces(
    lp: &ForceProblem,
    tol: &ContactTolerances,
) -> Result<(Vec<f64>, SolverStatus, f64, bool), ContactError> {
    let (a, b, n, m, nf) = (&lp.a, &lp.b, lp.n, lp.m, lp.nf);
    let settings = || {
        DefaultSettingsBuilder::default()
            .verbose(false)
            .tol_feas(tol.qp_feas)
            .build()
            .map_err(|e| ContactError::BadShape(format!("QP settings: {e:?}")))
    };
    // Phase 1: min 1'(s+ + s-)  s.t.  A_eq f + s+ - s- = b,  G f <= 0,  s+, s- >= 0.
    let n1 = n + 12;
    let m1 = m + 12;
    let mut a1 = vec![0.0; m1 * n1];
    for r in 0..m {
        a1[r * n1..r * n1 + n].copy_from_slice(&a[r * n..(r + 1) * n]);
    }
    for r in 0..6 {
        a1[r * n1 + n + r] = 1.0;
        a1[r * n1 + n + 6 + r] = -1.0;
    }
    for k in 0..12 {
        a1[(m + k) * n1 + n + k] = -1.0;
    }
    let mut b1 = b.clone();
    b1.resize(m1, 0.0);
    let mut q1 = vec![0.0; n1];
    for x in &mut q1[n..] {
        *x = 1.0;
    }
    let cones1 = [
        SupportedConeT::ZeroConeT(6),
        SupportedConeT::NonnegativeConeT(nf + 12),
    ];
    let mut phase1 = DefaultSolver::new(
        &CscMatrix::zeros((n1, n1)),
        &q1,
        &csc_from_dense(m1, n1, &a1),
        &b1,
        &cones1,
        settings()?,
    )
    .map_err(|e| ContactError::BadShape(format!("LP setup: {e:?}")))?;
    phase1.solve();
    let status1 = phase1.solution.status;
    let distance = phase1.solution.x[n..].iter().map(|x| x.abs()).sum::<f64>();
    let solved1 = matches!(status1, SolverStatus::Solved | SolverStatus::AlmostSolved);
    let (x, status) = if solved1 && distance > tol.qp_max_residual {
        (phase1.solution.x[..n].to_vec(), status1)
    } else if solved1 {
        // Phase 2: minimum-norm forces.
        let mut solver = DefaultSolver::new(
            &CscMatrix::identity(n),
            &vec![0.0; n],
            &csc_from_dense(m, n, a),
            b,
            &[
                SupportedConeT::ZeroConeT(6),
                SupportedConeT::NonnegativeConeT(nf),
            ],
            settings()?,
        )
        .map_err(|e| ContactError::BadShape(format!("QP setup: {e:?}")))?;
        solver.solve();
        let st = solver.solution.status;
        if matches!(st, SolverStatus::Solved | SolverStatus::AlmostSolved) {
            (solver.solution.x.clone(), st)
        } else {
            (phase1.solution.x[..n].to_vec(), status1)
        }
    } else {
        (phase1.solution.x[..n].to_vec(), status1)
    };
    Ok((x, status, distance, solved1))
}

/// The forces of `x` per contact: vertices, local and world forces (unscaled).
fn per_contact(stance: &Stance, lp: &ForceProblem, x: &[f64]) -> Vec<ContactForces> {
    let (points, scale) = (&lp.points, lp.scale);
    let mut contacts: Vec<ContactForces> = stance
        .contacts()
        .iter()
        .map(|c| ContactForces {
            contact: c.name().to_string(),
            points: vec![],
            forces_world: vec![],
            forces_local: vec![],
        })
        .collect();
    for (j, (i, qp)) in points.iter().enumerate() {
        let fl = [x[3 * j] * scale, x[3 * j + 1] * scale, x[3 * j + 2] * scale];
        let fw = stance.contacts()[*i].rotation() * nalgebra::Vector3::from(fl);
        contacts[*i].points.push(*qp);
        contacts[*i].forces_local.push(fl);
        contacts[*i].forces_world.push([fw[0], fw[1], fw[2]]);
    }
    contacts
}
