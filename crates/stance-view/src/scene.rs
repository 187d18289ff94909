//! The view of a scene: its contacts, friction pyramids, static polygon and robust region.

use polycone::polytope::polyhedron_from_halfspaces;
use stance_contact::equilibrium::{EquilibriumOptions, PolygonWorkspace, RobustRegion};
use stance_contact::{GiwcOptions, Scene};

use super::{
    round3, scale_of, ContactView, PolygonView, RegionView, StanceView, TableView, ViewData,
};
use stance_motion::StanceError;

/// What to compute for a scene's view.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SceneViewOptions {
    /// Height of the CoM (m) where the static polygon is drawn (default: 0.8 m above the
    /// highest contact).
    pub com_height: Option<f64>,
    /// The gravity-like vectors of the robust region `M` (default: the scene's gravity and four
    /// tilts of it by 10 % of its norm along the world's x and y axes: the CoM positions that stay
    /// statically stable under horizontal accelerations of 0.1 g).
    pub gravities: Vec<[f64; 3]>,
}

/// The default gravity-like vectors of [`SceneViewOptions::gravities`].
fn tilts(g: [f64; 3]) -> Vec<[f64; 3]> {
    let n = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    let d = 0.1 * n;
    vec![
        g,
        [g[0] + d, g[1], g[2]],
        [g[0] - d, g[1], g[2]],
        [g[0], g[1] + d, g[2]],
        [g[0], g[1] - d, g[2]],
    ]
}

/// Computes what the page shows of `scene` (named `title`).
///
/// An invalid scene is an error; a polygon or region that cannot be computed (for example a
/// lower-dimensional GIWC) is a note in the view, and the rest is drawn.
///
/// ```
/// use stance_view::{scene_view, SceneViewOptions};
/// let scene = stance_contact::examples::double_support_flat();
/// let v = scene_view(&scene, "double-support", &SceneViewOptions::default()).unwrap();
/// assert_eq!(v.stances[0].contacts.len(), 2);
/// assert_eq!(v.stances[0].polygon.as_ref().unwrap().status, "bounded");
/// assert_eq!(v.region.as_ref().unwrap().status, "bounded");
/// ```
pub fn scene_view(
    scene: &Scene,
    title: &str,
    options: &SceneViewOptions,
) -> Result<ViewData, StanceError> {
    let stance = scene.stance()?;
    let model = stance.friction_model();
    let contacts: Vec<ContactView> = stance
        .contacts()
        .iter()
        .map(|c| ContactView::of(c, model))
        .collect();
    let top = contacts
        .iter()
        .flat_map(|c| c.vertices.iter().chain(std::iter::once(&c.position)))
        .map(|p| p[2])
        .fold(f64::NEG_INFINITY, f64::max);
    let height = options.com_height.unwrap_or(top + 0.8);
    if !height.is_finite() {
        return Err(StanceError::BadMotion(format!(
            "the CoM height {height} is not a finite number of metres"
        )));
    }
    let mut notes = Vec::new();
    let opts = EquilibriumOptions::default();
    let polygon =
        match PolygonWorkspace::new().static_polygon(&stance, scene.gravity, height, &opts) {
            Ok(p) => Some(PolygonView::of(&p.polygon, height)),
            Err(e) => {
                notes.push(format!("no static-equilibrium polygon: {e}"));
                None
            }
        };
    let gravities = if options.gravities.is_empty() {
        tilts(scene.gravity)
    } else {
        options.gravities.clone()
    };
    // `M` above the lowest contact: the region's math extends below the feet (a CoM under the
    // ground is as balanced as one above it), which is not what a user looks for.
    let floor = contacts
        .iter()
        .flat_map(|c| c.vertices.iter())
        .map(|p| p[2])
        .fold(f64::INFINITY, f64::min);
    let region = stance
        .u_stance(&GiwcOptions::default())
        .and_then(|giwc| RobustRegion::new(&giwc, &gravities, &opts))
        .and_then(|m| {
            let h = &m.halfspaces;
            let mut normals = h.normals.clone();
            let mut offsets = h.offsets.clone();
            normals.push([0.0, 0.0, -1.0]);
            offsets.push(-floor);
            Ok(polyhedron_from_halfspaces(
                &normals,
                &offsets,
                &opts.polytope,
            )?)
        });
    let region = match region {
        Ok(p) => Some(RegionView {
            status: p.status.name(),
            gravities: gravities.clone(),
            vertices: p.vertices.iter().map(|&p| round3(p)).collect(),
            faces: p.faces.clone(),
        }),
        Err(e) => {
            notes.push(format!("no robust region: {e}"));
            None
        }
    };
    let table = TableView {
        columns: ["contact", "position (m)", "vertices", "friction"]
            .map(String::from)
            .to_vec(),
        rows: contacts
            .iter()
            .map(|c| {
                vec![
                    c.name.clone(),
                    format!(
                        "{:.3}, {:.3}, {:.3}",
                        c.position[0], c.position[1], c.position[2]
                    ),
                    c.vertices.len().to_string(),
                    format!("{}", c.friction),
                ]
            })
            .collect(),
    };
    let subtitle = format!(
        "{} contacts, mass {} kg; static polygon at z = {:.3} m ({}); robust region M for {} gravity vectors ({})",
        contacts.len(),
        scene.mass,
        height,
        polygon.as_ref().map_or("not computed", |p| p.status),
        gravities.len(),
        region.as_ref().map_or("not computed", |r| r.status),
    );
    let stances = vec![StanceView {
        name: title.to_string(),
        t_start: None,
        t_end: None,
        contacts,
        polygon,
    }];
    Ok(ViewData {
        kind: "scene",
        scale: scale_of(&stances),
        title: title.to_string(),
        subtitle,
        gravity: scene.gravity,
        environment: Vec::new(),
        stances,
        region,
        robot: None,
        phase: None,
        forces: None,
        clearance: None,
        torque: None,
        simulation: None,
        table,
        notes,
    })
}
