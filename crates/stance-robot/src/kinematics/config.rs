//! Checks of configuration and velocity vectors, and Pinocchio's `integrate` (`q (+) v`).

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use crate::error::RobotError;
use crate::model::{JointKind, Model};
use crate::spatial::{exp6, quaternion_matrix};

/// Checks that `q` has `model.nq` finite entries, a unit free-flyer quaternion and unit
/// continuous-joint `(cos, sin)` pairs (within `model.tolerances`).
///
/// ```
/// use stance_robot::{check_configuration, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let mut q = m.neutral();
/// assert!(check_configuration(&m, &q).is_ok());
/// q[6] = 2.0; // qw
/// assert!(check_configuration(&m, &q).is_err());
/// ```
pub fn check_configuration(model: &Model, q: &[f64]) -> Result<(), RobotError> {
    if q.len() != model.nq {
        return Err(RobotError::Dimension {
            what: "configuration q",
            expected: model.nq,
            got: q.len(),
        });
    }
    if let Some(index) = q.iter().position(|x| !x.is_finite()) {
        return Err(RobotError::NonFinite {
            what: "configuration q",
            index,
        });
    }
    for j in &model.joints {
        let i = j.idx_q;
        match j.kind {
            JointKind::FreeFlyer => {
                let norm =
                    (q[i + 3].powi(2) + q[i + 4].powi(2) + q[i + 5].powi(2) + q[i + 6].powi(2))
                        .sqrt();
                let tol = model.tolerances.quaternion_norm;
                if (norm - 1.0).abs() > tol {
                    return Err(RobotError::NotUnit {
                        what: "free-flyer quaternion (qx, qy, qz, qw)",
                        index: i + 3,
                        norm,
                        tol,
                    });
                }
            }
            JointKind::Continuous { .. } => {
                let norm = q[i].hypot(q[i + 1]);
                let tol = model.tolerances.unit_complex_norm;
                if (norm - 1.0).abs() > tol {
                    return Err(RobotError::NotUnit {
                        what: "continuous joint (cos, sin)",
                        index: i,
                        norm,
                        tol,
                    });
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// Checks that `v` has `model.nv` finite entries.
///
/// ```
/// use stance_robot::{check_velocity, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// assert!(check_velocity(&m, &vec![0.0; m.nv]).is_ok());
/// assert!(check_velocity(&m, &vec![f64::NAN; m.nv]).is_err());
/// ```
pub fn check_velocity(model: &Model, v: &[f64]) -> Result<(), RobotError> {
    if v.len() != model.nv {
        return Err(RobotError::Dimension {
            what: "velocity v",
            expected: model.nv,
            got: v.len(),
        });
    }
    if let Some(index) = v.iter().position(|x| !x.is_finite()) {
        return Err(RobotError::NonFinite {
            what: "velocity v",
            index,
        });
    }
    Ok(())
}

/// `q (+) v`: the configuration reached from `q` after unit time at constant velocity `v`
/// (Pinocchio's `integrate`: `SE(3)` exponential of the base-frame twist for the free flyer,
/// rotation of the `(cos, sin)` pair for continuous joints, addition otherwise).
///
/// ```
/// use stance_robot::{integrate, Model};
/// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let q = m.neutral();
/// let mut v = vec![0.0; m.nv];
/// v[0] = 0.5; // base forward
/// let q1 = integrate(&m, &q, &v).unwrap();
/// assert!((q1[0] - 0.5).abs() < 1e-15);
/// ```
pub fn integrate(model: &Model, q: &[f64], v: &[f64]) -> Result<Vec<f64>, RobotError> {
    check_configuration(model, q)?;
    check_velocity(model, v)?;
    let mut out = q.to_vec();
    for j in &model.joints {
        let (iq, iv) = (j.idx_q, j.idx_v);
        match j.kind {
            JointKind::Universe => {}
            JointKind::FreeFlyer => {
                let quat = UnitQuaternion::from_quaternion(Quaternion::new(
                    q[iq + 6],
                    q[iq + 3],
                    q[iq + 4],
                    q[iq + 5],
                ));
                let r = quaternion_matrix(quat.i, quat.j, quat.k, quat.w);
                let lin = Vector3::new(v[iv], v[iv + 1], v[iv + 2]);
                let ang = Vector3::new(v[iv + 3], v[iv + 4], v[iv + 5]);
                let step = exp6(&lin, &ang);
                let t = r * step.translation + Vector3::new(q[iq], q[iq + 1], q[iq + 2]);
                let qn = quat * UnitQuaternion::from_scaled_axis(ang);
                out[iq..iq + 3].copy_from_slice(t.as_slice());
                out[iq + 3] = qn.i;
                out[iq + 4] = qn.j;
                out[iq + 5] = qn.k;
                out[iq + 6] = qn.w;
            }
            JointKind::Continuous { .. } => {
                let n = q[iq].hypot(q[iq + 1]);
                let (c, s) = (q[iq] / n, q[iq + 1] / n);
                let (sd, cd) = v[iv].sin_cos();
                out[iq] = c * cd - s * sd;
                out[iq + 1] = s * cd + c * sd;
            }
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => out[iq] += v[iv],
        }
    }
    Ok(out)
}
