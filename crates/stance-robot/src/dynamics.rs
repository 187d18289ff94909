//! Inverse dynamics: the recursive Newton-Euler algorithm (RNEA), and its coefficients along a
//! joint path.
//!
//! # Math
//!
//! The equations of motion of the tree (Featherstone, "Rigid Body Dynamics Algorithms", 2008,
//! chapter 5) are `M(q) a + C(q, v) v + g(q) = tau`, where `tau` holds the generalized forces
//! the actuators and the contacts apply: for a free-flyer base its first six entries are the
//! wrench applied to the base (force, then moment about the base origin, **in the base frame**,
//! Pinocchio's convention), which only contact forces can supply.
//!
//! The RNEA runs in the world frame, at the world origin, with the motion subspaces `S_k` of
//! [`crate::kinematics`]: forward, `V_i = V_lambda(i) + S_i v_i` and
//! `A_i = A_lambda(i) + S_i a_i + V_i x (S_i v_i)` from `A_0 = (-g, 0)` (gravity as an upward
//! acceleration of the world); each body's net force `F_i = Y_i A_i + V_i x* (Y_i V_i)` with its
//! world inertia `Y_i` ([`crate::spatial`]); backward, `F_lambda(i) += F_i` and
//! `tau_k = S_k . F_joint(k)`.
//!
//! **Along a path** `q(s)` retimed as `s(t)`, `v = q_s s'` and `a = q_s s'' + q_ss s'^2`. The
//! Coriolis term is quadratic in `v`, so with `u = s''`, `x = s'^2` (docs/math.md section 5)
//!
//! ```text
//!     tau(s) = tau_a(s) u + tau_b(s) x + tau_c(s)
//!     tau_a = M q_s,   tau_b = M q_ss + C(q, q_s) q_s,   tau_c = g(q)
//! ```
//!
//! which [`torque_path_terms`] computes with one forward kinematics and three passes: `tau_c`
//! is the RNEA at rest with gravity, `tau_a` the RNEA of `(v, a) = (0, q_s)` without gravity,
//! `tau_b` that of `(q_s, q_ss)` without gravity. These are the coefficients of the torque
//! limits `|tau_j| <= tau_max_j` as rows `a u + b x + c <= 0` of the time-optimal retiming.
//!
//! # Far from the origin
//!
//! `tau` does not depend on where the world origin is (gravity is uniform), but the products
//! at the origin lose digits with the distance. With a free-flyer base farther than
//! [`crate::tol::FAR_BASE`] it is computed with the base translation set to zero; the placements
//! left in `data` are those of `q` as given.

use nalgebra::Vector3;

use crate::data::{Data, Spatial};
use crate::error::RobotError;
use crate::kinematics::{check_velocity, forward_kinematics};
use crate::model::Model;
use crate::spatial::WorldInertia;

/// The coefficients of `tau = tau_a u + tau_b x + tau_c` along a path (module doc), each of
/// length `nv`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TorquePathTerms {
    /// `M(q) q_s`: the coefficient of `u = s''`.
    pub tau_a: Vec<f64>,
    /// `M(q) q_ss + C(q, q_s) q_s`: the coefficient of `x = s'^2`.
    pub tau_b: Vec<f64>,
    /// `g(q)`: gravity.
    pub tau_c: Vec<f64>,
}

impl TorquePathTerms {
    /// `tau_a u + tau_b x + tau_c` at entry `k`.
    ///
    /// ```
    /// let t = stance_robot::TorquePathTerms { tau_a: vec![1.0], tau_b: vec![2.0], tau_c: vec![3.0] };
    /// assert_eq!(t.at(0, 1.0, 1.0), 6.0);
    /// ```
    #[inline]
    pub fn at(&self, k: usize, u: f64, x: f64) -> f64 {
        self.tau_a[k] * u + self.tau_b[k] * x + self.tau_c[k]
    }
}

