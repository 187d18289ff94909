//! Stage 1, validation: a motion file becomes a [`MotionPlan`] with every name resolved and
//! every number checked, before any computation; errors say what to fix.

use std::path::Path;

use nalgebra::{Matrix3, Vector3};
use stance_robot::Pose;

use super::environment::EnvSurface;
use super::robot::MotionRobot;
use super::spec::{ComTarget, InitialSpec, LinkMoveSpec, MotionSpec, RetimingSpec, SegmentSpec};
use super::stand::stand;
use crate::StanceError;

/// Where a free link goes in a move.
#[derive(Debug, Clone, PartialEq)]
pub enum LinkGoal {
    /// Offset of the origin (world axes) and rotation about the frame's own axes from the
    /// previous via-point.
    By {
        /// Offset (m).
        offset: Vector3<f64>,
        /// Rotation (identity for none).
        rotate: Matrix3<f64>,
    },
    /// A world position, and an orientation (or keep the previous one).
    To {
        /// Position (m).
        position: Vector3<f64>,
        /// Orientation, `world_from_frame`.
        rotation: Option<Matrix3<f64>>,
    },
    /// A placement on an environment surface.
    Onto {
        /// Index of the environment surface.
        surface: usize,
        /// Its placement there (`world_from_frame`).
        pose: Pose,
    },
}

impl LinkGoal {
    /// Where the link's frame is after this goal, from `from` (its previous via-point).
    ///
    /// ```
    /// use stance_motion::plan::LinkGoal;
    /// use stance_robot::Pose;
    /// let up = LinkGoal::By { offset: [0.0, 0.0, 0.1].into(), rotate: nalgebra::Matrix3::identity() };
    /// assert_eq!(up.after(&Pose::identity()).translation.z, 0.1);
    /// ```
    pub fn after(&self, from: &Pose) -> Pose {
        match self {
            LinkGoal::By { offset, rotate } => Pose {
                rotation: from.rotation * rotate,
                translation: from.translation + offset,
            },
            LinkGoal::To { position, rotation } => Pose {
                rotation: rotation.unwrap_or(from.rotation),
                translation: *position,
            },
            LinkGoal::Onto { pose, .. } => *pose,
        }
    }
}

/// A free link's via-point in a move.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkMove {
    /// Index of the robot surface.
    pub surface: usize,
    /// Where it goes.
    pub goal: LinkGoal,
}

/// A validated move.
#[derive(Debug, Clone, PartialEq)]
pub struct Move {
    /// Length in path units.
    pub duration: f64,
    /// CoM via-point (none: stay).
    pub com: Option<ComTarget>,
    /// Free-link via-points.
    pub links: Vec<LinkMove>,
}

/// A validated segment.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentPlan {
    /// Name.
    pub name: String,
    /// `(robot surface, environment surface)` of every contact.
    pub stance: Vec<(usize, usize)>,
    /// The moves.
    pub moves: Vec<Move>,
    /// Free-link weight.
    pub w_link: f64,
    /// Task gain.
    pub gain: f64,
}

/// A validated motion: robot, environment, initial configuration and segments.
#[derive(Debug, Clone)]
pub struct MotionPlan {
    /// Name.
    pub name: String,
    /// The robot.
    pub robot: MotionRobot,
    /// Gravity (m/s^2).
    pub gravity: [f64; 3],
    /// Environment surfaces.
    pub environment: Vec<EnvSurface>,
    /// Initial configuration (Pinocchio's `q`).
    pub q0: Vec<f64>,
    /// Segments.
    pub segments: Vec<SegmentPlan>,
    /// The actuated joints and the limits the retiming enforces (`None`: no limit applies, or
    /// `--no-limits`: contact stability alone).
    pub limits: Option<crate::limit_rows::LimitsPlan>,
    /// The robot's actuator limits as the file states them, enforced or not: the independent
    /// checks report the ratios to them, and the simulator's actuators saturate at their
    /// torques.
    pub actuator_limits: Option<crate::limit_rows::LimitsPlan>,
    /// The robot's bodies and the environment's solids (the collision check, the IK's
    /// clearance and the simulator's geometry).
    pub collision: super::collision::CollisionModel,
    /// Half-width of the rounding of the CoM path's corners (path units): `ik.com_blend`, or
    /// its default.
    pub com_blend: f64,
    /// The file, for the options.
    pub spec: MotionSpec,
}

