//! The reusable workspace of the algorithms (Pinocchio's `Data`): sized once for a model, then
//! filled in place by every call, so hot loops do not allocate.

use nalgebra::{Matrix3xX, Matrix6xX, Vector3, Vector6};

use crate::model::Model;
use crate::spatial::{Pose, WorldInertia};

/// A 6-D motion or force as `(linear, angular)`.
pub type Spatial = (Vector3<f64>, Vector3<f64>);

/// Workspace and results of the kinematic and centroidal algorithms for one [`Model`].
#[derive(Debug, Clone)]
pub struct Data {
    /// `world_from_joint[i]`: placement of joint `i`'s frame (after [`crate::forward_kinematics`]).
    pub world_from_joint: Vec<Pose>,
    /// Motion subspace of each velocity entry in the world frame, at the world origin.
    pub(crate) s_world: Vec<Spatial>,
    /// Spatial velocity of each joint's body (world frame, at the origin).
    pub(crate) velocity: Vec<Spatial>,
    /// Spatial acceleration of each joint's body for zero joint accelerations (world, at origin).
    pub(crate) drift: Vec<Spatial>,
    /// Spatial acceleration of each joint's body in the last inverse-dynamics pass (world, at
    /// the origin).
    pub(crate) acceleration: Vec<Spatial>,
    /// Net force on each joint's subtree in the last inverse-dynamics pass (world, at the
    /// origin).
    pub(crate) force: Vec<Spatial>,
    /// Generalized forces of [`crate::rnea`] (length `nv`).
    pub tau: Vec<f64>,
    /// The coefficients of [`crate::torque_path_terms`].
    pub torque_path: crate::dynamics::TorquePathTerms,
    /// The second `tau_b` of [`crate::torque_path_terms_two`].
    pub tau_b_other: Vec<f64>,
    /// Each joint's body inertia in the world (about the origin).
    pub(crate) body_world: Vec<WorldInertia>,
    /// Composite (subtree) inertias in the world (about the origin).
    pub(crate) composite: Vec<WorldInertia>,
    /// Total mass (kg), after [`crate::centroidal_map`] or [`crate::center_of_mass`].
    pub mass: f64,
    /// Centre of mass in the world (m).
    pub com: Vector3<f64>,
    /// Centroidal momentum matrix `A_g` (6 x nv; linear rows first, angular about the CoM).
    pub centroidal_map: Matrix6xX<f64>,
    /// `dA_g/dt v` (linear first, angular about the CoM), after [`crate::centroidal_map_dot_v`].
    pub centroidal_map_dot_v: Vector6<f64>,
    /// CoM Jacobian (3 x nv), after [`crate::com_jacobian`].
    pub com_jacobian: Matrix3xX<f64>,
    /// Whether `velocity`/`drift` match the last configuration.
    pub(crate) has_velocity: bool,
}

impl Data {
    /// Checks that this workspace was made for `model` (sizes match), so that no algorithm
    /// indexes out of bounds.
    ///
    /// ```
    /// use stance_robot::{Data, Model, UrdfOptions};
    /// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &UrdfOptions::default()).unwrap();
    /// let locked = UrdfOptions { locked: vec![("neck".into(), 0.0)], ..Default::default() };
    /// let m2 = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &locked).unwrap();
    /// assert!(Data::new(&m).check(&m).is_ok());
    /// assert!(Data::new(&m2).check(&m).is_err());
    /// ```
    pub fn check(&self, model: &Model) -> Result<(), crate::RobotError> {
        let n = model.joints.len();
        let ok = self.world_from_joint.len() == n
            && self.velocity.len() == n
            && self.drift.len() == n
            && self.body_world.len() == n
            && self.composite.len() == n
            && self.acceleration.len() == n
            && self.force.len() == n
            && self.tau.len() == model.nv
            && self.s_world.len() == model.nv
            && self.centroidal_map.ncols() == model.nv
            && self.com_jacobian.ncols() == model.nv;
        if ok {
            Ok(())
        } else {
            Err(crate::RobotError::Dimension {
                what: "workspace Data (made for another model: use Data::new(&model))",
                expected: model.nv,
                got: self.s_world.len(),
            })
        }
    }

    /// A workspace sized for `model`.
    ///
    /// ```
    /// use stance_robot::{Data, Model};
    /// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
    /// let d = Data::new(&m);
    /// assert_eq!(d.centroidal_map.ncols(), m.nv);
    /// ```
    pub fn new(model: &Model) -> Data {
        let n = model.joints.len();
        let zero = (Vector3::zeros(), Vector3::zeros());
        Data {
            world_from_joint: vec![Pose::identity(); n],
            s_world: vec![zero; model.nv],
            velocity: vec![zero; n],
            drift: vec![zero; n],
            acceleration: vec![zero; n],
            force: vec![zero; n],
            tau: vec![0.0; model.nv],
            tau_b_other: vec![0.0; model.nv],
            torque_path: crate::dynamics::TorquePathTerms {
                tau_a: vec![0.0; model.nv],
                tau_b: vec![0.0; model.nv],
                tau_c: vec![0.0; model.nv],
            },
            body_world: vec![WorldInertia::zero(); n],
            composite: vec![WorldInertia::zero(); n],
            mass: 0.0,
            com: Vector3::zeros(),
            centroidal_map: Matrix6xX::zeros(model.nv),
            centroidal_map_dot_v: Vector6::zeros(),
            com_jacobian: Matrix3xX::zeros(model.nv),
            has_velocity: false,
        }
    }
}
