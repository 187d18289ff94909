//! Centroidal terms along a joint path `q(s)` (docs/math.md section 6, the paper's Section V-B).
//!
//! # Math
//!
//! Along a path `q(s)` with tangent `q_s` and curvature `q_ss` (velocity-space vectors, so that
//! `v = q_s s'` and, with the free flyer's body twist held constant, `v' = q_ss s'^2 + q_s s''`):
//!
//! - CoM: `p = c(q)`, `p_s = J_com q_s`, `p_ss = J_com q_ss + (dJ_com/ds) q_s`, so that
//!   `p'' = p_s s'' + p_ss s'^2`;
//! - angular momentum about the CoM, `L = A_g,ang(q) q_s s'`:
//!   `l1 = A_g,ang q_s`, `l2 = A_g,ang q_ss + (dA_g,ang/ds) q_s`, so that `L' = l1 s'' + l2 s'^2`.
//!
//! `(dA_g/ds) q_s` is `(dA_g/dt) v` evaluated at `v = q_s` (it is quadratic in the velocity), and
//! `(dJ_com/ds) q_s` is its linear part over the mass.

use nalgebra::Vector3;

use crate::centroidal::centroidal_map_dot_v;
use crate::data::Data;
use crate::error::RobotError;
use crate::kinematics::check_velocity;
use crate::model::Model;

/// The terms of the retiming constraints (13)-(14) at one path point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathTerms {
    /// CoM `p(s)` (m).
    pub p: Vector3<f64>,
    /// `dp/ds` (m per unit of s).
    pub p_s: Vector3<f64>,
    /// `d^2p/ds^2`.
    pub p_ss: Vector3<f64>,
    /// `l1(s)`: coefficient of `s''` in `L'` (angular momentum about the CoM, kg m^2 per unit s).
    pub l1: Vector3<f64>,
    /// `l2(s)`: coefficient of `s'^2` in `L'`.
    pub l2: Vector3<f64>,
}

/// `p, p_s, p_ss, l1, l2` at a path point `(q, q_s, q_ss)`.
///
/// ```
/// use stance_robot::{path_terms, Data, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let mut q_s = vec![0.0; m.nv];
/// q_s[2] = 1.0; // the whole robot goes up along the path
/// let t = path_terms(&m, &mut d, &m.neutral(), &q_s, &vec![0.0; m.nv]).unwrap();
/// assert!((t.p_s - nalgebra::Vector3::z()).norm() < 1e-14);
/// assert!(t.p_ss.norm() < 1e-14 && t.l1.norm() < 1e-12 && t.l2.norm() < 1e-12);
/// ```
pub fn path_terms(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    q_s: &[f64],
    q_ss: &[f64],
) -> Result<PathTerms, RobotError> {
    check_velocity(model, q_ss)?;
    centroidal_map_dot_v(model, data, q, q_s)?;
    Ok(path_terms_from_data(data, q_s, q_ss))
}

/// [`path_terms`] from a workspace that already holds `A_g` and `(dA_g/dt) q_s` at `(q, q_s)`
/// (after [`crate::centroidal_map_dot_v`], or an IK step's [`crate::IkWorkspace::build`]):
/// no kinematics recomputed. `q_s` and `q_ss` must have `nv` entries.
///
/// ```
/// use stance_robot::{centroidal_map_dot_v, path_terms, path_terms_from_data, Data, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let (q, q_s, q_ss) = (m.neutral(), vec![0.1; m.nv], vec![-0.2; m.nv]);
/// centroidal_map_dot_v(&m, &mut d, &q, &q_s).unwrap();
/// let t = path_terms_from_data(&d, &q_s, &q_ss);
/// assert_eq!(t, path_terms(&m, &mut d, &q, &q_s, &q_ss).unwrap());
/// ```
pub fn path_terms_from_data(data: &Data, q_s: &[f64], q_ss: &[f64]) -> PathTerms {
    let a = &data.centroidal_map;
    let mut h_s = nalgebra::Vector6::zeros();
    let mut h_ss = data.centroidal_map_dot_v;
    for k in 0..q_s.len() {
        let col = a.column(k);
        h_s += col * q_s[k];
        h_ss += col * q_ss[k];
    }
    let m = data.mass;
    PathTerms {
        p: data.com,
        p_s: h_s.fixed_rows::<3>(0) / m,
        p_ss: h_ss.fixed_rows::<3>(0) / m,
        l1: h_s.fixed_rows::<3>(3).into(),
        l2: h_ss.fixed_rows::<3>(3).into(),
    }
}

/// [`path_terms`] at every sample of a tracked path (see [`crate::track_path`]), with one
/// workspace.
///
/// ```
/// use nalgebra::Vector3;
/// use stance_robot::{center_of_mass, path_terms_along, track_path, Data, IkOptions, Model,
///     PointReference};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let q0 = m.neutral();
/// let c0 = center_of_mass(&m, &mut Data::new(&m), &q0).unwrap();
/// let feet = [m.frame_id("r_sole").unwrap(), m.frame_id("l_sole").unwrap()];
/// let grid: Vec<f64> = (0..=10).map(|i| i as f64 / 10.0).collect();
/// let path = track_path(&m, &q0, &vec![0.0; m.nv], &feet, &grid,
///     &|s| (PointReference::segment(c0, c0 + Vector3::new(0.0, 0.0, -0.01), s), vec![]),
///     &IkOptions::default()).unwrap();
/// let terms = path_terms_along(&m, &path.samples).unwrap();
/// assert_eq!(terms.len(), grid.len());
/// assert!((terms[0].p - c0).norm() < 1e-12);
/// ```
pub fn path_terms_along(
    model: &Model,
    samples: &[crate::ik::PathSample],
) -> Result<Vec<PathTerms>, RobotError> {
    let mut data = Data::new(model);
    samples
        .iter()
        .map(|s| path_terms(model, &mut data, &s.q, &s.q_s, &s.q_ss))
        .collect()
}