fn bad(msg: String) -> StanceError {
    StanceError::BadMotion(msg)
}

/// How messages name segment `k` (from 0) called `name`: "segment 2 (step up)", or "segment 2"
/// when the file gave it no name (its default name is that).
///
/// ```
/// use stance_motion::plan::segment_label;
/// assert_eq!(segment_label(1, "step up"), "segment 2 (step up)");
/// assert_eq!(segment_label(1, "segment 2"), "segment 2");
/// ```
pub fn segment_label(k: usize, name: &str) -> String {
    let number = format!("segment {}", k + 1);
    if name == number {
        number
    } else {
        format!("{number} ({name})")
    }
}

fn finite_in(what: &str, x: f64, lo: f64, hi: f64, hint: &str) -> Result<(), StanceError> {
    if x.is_finite() && x >= lo && x <= hi {
        Ok(())
    } else {
        Err(bad(format!("{what} is {x}; {hint}")))
    }
}

fn rpy(r: [f64; 3]) -> Matrix3<f64> {
    Pose::from_xyz_rpy([0.0; 3], r).rotation
}

/// Checks the options that do not depend on the robot (also used by the command line's
/// overrides).
///
/// ```
/// let mut r = stance_motion::spec::RetimingSpec::default();
/// assert!(stance_motion::plan::check_retiming(&r).is_ok());
/// r.dt = 0.0;
/// assert!(stance_motion::plan::check_retiming(&r).is_err());
/// ```
pub fn check_retiming(r: &RetimingSpec) -> Result<(), StanceError> {
    if !(2..=crate::tol::MAX_MOTION_GRID).contains(&r.grid) {
        return Err(bad(format!(
            "retiming.grid is {}; give 2 to {} intervals per segment",
            r.grid,
            crate::tol::MAX_MOTION_GRID
        )));
    }
    finite_in(
        "retiming.dt",
        r.dt,
        crate::tol::MIN_MOTION_DT,
        f64::MAX,
        &format!(
            "give a finite output time step of at least {} s",
            crate::tol::MIN_MOTION_DT
        ),
    )?;
    finite_in(
        "retiming.check_dt",
        r.check_dt,
        crate::tol::MIN_MOTION_DT,
        f64::MAX,
        &format!(
            "give a finite time step of the checks of at least {} s",
            crate::tol::MIN_MOTION_DT
        ),
    )
}

impl MotionPlan {
    /// Validates a motion file (relative URDF paths from `base_dir`) and finds its initial
    /// configuration.
    ///
    /// ```
    /// use stance_motion::{experiments, plan::MotionPlan};
    /// let spec = experiments::by_name("small-sway").unwrap();
    /// let plan = MotionPlan::new(spec, None).unwrap();
    /// assert_eq!(plan.q0.len(), plan.robot.model.nq);
    /// ```
    pub fn new(spec: MotionSpec, base_dir: Option<&Path>) -> Result<Self, StanceError> {
        let robot = MotionRobot::load(&spec.robot, base_dir)?;
        if let Some(g) = spec.gravity.iter().find(|g| !g.is_finite()) {
            return Err(bad(format!("gravity has a non-finite entry {g}")));
        }
        let [lo, hi] = crate::tol::MOTION_GRAVITY_RANGE;
        let g = spec.gravity.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(lo..=hi).contains(&g) {
            return Err(bad(format!(
                "gravity {:?} has magnitude {g:e} m/s^2; whole-body motions support {lo} to \
                 {hi} m/s^2",
                spec.gravity
            )));
        }
        let environment = environment(&spec)?;
        check_options(&spec)?;
        let names = Names {
            robot: &robot,
            environment: &environment,
        };
        if spec.segments.is_empty() {
            return Err(bad("the motion has no segments; give at least one".into()));
        }
        let segments = spec
            .segments
            .iter()
            .enumerate()
            .map(|(k, s)| segment(k, s, &spec, &names))
            .collect::<Result<Vec<_>, _>>()?;
        let shortest = segments
            .iter()
            .flat_map(|s| s.moves.iter().map(|m| m.duration))
            .fold(f64::INFINITY, f64::min);
        let com_blend = match spec.ik.com_blend {
            Some(h) => {
                finite_in(
                    "ik.com_blend",
                    h,
                    f64::MIN_POSITIVE,
                    0.25 * shortest,
                    &format!(
                        "give a half-width > 0 and at most a quarter of the shortest move \
                         ({shortest} path units)"
                    ),
                )?;
                h
            }
            None => super::spec::DEFAULT_COM_BLEND.min(0.25 * shortest),
        };
        let q0 = initial(&spec, &names)?;
        let limits = crate::limit_rows::LimitsPlan::new(&robot.model, &spec.limits)?;
        let collision = super::collision::CollisionModel::new(&robot, &environment)?;
        Ok(Self {
            com_blend,
            collision,
            actuator_limits: limits.clone(),
            limits,
            name: spec.name.clone().unwrap_or_else(|| "motion".into()),
            robot,
            gravity: spec.gravity,
            environment,
            q0,
            segments,
            spec,
        })
    }
}

