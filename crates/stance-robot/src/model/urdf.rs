//! Building a [`Model`] from URDF text: validation of the tree and inertias, Pinocchio's joint
//! order, fixed and locked joints merged into their parent body.

use std::collections::HashMap;

use nalgebra::{Matrix3, SymmetricEigen, Vector3};

use super::{Frame, FrameKind, Joint, JointKind, Model, RootJoint, UrdfOptions};
use crate::error::RobotError;
use crate::spatial::{axis_angle, Inertia, Pose};

/// Where a URDF link ends up: the joint it moves with and its placement in that joint's frame.
#[derive(Clone, Copy)]
struct Attach {
    joint: usize,
    joint_from_link: Pose,
}

impl Model {
    /// Reads a URDF file; see [`Model::from_urdf_str`].
    ///
    /// ```
    /// let r = stance_robot::Model::from_urdf_file("no/such/file.urdf", &Default::default());
    /// assert!(matches!(r, Err(stance_robot::RobotError::Io { .. })));
    /// ```
    pub fn from_urdf_file(
        path: impl AsRef<std::path::Path>,
        options: &UrdfOptions,
    ) -> Result<Model, RobotError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| RobotError::Io {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
        Model::from_urdf_str(&text, options)
    }

    /// Builds the model from URDF text: free-flyer (or fixed) root, revolute, continuous,
    /// prismatic and fixed joints, link inertias, joint limits; the joints of
    /// `options.locked` are fixed at the given values. Mimic tags are ignored (the joints are
    /// independent, as in Pinocchio's default URDF parser); lock mimic joints if they must not
    /// move.
    ///
    /// ```
    /// use stance_robot::{Model, UrdfOptions};
    /// let m = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &UrdfOptions::default()).unwrap();
    /// assert_eq!(m.nv + 1, m.nq - 1); // free flyer (7, 6) and one continuous joint (2, 1)
    /// let locked = UrdfOptions { locked: vec![("neck".into(), 0.0)], ..Default::default() };
    /// let m2 = Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &locked).unwrap();
    /// assert_eq!(m2.nv, m.nv - 1);
    /// assert!((m2.total_mass() - m.total_mass()).abs() < 1e-12);
    /// ```
    pub fn from_urdf_str(text: &str, options: &UrdfOptions) -> Result<Model, RobotError> {
        let unknown = check_nesting(text)?;
        let robot = urdf_rs::read_from_string(text)
            .map_err(|e| RobotError::Urdf(e.to_string().replace('\n', " ")))?;
        let mut model = build(&robot, options)?;
        model.unknown_elements = unknown;
        Ok(model)
    }
}

