//! The MuJoCo model (MJCF) of a motion's robot and environment, written from the project's own
//! data: the URDF model as parsed (joint tree, placements, axes, limits, inertias with fixed and
//! locked links merged), the robot's contact surfaces and the motion's environment surfaces.
//!
//! - **Bodies** follow the model's joints in their order (Pinocchio's depth-first order, which is
//!   also MuJoCo's `qpos` order): the root body has a free joint, every other body one hinge or
//!   slide joint with the URDF's axis and range, and the inertial (mass, CoM, rotational inertia
//!   about the CoM) of the model.
//! - **Collision geometry** is primitive (MuJoCo cannot read JVRC-1's Collada meshes) and is
//!   the plan's own collision model ([`stance_motion::collision`], which the collision check
//!   and the IK's clearance use): each robot contact surface is a thin box whose face `z = 0`
//!   in the surface frame is the contact rectangle (its thickness on the robot side), with a
//!   site at the surface frame; each link has a capsule to each child joint (to detect
//!   unplanned contacts, e.g. a shin on a step edge); each environment surface is a box (or an
//!   extruded convex polygon) whose top face is the surface, as thick as the file's
//!   `thickness`. The sizes are the collision model's own (not options, so that what the
//!   plan's check measures is what MuJoCo simulates). Robot geoms collide only with
//!   environment geoms (no self-collision).
//! - **Contacts**: each environment surface's own `friction` from the motion file (or
//!   [`MjcfOptions::friction`] for every surface when given), carried by the environment geom
//!   with a higher `priority` than the robot's so that MuJoCo uses it alone, `condim` 3
//!   (sliding friction, no torsional or rolling friction), elliptic friction cones (a circle of
//!   radius `mu`, rotation invariant, made hard by [`MjcfOptions::impratio`]), soft contacts
//!   with the time constant and damping ratio of [`MjcfOptions::solref`]. Against the
//!   planning model: the paper plans with an outer 4-sided pyramid of `mu = 0.7` on 70 % of
//!   each contact's area, whose diagonals reach `0.7 sqrt 2 = 0.99`, beyond the simulator's
//!   circle of 0.9 (the planned minimum-norm forces do use them); whether the motion needs
//!   them is checked separately (the force check with the simulator's own friction, an inner
//!   8-sided pyramid of 0.9 on the full areas).
//! - **Actuators**: one per actuated joint, `force = kp ctrl - kp q - kv qdot` (a general
//!   actuator with an affine bias), saturated at the joint's torque limit of the motion
//!   (`forcerange`, the file's `[limits]`, whether the retiming enforced them or not), so that
//!   `ctrl = q* + (kv / kp) v* + tau_ff / kp` gives
//!   `tau = tau_ff + kp (q* - q) + kv (v* - qdot)`: PD tracking plus feedforward, the PD part
//!   integrated implicitly by MuJoCo's `implicitfast` integrator (stable at 1 ms with stiff
//!   gains).
//! - **Armature** (rotor inertia reflected at the joint) on every actuated joint.

use std::fmt::Write as _;

use nalgebra::{UnitQuaternion, Vector3};
use stance_contact::Shape;
use stance_robot::{JointKind, Pose};

use stance_motion::collision::{surface_box_half_sizes, CAPSULE_RADIUS, SURFACE_THICKNESS};
use stance_motion::environment::polygon_of;
use stance_motion::plan::MotionPlan;
use stance_motion::robot::bones;
use stance_motion::StanceError;

/// Options of the model.
#[derive(Debug, Clone, PartialEq)]
pub struct MjcfOptions {
    /// Simulation time step (s).
    pub timestep: f64,
    /// Friction coefficient of every contact; `None`: each environment surface's own (the
    /// motion file's `friction`).
    pub friction: Option<f64>,
    /// Contact `solref`: time constant (s) and damping ratio.
    pub solref: [f64; 2],
    /// MuJoCo's `impratio`: how much harder friction is than the normal force (elliptic cones).
    pub impratio: f64,
    /// Armature of every actuated joint (kg m^2, or kg for slides).
    pub armature: f64,
    /// Proportional gain (N m / rad).
    pub kp: f64,
    /// Derivative gain (N m s / rad).
    pub kv: f64,
}

