//! Collisions with the environment: the robot's primitive bodies against the environment's
//! solids, their signed distances, and the collision check at every sample.
//!
//! # Model
//!
//! The one description of the robot's collision geometry, which the simulator
//! (`stance_sim::mjcf`) writes for MuJoCo too:
//!
//! - each colliding bone ([`super::robot::bones`]) is a capsule of radius [`CAPSULE_RADIUS`]
//!   from the origin of its joint to the origin of the child joint, moving with its joint;
//!   named `link:<joint>:<child>` as the simulator's geom;
//! - each robot contact surface is a box whose face `z = 0` in the surface frame is the
//!   polygon's bounding rectangle ([`surface_box_half_sizes`]), [`SURFACE_THICKNESS`] thick on
//!   the robot's side (`0 <= z <= t`: the surface normal points into the robot); named
//!   `surface:<name>`.
//!
//! Each environment surface is a solid: its rectangle (or convex polygon) extruded from its
//! plane to `z = -thickness` in its frame (the file's `thickness`, default
//! [`default_thickness`]).
//!
//! # Signed distance
//!
//! For a body `B` and a solid `S`, `d(B, S)` is the distance between their closest points when
//! they are apart and minus the depth of their overlap when they intersect (parry3d's `contact`
//! query: GJK for the distance, EPA for the depth). With it come the witness point `p` on `B`
//! and the unit normal `n` from `B` towards `S` (world axes): moving `B`'s point `p` by `dp`
//! changes the distance by `-n . dp` to first order, which the IK's clearance rows use.
//!
//! # The check
//!
//! At every sample, every body against every solid whose bounding boxes come within
//! [`crate::tol::CLEARANCE_RANGE`] (farther pairs are clear without a number), except a contact
//! surface held in the sample's segment against the surface it is on. A signed distance below
//! `-`[`crate::tol::COLLISION_PENETRATION`] is a collision, reported with the body, the surface,
//! the time and the segment; the smallest distance of each body is reported as its clearance.
//! A body that touches a solid (signed distance at most [`crate::tol::TOUCH_DISTANCE`]) it is
//! not held on for at least
//! [`crate::tol::UNPLANNED_TOUCH_TIME`] is an unplanned touch: within the penetration tolerance,
//! but what the simulator sees as an unplanned contact that may carry load (a foot that the plan
//! leaves on the floor after its stance ends). A touch that lasts until the body is held on
//! that solid is its landing, reached a little early (a landing arrives at rest, so its last
//! micrometre takes a while), and is not reported.

use nalgebra::{Matrix3, Vector3};
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::{Pose as PPose, Rotation, Vector as PVector};
use parry3d_f64::shape::{Capsule, ConvexPolyhedron, Cuboid, SharedShape};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use stance_contact::Shape;
use stance_robot::{forward_kinematics, Data, Pose};

use super::environment::{polygon_of, EnvSurface};
use super::ik_stage::SegmentPath;
use super::plan::MotionPlan;
use super::robot::{bones, MotionRobot};
use super::trajectory::TrajectorySample;
use crate::StanceError;

/// Radius of the link capsules (m). Default 3 cm: about a humanoid's shin or forearm.
pub const CAPSULE_RADIUS: f64 = 0.03;

/// Thickness of the robot's sole and hand boxes, on the robot's side of each contact surface
/// (m). Default 2 cm: a sole.
pub const SURFACE_THICKNESS: f64 = 0.02;

/// Least thickness of an environment solid (m), the default of a surface that does not face up.
/// Default 5 cm.
pub const MIN_SOLID_THICKNESS: f64 = 0.05;

