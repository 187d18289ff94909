//! Motion files (JSON or TOML): the robot and its contact surfaces, the environment, the initial
//! posture and the segments with their stances and task via-points. Strict like scene files:
//! unknown keys and arrays of the wrong length are errors.
//!
//! ```text
//! name = "..."                       # optional
//! robot = "jvrc1" | "small-humanoid" | {urdf = "path", locked = {J = 0.0}, posture = {J = 0.3},
//!          surfaces = [{name, link, position = [x, y, z], rpy = [r, p, y],
//!                       shape = {rectangle = {half_length, half_width}} | "point" | {polygon = [...]}}]}
//! gravity = [0, 0, -9.81]            # optional
//! [[environment]]                    # surfaces: frame z = normal out of the environment
//! name, position, rpy | rotation, shape = {rectangle = {...}} | {polygon = [...]}, friction
//! [initial]                          # one of
//! configuration = [q...]             #   Pinocchio's q
//! standing = {com_height, com_xy?, contacts = {LF = {surface, at = [x, y], yaw}, ...}}
//! [planning]   friction?, area_scale (1), margin (0),
//!              friction_cone ({sides = 8, approximation = "inner"}: within Coulomb's cone),
//!              switch_margin? and swing = {clearance = 0.05} (the footholds planner)
//! [ik]         w_com (1), w_link (0.1), w_posture (1e-5), gain (10), contact_gain (20),
//!              joint_range (0.95), substeps (4), com_blend (0.25, at most a quarter of the
//!              shortest move)
//! [retiming]   grid (100), discretization ("interpolation"), dt (0.01), check_dt (0.001),
//!              rest_to_rest (false)
//! [limits]     velocity (1.0: the URDF's; false), acceleration (none; 30.0 or
//!              {default = 30.0, J = 50.0}), torque (1.0: the URDF's efforts; false)
//! [[segments]] name?, stance = {LF = "floor", RF = "floor"}, w_link?, gain?
//! [[segments.moves]] (none, or one move of landings only: planned, crate::footholds)
//!                    duration (2), com = {by = [..]} | {to = [..]},
//!                    links = [{surface = "RF", by = [..], rotate_by = [r, p, y]}
//!                           | {surface, to = [..], rpy = [..]}
//!                           | {surface, onto = "box", at = [x, y], yaw = 0}]
//! ```
//!
//! Lengths in metres, angles in radians, `duration` in units of the path parameter (the paper's
//! "IK time"; the gains are per unit of it). A robot surface's frame has its z axis along the
//! surface normal pointing **into** the robot (a sole's z points up, towards the ankle), the
//! environment's along the normal pointing **out of** the environment, so that in contact the two
//! frames coincide (up to a yaw) and the GIWC contact frame is the robot surface's frame.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use stance_contact::FrictionModel;
use stance_contact::{scene::strict, Shape};
use stance_topp::Discretization;

/// The robot: a built-in name or a URDF with its surfaces.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum RobotRef {
    /// `"jvrc1"` or `"small-humanoid"`.
    Named(String),
    /// A URDF robot.
    Urdf(Box<RobotSpec>),
}

impl<'de> Deserialize<'de> for RobotRef {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Ok(
            match crate::name_or::NameOr::<RobotSpec>::deserialize(
                d,
                "a built-in robot name (\"jvrc1\", \"small-humanoid\") or a robot map",
            )? {
                crate::name_or::NameOr::Name(n) => RobotRef::Named(n),
                crate::name_or::NameOr::Value(s) => RobotRef::Urdf(Box::new(s)),
            },
        )
    }
}

/// A map whose keys are given once: a key written twice (a copied line) is an error, not the
/// last value silently winning.
fn unique_keys<'de, D, V>(d: D) -> Result<BTreeMap<String, V>, D::Error>
where
    D: serde::Deserializer<'de>,
    V: Deserialize<'de>,
{
    struct Unique<V>(std::marker::PhantomData<V>);
    impl<'de, V: Deserialize<'de>> serde::de::Visitor<'de> for Unique<V> {
        type Value = BTreeMap<String, V>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a map of names")
        }
        fn visit_map<A: serde::de::MapAccess<'de>>(
            self,
            mut map: A,
        ) -> Result<Self::Value, A::Error> {
            let mut out = BTreeMap::new();
            while let Some((k, v)) = map.next_entry::<String, V>()? {
                if out.contains_key(&k) {
                    return Err(serde::de::Error::custom(format!(
                        "{k:?} is given twice: give it once"
                    )));
                }
                out.insert(k, v);
            }
            Ok(out)
        }
    }
    d.deserialize_map(Unique(std::marker::PhantomData))
}