impl Default for MjcfOptions {
    /// 1 ms step, each surface's friction (the paper simulated 0.9, which its files give),
    /// `solref` (0.002 s, 1): the stiffest
    /// contacts MuJoCo recommends at this step (time constant twice the step), `impratio` 100:
    /// friction as hard as Coulomb's (with MuJoCo's default 1, soft friction lets a loaded foot
    /// creep inside its cone: measured 18.6 mm on the box climbing's fourth segment, where
    /// forces inside a circular cone of radius 0.9 exist at every sample), armature
    /// 0.05 kg m^2, gains `kp = 10 000` N m/rad and `kv = 200`
    /// N m s/rad (a stiff position-controlled humanoid; the paper's PID gains are not
    /// published).
    ///
    /// ```
    /// assert_eq!(stance_sim::mjcf::MjcfOptions::default().timestep, 1e-3);
    /// ```
    fn default() -> Self {
        Self {
            timestep: 1e-3,
            friction: None,
            solref: [0.002, 1.0],
            impratio: 100.0,
            armature: 0.05,
            kp: 10000.0,
            kv: 200.0,
        }
    }
}

fn v3(v: &Vector3<f64>) -> String {
    format!("{} {} {}", v.x, v.y, v.z)
}

fn quat(p: &Pose) -> String {
    let q = UnitQuaternion::from_matrix(&p.rotation);
    format!("{} {} {} {}", q.w, q.i, q.j, q.k)
}