/// The default thickness of each environment surface: an upward-facing surface (normal within
/// 45 degrees of the vertical, world z up) reaches down to the level of the lowest vertex of
/// all surfaces, measured along its normal, and at least [`MIN_SOLID_THICKNESS`]; any other
/// surface (a wall, a ceiling) is [`MIN_SOLID_THICKNESS`] thick.
///
/// ```
/// use stance_motion::{collision::default_thickness, environment::EnvSurface,
///     spec::EnvironmentSurfaceSpec};
/// use stance_contact::Shape;
/// let surface = |name: &str, z: f64| EnvSurface::new(&EnvironmentSurfaceSpec {
///     name: name.into(), position: [0.0, 0.0, z], rpy: None, rotation: None,
///     shape: Shape::Rectangle { half_length: 0.2, half_width: 0.2 }, friction: 0.9,
///     thickness: None }).unwrap();
/// let t = default_thickness(&[surface("floor", 0.0), surface("box", 0.3)]);
/// assert_eq!(t[0], 0.05);
/// assert!((t[1] - 0.3).abs() < 1e-12); // solid down to the floor
/// ```
pub fn default_thickness(environment: &[EnvSurface]) -> Vec<f64> {
    let world =
        |e: &EnvSurface, v: &[f64; 2]| e.pose.transform_point(&Vector3::new(v[0], v[1], 0.0)).z;
    let lowest = environment
        .iter()
        .flat_map(|e| e.polygon.iter().map(move |v| world(e, v)))
        .fold(f64::INFINITY, f64::min);
    environment
        .iter()
        .map(|e| {
            let n_z = e.pose.rotation[(2, 2)];
            if n_z < std::f64::consts::FRAC_1_SQRT_2 {
                return MIN_SOLID_THICKNESS;
            }
            let own = e
                .polygon
                .iter()
                .map(|v| world(e, v))
                .fold(f64::INFINITY, f64::min);
            ((own - lowest) / n_z).clamp(MIN_SOLID_THICKNESS, crate::tol::MAX_SOLID_THICKNESS)
        })
        .collect()
}

/// Half sizes `(x, y)` of the box of a robot contact surface: its polygon's bounding rectangle
/// about the surface frame's origin (a point gets 1 mm).
///
/// ```
/// use stance_contact::Shape;
/// let r = Shape::Rectangle { half_length: 0.1, half_width: 0.05 };
/// assert_eq!(stance_motion::collision::surface_box_half_sizes(&r, "LF").unwrap(), [0.1, 0.05]);
/// ```
pub fn surface_box_half_sizes(shape: &Shape, name: &str) -> Result<[f64; 2], StanceError> {
    let poly = polygon_of(shape, name, true)?;
    Ok([
        poly.iter().map(|p| p[0].abs()).fold(1e-3, f64::max),
        poly.iter().map(|p| p[1].abs()).fold(1e-3, f64::max),
    ])
}

/// What a robot body is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyKind {
    /// A link capsule towards child joint `child`.
    Bone {
        /// The child joint (model index).
        child: usize,
    },
    /// The box of robot contact surface `surface` (index in the robot's surfaces).
    Surface {
        /// The robot surface.
        surface: usize,
    },
}

/// A robot body of the collision model.
#[derive(Clone)]
pub struct RobotBody {
    /// Its name (the simulator's geom name).
    pub name: String,
    /// The joint it moves with (model index).
    pub joint: usize,
    /// What it is.
    pub kind: BodyKind,
    shape: SharedShape,
    joint_from_shape: PPose,
}

impl std::fmt::Debug for RobotBody {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RobotBody")
            .field("name", &self.name)
            .field("joint", &self.joint)
            .field("kind", &self.kind)
            .finish()
    }
}

/// An environment solid.
#[derive(Clone)]
pub struct Solid {
    /// Index of its environment surface.
    pub surface: usize,
    shape: SharedShape,
    pose: PPose,
    aabb: Aabb,
}

impl std::fmt::Debug for Solid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Solid")
            .field("surface", &self.surface)
            .finish()
    }
}

/// The signed distance of a body to a solid (module doc), world axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairDistance {
    /// Signed distance (m; negative: penetration depth).
    pub distance: f64,
    /// Witness point on the body (m).
    pub point: Vector3<f64>,
    /// Unit normal from the body towards the solid.
    pub normal: Vector3<f64>,
}

/// The robot's bodies and the environment's solids of a motion.
#[derive(Debug, Clone)]
pub struct CollisionModel {
    /// Robot bodies.
    pub bodies: Vec<RobotBody>,
    /// Environment solids (one per environment surface, in order).
    pub solids: Vec<Solid>,
}

fn ppose(p: &Pose) -> PPose {
    let r: &Matrix3<f64> = &p.rotation;
    let m = parry3d_f64::math::Matrix::from_cols(
        PVector::new(r[(0, 0)], r[(1, 0)], r[(2, 0)]),
        PVector::new(r[(0, 1)], r[(1, 1)], r[(2, 1)]),
        PVector::new(r[(0, 2)], r[(1, 2)], r[(2, 2)]),
    );
    PPose::from_parts(
        PVector::new(p.translation.x, p.translation.y, p.translation.z),
        Rotation::from_mat3(&m).normalize(),
    )
}

