//! The URDF's link geometry (`<visual>` and `<collision>`), placed on the model's joints: what
//! a viewer draws. The dynamics never read it.
//!
//! A link's geometry `G` with origin `link_from_geometry` moves with the joint the link is
//! attached to (after fixed and locked joints are merged), at
//! `joint_from_geometry = joint_from_link * link_from_geometry`; its world pose at a
//! configuration is `world_from_joint * joint_from_geometry`. A `<material>` that only names a
//! material gets the colour of the robot-level `<material>` of that name.

use super::{FrameKind, Model};
use crate::error::RobotError;
use crate::spatial::Pose;

/// A geometric primitive or mesh of the URDF, in its own frame (m).
#[derive(Debug, Clone, PartialEq)]
pub enum LinkShape {
    /// A box of full side lengths `size`, centred.
    Box {
        /// Side lengths (m).
        size: [f64; 3],
    },
    /// A cylinder along its z axis, centred.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Length (m).
        length: f64,
    },
    /// A capsule along its z axis, centred: `length` between the centres of its end spheres.
    Capsule {
        /// Radius (m).
        radius: f64,
        /// Length (m).
        length: f64,
    },
    /// A sphere.
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// A mesh file, as the URDF names it (`package://`, `file://` or a relative path).
    Mesh {
        /// The file name.
        filename: String,
        /// Scale along each axis.
        scale: [f64; 3],
    },
}

/// One `<visual>` or `<collision>` element of a link, placed on its joint.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkGeometry {
    /// The URDF link.
    pub link: String,
    /// The model joint the link moves with.
    pub joint: usize,
    /// Placement of the geometry's frame in the joint's frame.
    pub joint_from_geometry: Pose,
    /// Its shape.
    pub shape: LinkShape,
    /// Its colour (RGBA in `[0, 1]`), when the URDF gives one (for visuals).
    pub color: Option<[f64; 4]>,
}

/// The URDF's geometry: per link, its visuals and its collision shapes, in file order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RobotGeometry {
    /// `<visual>` elements.
    pub visuals: Vec<LinkGeometry>,
    /// `<collision>` elements.
    pub collisions: Vec<LinkGeometry>,
}

fn shape_of(g: &urdf_rs::Geometry) -> LinkShape {
    match g {
        urdf_rs::Geometry::Box { size } => LinkShape::Box { size: size.0 },
        urdf_rs::Geometry::Cylinder { radius, length } => LinkShape::Cylinder {
            radius: *radius,
            length: *length,
        },
        urdf_rs::Geometry::Capsule { radius, length } => LinkShape::Capsule {
            radius: *radius,
            length: *length,
        },
        urdf_rs::Geometry::Sphere { radius } => LinkShape::Sphere { radius: *radius },
        urdf_rs::Geometry::Mesh { filename, scale } => LinkShape::Mesh {
            filename: filename.clone(),
            scale: scale.map_or([1.0; 3], |s| s.0),
        },
    }
}

impl Model {
    /// The geometry of the URDF `text` this model was built from, placed on the model's
    /// joints (module doc). Links the model does not have (a different URDF) are an error.
    ///
    /// ```
    /// use stance_robot::{model::LinkShape, Model};
    /// let text = stance_robot::SMALL_HUMANOID_URDF;
    /// let m = Model::from_urdf_str(text, &Default::default()).unwrap();
    /// let g = m.geometry_from_urdf_str(text).unwrap();
    /// assert_eq!(g.visuals.len(), 26);
    /// assert!(g.visuals.iter().all(|v| !matches!(v.shape, LinkShape::Mesh { .. })));
    /// ```
    ///
    /// # Errors
    ///
    /// Text that is not a URDF, or a link that is not a frame of the model.
    pub fn geometry_from_urdf_str(&self, text: &str) -> Result<RobotGeometry, RobotError> {
        let robot = urdf_rs::read_from_string(text)
            .map_err(|e| RobotError::Urdf(e.to_string().replace('\n', " ")))?;
        let named: std::collections::HashMap<&str, [f64; 4]> = robot
            .materials
            .iter()
            .filter_map(|m| m.color.as_ref().map(|c| (m.name.as_str(), c.rgba.0)))
            .collect();
        let mut out = RobotGeometry::default();
        for link in &robot.links {
            if link.visual.is_empty() && link.collision.is_empty() {
                continue;
            }
            let frame = self
                .frames
                .iter()
                .find(|f| f.kind == FrameKind::Body && f.name == link.name)
                .ok_or_else(|| {
                    RobotError::Urdf(format!(
                        "link {:?} of the URDF is not a link of the model {:?}: give the URDF \
                         the model was built from",
                        link.name, self.name
                    ))
                })?;
            let place = |o: &urdf_rs::Pose| {
                frame
                    .joint_from_frame
                    .compose(&Pose::from_xyz_rpy(o.xyz.0, o.rpy.0))
            };
            for v in &link.visual {
                let color = v.material.as_ref().and_then(|m| {
                    m.color
                        .as_ref()
                        .map(|c| c.rgba.0)
                        .or_else(|| named.get(m.name.as_str()).copied())
                });
                out.visuals.push(LinkGeometry {
                    link: link.name.clone(),
                    joint: frame.parent_joint,
                    joint_from_geometry: place(&v.origin),
                    shape: shape_of(&v.geometry),
                    color,
                });
            }
            for c in &link.collision {
                out.collisions.push(LinkGeometry {
                    link: link.name.clone(),
                    joint: frame.parent_joint,
                    joint_from_geometry: place(&c.origin),
                    shape: shape_of(&c.geometry),
                    color: None,
                });
            }
        }
        Ok(out)
    }
}
