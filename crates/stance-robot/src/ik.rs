//! Acceleration-level inverse kinematics along a path (MATH.md section 6, the paper's Section
//! V-B): from a CoM path and free end-effector paths, with contact frames held fixed, compute the
//! joint path `q(s)` and its derivatives `q_s`, `q_ss` for [`crate::path_terms`].
//!
//! # Math
//!
//! At a path point with state `(q, q_s)` (`q_s` a velocity-space vector) the joint path
//! acceleration `x = q_ss` solves the quadratic program
//!
//! ```text
//! minimize    w_com |J_com x + Jd_com q_s - pdd_com*|^2 + sum_links w_link |J_l x + Jd_l q_s - pdd_l*|^2
//!             (+ w_link |J_l,ang x + Jd_l,ang q_s - alpha_l*|^2 for links with an orientation task)
//!             + eps |x|^2
//! subject to  J_c x = -Jd_c q_s - gamma J_c q_s                   (every contact frame, 6 rows)
//!             2 (lower - q - q_s ds) / ds^2 <= x <= 2 (upper - q - q_s ds) / ds^2   (bounded joints)
//!             -r_max <= q_s + x ds <= r_max             (revolute and prismatic joints, optional)
//! ```
//!
//! where `J` are Jacobians (the CoM Jacobian, `LocalWorldAligned` frame Jacobians), `Jd q_s`
//! their drifts for the velocity `q_s` (classical accelerations), and the desired task
//! accelerations track a reference `(p*, p*_s, p*_ss)` with the paper's gains:
//! `pdd* = p*_ss + K_d (p*_s - J q_s) + K_p (p* - p)`. The contact rows keep the contact frames'
//! velocities at zero (`gamma` damps any residual velocity). The joint bounds keep each bounded
//! joint within its limits over the next path step `ds`, and the optional rate bound `r_max`
//! ([`IkOptions::max_path_rate`]) bounds the joint rates along the path. Weights `w_com = 1`, `w_link = 0.1`,
//! gains `K_p = K_d = gamma = 10` are the paper's defaults; `eps` is
//! [`crate::tol::IK_REGULARIZATION`].
//!
//! Along a grid `s_0 < s_1 < ...` the path is integrated with constant `q_ss` on each step:
//! `q_{i+1} = q_i (+) (q_s,i ds + q_ss,i ds^2 / 2)`, `q_s,i+1 = q_s,i + q_ss,i ds`.
//!
//! The QP is solved by Clarabel (interior point). Each result reports its residuals: the largest
//! contact-equation residual and, along a path, the contact frames' drift from their initial
//! placements and the CoM tracking error.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus,
    SupportedConeT, ZeroConeT,
};
use nalgebra::{DMatrix, DVector, Matrix6xX, Vector3};

use crate::centroidal::centroidal_map_dot_v;
use crate::data::Data;
use crate::error::RobotError;
use crate::kinematics::{
    check_configuration, check_velocity, frame_classical_acceleration, frame_jacobian,
    frame_placement, integrate, ReferenceFrame,
};
use crate::model::{JointKind, Model};

/// Weights and gains of the IK (the paper's defaults). MATH.md names the two task gains
/// `K_s = K_ss = 10` without saying which multiplies which error; here they are named by role,
/// `k_p` on the position error and `k_d` on the rate error, both 10 by default, so the choice
/// does not matter at the defaults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IkOptions {
    /// Weight of the CoM task (default 1).
    pub w_com: f64,
    /// Weight of each free link task (default 0.1).
    pub w_link: f64,
    /// Position gain `K_p` of the task references (1/s^2 per unit path; default 10).
    pub k_p: f64,
    /// Velocity gain `K_d` (default 10).
    pub k_d: f64,
    /// Damping `gamma` of the contact velocities (default 10).
    pub gamma: f64,
    /// Regularization weight (default [`crate::tol::IK_REGULARIZATION`]).
    pub regularization: f64,
    /// QP solver tolerance (default [`crate::tol::IK_QP_TOL`]).
    pub qp_tol: f64,
    /// Largest joint rate along the path, `|dq_j/ds|` for every revolute and prismatic joint
    /// (rad or m per unit of `s`; default `+inf`, no bound). Enforced at the end of each step:
    /// `|q_s + q_ss ds| <= max_path_rate`.
    pub max_path_rate: f64,
}