/// A URDF robot with its contact surfaces.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSpec {
    /// Path of the URDF (relative paths: from the motion file's folder).
    pub urdf: String,
    /// Joints locked at a value (removed from `q` and `v`).
    #[serde(default, deserialize_with = "unique_keys")]
    pub locked: BTreeMap<String, f64>,
    /// Nominal joint values of the posture task and of the standing posture (others 0).
    #[serde(default, deserialize_with = "unique_keys")]
    pub posture: BTreeMap<String, f64>,
    /// Contact surfaces on the robot's links.
    pub surfaces: Vec<RobotSurfaceSpec>,
}

/// A contact surface on a robot link.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSurfaceSpec {
    /// Name used by stances and moves (e.g. `"LF"`).
    pub name: String,
    /// The URDF link (or frame) it is fixed to.
    pub link: String,
    /// Origin in the link frame (m).
    #[serde(deserialize_with = "strict::vec3")]
    pub position: [f64; 3],
    /// Orientation in the link frame (roll, pitch, yaw in rad, URDF convention).
    #[serde(default, deserialize_with = "strict::vec3")]
    pub rpy: [f64; 3],
    /// Shape in the surface frame (half sizes for rectangles).
    pub shape: Shape,
}

/// An environment surface.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentSurfaceSpec {
    /// Name used by stances and moves.
    pub name: String,
    /// Origin of the surface frame (m), within 1000 km of the world origin
    /// ([`crate::tol::MAX_SCENE_DISTANCE`]).
    #[serde(deserialize_with = "strict::vec3")]
    pub position: [f64; 3],
    /// Orientation as roll, pitch, yaw (rad); give this or `rotation`.
    #[serde(
        skip_serializing_if = "Option::is_none",
        default,
        deserialize_with = "opt_vec3"
    )]
    pub rpy: Option<[f64; 3]>,
    /// Orientation as a rotation matrix (row-major, surface frame -> world).
    #[serde(
        skip_serializing_if = "Option::is_none",
        default,
        deserialize_with = "opt_mat3"
    )]
    pub rotation: Option<[[f64; 3]; 3]>,
    /// Shape in the surface frame (the plane z = 0), within 100 km of its origin
    /// ([`crate::tol::MAX_SURFACE_EXTENT`]).
    pub shape: Shape,
    /// Friction coefficient of the surface (the physical one; planning may use less).
    pub friction: f64,
    /// Thickness of the solid below the surface, along its normal (m): the collision check, the
    /// IK's clearance and the simulator see the surface as this box (or extruded polygon).
    /// Default ([`super::collision::default_thickness`]): an upward-facing surface reaches down
    /// to the lowest surface's level (a step or a box is solid to the floor), at least
    /// [`super::collision::MIN_SOLID_THICKNESS`]; any other surface (a wall) that minimum.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<f64>,
}

/// The initial posture.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum InitialSpec {
    /// A configuration `q` in Pinocchio's conventions.
    Configuration(Vec<f64>),
    /// A standing posture found by the project.
    Standing(StandingSpec),
}

/// A standing posture to find: the contacts placed on environment surfaces and the CoM.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StandingSpec {
    /// Robot surface -> where it is placed.
    #[serde(deserialize_with = "unique_keys")]
    pub contacts: BTreeMap<String, Placement>,
    /// CoM height above the world origin (m).
    pub com_height: f64,
    /// CoM horizontal position (m); default: the mean of the contact origins.
    #[serde(
        skip_serializing_if = "Option::is_none",
        default,
        deserialize_with = "opt_vec2"
    )]
    pub com_xy: Option<[f64; 2]>,
}

