//! The interior-point route of the IK's QP (Clarabel): the fallback of the dense solver and the
//! independent check of it in the tests.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus,
    SupportedConeT, ZeroConeT,
};
use nalgebra::{DMatrix, DVector};

use super::{IkAnswerFrom, IkQp, IkStatus, IkStep};
use crate::error::RobotError;

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
        clearance_dropped: false,
        answer_from: IkAnswerFrom::Clarabel,
    })
}