impl Default for IkOptions {
    /// The paper's weights and gains.
    ///
    /// ```
    /// let o = stance_robot::IkOptions::default();
    /// assert_eq!((o.w_com, o.w_link, o.k_p, o.k_d, o.gamma), (1.0, 0.1, 10.0, 10.0, 10.0));
    /// ```
    fn default() -> Self {
        Self {
            w_com: 1.0,
            w_link: 0.1,
            k_p: 10.0,
            k_d: 10.0,
            gamma: 10.0,
            regularization: crate::tol::IK_REGULARIZATION,
            qp_tol: crate::tol::IK_QP_TOL,
            max_path_rate: f64::INFINITY,
        }
    }
}

/// A reference point path at one value of `s`: position, first and second derivative in `s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointReference {
    /// `p*(s)` (m).
    pub p: Vector3<f64>,
    /// `dp*/ds`.
    pub p_s: Vector3<f64>,
    /// `d^2p*/ds^2`.
    pub p_ss: Vector3<f64>,
}

impl PointReference {
    /// The straight segment from `a` (at `s = 0`) to `b` (at `s = 1`), evaluated at `s`.
    ///
    /// ```
    /// use nalgebra::Vector3;
    /// let r = stance_robot::PointReference::segment(Vector3::zeros(), Vector3::x(), 0.25);
    /// assert_eq!(r.p.x, 0.25);
    /// assert_eq!(r.p_s, Vector3::x());
    /// ```
    pub fn segment(a: Vector3<f64>, b: Vector3<f64>, s: f64) -> Self {
        Self {
            p: a + (b - a) * s,
            p_s: b - a,
            p_ss: Vector3::zeros(),
        }
    }
}

/// A free link's position task: the origin of `frame` follows `reference`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkTarget {
    /// Frame index (see [`Model::frame_id`]).
    pub frame: usize,
    /// Its reference at the current `s`.
    pub reference: PointReference,
    /// Optional orientation task for the same frame (same weight).
    pub orientation: Option<OrientationReference>,
}

/// A reference orientation path at one value of `s`: `world_from_frame*` and its angular rates
/// in world axes (`[w_s] = dR*/ds R*^T`, `w_ss = dw_s/ds`). Tracked with the same gains as
/// positions: `alpha* = w_ss + K_d (w_s - w) + K_p log(R* R^T)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrientationReference {
    /// `world_from_frame*` (a rotation matrix).
    pub rotation: nalgebra::Matrix3<f64>,
    /// Angular rate along the path (world axes, rad per unit s).
    pub w_s: Vector3<f64>,
    /// Its derivative along the path.
    pub w_ss: Vector3<f64>,
}

impl OrientationReference {
    /// Hold the orientation `rotation` (zero rates).
    ///
    /// ```
    /// let o = stance_robot::OrientationReference::hold(nalgebra::Matrix3::identity());
    /// assert_eq!(o.w_s.norm(), 0.0);
    /// ```
    pub fn hold(rotation: nalgebra::Matrix3<f64>) -> Self {
        Self {
            rotation,
            w_s: Vector3::zeros(),
            w_ss: Vector3::zeros(),
        }
    }
}

/// The outcome of an IK QP (a value, not an error).
#[derive(Debug, Clone, PartialEq)]
pub enum IkStatus {
    /// Solved to the requested tolerance.
    Solved,
    /// The contacts and joint bounds admit no acceleration (a joint limit is reached, or the
    /// contacts ask for incompatible motions).
    Infeasible,
    /// The solver stopped without an answer (its status, for diagnosis).
    Failed(String),
}

