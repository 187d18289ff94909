//! Centre of mass, its Jacobian, the centroidal momentum matrix `A_g` and `dA_g/dt v`.
//!
//! # Math
//!
//! With the bodies' world inertias `Y_i` about the world origin (compact form `(m_i, h_i = m_i
//! c_i, I_O,i)`, see [`crate::spatial`]) and the composite inertias `Y^c_i = sum_{j in subtree(i)}
//! Y_j`, the momentum about the world origin of the whole robot is
//! `h_O = sum_i Y_i V_i = sum_k Y^c_{joint(k)} S_k v_k`. The centroidal momentum
//! `h_G = (m c_dot, L_G)` (linear first, angular about the CoM `c`) is the same force moved to
//! `c`: `L_G = L_O - c x h_lin`. So column `k` of `A_g` (with `h_G = A_g v`) is
//! `(h_lin, L_O - c x h_lin)` of `Y^c_{joint(k)} S_k` (Orin and Goswami's centroidal momentum
//! matrix; Pinocchio's `ccrba`). The CoM Jacobian is the linear block over the mass:
//! `J_com = A_g[0..3] / m`.
//!
//! Time variation for zero joint accelerations (Pinocchio's
//! `computeCentroidalMomentumTimeVariation` with `a = 0`): `d(Y_i V_i)/dt = Y_i A_i + V_i x* (Y_i
//! V_i)` with `A_i` the drift acceleration, and since `h_lin = m c_dot` is parallel to
//! `c_dot`, `dL_G/dt = dL_O/dt - c x dh_lin/dt`. This is `(dA_g/dt) v`.
//!
//! # Far from the origin
//!
//! `A_g`, `J_com` and `(dA_g/dt) v` do not change when the world origin moves (`h_G` is about
//! the CoM, in world-aligned axes), but `L_O - c x h_lin` cancels `|c|`-sized terms. With a
//! free-flyer base farther than [`crate::tol::FAR_BASE`] from the origin they are computed with
//! the base translation set to zero (the same robot, the origin moved to it), and the CoM moved
//! back; the world placements in `data` are those of `q` as given.

use nalgebra::{Vector3, Vector6};

use crate::data::Data;
use crate::error::RobotError;
use crate::kinematics::{forward_kinematics, forward_kinematics_velocity};
use crate::model::Model;
use crate::spatial::WorldInertia;

/// Total mass (kg) and CoM (world, m) for the configuration `q`; also stored in `data.mass` and
/// `data.com`.
///
/// ```
/// use stance_robot::{center_of_mass, Data, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let mut q = m.neutral();
/// let c0 = center_of_mass(&m, &mut d, &q).unwrap();
/// q[0] += 1.0; // moving the base by 1 m moves the CoM by 1 m
/// let c1 = center_of_mass(&m, &mut d, &q).unwrap();
/// assert!((c1 - c0 - nalgebra::Vector3::x()).norm() < 1e-14);
/// ```
pub fn center_of_mass(
    model: &Model,
    data: &mut Data,
    q: &[f64],
) -> Result<Vector3<f64>, RobotError> {
    forward_kinematics(model, data, q)?;
    let mut total = WorldInertia::zero();
    for i in 1..model.joints.len() {
        let y = WorldInertia::from_local(&model.inertias[i], &data.world_from_joint[i]);
        data.body_world[i] = y;
        total.add(&y);
    }
    data.mass = total.mass;
    data.com = total.first_moment / total.mass;
    Ok(data.com)
}

/// After forward kinematics: body and composite inertias, mass, CoM, `A_g` and `J_com`.
fn fill_centroidal(model: &Model, data: &mut Data) {
    let n = model.joints.len();
    for i in 1..n {
        let y = WorldInertia::from_local(&model.inertias[i], &data.world_from_joint[i]);
        data.body_world[i] = y;
        data.composite[i] = y;
    }
    let mut total = WorldInertia::zero();
    for i in (1..n).rev() {
        let p = model.joints[i].parent;
        let c = data.composite[i];
        if p == 0 {
            total.add(&c);
        } else {
            data.composite[p].add(&c);
        }
    }
    data.mass = total.mass;
    let com = total.first_moment / total.mass;
    data.com = com;
    for k in 0..model.nv {
        let (sl, sa) = &data.s_world[k];
        let (h_lin, l_o) = data.composite[model.dof_joint[k]].momentum(sl, sa);
        let l_g = l_o - com.cross(&h_lin);
        data.centroidal_map
            .fixed_view_mut::<3, 1>(0, k)
            .copy_from(&h_lin);
        data.centroidal_map
            .fixed_view_mut::<3, 1>(3, k)
            .copy_from(&l_g);
        data.com_jacobian
            .column_mut(k)
            .copy_from(&(h_lin / total.mass));
    }
}

