//! The immutable robot description: a kinematic tree of joints with link inertias and frames.
//!
//! # Math
//!
//! Joint `i` (index 0 is the universe) has a parent `lambda(i) < i` and a fixed placement
//! `parent_from_joint` of its frame in its parent joint's frame; its configuration `q_i` moves
//! it by the joint motion `X_J(q_i)`, so that
//! `world_from_joint[i] = world_from_joint[lambda(i)] * parent_from_joint[i] * X_J(q_i)`.
//! The link rigidly attached to joint `i` (the URDF child link and everything welded to it by
//! fixed or locked joints) has the inertia `inertias[i]`, expressed in the joint frame. Frames
//! (`frames`) are placements `joint_from_frame` on a parent joint: one per URDF link (`Body`) and
//! per URDF joint (`Joint`, or `FixedJoint` for fixed and locked joints), as in Pinocchio.
//!
//! Joint order is Pinocchio's: depth first from the root link, the children of each link visited
//! in the byte order of their joint names (the order in which the URDF parser Pinocchio uses
//! stores them). Configuration and velocity layouts follow Pinocchio: a free flyer takes
//! `q = (x, y, z, qx, qy, qz, qw)` and `v = (linear, angular)` in the base frame; a continuous
//! joint takes `q = (cos theta, sin theta)` and one velocity; revolute and prismatic joints take
//! one of each.

mod geometry;
mod urdf;

pub use geometry::{LinkGeometry, LinkShape, RobotGeometry};

use nalgebra::Vector3;

use crate::spatial::{Inertia, Pose};
use crate::tol::Tolerances;

/// How a joint moves its frame relative to its parent placement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointKind {
    /// The universe (index 0): no degrees of freedom.
    Universe,
    /// Free-flyer base: `q = (x, y, z, qx, qy, qz, qw)`, `v = (linear, angular)` in the base frame.
    FreeFlyer,
    /// Revolute about a unit axis (joint frame), `q = angle` (rad).
    Revolute {
        /// Unit axis in the joint frame.
        axis: Vector3<f64>,
    },
    /// Continuous (unbounded revolute) about a unit axis: `q = (cos, sin)` of the angle, one
    /// velocity (Pinocchio's `RevoluteUnbounded`).
    Continuous {
        /// Unit axis in the joint frame.
        axis: Vector3<f64>,
    },
    /// Prismatic along a unit axis, `q = displacement` (m).
    Prismatic {
        /// Unit axis in the joint frame.
        axis: Vector3<f64>,
    },
}

impl JointKind {
    /// `(nq, nv)` of this joint kind.
    ///
    /// ```
    /// use stance_robot::JointKind;
    /// assert_eq!(JointKind::FreeFlyer.dims(), (7, 6));
    /// assert_eq!(JointKind::Continuous { axis: nalgebra::Vector3::z() }.dims(), (2, 1));
    /// ```
    pub fn dims(&self) -> (usize, usize) {
        match self {
            JointKind::Universe => (0, 0),
            JointKind::FreeFlyer => (7, 6),
            JointKind::Continuous { .. } => (2, 1),
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => (1, 1),
        }
    }
}

/// One joint of the tree.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// The URDF joint name (`root_joint` for the free flyer, `universe` for index 0).
    pub name: String,
    /// How it moves.
    pub kind: JointKind,
    /// Parent joint index (0 for joints attached to the universe; 0 for the universe itself).
    pub parent: usize,
    /// Placement of this joint's frame in the parent joint's frame at `q_i = 0`.
    pub parent_from_joint: Pose,
    /// First index in `q`.
    pub idx_q: usize,
    /// First index in `v`.
    pub idx_v: usize,
    /// Lower position limit from the URDF (rad or m; `-inf` when none).
    pub lower: f64,
    /// Upper position limit from the URDF (rad or m; `+inf` when none).
    pub upper: f64,
    /// Velocity limit from the URDF (rad/s or m/s; `+inf` when none).
    pub velocity_limit: f64,
    /// Effort limit from the URDF (N m or N; `+inf` when none).
    pub effort_limit: f64,
}