/// Refuses XML nested deeper than [`crate::tol::MAX_URDF_DEPTH`] before the XML parsers see it:
/// they recurse once per level, and a file of tens of thousands of nested elements overflowed
/// the stack (a crash, not an error). A scan of the tags: `</...>` closes a level, `<.../>`,
/// `<?...?>`, `<!...>` (comments, CDATA, declarations) do not open one; quoted attribute
/// values may contain `>`.
///
/// Returns the elements it does not know (outside the free-form ones and namespaced
/// extensions), each once with the line of its first occurrence: they do not change the model.
fn check_nesting(text: &str) -> Result<Vec<(String, usize)>, RobotError> {
    let mut unknown: Vec<(String, usize)> = Vec::new();
    let b = text.as_bytes();
    let (mut depth, mut i, mut line) = (0usize, 0usize, 1usize);
    // Inside `<gazebo>` or `<transmission>` (from this depth on) any element may appear.
    let mut free_from: Option<usize> = None;
    while i < b.len() {
        match b[i] {
            b'\n' => line += 1,
            b'<' => {
                let rest = &text[i..];
                // Skip constructs that do not nest, to their end (comments may hold `<`).
                let skip_to = |end: &str| rest.find(end).map(|k| k + end.len());
                let skip = if rest.starts_with("<!--") {
                    skip_to("-->")
                } else if rest.starts_with("<![CDATA[") {
                    skip_to("]]>")
                } else if rest.starts_with("<?") {
                    skip_to("?>")
                } else {
                    None
                };
                if let Some(k) = skip {
                    line += rest[..k].matches('\n').count();
                    i += k;
                    continue;
                }
                // The end of the tag, outside quotes.
                let (mut j, mut quote) = (i + 1, None);
                while j < b.len() {
                    match (b[j], quote) {
                        (b'"' | b'\'', None) => quote = Some(b[j]),
                        (q, Some(open)) if q == open => quote = None,
                        (b'>', None) => break,
                        _ => {}
                    }
                    j += 1;
                }
                let tag = &b[i..j.min(b.len())];
                if tag.starts_with(b"</") {
                    depth = depth.saturating_sub(1);
                    if free_from.is_some_and(|d| depth < d) {
                        free_from = None;
                    }
                } else if !tag.starts_with(b"<!") {
                    let name: String = text[i + 1..j.min(b.len())]
                        .chars()
                        .take_while(|c| !c.is_whitespace() && *c != '/' && *c != '>')
                        .collect();
                    if free_from.is_none() {
                        let known = check_element_name(&name, line)?;
                        if !known && !unknown.iter().any(|(n, _)| *n == name) {
                            unknown.push((name.clone(), line));
                        }
                        // An extension's content is its own (listed once, by the outer name).
                        if (!known || FREE_FORM_ELEMENTS.contains(&name.as_str()))
                            && !tag.ends_with(b"/")
                        {
                            free_from = Some(depth + 1);
                        }
                    }
                }
                if !tag.starts_with(b"</") && !tag.starts_with(b"<!") && !tag.ends_with(b"/") {
                    depth += 1;
                    if depth > crate::tol::MAX_URDF_DEPTH {
                        return Err(RobotError::Urdf(format!(
                            "elements nested {depth} deep at line {line}, more than the {} a \
                             URDF can need (robot, link, visual, geometry, ...): check the file \
                             for unclosed or runaway elements",
                            crate::tol::MAX_URDF_DEPTH
                        )));
                    }
                }
                line += tag.iter().filter(|&&c| c == b'\n').count();
                i = j + 1;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    Ok(unknown)
}

/// The elements of the URDF specification (and of its common extensions) outside the
/// free-form ones.
const URDF_ELEMENTS: &[&str] = &[
    "robot",
    "link",
    "joint",
    "inertial",
    "origin",
    "mass",
    "inertia",
    "visual",
    "collision",
    "geometry",
    "box",
    "cylinder",
    "sphere",
    "capsule",
    "mesh",
    "material",
    "color",
    "texture",
    "parent",
    "child",
    "axis",
    "calibration",
    "dynamics",
    "limit",
    "mimic",
    "safety_controller",
    "transmission",
    "gazebo",
    "xml",
    "version",
    "name",
];

/// Elements whose content is free-form (simulator and controller extensions).
const FREE_FORM_ELEMENTS: &[&str] = &["gazebo", "transmission", "plugin", "sensor"];

/// An element name one or two edits from a URDF element is a misspelling: URDF readers ignore
/// unknown elements, so `<orgin>` would silently put a link at the origin. An error naming the
/// line and the element meant. Other unknown names (extensions) pass.
///
/// Returns whether the name is known (a URDF element, a free-form one, a namespaced extension
/// or an XML construct).
fn check_element_name(name: &str, line: usize) -> Result<bool, RobotError> {
    if URDF_ELEMENTS.contains(&name)
        || FREE_FORM_ELEMENTS.contains(&name)
        || name.contains(':')
        || name.starts_with(['?', '!'])
        || name.is_empty()
    {
        return Ok(true);
    }
    if name.len() < 4 {
        return Ok(false);
    }
    let near = URDF_ELEMENTS
        .iter()
        .filter(|k| k.len() >= 4)
        .map(|k| (edit_distance(name, k), *k))
        .min();
    match near {
        Some((d, known)) if d <= 2 => Err(RobotError::Urdf(format!(
            "unknown element <{name}> at line {line}: did you mean <{known}>? (unknown elements \
             are ignored when the model is built, so a misspelled one changes the model)"
        ))),
        _ => Ok(false),
    }
}

/// Levenshtein distance (insertions, deletions, substitutions; one transposition counts two).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, &cb) in b.iter().enumerate() {
            cur[j + 1] = (prev[j] + usize::from(ca != cb))
                .min(prev[j + 1] + 1)
                .min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

/// The model of a parsed URDF, in phases: the kinematic tree ([`Tree::of`]), the locks
/// ([`locks`]), the link inertias, the universe and the root joint ([`universe`],
/// [`attach_root`]), the joints depth first ([`add_joints`]), then the subtree ranges and the
/// mass check ([`finish`]). Errors come in that order.
fn build(robot: &urdf_rs::Robot, options: &UrdfOptions) -> Result<Model, RobotError> {
    let tol = options.tolerances;
    let tree = Tree::of(robot)?;
    let locked = locks(robot, options)?;
    let link_inertia = robot
        .links
        .iter()
        .map(|l| link_inertia_of(l, tol.inertia_psd_rel))
        .collect::<Result<Vec<_>, _>>()?;
    let mut model = universe(robot, options);
    let root_attach = attach_root(&mut model, options.root);
    model.add_body(
        &robot.links[tree.root].name,
        root_attach,
        &link_inertia[tree.root],
    );
    add_joints(
        &mut model,
        robot,
        &tree,
        &locked,
        &link_inertia,
        root_attach,
    )?;
    finish(model)
}

/// The URDF's kinematic tree: unique names, one parent joint per link, one root.
struct Tree<'a> {
    /// Index of each link by name.
    link_index: HashMap<&'a str, usize>,
    /// Child joints of each link, in the byte order of their names (Pinocchio's traversal).
    children: Vec<Vec<usize>>,
    /// The one link without a parent joint.
    root: usize,
}

impl<'a> Tree<'a> {
    fn of(robot: &'a urdf_rs::Robot) -> Result<Self, RobotError> {
        let mut link_index: HashMap<&str, usize> = HashMap::new();
        for (i, l) in robot.links.iter().enumerate() {
            if link_index.insert(l.name.as_str(), i).is_some() {
                return Err(RobotError::DuplicateName {
                    kind: "link",
                    name: l.name.clone(),
                });
            }
        }
        let mut joint_names: HashMap<&str, usize> = HashMap::new();
        for (i, j) in robot.joints.iter().enumerate() {
            if joint_names.insert(j.name.as_str(), i).is_some() {
                return Err(RobotError::DuplicateName {
                    kind: "joint",
                    name: j.name.clone(),
                });
            }
        }
        if robot.links.is_empty() {
            return Err(RobotError::NotATree("the URDF has no <link>".into()));
        }
        // Parent joint of each link; children of each link.
        let mut parent_joint: Vec<Option<usize>> = vec![None; robot.links.len()];
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); robot.links.len()];
        for (ji, j) in robot.joints.iter().enumerate() {
            let link = |name: &String| {
                link_index
                    .get(name.as_str())
                    .copied()
                    .ok_or_else(|| RobotError::UnknownLink {
                        joint: j.name.clone(),
                        link: name.clone(),
                    })
            };
            let p = link(&j.parent.link)?;
            let c = link(&j.child.link)?;
            if let Some(prev) = parent_joint[c] {
                return Err(RobotError::MultipleParents {
                    link: j.child.link.clone(),
                    first: robot.joints[prev].name.clone(),
                    second: j.name.clone(),
                });
            }
            parent_joint[c] = Some(ji);
            children[p].push(ji);
        }
        for c in children.iter_mut() {
            c.sort_by(|a, b| robot.joints[*a].name.cmp(&robot.joints[*b].name));
        }
        let roots: Vec<usize> = (0..robot.links.len())
            .filter(|&l| parent_joint[l].is_none())
            .collect();
        let root = match roots.as_slice() {
            [r] => *r,
            [] => {
                return Err(RobotError::NotATree(
                    "every link has a parent joint, so the joints form a cycle; remove the joint that closes it".into(),
                ))
            }
            many => {
                let names: Vec<&str> =
                    many.iter().map(|&l| robot.links[l].name.as_str()).collect();
                return Err(RobotError::NotATree(format!(
                    "several links have no parent joint ({}); connect them with joints so that one root remains",
                    names.join(", ")
                )));
            }
        };
        Ok(Tree {
            link_index,
            children,
            root,
        })
    }
}

