//! Forward kinematics, frame placements, frame Jacobians and classical accelerations.
//!
//! # Math
//!
//! Forward kinematics:
//! `world_from_joint[i] = world_from_joint[lambda(i)] * parent_from_joint[i] * X_J(q_i)`.
//!
//! Each velocity entry `k` of joint `i` has a motion subspace column `S_k`, a unit twist in the
//! world frame at the world origin: `(p x w, w)` for a revolute or continuous joint with world
//! axis `w` through the joint origin `p`, `(a, 0)` for a prismatic joint of world axis `a`, and
//! for the free flyer the world images of the base-frame unit twists.
//!
//! The spatial velocity of body `i` is `V_i = V_lambda(i) + sum_k S_k v_k`, and with zero joint
//! accelerations its spatial acceleration is `A_i = A_lambda(i) + V_i x (sum_k S_k v_k)` (the
//! axes move with the body).
//!
//! A frame Jacobian's column `k` is `S_k` for every velocity entry of the frame's supporting
//! joints, zero otherwise, expressed in one of three ways:
//!
//! - [`ReferenceFrame::World`]: `S_k` itself (spatial velocity at the world origin);
//! - [`ReferenceFrame::LocalWorldAligned`]: `(v_O + w x p_f, w)`, the velocity of the frame
//!   origin `p_f` and the angular velocity, world axes;
//! - [`ReferenceFrame::Local`]: the same rotated into the frame's axes.
//!
//! The classical acceleration of a frame (Pinocchio's `getFrameClassicalAcceleration` with zero
//! joint accelerations, i.e. the drift `J_dot v`) is, for the origin `p_f`:
//! `p_f_dot = v_O + w x p_f`, `p_f_ddot = a_O + alpha x p_f + w x p_f_dot`, angular `alpha`.

mod config;
mod frames;

pub use config::{check_configuration, check_velocity, integrate};
pub use frames::{frame_classical_acceleration, frame_jacobian, frame_placement, ReferenceFrame};

use nalgebra::Vector3;

use crate::data::{Data, Spatial};
use crate::error::RobotError;
use crate::model::{JointKind, Model};
use crate::spatial::{axis_cos_sin, quaternion_matrix, Pose};

/// Forward kinematics: fills `data.world_from_joint` and the world motion subspaces for the
/// configuration `q` (Pinocchio's layout, length `model.nq`).
///
/// ```
/// use stance_robot::{forward_kinematics, Data, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let mut q = m.neutral();
/// q[2] = 1.0; // lift the base by 1 m
/// forward_kinematics(&m, &mut d, &q).unwrap();
/// assert!((d.world_from_joint[1].translation.z - 1.0).abs() < 1e-15);
/// assert!(forward_kinematics(&m, &mut d, &q[1..]).is_err());
/// ```
pub fn forward_kinematics(model: &Model, data: &mut Data, q: &[f64]) -> Result<(), RobotError> {
    check_configuration(model, q)?;
    data.check(model)?;
    data.has_velocity = false;
    for i in 1..model.joints.len() {
        let j = &model.joints[i];
        let local = joint_placement(&j.kind, &j.parent_from_joint, &q[j.idx_q..]);
        let world = data.world_from_joint[j.parent].compose(&local);
        data.world_from_joint[i] = world;
        let r = &world.rotation;
        let p = &world.translation;
        let s = &mut data.s_world[j.idx_v..];
        match j.kind {
            JointKind::Universe => {}
            JointKind::FreeFlyer => {
                for k in 0..3 {
                    let e: Vector3<f64> = r.column(k).into();
                    s[k] = (e, Vector3::zeros());
                    s[3 + k] = (p.cross(&e), e);
                }
            }
            JointKind::Revolute { axis } | JointKind::Continuous { axis } => {
                let w = r * axis;
                s[0] = (p.cross(&w), w);
            }
            JointKind::Prismatic { axis } => {
                s[0] = (r * axis, Vector3::zeros());
            }
        }
    }
    Ok(())
}

/// Forward kinematics with velocities: [`forward_kinematics`], then the spatial velocity of every
/// body and its acceleration for zero joint accelerations (the drift), used by
/// [`frame_classical_acceleration`] and [`crate::centroidal_map_dot_v`].
///
/// ```
/// use stance_robot::{forward_kinematics_velocity, frame_classical_acceleration, Data, Model,
///     ReferenceFrame};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let q = m.neutral();
/// let v = vec![0.0; m.nv]; // at rest the drift is zero
/// forward_kinematics_velocity(&m, &mut d, &q, &v).unwrap();
/// let f = m.frame_id("r_sole").unwrap();
/// let (lin, ang) = frame_classical_acceleration(&m, &d, f, ReferenceFrame::Local).unwrap();
/// assert_eq!(lin.norm() + ang.norm(), 0.0);
/// ```
pub fn forward_kinematics_velocity(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    v: &[f64],
) -> Result<(), RobotError> {
    check_velocity(model, v)?;
    forward_kinematics(model, data, q)?;
    for i in 1..model.joints.len() {
        let j = &model.joints[i];
        let (nv_j, iv) = (j.dims().1, j.idx_v);
        let mut vj: Spatial = (Vector3::zeros(), Vector3::zeros());
        for k in 0..nv_j {
            let (sl, sa) = &data.s_world[iv + k];
            vj.0 += sl * v[iv + k];
            vj.1 += sa * v[iv + k];
        }
        let (vp, ap) = (data.velocity[j.parent], data.drift[j.parent]);
        let vi = (vp.0 + vj.0, vp.1 + vj.1);
        let c = motion_cross(&vi, &vj);
        data.velocity[i] = vi;
        data.drift[i] = (ap.0 + c.0, ap.1 + c.1);
    }
    data.has_velocity = true;
    Ok(())
}

/// `V1 x V2` on motions `(v, w)`.
#[inline]
pub(crate) fn motion_cross(a: &Spatial, b: &Spatial) -> Spatial {
    (a.1.cross(&b.0) + a.0.cross(&b.1), a.1.cross(&b.1))
}

/// `parent_from_joint * X_J(q)` for one joint; `q` starts at the joint's first entry. The
/// configuration has been checked (unit quaternion and (cos, sin) within tolerance).
#[inline]
fn joint_placement(kind: &JointKind, placement: &Pose, q: &[f64]) -> Pose {
    match kind {
        JointKind::Universe => *placement,
        JointKind::FreeFlyer => {
            let n = (q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6]).sqrt();
            let motion = Pose {
                rotation: quaternion_matrix(q[3] / n, q[4] / n, q[5] / n, q[6] / n),
                translation: Vector3::new(q[0], q[1], q[2]),
            };
            placement.compose(&motion)
        }
        JointKind::Revolute { axis } => {
            let (s, c) = q[0].sin_cos();
            Pose {
                rotation: placement.rotation * axis_cos_sin(axis, c, s),
                translation: placement.translation,
            }
        }
        JointKind::Continuous { axis } => {
            let n = q[0].hypot(q[1]);
            Pose {
                rotation: placement.rotation * axis_cos_sin(axis, q[0] / n, q[1] / n),
                translation: placement.translation,
            }
        }
        JointKind::Prismatic { axis } => Pose {
            rotation: placement.rotation,
            translation: placement.translation + placement.rotation * (axis * q[0]),
        },
    }
}