fn pvec(v: &Vector3<f64>) -> PVector {
    PVector::new(v.x, v.y, v.z)
}

fn nvec(v: PVector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

impl CollisionModel {
    /// The collision model of a robot in an environment (module doc); a plan holds its own
    /// ([`MotionPlan::collision`]).
    ///
    /// ```
    /// use stance_motion::{collision::CollisionModel, experiments, plan::MotionPlan};
    /// let plan = MotionPlan::new(experiments::by_name("small-sway").unwrap(), None).unwrap();
    /// let c = CollisionModel::new(&plan.robot, &plan.environment).unwrap();
    /// assert!(c.bodies.iter().any(|b| b.name == "surface:LF"));
    /// assert_eq!(c.solids.len(), plan.environment.len());
    /// ```
    pub fn new(robot: &MotionRobot, environment: &[EnvSurface]) -> Result<Self, StanceError> {
        let m = &robot.model;
        let mut bodies = Vec::new();
        for b in bones(m, CAPSULE_RADIUS) {
            if !b.collides {
                continue;
            }
            let to = m.joints[b.child].parent_from_joint.translation;
            bodies.push(RobotBody {
                name: format!(
                    "link:{}:{}",
                    m.joints[b.parent].name, m.joints[b.child].name
                ),
                joint: b.parent,
                kind: BodyKind::Bone { child: b.child },
                shape: SharedShape::new(Capsule::new(PVector::ZERO, pvec(&to), CAPSULE_RADIUS)),
                joint_from_shape: PPose::IDENTITY,
            });
        }
        for (k, s) in robot.surfaces.iter().enumerate() {
            let f = &m.frames[s.frame];
            let [hl, hw] = surface_box_half_sizes(&s.shape, &s.name)?;
            let joint_from_box = f.joint_from_frame.compose(&Pose {
                rotation: Matrix3::identity(),
                translation: Vector3::new(0.0, 0.0, 0.5 * SURFACE_THICKNESS),
            });
            bodies.push(RobotBody {
                name: format!("surface:{}", s.name),
                joint: f.parent_joint,
                kind: BodyKind::Surface { surface: k },
                shape: SharedShape::new(Cuboid::new(PVector::new(hl, hw, 0.5 * SURFACE_THICKNESS))),
                joint_from_shape: ppose(&joint_from_box),
            });
        }
        let mut solids = Vec::new();
        for (k, e) in environment.iter().enumerate() {
            let t = e.thickness;
            let (shape, local) = match e.shape {
                Shape::Rectangle {
                    half_length,
                    half_width,
                } => (
                    SharedShape::new(Cuboid::new(PVector::new(half_length, half_width, 0.5 * t))),
                    Pose {
                        rotation: Matrix3::identity(),
                        translation: Vector3::new(0.0, 0.0, -0.5 * t),
                    },
                ),
                _ => {
                    let pts: Vec<PVector> = e
                        .polygon
                        .iter()
                        .flat_map(|v| [PVector::new(v[0], v[1], 0.0), PVector::new(v[0], v[1], -t)])
                        .collect();
                    let hull = ConvexPolyhedron::from_convex_hull(&pts).ok_or_else(|| {
                        StanceError::BadMotion(format!(
                            "environment surface {:?}: its solid (polygon extruded by {t} m) is \
                             degenerate; give a polygon with an area",
                            e.name
                        ))
                    })?;
                    (
                        SharedShape::new(hull),
                        Pose {
                            rotation: Matrix3::identity(),
                            translation: Vector3::zeros(),
                        },
                    )
                }
            };
            let pose = ppose(&e.pose.compose(&local));
            let aabb = shape.compute_aabb(&pose);
            solids.push(Solid {
                surface: k,
                shape,
                pose,
                aabb,
            });
        }
        Ok(Self { bodies, solids })
    }

    /// The index of the body named `name` (`surface:LF`, `link:R_KNEE:R_ANKLE_R`).
    ///
    /// ```
    /// use stance_motion::{experiments, plan::MotionPlan};
    /// let plan = MotionPlan::new(experiments::by_name("small-sway").unwrap(), None).unwrap();
    /// let lf = plan.collision.body("surface:LF").unwrap();
    /// assert_eq!(plan.collision.bodies[lf].name, "surface:LF");
    /// assert!(plan.collision.body("surface:nose").is_none());
    /// ```
    pub fn body(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    /// The signed distance of body `body` to solid `solid` at the kinematics in `data` (after
    /// [`forward_kinematics`]), when their bounding boxes come within `range` (m); `None` for a
    /// farther pair.
    ///
    /// ```
    /// use stance_motion::{collision::CollisionModel, experiments, plan::MotionPlan};
    /// let plan = MotionPlan::new(experiments::by_name("small-sway").unwrap(), None).unwrap();
    /// let c = &plan.collision;
    /// let mut d = stance_robot::Data::new(&plan.robot.model);
    /// stance_robot::forward_kinematics(&plan.robot.model, &mut d, &plan.q0).unwrap();
    /// let lf = c.body("surface:LF").unwrap();
    /// let on_floor = c.distance(&d, lf, 0, 0.1).unwrap();
    /// assert!(on_floor.distance.abs() < 1e-6 && on_floor.normal.z < -0.99);
    /// ```
    pub fn distance(
        &self,
        data: &Data,
        body: usize,
        solid: usize,
        range: f64,
    ) -> Option<PairDistance> {
        let (pose, aabb) = self.placed(data, body, range);
        self.pair(&pose, &aabb, body, solid, range)
    }

    /// [`Self::distance`] of body `body` to every solid within `range`, in order, into `f`
    /// (the body is placed once).
    ///
    /// ```
    /// use stance_motion::{experiments, plan::MotionPlan};
    /// let plan = MotionPlan::new(experiments::by_name("small-sway").unwrap(), None).unwrap();
    /// let c = &plan.collision;
    /// let mut d = stance_robot::Data::new(&plan.robot.model);
    /// stance_robot::forward_kinematics(&plan.robot.model, &mut d, &plan.q0).unwrap();
    /// let lf = c.body("surface:LF").unwrap();
    /// let mut near = Vec::new();
    /// c.distances(&d, lf, 0.1, |s, x| near.push((s, x.distance)));
    /// assert_eq!(near.len(), 1);
    /// assert_eq!(near[0].1, c.distance(&d, lf, 0, 0.1).unwrap().distance);
    /// ```
    pub fn distances(
        &self,
        data: &Data,
        body: usize,
        range: f64,
        mut f: impl FnMut(usize, PairDistance),
    ) {
        let (pose, aabb) = self.placed(data, body, range);
        for solid in 0..self.solids.len() {
            if let Some(d) = self.pair(&pose, &aabb, body, solid, range) {
                f(solid, d);
            }
        }
    }

    /// The signed distance of robot surface `surface`'s box (module doc) placed with its
    /// surface frame at `world_from_surface`, to solid `solid`, when within `range` (m): where
    /// a link would be, without the robot's kinematics (the footholds planner's swing paths).
    ///
    /// ```
    /// use stance_motion::{experiments, plan::MotionPlan};
    /// let plan = MotionPlan::new(experiments::by_name("small-sway").unwrap(), None).unwrap();
    /// let lf = plan.robot.surfaces.iter().position(|s| s.name == "LF").unwrap();
    /// let above = stance_robot::Pose::from_xyz_rpy([0.0, 0.1, 0.05], [0.0; 3]);
    /// let d = plan.collision.surface_distance(lf, &above, 0, 0.1).unwrap();
    /// assert!((d.distance - 0.05).abs() < 1e-9);
    /// ```
    pub fn surface_distance(
        &self,
        surface: usize,
        world_from_surface: &Pose,
        solid: usize,
        range: f64,
    ) -> Option<PairDistance> {
        let body = self
            .bodies
            .iter()
            .position(|b| b.kind == BodyKind::Surface { surface })?;
        let shape_pose = world_from_surface.compose(&Pose {
            rotation: Matrix3::identity(),
            translation: Vector3::new(0.0, 0.0, 0.5 * SURFACE_THICKNESS),
        });
        let pose = ppose(&shape_pose);
        let aabb = self.bodies[body].shape.compute_aabb(&pose).loosened(range);
        self.pair(&pose, &aabb, body, solid, range)
    }

    /// Body `body`'s pose and its bounding box grown by `range`.
    fn placed(&self, data: &Data, body: usize, range: f64) -> (PPose, Aabb) {
        let b = &self.bodies[body];
        let pose = ppose(&data.world_from_joint[b.joint]) * b.joint_from_shape;
        let aabb = b.shape.compute_aabb(&pose).loosened(range);
        (pose, aabb)
    }

    fn pair(
        &self,
        pose: &PPose,
        aabb: &Aabb,
        body: usize,
        solid: usize,
        range: f64,
    ) -> Option<PairDistance> {
        let s = &self.solids[solid];
        if !aabb.intersects(&s.aabb) {
            return None;
        }
        let c =
            parry3d_f64::query::contact(pose, &*self.bodies[body].shape, &s.pose, &*s.shape, range)
                .ok()
                .flatten()?;
        Some(PairDistance {
            distance: c.dist,
            point: nvec(c.point1),
            normal: nvec(c.normal1),
        })
    }
}

/// The smallest clearance of one robot body over a motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClearanceInfo {
    /// The body (`link:<joint>:<child>` or `surface:<name>`).
    pub body: String,
    /// The environment surface it comes closest to.
    pub surface: String,
    /// Its signed distance (m; negative: penetration).
    pub distance: f64,
    /// When (s).
    pub t: f64,
    /// In which segment (number, from 1).
    pub segment: usize,
    /// The segment's name.
    pub segment_name: String,
}

/// A collision: a robot body deeper than [`crate::tol::COLLISION_PENETRATION`] inside an
/// environment solid.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CollisionInfo {
    /// The body.
    pub body: String,
    /// The environment surface.
    pub surface: String,
    /// Its deepest penetration (m, > 0).
    pub depth: f64,
    /// When it is deepest (s).
    pub t: f64,
    /// When it starts (s).
    pub t_first: f64,
    /// Samples in collision.
    pub samples: usize,
    /// The segment where it is deepest (number, from 1).
    pub segment: usize,
    /// The segment's name.
    pub segment_name: String,
}

