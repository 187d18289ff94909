//! The robot of a motion: its model, locked joints, nominal posture and contact surfaces (each an
//! operational frame of the model, so that the IK, the GIWC, the simulator and the viewer read
//! one and the same pose).
//!
//! Built in:
//!
//! - `jvrc1`: JVRC-1 from PyPI `jvrc-description` (located with
//!   [`stance_robot::jvrc1::locate_urdf`]), fingers locked. Surfaces: the soles `LF`, `RF`
//!   (0.20 x 0.08 m rectangles at (0.0303, -0.0012, -0.1077) m in `*_ANKLE_P_S`, the project's
//!   JVRC-1 data) and hand patches `RH`, `LH`: JVRC-1 has no forearm surface, so the project
//!   defines a 4 x 3 cm patch at the base of each gripper, at (0.025, 0, -0.095) m in `r_wrist`
//!   / `l_wrist` (the point of the gripper surface of JVRC-1's usual controller data), its normal
//!   along the wrist's +z: the hand leans on a surface with its closed gripper, the forearm above
//!   it. Nominal posture: knees bent (hip pitch -0.38, knee 0.72, ankle pitch -0.33 rad), arms
//!   slightly away from the body (shoulder roll -+0.17, elbow pitch -0.5 rad).
//! - `small-humanoid`: the project's own URDF (`models/small_humanoid.urdf`, no Python
//!   needed). Surfaces: soles `LF`, `RF` (0.22 x 0.10 m, the `*_sole` frames) and hand patches
//!   `RH`, `LH` (8 x 4 cm at the bottom of each hand box). Nominal posture: knees bent (hip -0.4,
//!   knee 0.8, ankle -0.4 rad), elbows -0.3 rad.

use std::path::{Path, PathBuf};

use stance_contact::Shape;
use stance_robot::{Model, Pose, UrdfOptions};

use super::spec::{RobotRef, RobotSpec, RobotSurfaceSpec};
use crate::StanceError;

/// A contact surface of the robot: an operational frame of the model and a shape in it.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotSurface {
    /// Its name (`"LF"`).
    pub name: String,
    /// The link (or URDF frame) it is fixed to.
    pub link: String,
    /// Index of its frame in the model (named `surface:<name>`).
    pub frame: usize,
    /// Its shape (half sizes for rectangles), in the surface frame.
    pub shape: Shape,
}

/// The robot of a motion.
#[derive(Debug, Clone)]
pub struct MotionRobot {
    /// Built-in name, or the URDF's file name.
    pub name: String,
    /// The model (with one operational frame per surface).
    pub model: Model,
    /// The URDF's path (`None` for the embedded small humanoid).
    pub urdf: Option<PathBuf>,
    /// Locked joints and their values.
    pub locked: Vec<(String, f64)>,
    /// The nominal posture (`nq`, base at the origin): posture task reference and the start of
    /// the standing-posture search.
    pub posture: Vec<f64>,
    /// Contact surfaces.
    pub surfaces: Vec<RobotSurface>,
}