/// A robot surface placed on an environment surface.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Placement {
    /// The environment surface.
    pub surface: String,
    /// Coordinates of the robot surface's origin in the environment surface's frame (m).
    #[serde(deserialize_with = "vec2")]
    pub at: [f64; 2],
    /// Rotation about the surface normal (rad).
    #[serde(default)]
    pub yaw: f64,
}

/// Planning options of the GIWC (the paper: friction 0.7 and area 0.7 while simulating 0.9).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanningSpec {
    /// Friction used in the GIWC, at most every environment surface's (default: each
    /// surface's own).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub friction: Option<f64>,
    /// Area scale of every contact polygon in the GIWC (in [1e-6, 1]; half sizes scaled by its
    /// square root; default 1).
    #[serde(default = "one")]
    pub area_scale: f64,
    /// The polyhedral friction cone of every contact (key `friction_cone`; `friction_model`,
    /// the scene files' name, is accepted). Default: the 8-sided pyramid inscribed in
    /// Coulomb's circular cone, so that a plan never needs more friction than the surface's
    /// `friction`; the paper's outer 4-sided pyramid (`{ sides = 4, approximation = "outer" }`)
    /// reaches `mu sqrt 2` at its corners.
    #[serde(default = "coulomb_cone", alias = "friction_model")]
    pub friction_cone: FrictionModel,
    /// Safety margin of the retiming rows, as a fraction of the weight `m |g|` (default 0):
    /// every row of eq. 14 must hold with `a u + b x + c <= -margin m |g|`.
    #[serde(default)]
    pub margin: f64,
    /// The footholds planner's margin fraction at the stance switches, in (0, 1] (default:
    /// searched by the retimed duration; [`crate::footholds`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub switch_margin: Option<f64>,
    /// The footholds planner's swing paths ([`crate::footholds`]).
    #[serde(default, skip_serializing_if = "SwingSpec::is_default")]
    pub swing: SwingSpec,
}

/// Options of the footholds planner's swing paths (key `planning.swing`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SwingSpec {
    /// Clearance (m) of a swinging link's contact box over every environment solid, and its
    /// lift-off and approach along the surfaces' normals (0.05).
    #[serde(default = "swing_clearance")]
    pub clearance: f64,
}

impl Default for SwingSpec {
    fn default() -> Self {
        Self {
            clearance: swing_clearance(),
        }
    }
}

impl SwingSpec {
    fn is_default(&self) -> bool {
        *self == Self::default()
    }
}

fn swing_clearance() -> f64 {
    0.05
}

/// The default friction cone of motion files: 8 sides inscribed in Coulomb's cone.
///
/// ```
/// use stance_contact::Approximation;
/// let c = stance_motion::spec::coulomb_cone();
/// assert_eq!((c.sides, c.approximation), (8, Approximation::Inner));
/// ```
pub fn coulomb_cone() -> FrictionModel {
    FrictionModel {
        sides: 8,
        approximation: stance_contact::Approximation::Inner,
    }
}

impl Default for PlanningSpec {
    fn default() -> Self {
        Self {
            friction: None,
            area_scale: 1.0,
            friction_cone: coulomb_cone(),
            margin: 0.0,
            switch_margin: None,
            swing: SwingSpec::default(),
        }
    }
}

/// IK options (the paper's weights and gains by default).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IkSpec {
    /// CoM task weight (1).
    #[serde(default = "one")]
    pub w_com: f64,
    /// Free-link task weight (0.1).
    #[serde(default = "w_link")]
    pub w_link: f64,
    /// Posture task weight (1e-5).
    #[serde(default = "w_posture")]
    pub w_posture: f64,
    /// Task gains `K_p = K_d` (10, per unit of path).
    #[serde(default = "ten")]
    pub gain: f64,
    /// Contact gains (velocity damping and pose correction; 20).
    #[serde(default = "twenty")]
    pub contact_gain: f64,
    /// Fraction of each joint range kept by the joint-limit damper (0.95).
    #[serde(default = "joint_range")]
    pub joint_range: f64,
    /// IK steps per retiming grid interval (4).
    #[serde(default = "four")]
    pub substeps: usize,
    /// Half-width of the rounding of the CoM path's corners (path units; by default 0.25, or a
    /// quarter of the shortest move if that is less; at most a quarter of the shortest move).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub com_blend: Option<f64>,
    /// Clearance (m) that the links not in contact keep from every environment solid (0.01;
    /// module [`super::collision`]); 0 keeps them out of the solids only. A body closer than
    /// this (a foot lifting off its surface) is pushed out gently (the IK's clearance damper).
    #[serde(default = "clearance")]
    pub clearance: f64,
}