/// An unplanned touch: a robot body in contact with (within [`crate::tol::TOUCH_DISTANCE`] of)
/// an environment solid it is not held on, for at least [`crate::tol::UNPLANNED_TOUCH_TIME`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TouchInfo {
    /// The body.
    pub body: String,
    /// The environment surface.
    pub surface: String,
    /// How long (s): from its first touching sample to the first sample after.
    pub duration: f64,
    /// When it starts (s).
    pub t: f64,
    /// The segment where it starts (number, from 1).
    pub segment: usize,
    /// The segment's name.
    pub segment_name: String,
}

/// What the collision check found.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CollisionCheck {
    /// Per body within [`crate::tol::CLEARANCE_RANGE`] of a surface at some sample: its
    /// smallest clearance, smallest first.
    pub clearances: Vec<ClearanceInfo>,
    /// Collisions per (body, surface), deepest first.
    pub collisions: Vec<CollisionInfo>,
    /// Deepest penetration of a checked pair (m; 0 without contact).
    pub max_penetration: f64,
    /// The longest unplanned touch of each (body, surface) that lasts, longest first.
    pub touches: Vec<TouchInfo>,
}

/// A measured pair at a sample: (body, solid, signed distance).
type MeasuredPair = (usize, usize, f64);

/// A body's closest approach: (sample, solid, signed distance).
type Closest = (usize, usize, f64);