fn check_len(model: &Model, what: &'static str, x: &[f64]) -> Result<(), RobotError> {
    if x.len() != model.nv {
        return Err(RobotError::Dimension {
            what,
            expected: model.nv,
            got: x.len(),
        });
    }
    if let Some(index) = x.iter().position(|v| !v.is_finite()) {
        return Err(RobotError::NonFinite { what, index });
    }
    Ok(())
}

fn check_gravity(gravity: &[f64; 3]) -> Result<(), RobotError> {
    if let Some(index) = gravity.iter().position(|v| !v.is_finite()) {
        return Err(RobotError::NonFinite {
            what: "gravity",
            index,
        });
    }
    Ok(())
}

/// `q` with a far free-flyer base moved to the origin (module doc), or `None`.
fn near_origin(model: &Model, q: &[f64]) -> Option<Vec<f64>> {
    if !model.has_free_flyer() {
        return None;
    }
    let at = model.joints[1].idx_q;
    if q[at..at + 3]
        .iter()
        .all(|x| x.abs() <= crate::tol::FAR_BASE)
    {
        return None;
    }
    let mut q0 = q.to_vec();
    q0[at..at + 3].fill(0.0);
    Some(q0)
}

/// Forward kinematics for the dynamics: of `q`, or of `q` moved to the origin when its base is
/// far; returns whether the placements must be restored afterwards.
fn kinematics(model: &Model, data: &mut Data, q: &[f64]) -> Result<bool, RobotError> {
    forward_kinematics(model, data, q)?;
    if let Some(q0) = near_origin(model, q) {
        forward_kinematics(model, data, &q0)?;
        return Ok(true);
    }
    Ok(false)
}

/// One RNEA pass on the current kinematics of `data` (module doc): `tau` from `v` (or zero),
/// `a` (or zero) and the world acceleration `a0` of the root (`(-g, 0)` with gravity).
fn pass(
    model: &Model,
    data: &mut Data,
    v: Option<&[f64]>,
    a: Option<&[f64]>,
    a0: Vector3<f64>,
    tau: &mut [f64],
) {
    let n = model.joints.len();
    let zero: Spatial = (Vector3::zeros(), Vector3::zeros());
    for i in 1..n {
        let j = &model.joints[i];
        let (nv_j, iv) = (j.dims().1, j.idx_v);
        let mut sv = zero;
        let mut sa = zero;
        for k in 0..nv_j {
            let (sl, sw) = &data.s_world[iv + k];
            if let Some(v) = v {
                sv.0 += sl * v[iv + k];
                sv.1 += sw * v[iv + k];
            }
            if let Some(a) = a {
                sa.0 += sl * a[iv + k];
                sa.1 += sw * a[iv + k];
            }
        }
        let (vp, ap) = if j.parent == 0 {
            (zero, (-a0, Vector3::zeros()))
        } else {
            (data.velocity[j.parent], data.acceleration[j.parent])
        };
        let y: &WorldInertia = &data.body_world[i];
        if v.is_none() {
            // every body at rest: no velocity product terms (they are zero), F = Y A
            let ai = (ap.0 + sa.0, ap.1 + sa.1);
            data.velocity[i] = zero;
            data.acceleration[i] = ai;
            data.force[i] = y.momentum(&ai.0, &ai.1);
            continue;
        }
        let vi = (vp.0 + sv.0, vp.1 + sv.1);
        let c = crate::kinematics::motion_cross(&vi, &sv);
        let ai = (ap.0 + sa.0 + c.0, ap.1 + sa.1 + c.1);
        data.velocity[i] = vi;
        data.acceleration[i] = ai;
        let (fl, fa) = y.momentum(&ai.0, &ai.1);
        let (hl, ha) = y.momentum(&vi.0, &vi.1);
        // F = Y A + V x* (Y V), with V x* (f, n) = (w x f, w x n + v x f)
        data.force[i] = (fl + vi.1.cross(&hl), fa + vi.1.cross(&ha) + vi.0.cross(&hl));
    }
    for i in (1..n).rev() {
        let j = &model.joints[i];
        let (nv_j, iv) = (j.dims().1, j.idx_v);
        let (f, m) = data.force[i];
        for k in 0..nv_j {
            let (sl, sw) = &data.s_world[iv + k];
            tau[iv + k] = sl.dot(&f) + sw.dot(&m);
        }
        if j.parent != 0 {
            let p = &mut data.force[j.parent];
            p.0 += f;
            p.1 += m;
        }
    }
    // the velocities of this pass are not those of `forward_kinematics_velocity`
    data.has_velocity = false;
}