impl Default for IkSpec {
    fn default() -> Self {
        Self {
            w_com: 1.0,
            w_link: w_link(),
            w_posture: w_posture(),
            gain: 10.0,
            contact_gain: 20.0,
            joint_range: joint_range(),
            substeps: 4,
            com_blend: None,
            clearance: clearance(),
        }
    }
}

/// Retiming options.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RetimingSpec {
    /// Grid intervals per segment (100, the paper's N).
    #[serde(default = "hundred")]
    pub grid: usize,
    /// Discretization (interpolation).
    #[serde(default = "crate::retime::interpolation")]
    pub discretization: Discretization,
    /// Output time step of the trajectory (s; 0.01): its samples are every `dt`, with the
    /// instants where the path acceleration switches added where two samples would disagree
    /// (module [`super::trajectory`]).
    #[serde(default = "dt")]
    pub dt: f64,
    /// Time step of the independent checks (s; 0.001).
    #[serde(default = "check_dt")]
    pub check_dt: f64,
    /// Retime every segment from rest to rest (the paper's way) instead of the whole motion
    /// as one problem (false).
    #[serde(default)]
    pub rest_to_rest: bool,
}

impl Default for RetimingSpec {
    fn default() -> Self {
        Self {
            grid: 100,
            discretization: Discretization::Interpolation,
            dt: dt(),
            check_dt: check_dt(),
            rest_to_rest: false,
        }
    }
}

/// A segment: a fixed stance and its moves.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpec {
    /// Name (default `"segment k"`).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub name: Option<String>,
    /// Robot surface -> environment surface, for every contact held during the segment.
    #[serde(deserialize_with = "unique_keys")]
    pub stance: BTreeMap<String, String>,
    /// The moves, one after the other. None (or one move of landings only, without `com`):
    /// the footholds planner plans them ([`crate::footholds`]).
    #[serde(default)]
    pub moves: Vec<MoveSpec>,
    /// Free-link weight for this segment (default: the `ik` one).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub w_link: Option<f64>,
    /// Task gain for this segment (default: the `ik` one).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub gain: Option<f64>,
}

/// One move: the CoM and free links driven in straight lines to their via-points.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MoveSpec {
    /// Length of the move in path units (2, the paper's 2 s of IK time).
    #[serde(default = "two")]
    pub duration: f64,
    /// The CoM via-point (default: stay).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub com: Option<ComTarget>,
    /// Free-link via-points.
    #[serde(default)]
    pub links: Vec<LinkMoveSpec>,
}

/// A CoM via-point: exactly one of `by` and `to`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", try_from = "ComTargetKeys")]
pub enum ComTarget {
    /// Offset from the previous CoM via-point (m).
    By([f64; 3]),
    /// World position (m).
    To([f64; 3]),
}

/// A CoM via-point as written (both keys optional), so that a wrong count of keys gets a
/// message saying which keys there are.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ComTargetKeys {
    by: Option<Vec<f64>>,
    to: Option<Vec<f64>>,
}

impl TryFrom<ComTargetKeys> for ComTarget {
    type Error = String;

    fn try_from(k: ComTargetKeys) -> Result<Self, String> {
        let three = |key: &str, v: Option<Vec<f64>>| -> Result<Option<[f64; 3]>, String> {
            v.map(|v| {
                <[f64; 3]>::try_from(v.as_slice()).map_err(|_| {
                    format!(
                        "a com move's `{key}` needs 3 numbers [x, y, z], not {}",
                        v.len()
                    )
                })
            })
            .transpose()
        };
        match (three("by", k.by)?, three("to", k.to)?) {
            (Some(v), None) => Ok(ComTarget::By(v)),
            (None, Some(v)) => Ok(ComTarget::To(v)),
            (Some(_), Some(_)) => Err("a com move takes one of `by` (an offset from the \
                                       previous CoM via-point) and `to` (a world position), not \
                                       both"
                .into()),
            (None, None) => Err("a com move needs `by` (an offset from the previous CoM \
                                 via-point) or `to` (a world position)"
                .into()),
        }
    }
}