fn xml_name(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The geom name of robot surface `name`, and of its site.
pub fn surface_geom(name: &str) -> String {
    format!("surface:{name}")
}

/// The geom name of environment surface `name`.
pub fn environment_geom(name: &str) -> String {
    format!("environment:{name}")
}

/// A convex polygon's box half sizes and centre when it is an axis-aligned rectangle centred on
/// the origin, else `None`.
fn rectangle(shape: &Shape) -> Option<[f64; 2]> {
    match shape {
        Shape::Rectangle {
            half_length,
            half_width,
        } => Some([*half_length, *half_width]),
        _ => None,
    }
}

/// Writes the MJCF of the plan's robot and environment.
///
/// ```
/// use stance_motion::{experiments, plan::MotionPlan};
/// let plan = MotionPlan::new(experiments::by_name("small-sway").unwrap(), None).unwrap();
/// let xml = stance_sim::mjcf::mjcf(&plan, &Default::default()).unwrap();
/// assert!(xml.contains("<freejoint name=\"root_joint\"/>"));
/// assert!(xml.contains("surface:LF"));
/// ```
pub fn mjcf(plan: &MotionPlan, o: &MjcfOptions) -> Result<String, StanceError> {
    let m = &plan.robot.model;
    let mut x = String::new();
    let g = plan.gravity;
    let _ = writeln!(x, "<mujoco model=\"{}\">", xml_name(&plan.name));
    let _ = writeln!(
        x,
        "  <compiler angle=\"radian\" boundmass=\"1e-6\" boundinertia=\"1e-9\"/>"
    );
    let _ = writeln!(
        x,
        "  <option timestep=\"{}\" gravity=\"{} {} {}\" integrator=\"implicitfast\" \
         cone=\"elliptic\" impratio=\"{}\"/>",
        o.timestep, g[0], g[1], g[2], o.impratio
    );
    let _ = writeln!(
        x,
        "  <default>\n    <geom condim=\"3\" solref=\"{} {}\"/>\n  </default>",
        o.solref[0], o.solref[1]
    );
    // environment meshes (polygons)
    let mut assets = String::new();
    for e in &plan.environment {
        if rectangle(&e.shape).is_none() {
            let poly = polygon_of(&e.shape, &e.name, false)?;
            let mut verts = String::new();
            for p in &poly {
                let _ = write!(
                    verts,
                    "{} {} 0 {} {} {} ",
                    p[0], p[1], p[0], p[1], -e.thickness
                );
            }
            let _ = writeln!(
                assets,
                "    <mesh name=\"{}\" vertex=\"{}\"/>",
                xml_name(&environment_geom(&e.name)),
                verts.trim()
            );
        }
    }
    if !assets.is_empty() {
        let _ = writeln!(x, "  <asset>\n{assets}  </asset>");
    }
    let _ = writeln!(x, "  <worldbody>");
    for e in &plan.environment {
        let name = xml_name(&environment_geom(&e.name));
        // the surface's friction, used alone in its contacts (priority over the robot's geoms)
        let friction = format!(
            "priority=\"1\" friction=\"{} 0 0\"",
            o.friction.unwrap_or(e.friction)
        );
        let body = Pose {
            rotation: e.pose.rotation,
            translation: e.pose.translation,
        };
        let geom = match rectangle(&e.shape) {
            Some([hl, hw]) => format!(
                "<geom name=\"{name}\" type=\"box\" size=\"{hl} {hw} {}\" pos=\"0 0 {}\" \
                 contype=\"0\" conaffinity=\"1\" {friction} rgba=\"0.7 0.7 0.65 1\"/>",
                0.5 * e.thickness,
                -0.5 * e.thickness
            ),
            None => format!(
                "<geom name=\"{name}\" type=\"mesh\" mesh=\"{name}\" contype=\"0\" \
                 conaffinity=\"1\" {friction} rgba=\"0.7 0.7 0.65 1\"/>"
            ),
        };
        let _ = writeln!(
            x,
            "    <body name=\"{name}\" pos=\"{}\" quat=\"{}\">\n      {geom}\n    </body>",
            v3(&body.translation),
            quat(&body)
        );
    }
    write_body(&mut x, plan, o, 1, 2)?;
    let _ = writeln!(x, "  </worldbody>");
    // actuators, saturating at the motion's torque limits
    let _ = writeln!(x, "  <actuator>");
    let torque_of = |name: &str| {
        plan.actuator_limits.as_ref().and_then(|lp| {
            lp.names
                .iter()
                .position(|n| n == name)
                .map(|c| lp.torque[c])
                .filter(|t| t.is_finite())
        })
    };
    for j in &m.joints[2..] {
        if matches!(
            j.kind,
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } | JointKind::Continuous { .. }
        ) {
            let n = xml_name(&j.name);
            let range = torque_of(&j.name).map_or(String::new(), |t| {
                format!(" forcelimited=\"true\" forcerange=\"{} {t}\"", -t)
            });
            let _ = writeln!(
                x,
                "    <general name=\"{n}\" joint=\"{n}\" gaintype=\"fixed\" gainprm=\"{kp}\" \
                 biastype=\"affine\" biasprm=\"0 {} {}\"{range}/>",
                -o.kp,
                -o.kv,
                kp = o.kp
            );
        }
    }
    let _ = writeln!(x, "  </actuator>");
    let _ = writeln!(x, "</mujoco>");
    Ok(x)
}

