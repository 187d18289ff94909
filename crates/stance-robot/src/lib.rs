//! # stance-robot
//!
//! A floating-base robot model from URDF with the quantities the paper's whole-body retiming needs
//! (Caron, Pham and Nakamura, RSS 2015, Section V-B): forward kinematics, frame Jacobians and
//! their drifts, the centre of mass and its Jacobian, the centroidal momentum matrix `A_g` and
//! `(dA_g/dt) v`, and the path terms `p, p_s, p_ss, l1, l2`. Conventions are Pinocchio's, and
//! every quantity is checked against Pinocchio 4.1.0 to round-off (tests/pinocchio_fixtures.rs).
//!
//! # Math
//!
//! **Spatial algebra** ([`spatial`]): placements `a_from_b = (R, t)`, `x_a = R x_b + t`; motions
//! and forces are 6-vectors with the **linear part first**; a body's spatial velocity in the world
//! frame is taken at the world origin, `V = (v_O, w)` with `v_O` the velocity of the body point at
//! the origin.
//!
//! **Configuration and velocity** (Pinocchio's): `q = (x, y, z, qx, qy, qz, qw, q_joints)` for a
//! free-flyer base, `v = (v_base, w_base, v_joints)` with the base twist **in the base frame**;
//! continuous joints take `(cos, sin)` in `q` and one entry in `v`; joints are ordered depth first
//! from the root link, siblings by joint name ([`model`]).
//!
//! **Kinematics** ([`kinematics`]): `world_from_joint[i] = world_from_joint[lambda(i)]
//! parent_from_joint[i] X_J(q_i)`; motion subspace columns `S_k` in the world; frame Jacobians in
//! `World`, `Local` and `LocalWorldAligned` ([`ReferenceFrame`]); classical accelerations
//! `J_dot v` for zero joint accelerations.
//!
//! **Centroidal momentum** ([`centroidal`]): `h_G = (m c_dot, L_G) = A_g(q) v`, linear first, the
//! angular momentum about the CoM `c`; column `k` of `A_g` is the momentum of the composite
//! rigid body of the subtree moved by velocity entry `k`, transported from the world origin to the
//! CoM (`L_G = L_O - c x h_lin`). `J_com = A_g,lin / m`. `(dA_g/dt) v` is the rate of change of
//! `h_G` when `v` is constant.
//!
//! **Whole-body path** ([`ik`], docs/math.md section 6): an acceleration-level IK QP tracks a CoM path
//! and free-link paths with the contacts held, and is integrated along a grid into `q(s)`,
//! `q_s(s)`, `q_ss(s)`.
//!
//! **Inverse dynamics** ([`dynamics`]): `tau = M(q) a + C(q, v) v + g(q)` by the recursive
//! Newton-Euler algorithm in the world frame (Pinocchio's `rnea`), and along a path
//! `tau = tau_a s'' + tau_b s'^2 + tau_c` for the torque limits of the retiming.
//!
//! **Path terms** ([`path`], docs/math.md section 6): `p = c(q)`, `p_s = J_com q_s`,
//! `p_ss = J_com q_ss + (dJ_com/ds) q_s`, `l1 = A_g,ang q_s`, `l2 = A_g,ang q_ss + (dA_g,ang/ds) q_s`.
//!
//! # Use
//!
//! ```
//! use stance_robot::{centroidal_map, Data, Model, UrdfOptions};
//! let model = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &UrdfOptions::default())?;
//! let mut data = Data::new(&model); // reusable workspace: no allocation in the calls below
//! let q = model.neutral();
//! centroidal_map(&model, &mut data, &q)?;
//! assert!((data.mass - 43.2).abs() < 1e-12);
//! assert_eq!(data.centroidal_map.shape(), (6, model.nv));
//! # Ok::<(), stance_robot::RobotError>(())
//! ```
//!
//! # Limitations
//!
//! - Joint types: free flyer (root only), revolute, continuous, prismatic, fixed. Floating,
//!   planar and spherical URDF joints are rejected with an error.
//! - Mimic tags are ignored, as by Pinocchio's default URDF parser: mimic joints are independent
//!   degrees of freedom. Lock them (as the JVRC-1 setup does for the fingers) when they must not
//!   move.
//! - Locked joints are fixed at the given value: they are not degrees of freedom and no
//!   quantity reports their motion.
//! - Geometry (visual, collision) and meshes are not read; `<transmission>`, `<gazebo>` and
//!   `<sensor>` elements are ignored.
//! - Quantities are computed about the world origin and transported to the CoM, like Pinocchio:
//!   with the robot kilometres away from the origin, round-off in `A_g`'s angular rows grows with
//!   the squared distance.
//! - Dynamics: inverse dynamics only ([`dynamics`]: the RNEA and its coefficients along a
//!   path); no mass matrix, forward dynamics or contact dynamics. Joint friction, rotor inertia
//!   (URDF `<dynamics>`) and transmissions are not modelled.
//! - [`SMALL_HUMANOID_URDF`] is included from the project's `models/` folder, outside the crate:
//!   the crate builds inside the project workspace only (not as a stand-alone package).
//! - JVRC-1's URDF is not shipped: [`jvrc1::locate_urdf`] finds it in the project virtualenv
//!   (PyPI `jvrc-description`), and the JVRC-1 tests skip, saying why, when it is absent.
//! - The acceleration-level IK ([`ik`]) tracks CoM and link positions and orientations and a
//!   posture, holds contacts as fixed 6-D frames, and bounds joint positions either over the
//!   next path step (a joint that arrives fast at its limit is stopped within one step, which
//!   can make the next QP infeasible: reported as a status) or by the paper's damper, and
//!   optionally the joint rates along the path; a target out of reach drives the limbs to
//!   singular configurations and ends as an infeasible or failed status. Its dense QP solver
//!   handles bounds on single coordinates only (all the IK has) and needs independent contact
//!   rows (two contact frames on one rigid body go to the Clarabel fallback, an interior-point
//!   method, much slower: `bench/peers/robot.md` has the figures); the step returns its `q_ss`
//!   in a new vector, the rest reuses [`IkWorkspace`].