/// The collision check at every sample (module doc), in parallel.
pub fn check_collisions(
    plan: &MotionPlan,
    model: &CollisionModel,
    paths: &[SegmentPath],
    samples: &[TrajectorySample],
) -> Result<CollisionCheck, StanceError> {
    let per_sample = measured_pairs(plan, model, paths, samples)?;
    let longest = longest_touches(model, paths, samples, &per_sample);
    let (best, hits, max_penetration) = closest_and_hits(plan, model, samples, &per_sample);
    let touches = touch_infos(plan, model, samples, &longest);
    let clearances = clearance_infos(plan, model, samples, &best);
    let mut collisions: Vec<CollisionInfo> = hits.into_iter().flatten().collect();
    collisions.sort_by(|a, b| b.depth.total_cmp(&a.depth));
    Ok(CollisionCheck {
        clearances,
        collisions,
        max_penetration,
        touches,
    })
}

/// The pairs (body, solid) within `range` (m) at configuration `q` of segment `segment`
/// (from 0), held contacts left out as in the check, with their signed distances: what a
/// viewer shows near a sample.
///
/// ```
/// use stance_motion::{collision::near_pairs, experiments, run_full, RunOptions};
/// let options = RunOptions { skip_checks: true, ..Default::default() };
/// let run = run_full(experiments::by_name("small-sway").unwrap(), &options).unwrap();
/// let mut d = stance_robot::Data::new(&run.plan.robot.model);
/// // standing: the feet are held on the floor, nothing else within 2 cm of it
/// let near = near_pairs(&run.plan, &run.paths, 0, &run.samples[0].q, 0.02, &mut d).unwrap();
/// assert!(near.is_empty());
/// ```
///
/// # Errors
///
/// A configuration that does not fit the model.
pub fn near_pairs(
    plan: &MotionPlan,
    paths: &[SegmentPath],
    segment: usize,
    q: &[f64],
    range: f64,
    data: &mut Data,
) -> Result<Vec<(usize, usize, PairDistance)>, StanceError> {
    let model = &plan.collision;
    forward_kinematics(&plan.robot.model, data, q).map_err(StanceError::Robot)?;
    let mut out = Vec::new();
    for b in 0..model.bodies.len() {
        model.distances(data, b, range, |s, d| {
            if d.distance <= range && !held_on(model, paths, segment, b, s) {
                out.push((b, s, d));
            }
        });
    }
    Ok(out)
}