/// The bodies' world inertias of the current kinematics.
fn fill_inertias(model: &Model, data: &mut Data) {
    for i in 1..model.joints.len() {
        data.body_world[i] =
            WorldInertia::from_local(&model.inertias[i], &data.world_from_joint[i]);
    }
}

/// Inverse dynamics (Pinocchio's `rnea`): `tau = M(q) a + C(q, v) v + g(q)` with the world's
/// `gravity` (e.g. `[0, 0, -9.81]`), in `data.tau` (length `nv`; for a free-flyer base the first
/// six entries are the base wrench in the base frame, module doc).
///
/// # Errors
///
/// [`RobotError::Dimension`] or [`RobotError::NonFinite`] for vectors of the wrong size or with
/// non-finite entries; the configuration checks of [`crate::check_configuration`].
///
/// ```
/// use stance_robot::{rnea, Data, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let z = vec![0.0; m.nv];
/// rnea(&m, &mut d, &m.neutral(), &z, &z, [0.0, 0.0, -9.81]).unwrap();
/// // at rest the base must be pushed up with the robot's weight
/// assert!((d.tau[2] - m.total_mass() * 9.81).abs() < 1e-9);
/// ```
pub fn rnea(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    gravity: [f64; 3],
) -> Result<(), RobotError> {
    check_velocity(model, v)?;
    check_len(model, "joint acceleration a", a)?;
    check_gravity(&gravity)?;
    let restore = kinematics(model, data, q)?;
    fill_inertias(model, data);
    let mut tau = std::mem::take(&mut data.tau);
    pass(
        model,
        data,
        Some(v),
        Some(a),
        Vector3::from(gravity),
        &mut tau,
    );
    data.tau = tau;
    if restore {
        forward_kinematics(model, data, q)?;
    }
    Ok(())
}

/// The coefficients `tau_a`, `tau_b`, `tau_c` of the generalized forces along a path at
/// `(q, q_s, q_ss)` (module doc), in `data.torque_path`.
///
/// # Errors
///
/// As [`rnea`].
///
/// ```
/// use stance_robot::{rnea, torque_path_terms, Data, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let q = m.neutral();
/// let q_s: Vec<f64> = (0..m.nv).map(|k| 0.1 * k as f64).collect();
/// let q_ss: Vec<f64> = (0..m.nv).map(|k| 0.05 - 0.01 * k as f64).collect();
/// let g = [0.0, 0.0, -9.81];
/// torque_path_terms(&m, &mut d, &q, &q_s, &q_ss, g).unwrap();
/// let terms = d.torque_path.clone();
/// // at u = 0.7, x = 2: v = q_s sqrt(x), a = q_s u + q_ss x
/// let (u, x): (f64, f64) = (0.7, 2.0);
/// let v: Vec<f64> = q_s.iter().map(|y| y * x.sqrt()).collect();
/// let a: Vec<f64> = q_s.iter().zip(&q_ss).map(|(y, z)| y * u + z * x).collect();
/// rnea(&m, &mut d, &q, &v, &a, g).unwrap();
/// for k in 0..m.nv {
///     assert!((terms.at(k, u, x) - d.tau[k]).abs() < 1e-9);
/// }
/// ```
pub fn torque_path_terms(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    q_s: &[f64],
    q_ss: &[f64],
    gravity: [f64; 3],
) -> Result<(), RobotError> {
    path_terms(model, data, q, q_s, q_ss, None, gravity)
}