impl Joint {
    /// `(nq, nv)`.
    ///
    /// ```
    /// let m = stance_robot::Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF,
    ///     &Default::default()).unwrap();
    /// assert_eq!(m.joints[1].dims(), (7, 6));
    /// ```
    pub fn dims(&self) -> (usize, usize) {
        self.kind.dims()
    }
}

/// What a frame stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameKind {
    /// A movable joint's frame.
    Joint,
    /// A fixed (or locked) URDF joint's frame.
    FixedJoint,
    /// A URDF link's frame.
    Body,
    /// A frame added by the user ([`Model::add_frame`]), e.g. a contact surface on a link
    /// (Pinocchio's operational frame).
    Operational,
}

/// A named frame rigidly attached to a joint.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// The URDF link or joint name.
    pub name: String,
    /// What it stands for.
    pub kind: FrameKind,
    /// The joint it moves with.
    pub parent_joint: usize,
    /// Its placement in that joint's frame.
    pub joint_from_frame: Pose,
}

/// How the root link is attached to the world.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RootJoint {
    /// A free-flyer joint named `root_joint` (Pinocchio's `JointModelFreeFlyer`).
    #[default]
    FreeFlyer,
    /// The root link is fixed to the world.
    Fixed,
}

/// Options of [`Model::from_urdf_str`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct UrdfOptions {
    /// Root attachment (default: free flyer).
    pub root: RootJoint,
    /// Joints to lock, by URDF name, at the given position (rad or m; for continuous joints the
    /// angle). Locked joints become fixed joints: removed from `q` and `v`, their child link's
    /// inertia merged into the parent, their frames kept (as Pinocchio's `buildReducedModel`).
    pub locked: Vec<(String, f64)>,
    /// Numerical thresholds.
    pub tolerances: Tolerances,
}

/// The robot model: immutable after construction. Pair it with a [`crate::Data`] workspace.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    /// The robot name from the URDF.
    pub name: String,
    /// Joints, index 0 the universe, parents before children (Pinocchio's order).
    pub joints: Vec<Joint>,
    /// Inertia of the bodies attached to each joint, in the joint frame (index 0: what is fixed to
    /// the world, not counted in the mass and CoM).
    pub inertias: Vec<Inertia>,
    /// Frames (URDF links and joints), the universe first.
    pub frames: Vec<Frame>,
    /// Configuration size.
    pub nq: usize,
    /// Velocity size.
    pub nv: usize,
    /// Joint index of each velocity entry.
    pub dof_joint: Vec<usize>,
    /// Last joint index of the subtree rooted at each joint (subtrees are contiguous).
    pub subtree_end: Vec<usize>,
    /// The locked joints and their values.
    pub locked: Vec<(String, f64)>,
    /// Elements of the URDF the model does not use (not URDF elements, outside `<gazebo>`,
    /// `<transmission>` and namespaced extensions), each with the line of its first
    /// occurrence: a front end shows them as a warning (a misspelled URDF element is an error
    /// instead).
    pub unknown_elements: Vec<(String, usize)>,
    /// Thresholds used by the configuration checks.
    pub tolerances: Tolerances,
}

impl Model {
    /// Adds an operational frame `name` rigidly attached to the frame `parent` at
    /// `parent_from_frame`, and returns its index.
    ///
    /// # Errors
    ///
    /// [`crate::RobotError::InvalidOption`] when a frame of that name exists or `parent` is not a
    /// frame index.
    ///
    /// ```
    /// use stance_robot::{Model, Pose};
    /// let mut m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
    /// let sole = m.frame_id("r_sole").unwrap();
    /// let toe = m.add_frame("r_toe", sole, Pose::from_xyz_rpy([0.11, 0.0, 0.0], [0.0; 3])).unwrap();
    /// assert_eq!(m.frame_id("r_toe").unwrap(), toe);
    /// assert!(m.add_frame("r_toe", sole, Pose::identity()).is_err());
    /// ```
    pub fn add_frame(
        &mut self,
        name: &str,
        parent: usize,
        parent_from_frame: Pose,
    ) -> Result<usize, crate::RobotError> {
        if self.frames.iter().any(|f| f.name == name) {
            return Err(crate::RobotError::InvalidOption {
                name: "frame name",
                reason: format!("a frame named '{name}' exists already; choose another name"),
            });
        }
        let p = self
            .frames
            .get(parent)
            .ok_or_else(|| crate::RobotError::UnknownFrame(format!("#{parent}")))?;
        let frame = Frame {
            name: name.to_string(),
            kind: FrameKind::Operational,
            parent_joint: p.parent_joint,
            joint_from_frame: p.joint_from_frame.compose(&parent_from_frame),
        };
        self.frames.push(frame);
        Ok(self.frames.len() - 1)
    }