/// The QP of one IK step in dense form: minimize `x^T P x / 2 + c^T x` subject to
/// `A_eq x = b_eq` and `G x <= h`.
#[derive(Debug, Clone, PartialEq)]
pub struct IkQp {
    /// Hessian (nv x nv, symmetric positive definite).
    pub p: DMatrix<f64>,
    /// Linear term.
    pub c: DVector<f64>,
    /// Contact equations (6 per contact).
    pub a_eq: DMatrix<f64>,
    /// Their right-hand side.
    pub b_eq: DVector<f64>,
    /// Joint bounds.
    pub g: DMatrix<f64>,
    /// Their right-hand side.
    pub h: DVector<f64>,
}

/// One IK step's answer.
#[derive(Debug, Clone, PartialEq)]
pub struct IkStep {
    /// Outcome.
    pub status: IkStatus,
    /// `q_ss` (zeros unless solved).
    pub q_ss: Vec<f64>,
    /// Largest absolute residual of the contact equations `|A_eq x - b_eq|_inf`.
    pub contact_residual: f64,
    /// Largest violation of the joint bounds `max(G x - h, 0)`.
    pub bound_violation: f64,
}

fn check_options(o: &IkOptions) -> Result<(), RobotError> {
    let fields = [
        ("w_com", o.w_com),
        ("w_link", o.w_link),
        ("k_p", o.k_p),
        ("k_d", o.k_d),
        ("gamma", o.gamma),
        ("regularization", o.regularization),
        ("qp_tol", o.qp_tol),
    ];
    for (name, x) in fields {
        if !(x.is_finite() && x >= 0.0) {
            return Err(RobotError::InvalidOption {
                name,
                reason: format!("{x} must be finite and >= 0"),
            });
        }
    }
    if o.max_path_rate.is_nan() || o.max_path_rate <= 0.0 {
        return Err(RobotError::InvalidOption {
            name: "max_path_rate",
            reason: format!("{} must be > 0 (+inf for no bound)", o.max_path_rate),
        });
    }
    if o.regularization <= 0.0 || o.qp_tol <= 0.0 {
        return Err(RobotError::InvalidOption {
            name: "regularization / qp_tol",
            reason: "must be > 0".into(),
        });
    }
    Ok(())
}