/// The locked joints by name: each exists, is movable, has a finite value and is locked once.
fn locks<'a>(
    robot: &urdf_rs::Robot,
    options: &'a UrdfOptions,
) -> Result<HashMap<&'a str, f64>, RobotError> {
    let mut locked: HashMap<&str, f64> = HashMap::new();
    for (name, value) in &options.locked {
        let cannot = |reason: String| RobotError::CannotLock {
            joint: name.clone(),
            reason,
        };
        let Some(j) = robot.joints.iter().find(|j| j.name == *name) else {
            return Err(cannot("no joint of that name in the URDF".into()));
        };
        if !value.is_finite() {
            return Err(cannot("the lock value is not finite".into()));
        }
        if j.joint_type == urdf_rs::JointType::Fixed {
            return Err(cannot("it is a fixed joint already".into()));
        }
        if let Some(first) = locked.insert(name.as_str(), *value) {
            return Err(cannot(format!(
                "it is locked twice (at {first} and at {value}): give each joint one value"
            )));
        }
    }
    Ok(locked)
}

/// A model holding only the universe joint and frame.
fn universe(robot: &urdf_rs::Robot, options: &UrdfOptions) -> Model {
    Model {
        name: robot.name.clone(),
        unknown_elements: Vec::new(),
        joints: vec![Joint {
            name: "universe".into(),
            kind: JointKind::Universe,
            parent: 0,
            parent_from_joint: Pose::identity(),
            idx_q: 0,
            idx_v: 0,
            lower: f64::NEG_INFINITY,
            upper: f64::INFINITY,
            velocity_limit: f64::INFINITY,
            effort_limit: f64::INFINITY,
        }],
        inertias: vec![Inertia::zero()],
        frames: vec![Frame {
            name: "universe".into(),
            kind: FrameKind::FixedJoint,
            parent_joint: 0,
            joint_from_frame: Pose::identity(),
        }],
        nq: 0,
        nv: 0,
        dof_joint: Vec::new(),
        subtree_end: Vec::new(),
        locked: options.locked.clone(),
        tolerances: options.tolerances,
    }
}

