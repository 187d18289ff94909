//! A standing posture: the robot surfaces of the initial stance placed exactly on their
//! environment surfaces, the CoM at a given point, the joints as close as possible to the nominal
//! posture.
//!
//! # Math
//!
//! Gauss-Newton on the hard tasks with the posture in their null space: with the stacked
//! residual `e(q)` of the contact placements (position error and rotation vector of
//! `R* R^T`, 6 per contact) and of the CoM (3), and their Jacobian `J` (frame Jacobians in
//! world-aligned axes, the CoM Jacobian), each step is the weighted least-norm correction
//!
//! ```text
//! dq = d + W^-1 J^T (J W^-1 J^T + mu I)^-1 (-e - J d),    d = (0_base, q_nom - q)
//! ```
//!
//! (`W` weighs the base coordinates by [`crate::tol::STAND_BASE_WEIGHT`] against 1 for the
//! joints, `mu` = [`crate::tol::STAND_DAMPING`]), applied with `q <- q (+) dq` and the joints
//! clamped to their limits (a joint at a limit is held there for the next step: infinite
//! weight, no posture pull); once `|e|_inf <= `[`crate::tol::STAND_POLISH`] the posture pull
//! stops (`d = 0`: Gauss-Newton on the tasks alone, quadratic convergence from there), until
//! `|e|_inf <= `[`crate::tol::STAND_RESIDUAL`] (plus [`crate::tol::STAND_ULPS`] units in the
//! last place of the largest target coordinate: what floating point can reach far from the
//! origin). At the answer, the tasks hold and `q - q_nom` has no component left in their null
//! space: the posture is the closest to the nominal one, in `W`, among those that satisfy them.

use nalgebra::{DMatrix, DVector, Matrix6xX, Vector3};
use stance_robot::spatial::rotation_log;
use stance_robot::{
    center_of_mass, forward_kinematics, frame_jacobian, frame_placement, integrate, Data, Pose,
    ReferenceFrame,
};

use super::robot::MotionRobot;
use crate::StanceError;