/// Builds the IK QP at `(q, q_s)` (see the module doc) for a step `ds > 0`.
///
/// ```
/// use stance_robot::{ik_qp, Data, IkOptions, Model, PointReference};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let q = m.neutral();
/// let feet = [m.frame_id("r_sole").unwrap(), m.frame_id("l_sole").unwrap()];
/// let com = PointReference { p: nalgebra::Vector3::zeros(), p_s: nalgebra::Vector3::zeros(),
///                            p_ss: nalgebra::Vector3::zeros() };
/// let qp = ik_qp(&m, &mut d, &q, &vec![0.0; m.nv], &feet, &com, &[], 0.01, &IkOptions::default()).unwrap();
/// assert_eq!(qp.a_eq.nrows(), 12);
/// assert_eq!(qp.p.nrows(), m.nv);
/// ```
#[allow(clippy::too_many_arguments)]
pub fn ik_qp(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    q_s: &[f64],
    contacts: &[usize],
    com: &PointReference,
    links: &[LinkTarget],
    ds: f64,
    options: &IkOptions,
) -> Result<IkQp, RobotError> {
    check_options(options)?;
    if !(ds.is_finite() && ds > 0.0) {
        return Err(RobotError::InvalidOption {
            name: "ds",
            reason: format!("the path step {ds} must be finite and > 0"),
        });
    }
    let refs_finite = std::iter::once(com)
        .chain(links.iter().map(|l| &l.reference))
        .all(|r| {
            r.p.iter()
                .chain(r.p_s.iter())
                .chain(r.p_ss.iter())
                .all(|x| x.is_finite())
        });
    if !refs_finite {
        return Err(RobotError::InvalidOption {
            name: "reference",
            reason: "a task reference is not finite".into(),
        });
    }
    for &f in contacts.iter().chain(links.iter().map(|l| &l.frame)) {
        if f >= model.frames.len() {
            return Err(RobotError::UnknownFrame(format!("#{f}")));
        }
    }
    let nv = model.nv;
    let dh = centroidal_map_dot_v(model, data, q, q_s)?;
    let qs = DVector::from_column_slice(q_s);
    let mut p = DMatrix::identity(nv, nv) * (2.0 * options.regularization);
    let mut c = DVector::zeros(nv);
    // CoM task
    let j_com = DMatrix::from_column_slice(3, nv, data.com_jacobian.as_slice());
    let com_s = &j_com * &qs;
    let drift_com = Vector3::new(dh[0], dh[1], dh[2]) / data.mass;
    let desired = com.p_ss
        + (com.p_s - Vector3::new(com_s[0], com_s[1], com_s[2])) * options.k_d
        + (com.p - data.com) * options.k_p;
    add_task(
        &mut p,
        &mut c,
        &j_com,
        &(desired - drift_com),
        options.w_com,
    );
    // link tasks
    let mut jac = Matrix6xX::zeros(nv);
    for l in links {
        frame_jacobian(
            model,
            data,
            l.frame,
            ReferenceFrame::LocalWorldAligned,
            &mut jac,
        )?;
        let j = DMatrix::from_fn(3, nv, |r, k| jac[(r, k)]);
        let vel = &j * &qs;
        let pos = frame_placement(model, data, l.frame)?.translation;
        let (drift, _) =
            frame_classical_acceleration(model, data, l.frame, ReferenceFrame::LocalWorldAligned)?;
        let r = &l.reference;
        let desired = r.p_ss
            + (r.p_s - Vector3::new(vel[0], vel[1], vel[2])) * options.k_d
            + (r.p - pos) * options.k_p;
        add_task(&mut p, &mut c, &j, &(desired - drift), options.w_link);
        if let Some(o) = &l.orientation {
            let j_ang = DMatrix::from_fn(3, nv, |r, k| jac[(r + 3, k)]);
            let w = &j_ang * &qs;
            let w = Vector3::new(w[0], w[1], w[2]);
            let (_, alpha_drift) = frame_classical_acceleration(
                model,
                data,
                l.frame,
                ReferenceFrame::LocalWorldAligned,
            )?;
            let rotation = frame_placement(model, data, l.frame)?.rotation;
            let error = nalgebra::Rotation3::from_matrix(&(o.rotation * rotation.transpose()))
                .scaled_axis();
            let desired = o.w_ss + (o.w_s - w) * options.k_d + error * options.k_p;
            add_task(
                &mut p,
                &mut c,
                &j_ang,
                &(desired - alpha_drift),
                options.w_link,
            );
        }
    }
    // contacts
    let mut a_eq = DMatrix::zeros(6 * contacts.len(), nv);
    let mut b_eq = DVector::zeros(6 * contacts.len());
    for (i, &f) in contacts.iter().enumerate() {
        frame_jacobian(model, data, f, ReferenceFrame::LocalWorldAligned, &mut jac)?;
        let (lin, ang) =
            frame_classical_acceleration(model, data, f, ReferenceFrame::LocalWorldAligned)?;
        let vel = &jac * &qs;
        for r in 0..6 {
            for k in 0..nv {
                a_eq[(6 * i + r, k)] = jac[(r, k)];
            }
            let drift = if r < 3 { lin[r] } else { ang[r - 3] };
            b_eq[6 * i + r] = -drift - options.gamma * vel[r];
        }
    }
    // joint bounds over the next step
    let mut rows: Vec<(usize, f64, f64)> = Vec::new();
    for j in &model.joints[1..] {
        if matches!(
            j.kind,
            JointKind::Revolute { .. } | JointKind::Prismatic { .. }
        ) {
            let (qj, vj) = (q[j.idx_q], q_s[j.idx_v]);
            let scale = 2.0 / (ds * ds);
            if j.upper.is_finite() {
                rows.push((j.idx_v, 1.0, scale * (j.upper - qj - vj * ds)));
            }
            if j.lower.is_finite() {
                rows.push((j.idx_v, -1.0, -scale * (j.lower - qj - vj * ds)));
            }
            if options.max_path_rate.is_finite() {
                rows.push((j.idx_v, 1.0, (options.max_path_rate - vj) / ds));
                rows.push((j.idx_v, -1.0, (options.max_path_rate + vj) / ds));
            }
        }
    }
    let mut g = DMatrix::zeros(rows.len(), nv);
    let mut h = DVector::zeros(rows.len());
    for (r, (k, sign, bound)) in rows.into_iter().enumerate() {
        g[(r, k)] = sign;
        h[r] = bound;
    }
    Ok(IkQp {
        p,
        c,
        a_eq,
        b_eq,
        g,
        h,
    })
}