pub mod centroidal;
pub mod data;
pub mod dynamics;
pub mod error;
pub mod ik;
pub mod jvrc1;
pub mod kinematics;
pub mod model;
pub mod path;
pub mod spatial;
pub mod tol;

pub use centroidal::{center_of_mass, centroidal_map, centroidal_map_dot_v, com_jacobian};
pub use data::Data;
pub use dynamics::{rnea, torque_path_terms, torque_path_terms_two, TorquePathTerms};
pub use error::RobotError;
pub use ik::{
    ik_qp, ik_step, solve_ik_qp, track_path, ContactHold, DistanceBound, IkAnswerFrom, IkOptions,
    IkPath, IkQp, IkSolver, IkStatus, IkStep, IkTasks, IkWorkspace, JointBounds, LinkTarget,
    OrientationReference, PathSample, PointReference,
};
pub use kinematics::{
    check_configuration, check_velocity, forward_kinematics, forward_kinematics_velocity,
    frame_classical_acceleration, frame_jacobian, frame_placement, integrate, ReferenceFrame,
};
pub use model::{Frame, FrameKind, Joint, JointKind, Model, RootJoint, UrdfOptions};
pub use nalgebra;
pub use path::{path_terms, path_terms_along, path_terms_from_data, PathTerms};
pub use spatial::{Inertia, Pose};
pub use tol::Tolerances;

/// The project's small humanoid (boxes and cylinders with analytic inertias; every supported
/// joint type), for tests and examples that need no external model.
///
/// ```
/// let m = stance_robot::Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF,
///     &Default::default()).unwrap();
/// assert_eq!((m.nq, m.nv), (29, 27));
/// ```
pub const SMALL_HUMANOID_URDF: &str = include_str!("../../../models/small_humanoid.urdf");