impl MotionRobot {
    /// The surface called `name`, or an error listing the known ones.
    ///
    /// ```
    /// use stance_motion::{robot::MotionRobot, spec::RobotRef};
    /// let r = MotionRobot::load(&RobotRef::Named("small-humanoid".into()), None).unwrap();
    /// assert_eq!(r.surface("LF").unwrap().link, "l_sole");
    /// assert!(r.surface("tail").is_err());
    /// ```
    pub fn surface(&self, name: &str) -> Result<&RobotSurface, StanceError> {
        self.surfaces
            .iter()
            .find(|s| s.name == name)
            .ok_or_else(|| {
                StanceError::BadMotion(format!(
                    "the robot has no surface {name:?}; its surfaces are {}",
                    self.surfaces
                        .iter()
                        .map(|s| s.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            })
    }

    /// Loads the robot of a motion file; relative URDF paths are taken from `base_dir`.
    ///
    /// ```
    /// use stance_motion::{robot::MotionRobot, spec::RobotRef};
    /// let r = MotionRobot::load(&RobotRef::Named("small-humanoid".into()), None).unwrap();
    /// assert_eq!(r.surfaces.len(), 4);
    /// assert!(MotionRobot::load(&RobotRef::Named("hrp4".into()), None).is_err());
    /// ```
    pub fn load(robot: &RobotRef, base_dir: Option<&Path>) -> Result<Self, StanceError> {
        match robot {
            RobotRef::Named(n) if n == "small-humanoid" => small_humanoid(),
            RobotRef::Named(n) if n == "jvrc1" => jvrc1(),
            RobotRef::Named(n) => Err(StanceError::unknown_name(
                n,
                "robot",
                &["jvrc1", "small-humanoid", "a map with a urdf"],
                false,
            )),
            RobotRef::Urdf(spec) => from_spec(spec, base_dir),
        }
    }
}

fn rect(h_l: f64, h_w: f64) -> Shape {
    Shape::Rectangle {
        half_length: h_l,
        half_width: h_w,
    }
}

fn surface(name: &str, link: &str, position: [f64; 3], shape: Shape) -> RobotSurfaceSpec {
    RobotSurfaceSpec {
        name: name.into(),
        link: link.into(),
        position,
        rpy: [0.0; 3],
        shape,
    }
}

fn small_humanoid() -> Result<MotionRobot, StanceError> {
    let model = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &UrdfOptions::default())
        .map_err(StanceError::Robot)?;
    let surfaces = vec![
        surface("LF", "l_sole", [0.0; 3], rect(0.11, 0.05)),
        surface("RF", "r_sole", [0.0; 3], rect(0.11, 0.05)),
        surface("LH", "l_hand", [0.0, 0.0, -0.1], rect(0.04, 0.02)),
        surface("RH", "r_hand", [0.0, 0.0, -0.1], rect(0.04, 0.02)),
    ];
    let mut posture = Vec::new();
    for side in ["l", "r"] {
        for (j, x) in [
            ("hip_p", -0.4),
            ("knee", 0.8),
            ("ankle_p", -0.4),
            ("elbow", -0.3),
        ] {
            posture.push((format!("{side}_{j}"), x));
        }
    }
    finish(
        "small-humanoid".into(),
        model,
        None,
        Vec::new(),
        &posture,
        &surfaces,
    )
}

fn jvrc1() -> Result<MotionRobot, StanceError> {
    let urdf = crate::venv::jvrc1_urdf()?;
    let options = stance_robot::jvrc1::urdf_options();
    let model = Model::from_urdf_file(&urdf, &options).map_err(StanceError::Robot)?;
    let mut surfaces = Vec::new();
    for (name, sole) in ["RF", "LF"]
        .iter()
        .zip(stance_robot::jvrc1::sole_rectangles())
    {
        surfaces.push(surface(
            name,
            sole.frame,
            sole.center_in_ankle,
            rect(sole.half_length, sole.half_width),
        ));
    }
    surfaces.push(surface(
        "RH",
        "r_wrist",
        [0.025, 0.0, -0.095],
        rect(0.02, 0.015),
    ));
    surfaces.push(surface(
        "LH",
        "l_wrist",
        [0.025, 0.0, -0.095],
        rect(0.02, 0.015),
    ));
    let mut posture = Vec::new();
    for (side, roll) in [("R", -0.17), ("L", 0.17)] {
        for (j, x) in [
            ("HIP_P", -0.38),
            ("KNEE", 0.72),
            ("ANKLE_P", -0.33),
            ("SHOULDER_R", roll),
            ("ELBOW_P", -0.5),
        ] {
            posture.push((format!("{side}_{j}"), x));
        }
    }
    finish(
        "jvrc1".into(),
        model,
        Some(urdf),
        options.locked,
        &posture,
        &surfaces,
    )
}

fn from_spec(spec: &RobotSpec, base_dir: Option<&Path>) -> Result<MotionRobot, StanceError> {
    let path = Path::new(&spec.urdf);
    let path = match base_dir {
        Some(d) if path.is_relative() => d.join(path),
        _ => path.to_path_buf(),
    };
    let options = UrdfOptions {
        locked: spec.locked.iter().map(|(k, v)| (k.clone(), *v)).collect(),
        ..Default::default()
    };
    let model = Model::from_urdf_file(&path, &options).map_err(StanceError::Robot)?;
    let posture: Vec<(String, f64)> = spec.posture.iter().map(|(k, v)| (k.clone(), *v)).collect();
    let name = path
        .file_name()
        .map_or_else(|| spec.urdf.clone(), |f| f.to_string_lossy().into_owned());
    finish(
        name,
        model,
        Some(path),
        options.locked,
        &posture,
        &spec.surfaces,
    )
}

fn finish(
    name: String,
    mut model: Model,
    urdf: Option<PathBuf>,
    locked: Vec<(String, f64)>,
    posture: &[(String, f64)],
    surfaces: &[RobotSurfaceSpec],
) -> Result<MotionRobot, StanceError> {
    if !model.has_free_flyer() {
        return Err(StanceError::BadMotion(
            "the robot needs a free-flyer base for motions across stances".into(),
        ));
    }
    let mut q = model.neutral();
    for (joint, value) in posture {
        let j = model.joint_id(joint).map_err(|_| {
            StanceError::BadMotion(format!(
                "posture names the joint {joint:?}, which the robot does not have (or is locked)"
            ))
        })?;
        let j = &model.joints[j];
        if j.dims().0 != 1 {
            return Err(StanceError::BadMotion(format!(
                "posture gives a value for {joint:?}, which is not a revolute or prismatic joint"
            )));
        }
        if !(value.is_finite() && *value >= j.lower && *value <= j.upper) {
            return Err(StanceError::BadMotion(format!(
                "posture value {value} of {joint:?} is outside its limits [{}, {}]",
                j.lower, j.upper
            )));
        }
        q[j.idx_q] = *value;
    }
    let mut out = Vec::new();
    for s in surfaces {
        if out.iter().any(|o: &RobotSurface| o.name == s.name) {
            return Err(StanceError::BadMotion(format!(
                "two robot surfaces are named {:?}; names must be unique",
                s.name
            )));
        }
        if s.position.iter().chain(&s.rpy).any(|x| !x.is_finite()) {
            return Err(StanceError::BadMotion(format!(
                "robot surface {:?}: position and rpy must be finite",
                s.name
            )));
        }
        super::environment::polygon_of(&s.shape, &format!("robot surface {:?}", s.name), true)?;
        let parent = model.frame_id(&s.link).map_err(|_| {
            StanceError::BadMotion(format!(
                "robot surface {:?} is on {:?}, which is not a link or frame of the URDF",
                s.name, s.link
            ))
        })?;
        let frame = model
            .add_frame(
                &format!("surface:{}", s.name),
                parent,
                Pose::from_xyz_rpy(s.position, s.rpy),
            )
            .map_err(StanceError::Robot)?;
        out.push(RobotSurface {
            name: s.name.clone(),
            link: s.link.clone(),
            frame,
            shape: s.shape.clone(),
        });
    }
    Ok(MotionRobot {
        name,
        model,
        urdf,
        locked,
        posture: q,
        surfaces: out,
    })
}

/// A link drawn as a capsule: from the origin of joint `parent` to the origin of its child joint
/// `child` (both model joint indices). The one description of the robot's primitive geometry:
/// the simulator's collision capsules (`stance_sim`) and the viewer's links (`stance_view`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bone {
    /// Joint whose body the capsule belongs to.
    pub parent: usize,
    /// The child joint the capsule reaches.
    pub child: usize,
    /// Whether the simulator gives it collision geometry (not the free-flyer's body, whose
    /// capsules would overlap the legs at the hips, and not a bone shorter than two radii).
    pub collides: bool,
}

/// The bones of `model` for capsules of radius `radius` (m): every joint towards each of its
/// children, except from the universe; bones shorter than `2 radius` or from the free flyer do
/// not collide.
///
/// ```
/// use stance_motion::robot::{bones, MotionRobot};
/// use stance_motion::spec::RobotRef;
/// let r = MotionRobot::load(&RobotRef::Named("small-humanoid".into()), None).unwrap();
/// let b = bones(&r.model, 0.03);
/// assert!(b.iter().any(|b| b.collides) && b.iter().any(|b| !b.collides));
/// assert!(b.iter().all(|b| r.model.joints[b.child].parent == b.parent));
/// ```
pub fn bones(model: &Model, radius: f64) -> Vec<Bone> {
    use stance_robot::JointKind;
    (2..model.joints.len())
        .map(|k| {
            let j = &model.joints[k];
            let parent = &model.joints[j.parent];
            let long = j.parent_from_joint.translation.norm() > 2.0 * radius;
            Bone {
                parent: j.parent,
                child: k,
                collides: long && parent.kind != JointKind::FreeFlyer,
            }
        })
        .filter(|b| b.parent != 0)
        .collect()
}