/// Adds `w |J x - r|^2` to `x^T P x / 2 + c^T x`.
fn add_task(
    p: &mut DMatrix<f64>,
    c: &mut DVector<f64>,
    j: &DMatrix<f64>,
    r: &Vector3<f64>,
    w: f64,
) {
    let jt = j.transpose();
    *p += &jt * j * (2.0 * w);
    let r = DVector::from_column_slice(r.as_slice());
    *c -= &jt * r * (2.0 * w);
}

fn csc(m: &DMatrix<f64>) -> CscMatrix<f64> {
    let mut colptr = vec![0];
    let (mut rowval, mut nzval) = (Vec::new(), Vec::new());
    for k in 0..m.ncols() {
        for r in 0..m.nrows() {
            let x = m[(r, k)];
            if x != 0.0 {
                rowval.push(r);
                nzval.push(x);
            }
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(m.nrows(), m.ncols(), colptr, rowval, nzval)
}

/// Solves an [`IkQp`] with Clarabel.
///
/// ```
/// use nalgebra::{DMatrix, DVector};
/// use stance_robot::{solve_ik_qp, IkQp, IkStatus};
/// // minimize |x - (1, 2)|^2 subject to x0 = 0, x1 <= 1
/// let qp = IkQp { p: DMatrix::identity(2, 2) * 2.0, c: DVector::from_vec(vec![-2.0, -4.0]),
///     a_eq: DMatrix::from_row_slice(1, 2, &[1.0, 0.0]), b_eq: DVector::from_vec(vec![0.0]),
///     g: DMatrix::from_row_slice(1, 2, &[0.0, 1.0]), h: DVector::from_vec(vec![1.0]) };
/// let s = solve_ik_qp(&qp, 1e-9).unwrap();
/// assert_eq!(s.status, IkStatus::Solved);
/// assert!((s.q_ss[0]).abs() < 1e-7 && (s.q_ss[1] - 1.0).abs() < 1e-7);
/// ```
pub fn solve_ik_qp(qp: &IkQp, tol: f64) -> Result<IkStep, RobotError> {
    let n = qp.p.nrows();
    let a = if qp.g.nrows() > 0 {
        let mut a = DMatrix::zeros(qp.a_eq.nrows() + qp.g.nrows(), n);
        a.rows_mut(0, qp.a_eq.nrows()).copy_from(&qp.a_eq);
        a.rows_mut(qp.a_eq.nrows(), qp.g.nrows()).copy_from(&qp.g);
        a
    } else {
        qp.a_eq.clone()
    };
    let b: Vec<f64> = qp.b_eq.iter().chain(qp.h.iter()).copied().collect();
    let mut cones: Vec<SupportedConeT<f64>> = Vec::new();
    if qp.a_eq.nrows() > 0 {
        cones.push(ZeroConeT(qp.a_eq.nrows()));
    }
    if qp.g.nrows() > 0 {
        cones.push(NonnegativeConeT(qp.g.nrows()));
    }
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_feas(tol)
        .tol_gap_abs(tol)
        .tol_gap_rel(tol)
        .build()
        .map_err(|e| RobotError::InvalidOption {
            name: "qp_tol",
            reason: e.to_string(),
        })?;
    let mut solver =
        DefaultSolver::new(&csc(&qp.p), qp.c.as_slice(), &csc(&a), &b, &cones, settings).map_err(
            |e| RobotError::InvalidOption {
                name: "IK QP",
                reason: e.to_string(),
            },
        )?;
    solver.solve();
    let status = match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => IkStatus::Solved,
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
            IkStatus::Infeasible
        }
        other => IkStatus::Failed(format!("{other:?}")),
    };
    let q_ss = if status == IkStatus::Solved {
        solver.solution.x.clone()
    } else {
        vec![0.0; n]
    };
    let x = DVector::from_column_slice(&q_ss);
    let contact_residual = (&qp.a_eq * &x - &qp.b_eq).amax();
    let bound_violation = (&qp.g * &x - &qp.h).iter().fold(0.0f64, |m, v| m.max(*v));
    Ok(IkStep {
        status,
        q_ss,
        contact_residual,
        bound_violation,
    })
}