/// The environment's surfaces, names unique.
fn environment(spec: &MotionSpec) -> Result<Vec<EnvSurface>, StanceError> {
    let mut environment: Vec<EnvSurface> = Vec::new();
    for e in &spec.environment {
        if environment.iter().any(|o| o.name == e.name) {
            return Err(bad(format!(
                "two environment surfaces are named {:?}; names must be unique",
                e.name
            )));
        }
        environment.push(EnvSurface::new(e)?);
    }
    let defaults = super::collision::default_thickness(&environment);
    for ((e, t), spec) in environment.iter_mut().zip(defaults).zip(&spec.environment) {
        if spec.thickness.is_none() {
            e.thickness = t;
        }
    }
    Ok(environment)
}

/// The planning, IK and retiming options, each in its range.
fn check_options(spec: &MotionSpec) -> Result<(), StanceError> {
    finite_in(
        "ik.clearance",
        spec.ik.clearance,
        0.0,
        crate::tol::MAX_CLEARANCE,
        &format!(
            "give the distance in metres the links keep from the environment, in [0, {}] \
             (default 0.01)",
            crate::tol::MAX_CLEARANCE
        ),
    )?;
    let p = &spec.planning;
    finite_in(
        "planning.area_scale",
        p.area_scale,
        crate::tol::MIN_AREA_SCALE,
        1.0,
        "give a fraction in [1e-6, 1] (the paper: 0.7)",
    )?;
    finite_in(
        "planning.margin",
        p.margin,
        0.0,
        0.5,
        "give a fraction of the weight in [0, 0.5]",
    )?;
    if let Some(mu) = p.friction {
        finite_in(
            "planning.friction",
            mu,
            f64::MIN_POSITIVE,
            f64::MAX,
            "give a friction coefficient > 0, at most each surface's (the paper: 0.7); \
             frictionless contacts cannot hold a motion",
        )?;
    }
    p.friction_cone
        .validate()
        .map_err(|e| bad(format!("planning.friction_cone: {e}")))?;
    finite_in(
        "planning.swing.clearance",
        p.swing.clearance,
        crate::tol::MIN_SWING_CLEARANCE,
        crate::tol::MAX_CLEARANCE,
        &format!(
            "give the clearance of a swinging link in metres, in [{}, {}] (default 0.05)",
            crate::tol::MIN_SWING_CLEARANCE,
            crate::tol::MAX_CLEARANCE
        ),
    )?;
    if let Some(a) = p.switch_margin {
        finite_in(
            "planning.switch_margin",
            a,
            f64::MIN_POSITIVE,
            1.0,
            "give a fraction in (0, 1] of the largest static margin at each stance switch, or \
             leave it out for the planner to search it",
        )?;
    }
    let ik = &spec.ik;
    for (what, x) in [
        ("ik.w_com", ik.w_com),
        ("ik.w_link", ik.w_link),
        ("ik.w_posture", ik.w_posture),
    ] {
        finite_in(what, x, 0.0, f64::MAX, "give a finite weight >= 0")?;
    }
    for (what, x) in [("ik.gain", ik.gain), ("ik.contact_gain", ik.contact_gain)] {
        finite_in(
            what,
            x,
            f64::MIN_POSITIVE,
            f64::MAX,
            "give a finite gain > 0",
        )?;
    }
    finite_in(
        "ik.joint_range",
        ik.joint_range,
        f64::MIN_POSITIVE,
        1.0,
        "give a fraction in (0, 1] (the paper: 0.95)",
    )?;
    if !(1..=crate::tol::MAX_IK_SUBSTEPS).contains(&ik.substeps) {
        return Err(bad(format!(
            "ik.substeps is {}; give 1 to {}",
            ik.substeps,
            crate::tol::MAX_IK_SUBSTEPS
        )));
    }
    check_retiming(&spec.retiming)
}