/// Where the root link goes: on a free-flyer joint (added here, with its frame) or on the
/// universe.
fn attach_root(model: &mut Model, root: RootJoint) -> Attach {
    match root {
        RootJoint::FreeFlyer => moving_joint(
            model,
            "root_joint",
            JointKind::FreeFlyer,
            0,
            Pose::identity(),
            None,
        ),
        RootJoint::Fixed => Attach {
            joint: 0,
            joint_from_link: Pose::identity(),
        },
    }
}

/// A joint that moves, with its frame; its child link is attached at the joint's origin.
fn moving_joint(
    model: &mut Model,
    name: &str,
    kind: JointKind,
    parent: usize,
    placement: Pose,
    limit: Option<&urdf_rs::JointLimit>,
) -> Attach {
    let k = model.add_joint(name.to_string(), kind, parent, placement, limit);
    model.frames.push(Frame {
        name: name.to_string(),
        kind: FrameKind::Joint,
        parent_joint: k,
        joint_from_frame: Pose::identity(),
    });
    Attach {
        joint: k,
        joint_from_link: Pose::identity(),
    }
}

/// Every joint below the root, depth first with children in name order, on an explicit stack (no
/// recursion limit on deep files); each child link's body added where its joint attaches it.
fn add_joints(
    model: &mut Model,
    robot: &urdf_rs::Robot,
    tree: &Tree,
    locked: &HashMap<&str, f64>,
    link_inertia: &[Inertia],
    root_attach: Attach,
) -> Result<(), RobotError> {
    let mut visited = vec![false; robot.links.len()];
    visited[tree.root] = true;
    let mut stack: Vec<(usize, Attach)> = tree.children[tree.root]
        .iter()
        .rev()
        .map(|&j| (j, root_attach))
        .collect();
    while let Some((ji, parent_attach)) = stack.pop() {
        let j = &robot.joints[ji];
        let c = tree.link_index[j.child.link.as_str()];
        visited[c] = true;
        let attach = add_joint_of(model, j, parent_attach, locked.get(j.name.as_str()))?;
        model.add_body(&j.child.link, attach, &link_inertia[c]);
        stack.extend(tree.children[c].iter().rev().map(|&g| (g, attach)));
    }
    if let Some(l) = visited.iter().position(|v| !v) {
        return Err(RobotError::NotATree(format!(
            "link '{}' is not reachable from the root link '{}' (a cycle of joints); remove the joint that closes it",
            robot.links[l].name, robot.links[tree.root].name
        )));
    }
    Ok(())
}