/// A free link's via-point: exactly one of `by`, `to`, `onto`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinkMoveSpec {
    /// The robot surface whose frame moves.
    pub surface: String,
    /// Offset of the origin from its previous via-point (world axes, m).
    #[serde(
        skip_serializing_if = "Option::is_none",
        default,
        deserialize_with = "opt_vec3"
    )]
    pub by: Option<[f64; 3]>,
    /// Rotation from the previous via-point's orientation, as roll, pitch, yaw (rad) about the
    /// surface frame's own axes (with `by`).
    #[serde(
        skip_serializing_if = "Option::is_none",
        default,
        deserialize_with = "opt_vec3"
    )]
    pub rotate_by: Option<[f64; 3]>,
    /// World position of the origin (m).
    #[serde(
        skip_serializing_if = "Option::is_none",
        default,
        deserialize_with = "opt_vec3"
    )]
    pub to: Option<[f64; 3]>,
    /// World orientation as roll, pitch, yaw (rad; with `to`; default: keep).
    #[serde(
        skip_serializing_if = "Option::is_none",
        default,
        deserialize_with = "opt_vec3"
    )]
    pub rpy: Option<[f64; 3]>,
    /// Place the surface on this environment surface (a landing: the contact of the next
    /// segment).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub onto: Option<String>,
    /// Coordinates on that surface (m; with `onto`).
    #[serde(
        skip_serializing_if = "Option::is_none",
        default,
        deserialize_with = "opt_vec2"
    )]
    pub at: Option<[f64; 2]>,
    /// Rotation about its normal (rad; with `onto`).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub yaw: Option<f64>,
}

/// A motion file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionSpec {
    /// Name for reports.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub name: Option<String>,
    /// The robot.
    pub robot: RobotRef,
    /// Gravity (m/s^2; default `[0, 0, -9.81]`).
    #[serde(default = "gravity", deserialize_with = "strict::vec3")]
    pub gravity: [f64; 3],
    /// Environment surfaces.
    pub environment: Vec<EnvironmentSurfaceSpec>,
    /// Initial posture.
    pub initial: InitialSpec,
    /// The segments.
    pub segments: Vec<SegmentSpec>,
    /// GIWC planning options.
    #[serde(default)]
    pub planning: PlanningSpec,
    /// IK options.
    #[serde(default)]
    pub ik: IkSpec,
    /// Retiming options.
    #[serde(default)]
    pub retiming: RetimingSpec,
    /// Actuator limits of the retiming (default: the URDF's velocity and effort limits).
    #[serde(default)]
    pub limits: crate::limits::LimitsSpec,
}

fn one() -> f64 {
    1.0
}
fn two() -> f64 {
    2.0
}
fn four() -> usize {
    4
}
fn ten() -> f64 {
    10.0
}
fn twenty() -> f64 {
    20.0
}
fn hundred() -> usize {
    100
}
fn w_link() -> f64 {
    0.1
}
/// `ik.com_blend` when the file gives none and every move is at least 1 path unit long.
pub const DEFAULT_COM_BLEND: f64 = 0.25;

fn check_dt() -> f64 {
    0.001
}

fn w_posture() -> f64 {
    1e-5
}
fn clearance() -> f64 {
    0.01
}

fn joint_range() -> f64 {
    0.95
}
fn dt() -> f64 {
    0.01
}
fn gravity() -> [f64; 3] {
    stance_contact::scene::STANDARD_GRAVITY
}

fn opt_vec3<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<[f64; 3]>, D::Error> {
    strict::vec3(d).map(Some)
}
fn opt_mat3<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<[[f64; 3]; 3]>, D::Error> {
    strict::mat3(d).map(Some)
}
fn vec2<'de, D: serde::Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
    use serde::de::Error;
    let v: Vec<f64> = Vec::deserialize(d)?;
    let len = v.len();
    v.try_into()
        .map_err(|_| D::Error::invalid_length(len, &"2 numbers [x, y]"))
}
fn opt_vec2<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
    vec2(d).map(Some)
}