/// Whether body `b` is a contact surface held on solid `s` in segment `k` (a pair the check
/// leaves out, module doc).
fn held_on(model: &CollisionModel, paths: &[SegmentPath], k: usize, b: usize, s: usize) -> bool {
    match model.bodies[b].kind {
        BodyKind::Surface { surface } => paths[k]
            .contacts
            .iter()
            .any(|c| c.surface == surface && c.environment == s),
        BodyKind::Bone { .. } => false,
    }
}

/// The segment `k` as the reports name it: its number (from 1) and its name.
fn segment_of(plan: &MotionPlan, k: usize) -> (usize, String) {
    (k + 1, plan.segments[k].name.clone())
}

/// Per sample, in parallel (one kinematics workspace per thread): every pair (body, solid)
/// within [`crate::tol::CLEARANCE_RANGE`] and its signed distance, the held contacts left out.
fn measured_pairs(
    plan: &MotionPlan,
    model: &CollisionModel,
    paths: &[SegmentPath],
    samples: &[TrajectorySample],
) -> Result<Vec<Vec<MeasuredPair>>, StanceError> {
    let m = &plan.robot.model;
    let nb = model.bodies.len();
    samples
        .par_iter()
        .map_init(
            || Data::new(m),
            |data, smp| -> Result<Vec<MeasuredPair>, StanceError> {
                forward_kinematics(m, data, &smp.q).map_err(StanceError::Robot)?;
                let mut out = Vec::new();
                for b in 0..nb {
                    model.distances(data, b, crate::tol::CLEARANCE_RANGE, |s, d| {
                        if !held_on(model, paths, smp.segment, b, s) {
                            out.push((b, s, d.distance));
                        }
                    });
                }
                Ok(out)
            },
        )
        .collect()
}

/// Per pair (index `body * solids + solid`): its longest touch, as its first sample and its
/// duration (from that sample to the first sample after it, or to the last sample for a
/// touch still open there). A touch is a run of samples where the pair's signed distance is at
/// most [`crate::tol::TOUCH_DISTANCE`]; one that ends in the contact being held is its
/// landing, early, and does not count.
fn longest_touches(
    model: &CollisionModel,
    paths: &[SegmentPath],
    samples: &[TrajectorySample],
    per_sample: &[Vec<MeasuredPair>],
) -> Vec<Option<(usize, f64)>> {
    let (nb, ns) = (model.bodies.len(), model.solids.len());
    // per pair: the sample where the current touch started, and the longest touch so far
    let mut open: Vec<Option<usize>> = vec![None; nb * ns];
    let mut longest: Vec<Option<(usize, f64)>> = vec![None; nb * ns];
    let mut touching = vec![false; nb * ns];
    for (i, pairs) in per_sample.iter().enumerate() {
        let smp = &samples[i];
        touching.iter_mut().for_each(|x| *x = false);
        for &(b, s, d) in pairs {
            if d <= crate::tol::TOUCH_DISTANCE {
                touching[b * ns + s] = true;
            }
        }
        for k in 0..nb * ns {
            match (open[k], touching[k]) {
                (None, true) => open[k] = Some(i),
                // a touch that ends in the contact being held is its landing, early
                (Some(_), false) if held_on(model, paths, smp.segment, k / ns, k % ns) => {
                    open[k] = None
                }
                (Some(start), false) => {
                    let duration = smp.t - samples[start].t;
                    if longest[k].is_none_or(|(_, l)| duration > l) {
                        longest[k] = Some((start, duration));
                    }
                    open[k] = None;
                }
                _ => {}
            }
        }
    }
    if let Some(last) = samples.last() {
        for k in 0..nb * ns {
            if let Some(start) = open[k] {
                let duration = last.t - samples[start].t;
                if longest[k].is_none_or(|(_, l)| duration > l) {
                    longest[k] = Some((start, duration));
                }
            }
        }
    }
    longest
}

