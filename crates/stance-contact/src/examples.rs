//! Built-in example scenes from the paper (load them by name with [`by_name`]).
//!
//! Feet are 22 x 13 cm rectangles, hands 10 x 8 cm; the mass (39 kg, the order of the HRP-4
//! humanoid of the paper) does not affect static equilibrium. Rotations are exactly orthonormal
//! to double precision (built from rational tan(angle/2) like the project's reference data).

use crate::scene::{ContactSpec, Scene, STANDARD_GRAVITY};
use crate::FrictionModel;
use crate::Shape;

const MASS: f64 = 39.0;
const EYE: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn foot(name: &str, position: [f64; 3], rotation: [[f64; 3]; 3], mu: f64) -> ContactSpec {
    ContactSpec {
        name: name.into(),
        position,
        rotation,
        shape: Shape::Rectangle {
            half_length: 0.11,
            half_width: 0.065,
        },
        friction: mu,
    }
}

fn scene(contacts: Vec<ContactSpec>) -> Scene {
    Scene {
        mass: MASS,
        gravity: STANDARD_GRAVITY,
        contacts,
        friction_model: FrictionModel::default(),
    }
}

/// Names accepted by [`by_name`].
pub const NAMES: [&str; 5] = [
    "single-support",
    "double-support",
    "stairs",
    "box-climbing",
    "robust-equilibrium",
];

/// One foot flat at the origin, mu = 0.7 (the paper's 16-row single support).
///
/// ```
/// assert_eq!(stance_contact::examples::single_support_flat().contacts.len(), 1);
/// ```
pub fn single_support_flat() -> Scene {
    scene(vec![foot("LF", [0.0, 0.0, 0.0], EYE, 0.7)])
}

/// Two feet flat on the ground 0.2 m apart, mu = 0.7 (flat double support).
///
/// ```
/// assert_eq!(stance_contact::examples::double_support_flat().contacts.len(), 2);
/// ```
pub fn double_support_flat() -> Scene {
    scene(vec![
        foot("LF", [0.0, 0.1, 0.0], EYE, 0.7),
        foot("RF", [0.0, -0.1, 0.0], EYE, 0.7),
    ])
}

/// Left foot on the ground, right foot one 24 cm step up and 28 cm ahead, yawed 10 deg,
/// mu = 0.7 (the paper's stair climbing).
///
/// ```
/// assert_eq!(stance_contact::examples::stairs().contacts[1].position[2], 0.24);
/// ```
pub fn stairs() -> Scene {
    scene(vec![
        foot("LF", [0.0, 0.1, 0.0], EYE, 0.7),
        foot(
            "RF",
            [0.28, -0.1, 0.24],
            [
                [0.9848038455574508, -0.17367033648627694, 0.0],
                [0.17367033648627694, 0.9848038455574508, 0.0],
                [0.0, 0.0, 1.0],
            ],
            0.7,
        ),
    ])
}

/// Box climbing (paper Fig. 3, Table II): left foot on the 25 deg inclined face of a 10 cm box,
/// right hand on a horizontal ledge 0.9 m high, mu = 0.7.
///
/// ```
/// assert_eq!(stance_contact::examples::box_climbing().contacts[1].name, "RH");
/// ```
pub fn box_climbing() -> Scene {
    let mut hand = foot(
        "RH",
        [0.45, -0.35, 0.9],
        [
            [0.9397105189599477, 0.3419709644926388, 0.0],
            [-0.3419709644926388, 0.9397105189599477, 0.0],
            [0.0, 0.0, 1.0],
        ],
        0.7,
    );
    hand.shape = Shape::Rectangle {
        half_length: 0.05,
        half_width: 0.04,
    };
    scene(vec![
        foot(
            "LF",
            [0.15, 0.1, 0.1],
            [
                [0.90284856741686, -0.079059944778177, -0.42262748306871284],
                [0.08723341122691407, 0.9961878999293838, 0.0],
                [0.4210163848106623, -0.03686723702632869, 0.9063034870036664],
            ],
            0.7,
        ),
        hand,
    ])
}

/// Roll-pitch-yaw (rad) to a rotation matrix, `Rz(yaw) Ry(pitch) Rx(roll)`, row-major.
fn rpy(roll: f64, pitch: f64, yaw: f64) -> [[f64; 3]; 3] {
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    let (sy, cy) = yaw.sin_cos();
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

/// The paper's robust static-equilibrium scene (Fig. 3): the right foot on a box tilted about
/// 9 deg (roll -8.6 deg, pitch 2.7 deg) at (0.552, -0.109, 0.087), the right forearm on a
/// ledge at (0.5, -0.4, 0.87); the paper's HRP-4 foot (0.224 x 0.13 m) and forearm patch
/// (0.03 x 0.05 m), mu = 0.7. The paper tests 10^6 random CoMs against the gravities
/// `(+-0.15, 0, -9.81)` and `(0, +-0.15, -9.81)`.
///
/// ```
/// let s = stance_contact::examples::robust_equilibrium();
/// assert_eq!(s.contacts[1].name, "RA");
/// assert!(s.stance().is_ok());
/// ```
pub fn robust_equilibrium() -> Scene {
    let deg = std::f64::consts::PI / 180.0;
    let mut arm = foot("RA", [0.5, -0.4, 0.87], EYE, 0.7);
    arm.shape = Shape::Rectangle {
        half_length: 0.015,
        half_width: 0.025,
    };
    let mut rf = foot(
        "RF",
        [0.552, -0.109, 0.087],
        rpy(-8.6 * deg, 2.7 * deg, 0.0),
        0.7,
    );
    rf.shape = Shape::Rectangle {
        half_length: 0.112,
        half_width: 0.065,
    };
    scene(vec![rf, arm])
}

/// The example scene called `name` (one of [`NAMES`]), or `None`.
///
/// ```
/// use stance_contact::examples;
/// assert!(examples::by_name("stairs").is_some());
/// assert!(examples::by_name("moon").is_none());
/// ```
pub fn by_name(name: &str) -> Option<Scene> {
    match name {
        "single-support" => Some(single_support_flat()),
        "double-support" => Some(double_support_flat()),
        "stairs" => Some(stairs()),
        "box-climbing" => Some(box_climbing()),
        "robust-equilibrium" => Some(robust_equilibrium()),
        _ => None,
    }
}