    /// Index of the frame called `name` (the first one if a link and a joint share the name).
    ///
    /// ```
    /// let m = stance_robot::Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF,
    ///     &Default::default()).unwrap();
    /// let f = m.frame_id("r_sole").unwrap();
    /// assert_eq!(m.frames[f].name, "r_sole");
    /// assert!(m.frame_id("nope").is_err());
    /// ```
    pub fn frame_id(&self, name: &str) -> Result<usize, crate::RobotError> {
        self.frames
            .iter()
            .position(|f| f.name == name)
            .ok_or_else(|| crate::RobotError::UnknownFrame(name.to_string()))
    }

    /// Index of the movable joint called `name` in [`Model::joints`] (an error for a name the
    /// model does not have, like [`Model::frame_id`]; it returned an `Option` before).
    ///
    /// ```
    /// let m = stance_robot::Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF,
    ///     &Default::default()).unwrap();
    /// assert_eq!(m.joint_id("root_joint").unwrap(), 1);
    /// assert!(m.joint_id("nope").is_err());
    /// ```
    pub fn joint_id(&self, name: &str) -> Result<usize, crate::RobotError> {
        self.joints
            .iter()
            .position(|j| j.name == name)
            .ok_or_else(|| crate::RobotError::UnknownJoint(name.to_string()))
    }

    /// Names of the movable joints in order (without the universe), as Pinocchio's
    /// `model.names[1:]`.
    ///
    /// ```
    /// let m = stance_robot::Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF,
    ///     &Default::default()).unwrap();
    /// assert_eq!(m.joint_names()[0], "root_joint");
    /// ```
    pub fn joint_names(&self) -> Vec<String> {
        self.joints[1..].iter().map(|j| j.name.clone()).collect()
    }

    /// Whether the root is a free flyer.
    ///
    /// ```
    /// let m = stance_robot::Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF,
    ///     &Default::default()).unwrap();
    /// assert!(m.has_free_flyer());
    /// ```
    pub fn has_free_flyer(&self) -> bool {
        self.joints
            .get(1)
            .is_some_and(|j| j.kind == JointKind::FreeFlyer)
    }

    /// Total mass of the moving bodies (kg).
    ///
    /// ```
    /// let m = stance_robot::Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF,
    ///     &Default::default()).unwrap();
    /// assert!(m.total_mass() > 10.0);
    /// ```
    pub fn total_mass(&self) -> f64 {
        self.inertias[1..].iter().map(|i| i.mass).sum()
    }

    /// The neutral configuration (Pinocchio's `neutral`): zero position, identity quaternion,
    /// continuous joints at angle 0, other joints at 0.
    ///
    /// ```
    /// let m = stance_robot::Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF,
    ///     &Default::default()).unwrap();
    /// let q = m.neutral();
    /// assert_eq!(q.len(), m.nq);
    /// assert_eq!(q[6], 1.0);
    /// ```
    pub fn neutral(&self) -> Vec<f64> {
        let mut q = vec![0.0; self.nq];
        for j in &self.joints {
            match j.kind {
                JointKind::FreeFlyer => q[j.idx_q + 6] = 1.0,
                JointKind::Continuous { .. } => q[j.idx_q] = 1.0,
                _ => {}
            }
        }
        q
    }
}