/// Writes the body of joint `i` and its subtree.
fn write_body(
    x: &mut String,
    plan: &MotionPlan,
    o: &MjcfOptions,
    i: usize,
    depth: usize,
) -> Result<(), StanceError> {
    let m = &plan.robot.model;
    let j = &m.joints[i];
    let pad = "  ".repeat(depth);
    let placement = j.parent_from_joint;
    let name = xml_name(&j.name);
    let _ = writeln!(
        x,
        "{pad}<body name=\"{name}\" pos=\"{}\" quat=\"{}\">",
        v3(&placement.translation),
        quat(&placement)
    );
    match j.kind {
        JointKind::FreeFlyer => {
            let _ = writeln!(x, "{pad}  <freejoint name=\"{name}\"/>");
        }
        JointKind::Revolute { axis } | JointKind::Continuous { axis } => {
            let range = if j.lower.is_finite()
                && j.upper.is_finite()
                && matches!(j.kind, JointKind::Revolute { .. })
            {
                format!(" limited=\"true\" range=\"{} {}\"", j.lower, j.upper)
            } else {
                " limited=\"false\"".to_string()
            };
            let _ = writeln!(
                x,
                "{pad}  <joint name=\"{name}\" type=\"hinge\" axis=\"{}\"{range} armature=\"{}\"/>",
                v3(&axis),
                o.armature
            );
        }
        JointKind::Prismatic { axis } => {
            let range = if j.lower.is_finite() && j.upper.is_finite() {
                format!(" limited=\"true\" range=\"{} {}\"", j.lower, j.upper)
            } else {
                " limited=\"false\"".to_string()
            };
            let _ = writeln!(
                x,
                "{pad}  <joint name=\"{name}\" type=\"slide\" axis=\"{}\"{range} armature=\"{}\"/>",
                v3(&axis),
                o.armature
            );
        }
        JointKind::Universe => {}
    }
    let inertia = &m.inertias[i];
    let c = &inertia.inertia_com;
    let _ = writeln!(
        x,
        "{pad}  <inertial pos=\"{}\" mass=\"{}\" fullinertia=\"{} {} {} {} {} {}\"/>",
        v3(&inertia.lever),
        inertia.mass,
        c[(0, 0)],
        c[(1, 1)],
        c[(2, 2)],
        c[(0, 1)],
        c[(0, 2)],
        c[(1, 2)]
    );
    // contact surfaces on this body
    for s in &plan.robot.surfaces {
        let f = &m.frames[s.frame];
        if f.parent_joint != i {
            continue;
        }
        let [hl, hw] = surface_box_half_sizes(&s.shape, &s.name)?;
        let gname = xml_name(&surface_geom(&s.name));
        let body_from_box = f.joint_from_frame.compose(&Pose {
            rotation: nalgebra::Matrix3::identity(),
            translation: Vector3::new(0.0, 0.0, 0.5 * SURFACE_THICKNESS),
        });
        let _ = writeln!(
            x,
            "{pad}  <geom name=\"{gname}\" type=\"box\" size=\"{hl} {hw} {}\" pos=\"{}\" quat=\"{}\" \
             contype=\"1\" conaffinity=\"0\" rgba=\"0.2 0.5 0.9 1\"/>",
            0.5 * SURFACE_THICKNESS,
            v3(&body_from_box.translation),
            quat(&body_from_box),
        );
        let _ = writeln!(
            x,
            "{pad}  <site name=\"{gname}\" pos=\"{}\" quat=\"{}\" size=\"0.01\"/>",
            v3(&f.joint_from_frame.translation),
            quat(&f.joint_from_frame)
        );
    }
    // link capsules towards the children, and the children
    let children: Vec<usize> = (i + 1..m.joints.len())
        .filter(|&k| m.joints[k].parent == i)
        .collect();
    for b in bones(m, CAPSULE_RADIUS) {
        if b.parent != i || !b.collides {
            continue;
        }
        let k = b.child;
        let to = m.joints[k].parent_from_joint.translation;
        let _ = writeln!(
            x,
            "{pad}  <geom name=\"link:{name}:{}\" type=\"capsule\" fromto=\"0 0 0 {}\" size=\"{}\" \
             contype=\"1\" conaffinity=\"0\" rgba=\"0.8 0.5 0.2 1\"/>",
            xml_name(&m.joints[k].name),
            v3(&to),
            CAPSULE_RADIUS
        );
    }
    for &k in &children {
        write_body(x, plan, o, k, depth + 1)?;
    }
    let _ = writeln!(x, "{pad}</body>");
    Ok(())
}