/// One URDF joint: a model joint (with its frame) when it moves, a fixed frame merged into the
/// parent body when it is fixed or locked (at its lock value). Returns where its child link goes.
fn add_joint_of(
    model: &mut Model,
    j: &urdf_rs::Joint,
    parent_attach: Attach,
    lock: Option<&f64>,
) -> Result<Attach, RobotError> {
    let placement = parent_attach
        .joint_from_link
        .compose(&Pose::from_xyz_rpy(*j.origin.xyz, *j.origin.rpy));
    let kind = joint_kind(j, model.tolerances.min_axis_norm)?;
    if j.limit.lower.is_nan() || j.limit.upper.is_nan() || j.limit.lower > j.limit.upper {
        return Err(RobotError::InvalidLimits {
            joint: j.name.clone(),
            lower: j.limit.lower,
            upper: j.limit.upper,
        });
    }
    Ok(match (kind, lock) {
        (Some(kind), None) => moving_joint(
            model,
            &j.name,
            kind,
            parent_attach.joint,
            placement,
            Some(&j.limit),
        ),
        (kind, lock) => {
            let placement = match (kind, lock) {
                (Some(kind), Some(&value)) => placement.compose(&locked_motion(&kind, value)),
                _ => placement,
            };
            model.frames.push(Frame {
                name: j.name.clone(),
                kind: FrameKind::FixedJoint,
                parent_joint: parent_attach.joint,
                joint_from_frame: placement,
            });
            Attach {
                joint: parent_attach.joint,
                joint_from_link: placement,
            }
        }
    })
}

/// Subtree ranges (parents precede children), then the check that the model has mass.
fn finish(mut model: Model) -> Result<Model, RobotError> {
    let n = model.joints.len();
    model.subtree_end = (0..n).collect();
    for i in (1..n).rev() {
        let p = model.joints[i].parent;
        if i != p {
            model.subtree_end[p] = model.subtree_end[p].max(model.subtree_end[i]);
        }
    }
    model.subtree_end[0] = n - 1;
    if n == 1 {
        return Err(RobotError::NothingMoves);
    }
    let mass = model.total_mass();
    if mass <= model.tolerances.min_total_mass {
        return Err(RobotError::MissingInertia { mass });
    }
    Ok(model)
}

impl Model {
    fn add_joint(
        &mut self,
        name: String,
        kind: JointKind,
        parent: usize,
        parent_from_joint: Pose,
        limit: Option<&urdf_rs::JointLimit>,
    ) -> usize {
        let (nq, nv) = kind.dims();
        let k = self.joints.len();
        let finite_or = |x: f64, d: f64| if x.is_finite() { x } else { d };
        let (mut lower, mut upper, mut velocity_limit, mut effort_limit) = (
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::INFINITY,
            f64::INFINITY,
        );
        // urdf-rs reads a missing <limit> as all zeros; no joint is built with such limits, so
        // they mean "no limits" (as in Pinocchio, which leaves such joints unbounded).
        let limit = limit.filter(|l| {
            !(l.lower == 0.0 && l.upper == 0.0 && l.effort == 0.0 && l.velocity == 0.0)
        });
        if let Some(l) = limit {
            if matches!(
                kind,
                JointKind::Revolute { .. } | JointKind::Prismatic { .. }
            ) {
                lower = finite_or(l.lower, f64::NEG_INFINITY);
                upper = finite_or(l.upper, f64::INFINITY);
            }
            velocity_limit = finite_or(l.velocity, f64::INFINITY);
            effort_limit = finite_or(l.effort, f64::INFINITY);
        }
        self.joints.push(Joint {
            name,
            kind,
            parent,
            parent_from_joint,
            idx_q: self.nq,
            idx_v: self.nv,
            lower,
            upper,
            velocity_limit,
            effort_limit,
        });
        self.inertias.push(Inertia::zero());
        self.dof_joint.extend(std::iter::repeat_n(k, nv));
        self.nq += nq;
        self.nv += nv;
        k
    }