/// The centroidal momentum matrix `A_g` (6 x nv, linear rows first, angular about the CoM) for
/// the configuration `q`, in `data.centroidal_map`; also fills `data.mass`, `data.com` and
/// `data.com_jacobian` (Pinocchio's `ccrba` and `jacobianCenterOfMass`).
///
/// ```
/// use stance_robot::{centroidal_map, Data, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// centroidal_map(&m, &mut d, &m.neutral()).unwrap();
/// // a base translation at 1 m/s gives linear momentum m * 1 m/s
/// assert!((d.centroidal_map[(0, 0)] - m.total_mass()).abs() < 1e-12);
/// assert!((d.com_jacobian[(0, 0)] - 1.0).abs() < 1e-14);
/// ```
pub fn centroidal_map(model: &Model, data: &mut Data, q: &[f64]) -> Result<(), RobotError> {
    forward_kinematics(model, data, q)?;
    fill_centroidal(model, data);
    if let Some((t, q0)) = far_base(model, q) {
        // The same quantities with the origin at the base; the placements stay those of `q`.
        let (placements, s_world) = (data.world_from_joint.clone(), data.s_world.clone());
        forward_kinematics(model, data, &q0)?;
        fill_centroidal(model, data);
        data.com += t;
        data.world_from_joint = placements;
        data.s_world = s_world;
    }
    Ok(())
}

/// The base translation of `q` and `q` with it zeroed, when the base is a free flyer farther
/// than [`crate::tol::FAR_BASE`] from the origin (see the module doc). `q` must have been
/// checked ([`crate::kinematics::check_configuration`]).
fn far_base(model: &Model, q: &[f64]) -> Option<(Vector3<f64>, Vec<f64>)> {
    if !model.has_free_flyer() {
        return None;
    }
    let at = model.joints[1].idx_q;
    let t = Vector3::new(q[at], q[at + 1], q[at + 2]);
    if t.amax() <= crate::tol::FAR_BASE {
        return None;
    }
    let mut q0 = q.to_vec();
    q0[at..at + 3].fill(0.0);
    Some((t, q0))
}

/// The CoM Jacobian (3 x nv) for `q`, in `data.com_jacobian` (computed with [`centroidal_map`],
/// which it also fills).
///
/// ```
/// use stance_robot::{com_jacobian, Data, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// com_jacobian(&m, &mut d, &m.neutral()).unwrap();
/// assert!((d.com_jacobian[(2, 2)] - 1.0).abs() < 1e-14);
/// ```
pub fn com_jacobian(model: &Model, data: &mut Data, q: &[f64]) -> Result<(), RobotError> {
    centroidal_map(model, data, q)
}

/// `(dA_g/dt) v` for the configuration `q` and velocity `v`, in `data.centroidal_map_dot_v`
/// (linear first, angular about the CoM); also fills everything [`centroidal_map`] fills and
/// the velocities of [`forward_kinematics_velocity`]. Returns `(dA_g/dt) v`.
///
/// ```
/// use stance_robot::{centroidal_map_dot_v, Data, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let mut v = vec![0.0; m.nv];
/// v[0] = 1.0; // pure base translation: the momentum does not change
/// let dh = centroidal_map_dot_v(&m, &mut d, &m.neutral(), &v).unwrap();
/// assert!(dh.norm() < 1e-12);
/// ```
pub fn centroidal_map_dot_v(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    v: &[f64],
) -> Result<Vector6<f64>, RobotError> {
    crate::kinematics::check_configuration(model, q)?;
    if let Some((t, q0)) = far_base(model, q) {
        // Everything centroidal with the origin at the base (module doc), then the world
        // placements and velocities of `q` as given.
        let out = centroidal_map_dot_v(model, data, &q0, v)?;
        let (a_g, j_com, com) = (
            data.centroidal_map.clone(),
            data.com_jacobian.clone(),
            data.com + t,
        );
        forward_kinematics_velocity(model, data, q, v)?;
        data.centroidal_map = a_g;
        data.com_jacobian = j_com;
        data.com = com;
        data.centroidal_map_dot_v = out;
        return Ok(out);
    }
    forward_kinematics_velocity(model, data, q, v)?;
    fill_centroidal(model, data);
    let mut dh_lin = Vector3::zeros();
    let mut dl_o = Vector3::zeros();
    for i in 1..model.joints.len() {
        let y = &data.body_world[i];
        let (vl, va) = &data.velocity[i];
        let (al, aa) = &data.drift[i];
        let (fa_l, fa_a) = y.momentum(al, aa);
        let (h_l, h_a) = y.momentum(vl, va);
        // V x* h = (w x f, w x n + v x f)
        dh_lin += fa_l + va.cross(&h_l);
        dl_o += fa_a + va.cross(&h_a) + vl.cross(&h_l);
    }
    let dl_g = dl_o - data.com.cross(&dh_lin);
    let out = Vector6::new(dh_lin.x, dh_lin.y, dh_lin.z, dl_g.x, dl_g.y, dl_g.z);
    data.centroidal_map_dot_v = out;
    Ok(out)
}