/// Name lookups while a plan is built: robot surfaces and environment surfaces by name, as
/// indices, with errors listing the names there are.
struct Names<'a> {
    robot: &'a MotionRobot,
    environment: &'a [EnvSurface],
}

impl Names<'_> {
    /// Robot surface `r` placed at `at` with `yaw` on environment surface `e`: its pose, or an
    /// error when the placed surface leaves `e`'s polygon by more than the contact tolerance
    /// (the same test the stances' contacts pass later, made here before any planning: a target
    /// kilometres off its surface is a typo, not a search problem).
    fn placement(
        &self,
        r: usize,
        e: usize,
        at: [f64; 2],
        yaw: f64,
        what: &str,
    ) -> Result<Pose, StanceError> {
        let env = &self.environment[e];
        let surf = &self.robot.surfaces[r];
        let pose = env.placement(at, yaw);
        let poly = super::environment::polygon_of(&surf.shape, &surf.name, true)?;
        let outside = env.check(&pose, &poly).outside;
        if outside > crate::tol::CONTACT_OUTSIDE {
            return Err(bad(format!(
                "{what}: {:?} placed at [{}, {}] on {:?} reaches {:.4} m outside that surface \
                 (tolerance {} mm); give an `at` (metres, in {:?}'s frame) at which the whole of \
                 {:?} lies on it",
                surf.name,
                at[0],
                at[1],
                env.name,
                outside,
                crate::tol::CONTACT_OUTSIDE * 1e3,
                env.name,
                surf.name,
            )));
        }
        Ok(pose)
    }

    fn env(&self, name: &str, what: &str) -> Result<usize, StanceError> {
        self.environment
            .iter()
            .position(|e| e.name == name)
            .ok_or_else(|| {
                bad(format!(
                    "{what} names the environment surface {name:?}, which does not exist; \
                     the surfaces are {}",
                    self.environment
                        .iter()
                        .map(|e| e.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            })
    }

    /// The robot surface `name`, used by `what` (the error says where).
    fn surface(&self, name: &str, what: &str) -> Result<usize, StanceError> {
        match self.robot.surface(name) {
            Ok(s) => Ok(self
                .robot
                .surfaces
                .iter()
                .position(|o| o.name == s.name)
                .unwrap_or(0)),
            Err(StanceError::BadMotion(m)) => Err(bad(format!("{what}: {m}"))),
            Err(e) => Err(e),
        }
    }
}

/// Bounded work: a stance's contact wrench cone has one generator per friction-cone edge at
/// every contact vertex, and the double description's work grows fast with their count (two
/// feet of 64-sided cones, 512 edges: 40 s and 7 GB); a stance with more than
/// [`crate::tol::MAX_STANCE_EDGES`] is refused with the sides that fit.
fn stance_size(
    stance: &[(usize, usize)],
    spec: &MotionSpec,
    names: &Names,
    what: &str,
) -> Result<(), StanceError> {
    let vertices: usize = stance
        .iter()
        .map(|&(r, _)| match &names.robot.surfaces[r].shape {
            stance_contact::Shape::Point => 1,
            stance_contact::Shape::Rectangle { .. } => 4,
            stance_contact::Shape::Polygon(p) => p.len(),
        })
        .sum();
    let sides = spec.planning.friction_cone.sides;
    let edges = vertices * sides;
    if edges > crate::tol::MAX_STANCE_EDGES {
        return Err(bad(format!(
            "{what}: its stance has {edges} friction-cone edges ({vertices} contact vertices x \
             {sides} sides), more than the {} whose contact wrench cone is computed in seconds: \
             give planning.friction_cone at most {} sides",
            crate::tol::MAX_STANCE_EDGES,
            (crate::tol::MAX_STANCE_EDGES / vertices.max(1)).max(3)
        )));
    }
    Ok(())
}

/// Segment `k` (from 0): its stance, its moves and its task options.
fn segment(
    k: usize,
    s: &SegmentSpec,
    spec: &MotionSpec,
    names: &Names,
) -> Result<SegmentPlan, StanceError> {
    let name = s
        .name
        .clone()
        .unwrap_or_else(|| format!("segment {}", k + 1));
    let what = segment_label(k, &name);
    if s.stance.is_empty() {
        return Err(bad(format!(
            "{what} has an empty stance; give at least one contact"
        )));
    }
    let mut stance = Vec::new();
    for (rs, es) in &s.stance {
        let r = names.surface(rs, &format!("{what}, stance"))?;
        let e = names.env(es, &what)?;
        if let Some(mu) = spec.planning.friction {
            let surface_mu = names.environment[e].friction;
            if mu > surface_mu {
                return Err(bad(format!(
                    "planning.friction {mu} exceeds the friction {surface_mu} of {es:?} (used by \
                     {what}); plan with at most the surface's friction"
                )));
            }
        }
        stance.push((r, e));
    }
    stance_size(&stance, spec, names, &what)?;
    if s.moves.is_empty() {
        return Err(bad(format!(
            "{what} has no moves; give at least one (the footholds planner plans a segment \
             without moves when the motion is run)"
        )));
    }
    let mut moves = Vec::new();
    for (i, m) in s.moves.iter().enumerate() {
        let mw = format!("{what}, move {}", i + 1);
        finite_in(
            &format!("{mw}: duration"),
            m.duration,
            crate::tol::MIN_MOVE_DURATION,
            crate::tol::MAX_MOVE_DURATION,
            &format!(
                "give a length between {} and {} path units",
                crate::tol::MIN_MOVE_DURATION,
                crate::tol::MAX_MOVE_DURATION
            ),
        )?;
        if let Some(ComTarget::By(v) | ComTarget::To(v)) = &m.com {
            if v.iter().any(|x| !x.is_finite()) {
                return Err(bad(format!("{mw}: the CoM target is not finite")));
            }
        }
        let mut links: Vec<LinkMove> = Vec::new();
        for l in &m.links {
            let surface = names.surface(&l.surface, &mw)?;
            if stance.iter().any(|&(r, _)| r == surface) {
                return Err(bad(format!(
                    "{mw} moves {:?}, which is a contact of the segment's stance; \
                     move only free links",
                    l.surface
                )));
            }
            if links.iter().any(|o| o.surface == surface) {
                return Err(bad(format!("{mw} moves {:?} twice", l.surface)));
            }
            let goal = link_goal(l, surface, &mw, names)?;
            links.push(LinkMove { surface, goal });
        }
        moves.push(Move {
            duration: m.duration,
            com: m.com.clone(),
            links,
        });
    }
    let w_link = s.w_link.unwrap_or(spec.ik.w_link);
    finite_in(
        &format!("{what}: w_link"),
        w_link,
        0.0,
        f64::MAX,
        "give a finite weight >= 0",
    )?;
    let gain = s.gain.unwrap_or(spec.ik.gain);
    finite_in(
        &format!("{what}: gain"),
        gain,
        f64::MIN_POSITIVE,
        f64::MAX,
        "give a finite gain > 0",
    )?;
    Ok(SegmentPlan {
        name,
        stance,
        moves,
        w_link,
        gain,
    })
}

/// A free link's goal: exactly one of `by` (with optional `rotate_by`), `to` (with optional
/// `rpy`) or `onto` (with `at` and optional `yaw`), all finite, an `onto` placing robot surface
/// `r` on its environment surface. `mw` names the move in errors.
fn link_goal(l: &LinkMoveSpec, r: usize, mw: &str, names: &Names) -> Result<LinkGoal, StanceError> {
    let finite = |v: &Option<[f64; 3]>| v.is_none_or(|v| v.iter().all(|x| x.is_finite()));
    if !(finite(&l.by) && finite(&l.to) && finite(&l.rotate_by) && finite(&l.rpy))
        || l.at.is_some_and(|a| a.iter().any(|x| !x.is_finite()))
        || l.yaw.is_some_and(|y| !y.is_finite())
    {
        return Err(bad(format!(
            "{mw}: {:?} has a non-finite target",
            l.surface
        )));
    }
    Ok(match (&l.by, &l.to, &l.onto) {
        (Some(by), None, None) if l.rpy.is_none() && l.at.is_none() && l.yaw.is_none() => {
            LinkGoal::By {
                offset: Vector3::from(*by),
                rotate: l.rotate_by.map_or(Matrix3::identity(), rpy),
            }
        }
        (None, Some(to), None) if l.rotate_by.is_none() && l.at.is_none() && l.yaw.is_none() => {
            LinkGoal::To {
                position: Vector3::from(*to),
                rotation: l.rpy.map(rpy),
            }
        }
        (None, None, Some(onto)) if l.rotate_by.is_none() && l.rpy.is_none() => {
            let e = names.env(onto, mw)?;
            let at = l.at.ok_or_else(|| {
                bad(format!(
                    "{mw}: onto {onto:?} needs at = [x, y] on that surface"
                ))
            })?;
            LinkGoal::Onto {
                surface: e,
                pose: names.placement(r, e, at, l.yaw.unwrap_or(0.0), mw)?,
            }
        }
        _ => {
            return Err(bad(format!(
                "{mw}: {:?} needs exactly one of `by` (with optional rotate_by), \
                 `to` (with optional rpy) or `onto` (with at and optional yaw)",
                l.surface
            )))
        }
    })
}

/// The initial configuration: given, or found by standing the robot on the placed contacts
/// with the CoM at the given height (above the contacts' mean by default).
fn initial(spec: &MotionSpec, names: &Names) -> Result<Vec<f64>, StanceError> {
    let robot = names.robot;
    Ok(match &spec.initial {
        InitialSpec::Configuration(q) => {
            stance_robot::check_configuration(&robot.model, q)
                .map_err(|e| bad(format!("initial.configuration: {e}")))?;
            q.clone()
        }
        InitialSpec::Standing(st) => {
            let mut targets = Vec::new();
            let mut mean = Vector3::zeros();
            for (rs, placement) in &st.contacts {
                let r = names.surface(rs, "initial.standing")?;
                let e = names.env(&placement.surface, "initial.standing")?;
                if !(placement.at.iter().all(|x| x.is_finite()) && placement.yaw.is_finite()) {
                    return Err(bad(format!(
                        "initial.standing: {rs:?} has a non-finite placement"
                    )));
                }
                let pose =
                    names.placement(r, e, placement.at, placement.yaw, "initial.standing")?;
                mean += pose.translation;
                targets.push((robot.surfaces[r].frame, pose));
            }
            if targets.is_empty() {
                return Err(bad(
                    "initial.standing has no contacts; place at least one surface".into(),
                ));
            }
            mean /= targets.len() as f64;
            finite_in(
                "initial.standing.com_height",
                st.com_height,
                -1e6,
                1e6,
                "give a finite height (m)",
            )?;
            let xy = st.com_xy.unwrap_or([mean.x, mean.y]);
            if xy.iter().any(|x| !x.is_finite()) {
                return Err(bad("initial.standing.com_xy is not finite".into()));
            }
            stand(robot, &targets, Vector3::new(xy[0], xy[1], st.com_height))?
        }
    })
}