/// [`torque_path_terms`] for two path accelerations at once, `q_ss` and `q_ss_other` (the two
/// sides of a sample of a joint path whose `q_ss` is constant per step): one forward
/// kinematics, `tau_a` and `tau_c` shared, `tau_b` of `q_ss` in `data.torque_path` and that of
/// `q_ss_other` in `data.tau_b_other`.
///
/// # Errors
///
/// As [`rnea`].
///
/// ```
/// use stance_robot::{torque_path_terms, torque_path_terms_two, Data, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let q = m.neutral();
/// let q_s: Vec<f64> = (0..m.nv).map(|k| 0.1 * k as f64).collect();
/// let (a, b): (Vec<f64>, Vec<f64>) = (0..m.nv).map(|k| (0.3 - 0.01 * k as f64, 0.02 * k as f64)).unzip();
/// let g = [0.0, 0.0, -9.81];
/// torque_path_terms_two(&m, &mut d, &q, &q_s, &a, &b, g).unwrap();
/// let (first, other) = (d.torque_path.clone(), d.tau_b_other.clone());
/// torque_path_terms(&m, &mut d, &q, &q_s, &b, g).unwrap();
/// assert_eq!(other, d.torque_path.tau_b);
/// assert_eq!(first.tau_c, d.torque_path.tau_c);
/// ```
pub fn torque_path_terms_two(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    q_s: &[f64],
    q_ss: &[f64],
    q_ss_other: &[f64],
    gravity: [f64; 3],
) -> Result<(), RobotError> {
    path_terms(model, data, q, q_s, q_ss, Some(q_ss_other), gravity)
}