/// One IK step: [`ik_qp`] then [`solve_ik_qp`].
///
/// ```
/// use stance_robot::{ik_step, Data, IkOptions, IkStatus, Model, PointReference};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let q = m.neutral();
/// let feet = [m.frame_id("r_sole").unwrap(), m.frame_id("l_sole").unwrap()];
/// let c0 = stance_robot::center_of_mass(&m, &mut d, &q).unwrap();
/// let com = PointReference::segment(c0, c0 + nalgebra::Vector3::new(0.0, 0.03, 0.0), 0.0);
/// let step = ik_step(&m, &mut d, &q, &vec![0.0; m.nv], &feet, &com, &[], 0.01, &IkOptions::default()).unwrap();
/// assert_eq!(step.status, IkStatus::Solved);
/// assert!(step.contact_residual < 1e-6);
/// ```
#[allow(clippy::too_many_arguments)]
pub fn ik_step(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    q_s: &[f64],
    contacts: &[usize],
    com: &PointReference,
    links: &[LinkTarget],
    ds: f64,
    options: &IkOptions,
) -> Result<IkStep, RobotError> {
    let qp = ik_qp(model, data, q, q_s, contacts, com, links, ds, options)?;
    solve_ik_qp(&qp, options.qp_tol)
}

/// One grid point of a tracked path.
#[derive(Debug, Clone, PartialEq)]
pub struct PathSample {
    /// Path parameter.
    pub s: f64,
    /// Configuration.
    pub q: Vec<f64>,
    /// `dq/ds` (velocity space).
    pub q_s: Vec<f64>,
    /// `d^2q/ds^2` (velocity space).
    pub q_ss: Vec<f64>,
}

/// A joint path from [`track_path`], with its certificates.
#[derive(Debug, Clone, PartialEq)]
pub struct IkPath {
    /// Outcome: `Solved` if every step was; otherwise the first failing step's status, and the
    /// samples up to it.
    pub status: IkStatus,
    /// The samples.
    pub samples: Vec<PathSample>,
    /// Largest contact-equation residual over the steps.
    pub max_contact_residual: f64,
    /// Largest displacement of a contact frame's origin from its initial position (m).
    pub max_contact_drift: f64,
    /// Largest rotation of a contact frame from its initial orientation (rad).
    pub max_contact_rotation: f64,
    /// Largest distance between the CoM and its reference at the samples (m).
    pub max_com_error: f64,
    /// Largest joint-bound violation of a QP solution.
    pub max_bound_violation: f64,
}

