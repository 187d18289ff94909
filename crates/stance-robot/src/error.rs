//! The crate's error type: every variant says what to fix.

use thiserror::Error;

/// Errors for bad input: malformed or unsupported URDF, wrong vector sizes, unknown names.
/// Negative outcomes are never errors.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum RobotError {
    /// The file could not be read.
    #[error("cannot read URDF file {path}: {reason}; check the path and its permissions")]
    Io {
        /// The path given.
        path: String,
        /// The operating system's reason.
        reason: String,
    },
    /// The text is not a URDF the parser understands (bad XML, missing attribute, unknown joint
    /// type, a number that does not parse).
    #[error(
        "malformed URDF: {0}; fix the XML (joint types are revolute, continuous, prismatic, fixed)"
    )]
    Urdf(String),
    /// Two links or two joints share a name.
    #[error("duplicate {kind} name '{name}' in the URDF; names must be unique")]
    DuplicateName {
        /// "link" or "joint".
        kind: &'static str,
        /// The repeated name.
        name: String,
    },
    /// A joint names a parent or child link that the URDF does not define.
    #[error("joint '{joint}' refers to link '{link}', which is not defined; add the <link> or fix the name")]
    UnknownLink {
        /// The joint.
        joint: String,
        /// The missing link.
        link: String,
    },
    /// A link is the child of more than one joint.
    #[error("link '{link}' is the child of joints '{first}' and '{second}'; a URDF is a tree, each link has at most one parent joint")]
    MultipleParents {
        /// The link.
        link: String,
        /// First parent joint.
        first: String,
        /// Second parent joint.
        second: String,
    },
    /// The links do not form a single tree (several roots, or a cycle that leaves no root).
    #[error("the URDF's links do not form one tree: {0}")]
    NotATree(String),
    /// A joint type the model does not support.
    #[error("joint '{joint}' has type '{kind}', which is not supported; use revolute, continuous, prismatic or fixed")]
    UnsupportedJointType {
        /// The joint.
        joint: String,
        /// Its type.
        kind: String,
    },
    /// A joint axis of (near) zero length.
    #[error("joint '{joint}' has a zero axis; give a non-zero <axis xyz=...>")]
    ZeroAxis {
        /// The joint.
        joint: String,
    },
    /// A joint's position limits are reversed or not numbers.
    #[error("joint '{joint}' has limits lower = {lower} > upper = {upper} (or not numbers); fix the <limit> element")]
    InvalidLimits {
        /// The joint.
        joint: String,
        /// Lower limit read.
        lower: f64,
        /// Upper limit read.
        upper: f64,
    },
    /// A link's inertial element is not physical.
    #[error("link '{link}' has an invalid inertia: {reason}")]
    InvalidInertia {
        /// The link.
        link: String,
        /// What is wrong.
        reason: String,
    },
    /// Nothing moves: the base is fixed and every joint is fixed or locked.
    #[error("no movable joint: the base is fixed and every joint of the URDF is fixed or locked; unlock a joint")]
    NothingMoves,
    /// The moving model has no mass, so it has no centre of mass.
    #[error("the model's total mass is {mass} kg: its links are missing <inertial> elements; add masses and inertias")]
    MissingInertia {
        /// Total mass found.
        mass: f64,
    },
    /// A joint asked to be locked is not in the URDF or is not movable.
    #[error("cannot lock joint '{joint}': {reason}")]
    CannotLock {
        /// The joint name.
        joint: String,
        /// Why.
        reason: String,
    },
    /// A vector or matrix of the wrong size.
    #[error("{what} has {got} entries, expected {expected}")]
    Dimension {
        /// Which argument.
        what: &'static str,
        /// Expected size.
        expected: usize,
        /// Given size.
        got: usize,
    },
    /// A NaN or infinite entry.
    #[error("{what}[{index}] is not finite; give finite numbers")]
    NonFinite {
        /// Which argument.
        what: &'static str,
        /// The entry.
        index: usize,
    },
    /// The free-flyer quaternion or a continuous joint's (cos, sin) pair is not of unit norm.
    #[error("{what} at q[{index}..] has norm {norm}, expected 1 (within {tol}); normalize it")]
    NotUnit {
        /// "free-flyer quaternion (qx, qy, qz, qw)" or "continuous joint (cos, sin)".
        what: &'static str,
        /// First index in q.
        index: usize,
        /// Its norm.
        norm: f64,
        /// Accepted deviation.
        tol: f64,
    },
    /// An acceleration was asked from a workspace without velocities.
    #[error("the workspace holds no velocity: call forward_kinematics_velocity(q, v) (or centroidal_map_dot_v) first")]
    NoVelocity,
    /// An option or argument of the IK is out of range.
    #[error("invalid {name}: {reason}")]
    InvalidOption {
        /// Which option.
        name: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// A frame name the model does not know.
    #[error("no frame named '{0}' in the model (frames are the URDF's link and joint names)")]
    UnknownFrame(String),
    /// A joint name the model does not know (or a joint the model locked).
    #[error(
        "no movable joint named '{0}' in the model (a locked joint is not a joint of the model)"
    )]
    UnknownJoint(String),
}
