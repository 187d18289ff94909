//! The robot as it looks: one [`MeshView`] per drawn geometry of the URDF, placed on its joint,
//! with the packed meshes they use ([`crate::meshes`]).
//!
//! Every `<visual>` is drawn: a primitive as itself, a mesh from its file (simplified to its
//! share of [`crate::MESH_TRIANGLE_BUDGET`], shared by the visuals that name the same file
//! and scale). A visual whose mesh cannot be found or read is replaced by its link's
//! `<collision>` primitives (none: the link is not drawn; the capsules of the `links` layer
//! still are), and the page's notes say so. Colours: the visual's `<material>` (or the
//! robot-level material it names), else light grey.

use std::path::Path;

use nalgebra::{Rotation3, UnitQuaternion};
use serde::Serialize;
use stance_motion::StanceError;
use stance_robot::model::{LinkGeometry, LinkShape, RobotGeometry};
use stance_robot::{Model, Pose};

use crate::meshes::{read_mesh, resolve, MeshData, TriMesh};

/// Colour of a visual without a material (RGBA).
const DEFAULT_COLOR: [f64; 4] = [0.7, 0.7, 0.7, 1.0];

/// A drawn geometry's shape (the URDF's, in its frame; m).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ShapeView {
    /// A mesh of [`RobotLook::mesh_data`], scaled.
    Mesh {
        /// Index into the mesh data.
        data: usize,
        /// Scale along each axis.
        scale: [f64; 3],
    },
    /// A centred box.
    Box {
        /// Side lengths.
        size: [f64; 3],
    },
    /// A centred cylinder along z.
    Cylinder {
        /// Radius.
        radius: f64,
        /// Length.
        length: f64,
    },
    /// A centred capsule along z (`length` between its sphere centres).
    Capsule {
        /// Radius.
        radius: f64,
        /// Length.
        length: f64,
    },
    /// A sphere.
    Sphere {
        /// Radius.
        radius: f64,
    },
}

/// One drawn geometry (`robot.meshes` in the page data).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeshView {
    /// The URDF link.
    pub link: String,
    /// Index into `robot.joints` of the joint it moves with.
    pub joint: usize,
    /// Its placement in that joint's frame: `[x, y, z, qx, qy, qz, qw]`.
    pub origin: [f64; 7],
    /// Its shape.
    pub shape: ShapeView,
    /// RGBA in `[0, 1]`.
    pub color: [f64; 4],
    /// `"visual"`, or `"collision"` where it stands for a visual whose mesh is missing.
    pub source: &'static str,
}

/// The drawn geometry of a robot.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct RobotLook {
    /// The drawn geometries.
    pub meshes: Vec<MeshView>,
    /// The meshes they use.
    pub mesh_data: Vec<MeshData>,
    /// The URDF's `<visual>` count.
    pub urdf_visuals: usize,
    /// What could not be drawn, and why (shown under the page's table).
    #[serde(skip)]
    pub notes: Vec<String>,
}

/// `[x, y, z, qx, qy, qz, qw]` of a pose.
pub(crate) fn pose7(p: &Pose) -> [f64; 7] {
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(p.rotation));
    let t = p.translation;
    [t.x, t.y, t.z, q.i, q.j, q.k, q.w]
}

fn primitive(shape: &LinkShape) -> Option<ShapeView> {
    Some(match *shape {
        LinkShape::Box { size } => ShapeView::Box { size },
        LinkShape::Cylinder { radius, length } => ShapeView::Cylinder { radius, length },
        LinkShape::Capsule { radius, length } => ShapeView::Capsule { radius, length },
        LinkShape::Sphere { radius } => ShapeView::Sphere { radius },
        LinkShape::Mesh { .. } => return None,
    })
}

/// The drawn geometry of `model`, built from the URDF at `urdf` (`None`: the embedded small
/// humanoid's text); with `meshes` false, primitives only (mesh visuals are replaced as if
/// their files were missing, without a note).
///
/// ```
/// let m = stance_robot::Model::from_urdf_str(stance_robot::SMALL_HUMANOID_URDF, &Default::default()).unwrap();
/// let look = stance_view::robot_look(&m, None, true).unwrap();
/// assert_eq!(look.meshes.len(), look.urdf_visuals);
/// assert!(look.mesh_data.is_empty()); // boxes and cylinders only
/// ```
///
/// # Errors
///
/// An unreadable URDF, or one the model was not built from.
pub fn robot_look(
    model: &Model,
    urdf: Option<&Path>,
    meshes: bool,
) -> Result<RobotLook, StanceError> {
    let text = match urdf {
        Some(path) => std::fs::read_to_string(path).map_err(|e| {
            StanceError::BadMotion(format!("cannot read the URDF {}: {e}", path.display()))
        })?,
        None => stance_robot::SMALL_HUMANOID_URDF.to_string(),
    };
    let geometry = model
        .geometry_from_urdf_str(&text)
        .map_err(StanceError::Robot)?;
    Ok(look_of(&geometry, urdf, meshes))
}

