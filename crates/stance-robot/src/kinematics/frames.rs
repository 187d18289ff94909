//! Frame placements, Jacobians and classical accelerations (see the parent module for the math).

use nalgebra::{Matrix6xX, Vector3};

use crate::data::Data;
use crate::error::RobotError;
use crate::model::Model;
use crate::spatial::Pose;

/// In which frame a frame's velocity (Jacobian) or acceleration is expressed (Pinocchio's
/// `ReferenceFrame`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReferenceFrame {
    /// World axes, linear part at the world origin (spatial velocity).
    World,
    /// The frame's own axes, linear part at the frame origin (body velocity).
    Local,
    /// World axes, linear part at the frame origin.
    LocalWorldAligned,
}

fn check_frame(model: &Model, data: &Data, frame: usize) -> Result<(), RobotError> {
    data.check(model)?;
    if frame >= model.frames.len() {
        return Err(RobotError::UnknownFrame(format!("#{frame}")));
    }
    Ok(())
}

/// `world_from_frame` after [`crate::forward_kinematics`].
///
/// ```
/// use stance_robot::{forward_kinematics, frame_placement, Data, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// forward_kinematics(&m, &mut d, &m.neutral()).unwrap();
/// let sole = frame_placement(&m, &d, m.frame_id("r_sole").unwrap()).unwrap();
/// assert!(sole.translation.z < -0.5); // the soles are below the pelvis
/// ```
pub fn frame_placement(model: &Model, data: &Data, frame: usize) -> Result<Pose, RobotError> {
    check_frame(model, data, frame)?;
    let f = &model.frames[frame];
    Ok(data.world_from_joint[f.parent_joint].compose(&f.joint_from_frame))
}

/// The 6 x nv Jacobian of `frame` (linear rows first) in `reference`, written into `out`, after
/// [`crate::forward_kinematics`]. Allocation-free when `out` already has nv columns.
///
/// ```
/// use stance_robot::{forward_kinematics, frame_jacobian, Data, Model, ReferenceFrame};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// forward_kinematics(&m, &mut d, &m.neutral()).unwrap();
/// let mut j = nalgebra::Matrix6xX::zeros(m.nv);
/// frame_jacobian(&m, &d, m.frame_id("r_sole").unwrap(), ReferenceFrame::LocalWorldAligned, &mut j).unwrap();
/// // a base translation moves the sole by the same amount
/// assert!((j[(0, 0)] - 1.0).abs() < 1e-15);
/// ```
pub fn frame_jacobian(
    model: &Model,
    data: &Data,
    frame: usize,
    reference: ReferenceFrame,
    out: &mut Matrix6xX<f64>,
) -> Result<(), RobotError> {
    check_frame(model, data, frame)?;
    if out.ncols() != model.nv {
        out.resize_horizontally_mut(model.nv, 0.0);
    }
    out.fill(0.0);
    let f = &model.frames[frame];
    let placement = data.world_from_joint[f.parent_joint].compose(&f.joint_from_frame);
    let p = placement.translation;
    let rt = placement.rotation.transpose();
    let mut i = f.parent_joint;
    while i != 0 {
        let j = &model.joints[i];
        for k in j.idx_v..j.idx_v + j.dims().1 {
            let (sl, sa) = data.s_world[k];
            let (lin, ang) = match reference {
                ReferenceFrame::World => (sl, sa),
                ReferenceFrame::LocalWorldAligned => (sl + sa.cross(&p), sa),
                ReferenceFrame::Local => (rt * (sl + sa.cross(&p)), rt * sa),
            };
            out.fixed_view_mut::<3, 1>(0, k).copy_from(&lin);
            out.fixed_view_mut::<3, 1>(3, k).copy_from(&ang);
        }
        i = j.parent;
    }
    Ok(())
}

/// The classical acceleration `(linear, angular)` of `frame` for zero joint accelerations (the
/// drift `J_dot v`; Pinocchio's `getFrameClassicalAcceleration` after `forwardKinematics(q, v,
/// 0)`), after [`crate::forward_kinematics_velocity`]. For `Local` and `LocalWorldAligned` the
/// linear part is the second time derivative of the frame origin; for `World` it is Pinocchio's
/// `a_O + w x v_O` at the world origin.
///
/// ```
/// use stance_robot::{forward_kinematics_velocity, frame_classical_acceleration, Data, Model,
///     ReferenceFrame};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut d = Data::new(&m);
/// let mut v = vec![0.0; m.nv];
/// v[5] = 2.0; // base yaw rate 2 rad/s: a point at distance r has centripetal acceleration 4 r
/// forward_kinematics_velocity(&m, &mut d, &m.neutral(), &v).unwrap();
/// let f = m.frame_id("r_sole").unwrap();
/// let (a, _) = frame_classical_acceleration(&m, &d, f, ReferenceFrame::LocalWorldAligned).unwrap();
/// let p = stance_robot::frame_placement(&m, &d, f).unwrap().translation;
/// assert!((a.xy() + 4.0 * p.xy()).norm() < 1e-12);
/// ```
pub fn frame_classical_acceleration(
    model: &Model,
    data: &Data,
    frame: usize,
    reference: ReferenceFrame,
) -> Result<(Vector3<f64>, Vector3<f64>), RobotError> {
    check_frame(model, data, frame)?;
    if !data.has_velocity {
        return Err(RobotError::NoVelocity);
    }
    let f = &model.frames[frame];
    let placement = data.world_from_joint[f.parent_joint].compose(&f.joint_from_frame);
    let (v_o, w) = data.velocity[f.parent_joint];
    let (a_o, alpha) = data.drift[f.parent_joint];
    let p = placement.translation;
    Ok(match reference {
        ReferenceFrame::World => (a_o + w.cross(&v_o), alpha),
        _ => {
            let p_dot = v_o + w.cross(&p);
            let p_ddot = a_o + alpha.cross(&p) + w.cross(&p_dot);
            if reference == ReferenceFrame::Local {
                let rt = placement.rotation.transpose();
                (rt * p_ddot, rt * alpha)
            } else {
                (p_ddot, alpha)
            }
        }
    })
}