    fn add_body(&mut self, link: &str, at: Attach, inertia: &Inertia) {
        self.frames.push(Frame {
            name: link.to_string(),
            kind: FrameKind::Body,
            parent_joint: at.joint,
            joint_from_frame: at.joint_from_link,
        });
        if inertia.mass > 0.0 || inertia.inertia_com.norm() > 0.0 {
            let y = inertia.transformed(&at.joint_from_link);
            self.inertias[at.joint] = self.inertias[at.joint].plus(&y);
        }
    }
}

fn joint_kind(j: &urdf_rs::Joint, min_axis_norm: f64) -> Result<Option<JointKind>, RobotError> {
    use urdf_rs::JointType as T;
    let axis = || {
        let a = Vector3::from(*j.axis.xyz);
        let n = a.norm();
        if !(n.is_finite() && n > min_axis_norm) {
            return Err(RobotError::ZeroAxis {
                joint: j.name.clone(),
            });
        }
        Ok(a / n)
    };
    Ok(match j.joint_type {
        T::Fixed => None,
        T::Revolute => Some(JointKind::Revolute { axis: axis()? }),
        T::Continuous => Some(JointKind::Continuous { axis: axis()? }),
        T::Prismatic => Some(JointKind::Prismatic { axis: axis()? }),
        ref other => {
            return Err(RobotError::UnsupportedJointType {
                joint: j.name.clone(),
                kind: format!("{other:?}").to_lowercase(),
            })
        }
    })
}

/// The joint motion of a locked joint at `value` (angle or displacement).
fn locked_motion(kind: &JointKind, value: f64) -> Pose {
    match kind {
        JointKind::Revolute { axis } | JointKind::Continuous { axis } => Pose {
            rotation: axis_angle(axis, value),
            translation: Vector3::zeros(),
        },
        JointKind::Prismatic { axis } => Pose {
            rotation: Matrix3::identity(),
            translation: axis * value,
        },
        JointKind::Universe | JointKind::FreeFlyer => Pose::identity(),
    }
}

/// The link's inertia in the link frame, after checking that it is physical.
fn link_inertia_of(l: &urdf_rs::Link, psd_rel: f64) -> Result<Inertia, RobotError> {
    let i = &l.inertial;
    let bad = |reason: String| RobotError::InvalidInertia {
        link: l.name.clone(),
        reason,
    };
    let m = i.mass.value;
    if !(m.is_finite() && m >= 0.0) {
        return Err(bad(format!("mass {m} must be finite and >= 0")));
    }
    let t = &i.inertia;
    let entries = [t.ixx, t.ixy, t.ixz, t.iyy, t.iyz, t.izz];
    if entries.iter().any(|x| !x.is_finite()) {
        return Err(bad("an inertia entry is not finite".into()));
    }
    let pose_ok = i
        .origin
        .xyz
        .iter()
        .chain(i.origin.rpy.iter())
        .all(|x| x.is_finite());
    if !pose_ok {
        return Err(bad("the <inertial><origin> is not finite".into()));
    }
    let inertia_com_local = Matrix3::new(
        t.ixx, t.ixy, t.ixz, t.ixy, t.iyy, t.iyz, t.ixz, t.iyz, t.izz,
    );
    let scale = t.ixx.abs().max(t.iyy.abs()).max(t.izz.abs());
    let eig = SymmetricEigen::new(inertia_com_local).eigenvalues;
    if eig.iter().any(|&e| e < -psd_rel * scale) {
        return Err(bad(format!(
            "the inertia matrix has a negative eigenvalue ({:.3e}); it must be positive semi-definite",
            eig.min()
        )));
    }
    let (a, b, c) = (eig[0], eig[1], eig[2]);
    let slack = psd_rel * scale;
    if a + b < c - slack || a + c < b - slack || b + c < a - slack {
        return Err(bad(
            "the principal moments violate the triangle inequality (no rigid body has them)".into(),
        ));
    }
    let frame = Pose::from_xyz_rpy(*i.origin.xyz, *i.origin.rpy);
    Ok(Inertia {
        mass: m,
        lever: frame.translation,
        inertia_com: frame.rotation * inertia_com_local * frame.rotation.transpose(),
    })
}