/// Per body, its closest approach (sample, solid, signed distance); per pair (index
/// `body * solids + solid`), its collision (signed distance below
/// `-`[`crate::tol::COLLISION_PENETRATION`] at some sample); and the deepest penetration of
/// any measured pair (0 without contact).
fn closest_and_hits(
    plan: &MotionPlan,
    model: &CollisionModel,
    samples: &[TrajectorySample],
    per_sample: &[Vec<MeasuredPair>],
) -> (Vec<Option<Closest>>, Vec<Option<CollisionInfo>>, f64) {
    let (nb, ns) = (model.bodies.len(), model.solids.len());
    let mut best: Vec<Option<Closest>> = vec![None; nb];
    let mut hits: Vec<Option<CollisionInfo>> = vec![None; nb * ns];
    let mut max_penetration = 0.0f64;
    for (i, pairs) in per_sample.iter().enumerate() {
        let smp = &samples[i];
        for &(b, s, d) in pairs {
            if best[b].is_none_or(|(_, _, x)| d < x) {
                best[b] = Some((i, s, d));
            }
            max_penetration = max_penetration.max(-d);
            if d < -crate::tol::COLLISION_PENETRATION {
                let (segment, segment_name) = segment_of(plan, smp.segment);
                let h = hits[b * ns + s].get_or_insert_with(|| CollisionInfo {
                    body: model.bodies[b].name.clone(),
                    surface: plan.environment[s].name.clone(),
                    depth: 0.0,
                    t: smp.t,
                    t_first: smp.t,
                    samples: 0,
                    segment,
                    segment_name: segment_name.clone(),
                });
                h.samples += 1;
                if -d > h.depth {
                    h.depth = -d;
                    h.t = smp.t;
                    h.segment = segment;
                    h.segment_name = segment_name;
                }
            }
        }
    }
    (best, hits, max_penetration)
}

/// The longest touch of each pair that lasts at least [`crate::tol::UNPLANNED_TOUCH_TIME`]
/// (from [`longest_touches`]), longest first.
fn touch_infos(
    plan: &MotionPlan,
    model: &CollisionModel,
    samples: &[TrajectorySample],
    longest: &[Option<(usize, f64)>],
) -> Vec<TouchInfo> {
    let ns = model.solids.len();
    let mut touches: Vec<TouchInfo> = longest
        .iter()
        .enumerate()
        .filter_map(|(k, x)| {
            let (start, duration) = (*x)?;
            if duration < crate::tol::UNPLANNED_TOUCH_TIME {
                return None;
            }
            let (segment, segment_name) = segment_of(plan, samples[start].segment);
            Some(TouchInfo {
                body: model.bodies[k / ns].name.clone(),
                surface: plan.environment[k % ns].name.clone(),
                duration,
                t: samples[start].t,
                segment,
                segment_name,
            })
        })
        .collect();
    touches.sort_by(|a, b| b.duration.total_cmp(&a.duration));
    touches
}

/// Each body's closest approach (from [`closest_and_hits`]) as its clearance, smallest first.
fn clearance_infos(
    plan: &MotionPlan,
    model: &CollisionModel,
    samples: &[TrajectorySample],
    best: &[Option<Closest>],
) -> Vec<ClearanceInfo> {
    let mut clearances: Vec<ClearanceInfo> = best
        .iter()
        .enumerate()
        .filter_map(|(b, x)| {
            x.map(|(i, s, d)| {
                let (segment, segment_name) = segment_of(plan, samples[i].segment);
                ClearanceInfo {
                    body: model.bodies[b].name.clone(),
                    surface: plan.environment[s].name.clone(),
                    distance: d,
                    t: samples[i].t,
                    segment,
                    segment_name,
                }
            })
        })
        .collect();
    clearances.sort_by(|a, b| a.distance.total_cmp(&b.distance));
    clearances
}