/// The body of [`torque_path_terms`] and [`torque_path_terms_two`]: `tau_c` (gravity), `tau_a`
/// (`q_s` as acceleration), `tau_b` (`q_s` as velocity, `q_ss` as acceleration), and with
/// `other` the second `tau_b` into `data.tau_b_other`, after one forward kinematics.
fn path_terms(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    q_s: &[f64],
    q_ss: &[f64],
    other: Option<&[f64]>,
    gravity: [f64; 3],
) -> Result<(), RobotError> {
    check_len(model, "path velocity q_s", q_s)?;
    check_len(model, "path acceleration q_ss", q_ss)?;
    if let Some(o) = other {
        check_len(model, "path acceleration q_ss", o)?;
    }
    check_gravity(&gravity)?;
    let restore = kinematics(model, data, q)?;
    fill_inertias(model, data);
    let mut t = std::mem::take(&mut data.torque_path);
    for x in [&mut t.tau_a, &mut t.tau_b, &mut t.tau_c] {
        x.resize(model.nv, 0.0);
    }
    let g = Vector3::from(gravity);
    let zero = Vector3::zeros();
    pass(model, data, None, None, g, &mut t.tau_c);
    pass(model, data, None, Some(q_s), zero, &mut t.tau_a);
    pass(model, data, Some(q_s), Some(q_ss), zero, &mut t.tau_b);
    if let Some(o) = other {
        let mut b = std::mem::take(&mut data.tau_b_other);
        b.resize(model.nv, 0.0);
        pass(model, data, Some(q_s), Some(o), zero, &mut b);
        data.tau_b_other = b;
    }
    data.torque_path = t;
    if restore {
        forward_kinematics(model, data, q)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn humanoid() -> Model {
        Model::from_urdf_str(crate::SMALL_HUMANOID_URDF, &Default::default()).unwrap()
    }

    /// `tau` is linear in `a` with the mass matrix, and the mass matrix is symmetric positive
    /// definite (`tau(a) - tau(0)` columns), and the kinetic energy's rate equals the power of
    /// the generalized forces without gravity (`v . (M a + C v) = d/dt (v M v / 2)`, checked by
    /// a finite difference along the motion).
    #[test]
    fn mass_matrix_is_symmetric_positive_definite() {
        let m = humanoid();
        let mut d = Data::new(&m);
        let mut q = m.neutral();
        for j in &m.joints {
            if let crate::JointKind::Revolute { .. } = j.kind {
                q[j.idx_q] = 0.1 * (j.idx_q as f64).sin();
            }
        }
        let nv = m.nv;
        let z = vec![0.0; nv];
        let g = [0.0; 3];
        let mut mm = nalgebra::DMatrix::zeros(nv, nv);
        for k in 0..nv {
            let mut e = z.clone();
            e[k] = 1.0;
            rnea(&m, &mut d, &q, &z, &e, g).unwrap();
            for i in 0..nv {
                mm[(i, k)] = d.tau[i];
            }
        }
        let asym = (&mm - mm.transpose()).amax();
        assert!(asym < 1e-12 * mm.amax(), "asymmetry {asym}");
        let eig = nalgebra::SymmetricEigen::new(mm.clone()).eigenvalues;
        assert!(eig.min() > 0.0, "smallest eigenvalue {}", eig.min());
    }

    /// The base entries of `tau` at rest are the weight in the base frame: with a rotated base
    /// the force rotates with it.
    #[test]
    fn gravity_wrench_at_rest() {
        let m = humanoid();
        let mut d = Data::new(&m);
        let mut q = m.neutral();
        // base rotated by 90 degrees about x: the world's z is the base's y
        let h = std::f64::consts::FRAC_1_SQRT_2;
        q[3..7].copy_from_slice(&[h, 0.0, 0.0, h]);
        let z = vec![0.0; m.nv];
        rnea(&m, &mut d, &q, &z, &z, [0.0, 0.0, -9.81]).unwrap();
        let w = m.total_mass() * 9.81;
        assert!(d.tau[0].abs() < 1e-9);
        assert!((d.tau[1] - w).abs() < 1e-9, "{}", d.tau[1]);
        assert!(d.tau[2].abs() < 1e-9);
    }

    /// Far from the origin the answer is the same as at the origin.
    #[test]
    fn far_base_gives_the_same_torques() {
        let m = humanoid();
        let mut d = Data::new(&m);
        let mut q = m.neutral();
        let v: Vec<f64> = (0..m.nv).map(|k| (k as f64 * 0.7).cos()).collect();
        let a: Vec<f64> = (0..m.nv).map(|k| (k as f64 * 0.3).sin()).collect();
        let g = [0.1, -0.2, -9.81];
        rnea(&m, &mut d, &q, &v, &a, g).unwrap();
        let near = d.tau.clone();
        q[0] = 1e7;
        q[1] = -3e6;
        rnea(&m, &mut d, &q, &v, &a, g).unwrap();
        for (x, y) in near.iter().zip(&d.tau) {
            assert!((x - y).abs() <= 1e-12 * x.abs().max(1.0), "{x} vs {y}");
        }
        // the placements in data are those of q as given
        assert!((d.world_from_joint[1].translation.x - 1e7).abs() < 1e-6);
    }

    #[test]
    fn bad_sizes_are_errors() {
        let m = humanoid();
        let mut d = Data::new(&m);
        let z = vec![0.0; m.nv];
        let q = m.neutral();
        assert!(rnea(&m, &mut d, &q, &z, &z[1..], [0.0; 3]).is_err());
        let mut bad = z.clone();
        bad[3] = f64::NAN;
        assert!(rnea(&m, &mut d, &q, &z, &bad, [0.0; 3]).is_err());
        assert!(torque_path_terms(&m, &mut d, &q, &z, &bad, [0.0; 3]).is_err());
        assert!(rnea(&m, &mut d, &q, &z, &z, [0.0, f64::INFINITY, 0.0]).is_err());
    }
}