/// One entry per mesh file: its name in the URDF and the mesh read (or why not).
type Loaded = (String, Result<TriMesh, String>);

fn look_of(geometry: &RobotGeometry, urdf: Option<&Path>, meshes: bool) -> RobotLook {
    let mut look = RobotLook {
        urdf_visuals: geometry.visuals.len(),
        ..Default::default()
    };
    // read each mesh file once
    let mut files: Vec<Loaded> = Vec::new();
    let mut file_of_visual = Vec::with_capacity(geometry.visuals.len());
    for v in &geometry.visuals {
        let LinkShape::Mesh { filename, .. } = &v.shape else {
            file_of_visual.push(None);
            continue;
        };
        if !meshes {
            file_of_visual.push(None);
            continue;
        }
        let k = files
            .iter()
            .position(|(f, _)| f == filename)
            .unwrap_or_else(|| {
                let mesh = match urdf.and_then(|u| resolve(filename, u)) {
                    Some(path) => read_mesh(&path),
                    None => Err(format!("{filename}: not found beside the URDF")),
                };
                files.push((filename.clone(), mesh));
                files.len() - 1
            });
        file_of_visual.push(Some(k));
    }
    // the budget, shared in proportion to the files' triangles
    let total: usize = files
        .iter()
        .filter_map(|(_, m)| m.as_ref().ok())
        .map(|m| m.triangles.len())
        .sum();
    let mut data_of_file = vec![None; files.len()];
    for (k, (name, mesh)) in files.iter().enumerate() {
        match mesh {
            Ok(m) if !m.triangles.is_empty() => {
                let share = if total <= crate::MESH_TRIANGLE_BUDGET {
                    m.triangles.len()
                } else {
                    (m.triangles.len() * crate::MESH_TRIANGLE_BUDGET / total).max(12)
                };
                let simple = m.within(share);
                look.mesh_data
                    .push(MeshData::pack(name, &simple, m.triangles.len()));
                data_of_file[k] = Some(look.mesh_data.len() - 1);
            }
            Ok(_) => look.notes.push(format!("mesh {name}: no triangles")),
            Err(e) => look.notes.push(format!("mesh not drawn: {e}")),
        }
    }
    for (v, file) in geometry.visuals.iter().zip(&file_of_visual) {
        let drawn = match (&v.shape, file.and_then(|k| data_of_file[k])) {
            (LinkShape::Mesh { scale, .. }, Some(data)) => Some(ShapeView::Mesh {
                data,
                scale: *scale,
            }),
            (shape, _) => primitive(shape),
        };
        match drawn {
            Some(shape) => push(&mut look, v, shape, "visual"),
            None => {
                // the link's collision primitives stand for it
                let stand_ins: Vec<&LinkGeometry> = geometry
                    .collisions
                    .iter()
                    .filter(|c| c.link == v.link && primitive(&c.shape).is_some())
                    .collect();
                if stand_ins.is_empty() && meshes {
                    look.notes.push(format!(
                        "link {}: its mesh is missing and it has no collision primitive",
                        v.link
                    ));
                }
                for c in stand_ins {
                    let mut c = c.clone();
                    c.color = v.color;
                    if let Some(shape) = primitive(&c.shape) {
                        push(&mut look, &c, shape, "collision");
                    }
                }
            }
        }
    }
    look
}

fn push(look: &mut RobotLook, g: &LinkGeometry, shape: ShapeView, source: &'static str) {
    if g.joint == 0 {
        // fixed to the world (a fixed-base robot's root): not played back
        return;
    }
    look.meshes.push(MeshView {
        link: g.link.clone(),
        joint: g.joint - 1,
        origin: pose7(&g.joint_from_geometry),
        shape,
        color: g.color.unwrap_or(DEFAULT_COLOR),
        source,
    });
}