/// Finds the standing posture of the module doc: `targets` are `(surface frame,
/// world_from_frame*)`, `com` the CoM target. The nominal posture is the robot's.
pub fn stand(
    robot: &MotionRobot,
    targets: &[(usize, Pose)],
    com: Vector3<f64>,
) -> Result<Vec<f64>, StanceError> {
    let m = &robot.model;
    let nv = m.nv;
    let rows = 6 * targets.len() + 3;
    let mut data = Data::new(m);
    let mut jac = Matrix6xX::zeros(nv);
    let mut j = DMatrix::zeros(rows, nv);
    let mut e = DVector::zeros(rows);
    let mut w_inv = DVector::from_element(nv, 1.0);
    for k in 0..6 {
        w_inv[k] = 1.0 / crate::tol::STAND_BASE_WEIGHT;
    }
    // start above the targets: base at the CoM target's height
    let mut q = robot.posture.clone();
    q[0] = com.x;
    q[1] = com.y;
    q[2] = com.z;
    // the residual a computation in floating point can reach where the targets are: a few
    // units in the last place of their coordinates (1.2e-10 m at 1,000 km from the origin)
    let scale = targets
        .iter()
        .map(|(_, t)| t.translation.amax())
        .fold(com.amax(), f64::max);
    let tolerance = crate::tol::STAND_RESIDUAL + crate::tol::STAND_ULPS * f64::EPSILON * scale;
    let mut residual = f64::INFINITY;
    for _ in 0..crate::tol::STAND_MAX_ITERATIONS {
        forward_kinematics(m, &mut data, &q).map_err(StanceError::Robot)?;
        for (i, (frame, target)) in targets.iter().enumerate() {
            let x = frame_placement(m, &data, *frame).map_err(StanceError::Robot)?;
            let dp = target.translation - x.translation;
            let dr = rotation_log(&(target.rotation * x.rotation.transpose()));
            for k in 0..3 {
                e[6 * i + k] = -dp[k];
                e[6 * i + 3 + k] = -dr[k];
            }
            frame_jacobian(
                m,
                &data,
                *frame,
                ReferenceFrame::LocalWorldAligned,
                &mut jac,
            )
            .map_err(StanceError::Robot)?;
            j.view_mut((6 * i, 0), (6, nv)).copy_from(&jac);
        }
        let c = center_of_mass(m, &mut data, &q).map_err(StanceError::Robot)?;
        stance_robot::com_jacobian(m, &mut data, &q).map_err(StanceError::Robot)?;
        let r0 = 6 * targets.len();
        for k in 0..3 {
            e[r0 + k] = c[k] - com[k];
        }
        j.view_mut((r0, 0), (3, nv)).copy_from(&data.com_jacobian);
        residual = e.amax();
        // posture step in the joints' coordinates (revolute and prismatic joints)
        // (a joint at a limit is held there: it takes no part in the step)
        let mut d = DVector::zeros(nv);
        let mut w_inv = w_inv.clone();
        for jt in &m.joints[2..] {
            if jt.dims() == (1, 1) {
                let x = q[jt.idx_q];
                if x <= jt.lower || x >= jt.upper {
                    w_inv[jt.idx_v] = 0.0;
                } else if residual > crate::tol::STAND_POLISH {
                    d[jt.idx_v] = robot.posture[jt.idx_q] - x;
                }
            }
        }
        let jw = DMatrix::from_fn(rows, nv, |r, k| j[(r, k)] * w_inv[k]);
        let mut s = &jw * j.transpose();
        for k in 0..rows {
            s[(k, k)] += crate::tol::STAND_DAMPING;
        }
        let rhs = -&e - &j * &d;
        let y = match s.cholesky() {
            Some(ch) => ch.solve(&rhs),
            None => break,
        };
        let dq = d + jw.transpose() * y;
        if dq.iter().any(|x| !x.is_finite()) {
            break;
        }
        if residual <= tolerance && dq.amax() <= tolerance {
            break;
        }
        // limit the step (Gauss-Newton far from the answer overshoots)
        let scale = (crate::tol::STAND_MAX_STEP / dq.amax()).min(1.0);
        q = integrate(m, &q, (dq * scale).as_slice()).map_err(StanceError::Robot)?;
        for jt in &m.joints[2..] {
            if jt.dims() == (1, 1) {
                q[jt.idx_q] = q[jt.idx_q].clamp(jt.lower, jt.upper);
            }
        }
    }
    if residual > tolerance {
        // a CoM far from every contact horizontally is the likely cause: say so
        let far = targets
            .iter()
            .map(|(_, t)| (t.translation.x - com.x).hypot(t.translation.y - com.y))
            .fold(f64::INFINITY, f64::min);
        let advice = if far > crate::tol::STAND_FAR_COM {
            format!(
                "the CoM is {far:.2} m from the nearest contact horizontally: put \
                 initial.standing.com_xy over the contacts"
            )
        } else {
            "move the contacts closer, or change com_height".to_string()
        };
        return Err(StanceError::BadMotion(format!(
            "no standing posture puts the initial contacts on their surfaces with the CoM at \
             ({:.3}, {:.3}, {:.3}) (residual {residual:.1e} m or rad after {} iterations): \
             {advice}",
            com.x,
            com.y,
            com.z,
            crate::tol::STAND_MAX_ITERATIONS
        )));
    }
    Ok(q)
}

#[cfg(test)]
mod doc_examples {
    //! The examples that were in the docs of this private module.

    #[test]
    fn stand_example() {
        use crate::{robot::MotionRobot, spec::RobotRef, stand::stand};
        use stance_robot::Pose;
        let r = MotionRobot::load(&RobotRef::Named("small-humanoid".into()), None).unwrap();
        let lf = Pose::from_xyz_rpy([0.0, 0.1, 0.0], [0.0; 3]);
        let rf = Pose::from_xyz_rpy([0.0, -0.1, 0.0], [0.0; 3]);
        let targets = [
            (r.surface("LF").unwrap().frame, lf),
            (r.surface("RF").unwrap().frame, rf),
        ];
        let q = stand(&r, &targets, nalgebra::Vector3::new(0.0, 0.0, 0.9)).unwrap();
        assert_eq!(q.len(), r.model.nq);
    }
}
