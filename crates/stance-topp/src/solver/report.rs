//! [`SolutionReport`]: what a solve returns, as plain data to write out (JSON, Python dicts):
//! the status, the profile's samples, the controllable sets and the largest normalized residual
//! of the rows on the profile. The command line's `stance topp` writes exactly this.

use serde::Serialize;

use super::{Discretization, Solution, Status};
use crate::CanonicalConstraints;

/// A [`Solution`] as plain data (see [`Solution::report`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolutionReport {
    /// Optimal, or why there is no profile (serialized as its name).
    pub status: Status,
    /// The discretization that ran.
    pub discretization: Discretization,
    /// The grid point of a failure ([`Status::grid_index`]).
    pub index: Option<usize>,
    /// Duration (s); `None` without a profile or when it is infinite (stalled).
    pub duration: Option<f64>,
    /// Path speed `s'` at the grid points (with a profile).
    pub sd: Option<Vec<f64>>,
    /// Path acceleration `s''` on each interval (with a profile).
    pub sdd: Option<Vec<f64>>,
    /// Time at the grid points (with a profile whose times are all finite: JSON has no
    /// infinity).
    pub t: Option<Vec<f64>>,
    /// Controllable sets `[lo, hi]` of `x = s'^2` (`None` where empty).
    pub controllable_sets: Vec<Option<[f64; 2]>>,
    /// Largest normalized residual of the rows on the profile (with a profile).
    pub max_residual: Option<f64>,
    /// Whether an LP optimum touched the bounding box.
    pub hit_box: bool,
}

impl Solution {
    /// This solution as plain data; `k` are the constraints it solved (for the residuals).
    ///
    /// ```
    /// use stance_topp::{solve, CanonicalConstraints, Discretization, SolveOptions};
    /// // |s''| <= 1 on [0, 1], rest to rest: bang-bang, 2 s.
    /// let k = CanonicalConstraints::from_dense(
    ///     &[0.0, 0.5, 1.0],
    ///     &vec![vec![0.0, 0.0]; 3],
    ///     &vec![vec![1.0, -1.0]; 3],
    ///     &vec![vec![-1.0, -1.0]; 3],
    /// )
    /// .unwrap();
    /// let sol = solve(&k, &SolveOptions::new(Discretization::Collocation)).unwrap();
    /// let report = sol.report(&k);
    /// assert_eq!(report.status, "optimal");
    /// assert!((report.duration.unwrap() - 2.0).abs() < 1e-9);
    /// assert!(report.max_residual.unwrap() < 1e-9);
    /// ```
    pub fn report(&self, k: &CanonicalConstraints) -> SolutionReport {
        let profile = self.profile.as_ref();
        SolutionReport {
            status: self.status,
            discretization: self.discretization,
            index: self.status.grid_index(),
            duration: profile.map(|p| p.duration()).filter(|d| d.is_finite()),
            sd: profile.map(|p| p.sd()),
            sdd: profile.map(|p| p.u().to_vec()),
            t: profile
                .filter(|p| p.times().iter().all(|t| t.is_finite()))
                .map(|p| p.times().to_vec()),
            controllable_sets: self.controllable.clone(),
            max_residual: profile.map(|p| p.residuals(k, self.discretization).max_normalized()),
            hit_box: self.hit_box,
        }
    }
}