/// Tracks the references along the increasing grid `s` from `(q0, q_s0)` with the contact frames
/// held: `references(s)` gives the CoM reference and the link targets at `s`.
///
/// ```
/// use nalgebra::Vector3;
/// use stance_robot::{center_of_mass, track_path, Data, IkOptions, IkStatus, Model, PointReference};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let q0 = m.neutral();
/// let c0 = center_of_mass(&m, &mut Data::new(&m), &q0).unwrap();
/// let c1 = c0 + Vector3::new(0.0, 0.0, -0.02); // crouch by 2 cm
/// let feet = [m.frame_id("r_sole").unwrap(), m.frame_id("l_sole").unwrap()];
/// let grid: Vec<f64> = (0..=20).map(|i| i as f64 / 20.0).collect();
/// let path = track_path(&m, &q0, &vec![0.0; m.nv], &feet, &grid,
///     &|s| (PointReference::segment(c0, c1, s), vec![]), &IkOptions::default()).unwrap();
/// assert_eq!(path.status, IkStatus::Solved);
/// assert!(path.max_contact_drift < 1e-3);
/// ```
#[allow(clippy::type_complexity)]
pub fn track_path(
    model: &Model,
    q0: &[f64],
    q_s0: &[f64],
    contacts: &[usize],
    grid: &[f64],
    references: &dyn Fn(f64) -> (PointReference, Vec<LinkTarget>),
    options: &IkOptions,
) -> Result<IkPath, RobotError> {
    check_configuration(model, q0)?;
    check_velocity(model, q_s0)?;
    if grid.len() < 2
        || grid.iter().any(|s| !s.is_finite())
        || grid.windows(2).any(|w| w[1] <= w[0])
    {
        return Err(RobotError::InvalidOption {
            name: "grid",
            reason: "give at least 2 finite, strictly increasing path parameters".into(),
        });
    }
    let mut data = Data::new(model);
    crate::kinematics::forward_kinematics(model, &mut data, q0)?;
    let mut initial = Vec::with_capacity(contacts.len());
    for &f in contacts {
        initial.push(frame_placement(model, &data, f)?);
    }
    let mut out = IkPath {
        status: IkStatus::Solved,
        samples: Vec::with_capacity(grid.len()),
        max_contact_residual: 0.0,
        max_contact_drift: 0.0,
        max_contact_rotation: 0.0,
        max_com_error: 0.0,
        max_bound_violation: 0.0,
    };
    let (mut q, mut q_s) = (q0.to_vec(), q_s0.to_vec());
    for (i, &s) in grid.iter().enumerate() {
        let ds = if i + 1 < grid.len() {
            grid[i + 1] - s
        } else {
            s - grid[i - 1]
        };
        let (com_ref, links) = references(s);
        let step = ik_step(
            model, &mut data, &q, &q_s, contacts, &com_ref, &links, ds, options,
        )?;
        // certificates at this sample (data holds the kinematics of q)
        out.max_com_error = out.max_com_error.max((data.com - com_ref.p).norm());
        for (f, x0) in contacts.iter().zip(&initial) {
            let x = frame_placement(model, &data, *f)?;
            out.max_contact_drift = out
                .max_contact_drift
                .max((x.translation - x0.translation).norm());
            let r = x0.rotation.transpose() * x.rotation;
            let angle = ((r.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos();
            out.max_contact_rotation = out.max_contact_rotation.max(angle);
        }
        if step.status != IkStatus::Solved {
            out.status = step.status;
            return Ok(out);
        }
        out.max_contact_residual = out.max_contact_residual.max(step.contact_residual);
        out.max_bound_violation = out.max_bound_violation.max(step.bound_violation);
        out.samples.push(PathSample {
            s,
            q: q.clone(),
            q_s: q_s.clone(),
            q_ss: step.q_ss.clone(),
        });
        if i + 1 < grid.len() {
            let delta: Vec<f64> = q_s
                .iter()
                .zip(&step.q_ss)
                .map(|(v, a)| v * ds + 0.5 * a * ds * ds)
                .collect();
            q = integrate(model, &q, &delta)?;
            for (v, a) in q_s.iter_mut().zip(&step.q_ss) {
                *v += a * ds;
            }
        }
    }
    Ok(out)
}
