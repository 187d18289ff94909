//! Independent check: the discretized retiming as ONE linear program over all states, solved by
//! clarabel (an interior-point solver, unrelated to the crate's LP kernel).
//!
//! Variables `x_0 .. x_N` and a free `u_N` (the acceleration at the end point, which collocation
//! leaves free); `u_i = (x_{i+1} - x_i) / (2 Delta_i)` is eliminated. Objective: maximize
//! `sum x_i`. The continuous time-optimal profile is the pointwise-largest admissible one; the
//! discretized problem need not have a pointwise-largest profile, and the greedy forward pass of
//! reachability analysis (each `x_{i+1}` as large as `x_i` allows) need not maximize the sum: on
//! the shared instance `ds_flat` the LP gives up a little of `x_57` to gain more of `x_58`, and
//! its duration is 1.2e-6 (relative) longer than the greedy profile's (`testdata/topp/README.md`).
//! The two agree to about 1e-6, not to rounding.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus, ZeroConeT,
};
use stance_topp::{CanonicalConstraints, Discretization};

pub enum LpOutcome {
    Optimal(Vec<f64>),
    Infeasible,
    Other(String),
}

pub fn one_shot(
    k: &CanonicalConstraints,
    disc: Discretization,
    x_start: f64,
    x_end: f64,
) -> LpOutcome {
    let mut q = vec![-1.0; k.num_points()];
    q.push(0.0);
    lp(k, disc, Some(x_start), [x_end, x_end], &q)
}

/// Minimizes `q . (x_0 .. x_N, u_N)` with an optional fixed start state and an end interval of
/// `x_N` (upper end may be infinite).
pub fn lp(
    k: &CanonicalConstraints,
    disc: Discretization,
    x_start: Option<f64>,
    x_end: [f64; 2],
    q: &[f64],
) -> LpOutcome {
    let n = k.num_points();
    let nv = n + 1; // x_0..x_N, u_N
    let s = k.grid();
    let mut eq: Vec<(Vec<f64>, f64)> = Vec::new();
    let mut ineq: Vec<(Vec<f64>, f64)> = Vec::new();
    if let Some(x0) = x_start {
        let mut e0 = vec![0.0; nv];
        e0[0] = 1.0;
        eq.push((e0, x0));
    }
    if x_end[0] == x_end[1] {
        let mut en = vec![0.0; nv];
        en[n - 1] = 1.0;
        eq.push((en, x_end[0]));
    } else {
        let mut en = vec![0.0; nv];
        en[n - 1] = -1.0;
        ineq.push((en, -x_end[0]));
        if x_end[1].is_finite() {
            let mut en = vec![0.0; nv];
            en[n - 1] = 1.0;
            ineq.push((en, x_end[1]));
        }
    }
    for i in 0..n {
        let mut row = vec![0.0; nv];
        row[i] = -1.0; // x_i >= 0
        ineq.push((row, 0.0));
    }
    for i in 0..n {
        for r in k.rows_at(i) {
            let mut row = vec![0.0; nv];
            if i + 1 < n {
                // a (x_{i+1} - x_i) / (2 D) + b x_i + c <= 0
                let w = r.a / (2.0 * (s[i + 1] - s[i]));
                row[i + 1] += w;
                row[i] += r.b - w;
            } else {
                row[n] += r.a;
                row[i] += r.b;
            }
            ineq.push((row, -r.c));
        }
        if disc == Discretization::Interpolation && i + 1 < n {
            for r in k.rows_at(i + 1) {
                // a u_i + b x_{i+1} + c <= 0
                let mut row = vec![0.0; nv];
                let w = r.a / (2.0 * (s[i + 1] - s[i]));
                row[i + 1] += w + r.b;
                row[i] -= w;
                ineq.push((row, -r.c));
            }
        }
        let [_, xh] = k.x_bounds_at(i);
        if xh.is_finite() {
            let mut row = vec![0.0; nv];
            row[i] = 1.0;
            ineq.push((row, xh));
        }
    }
    let m = eq.len() + ineq.len();
    let rows: Vec<&(Vec<f64>, f64)> = eq.iter().chain(ineq.iter()).collect();
    let mut colptr = vec![0usize];
    let mut rowval = Vec::new();
    let mut nzval = Vec::new();
    for j in 0..nv {
        for (ri, (row, _)) in rows.iter().enumerate() {
            if row[j] != 0.0 {
                rowval.push(ri);
                nzval.push(row[j]);
            }
        }
        colptr.push(rowval.len());
    }
    let a = CscMatrix::new(m, nv, colptr, rowval, nzval);
    let b: Vec<f64> = rows.iter().map(|(_, b)| *b).collect();
    let p = CscMatrix::<f64>::zeros((nv, nv));
    let cones = [ZeroConeT(eq.len()), NonnegativeConeT(ineq.len())];
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(1e-11)
        .tol_gap_rel(1e-11)
        .tol_feas(1e-11)
        .max_iter(400)
        .build()
        .unwrap();
    let mut solver = DefaultSolver::new(&p, q, &a, &b, &cones, settings).unwrap();
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {
            LpOutcome::Optimal(solver.solution.x[..n].to_vec())
        }
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
            LpOutcome::Infeasible
        }
        s => LpOutcome::Other(format!("{s:?}")),
    }
}
