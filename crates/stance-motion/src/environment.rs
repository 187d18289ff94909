//! Environment surfaces (planar convex patches with a friction coefficient), placements on them,
//! and the check that a robot surface lies on one.
//!
//! # Math
//!
//! A surface has a frame `world_from_surface = (R, p)` whose z axis is the normal pointing out of
//! the environment, and a convex polygon in its plane `z = 0`. A robot surface (frame
//! `world_from_robot`, normal pointing into the robot, polygon `v_j`) is **on** it when every
//! vertex `x_j = world_from_robot v_j`, written in the surface frame as `y_j = R^T (x_j - p)`,
//! has `|y_j,z| <= distance` and lies inside the polygon within `outside`, and the two normals
//! make an angle below `angle` ([`crate::tol`]). Placing a robot surface "at `(x, y)` with yaw
//! `psi`" on a surface gives `world_from_robot = world_from_surface * (Rz(psi), (x, y, 0))`.

use stance_contact::{Contact, Shape};
use stance_robot::Pose;

use super::spec::EnvironmentSurfaceSpec;
use crate::StanceError;

/// An environment surface.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvSurface {
    /// Its name.
    pub name: String,
    /// `world_from_surface`.
    pub pose: Pose,
    /// Its convex polygon in the surface frame (counter-clockwise or clockwise, as given).
    pub polygon: Vec<[f64; 2]>,
    /// Its shape as given.
    pub shape: Shape,
    /// Friction coefficient.
    pub friction: f64,
    /// Thickness of its solid below the surface (m; the file's, else the default of
    /// [`super::collision::default_thickness`], set by the plan).
    pub thickness: f64,
}

/// How well a robot surface lies on an environment surface (all in metres or radians; each is
/// the worst over the robot surface's vertices).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct OnSurface {
    /// Largest distance of a vertex from the surface's plane.
    pub distance: f64,
    /// Angle between the two normals.
    pub angle: f64,
    /// Largest distance of a vertex outside the surface's polygon (0 inside).
    pub outside: f64,
}

impl OnSurface {
    /// Within the tolerances of [`crate::tol`].
    ///
    /// ```
    /// let ok = stance_motion::environment::OnSurface { distance: 1e-4, angle: 1e-3, outside: 0.0 };
    /// assert!(ok.holds());
    /// ```
    pub fn holds(&self) -> bool {
        self.distance <= crate::tol::CONTACT_DISTANCE
            && self.angle <= crate::tol::CONTACT_ANGLE
            && self.outside <= crate::tol::CONTACT_OUTSIDE
    }
}

/// How far a robot surface is from lying on an environment surface, against the tolerances,
/// for messages: "12.3 mm from its plane, normals 38.42 deg apart, 0.0 mm outside it;
/// tolerances 5 mm, 2.86 deg, 5 mm".
pub fn describe(on: &OnSurface) -> String {
    format!(
        "{:.1} mm from its plane, normals {:.2} deg apart, {:.1} mm outside it; tolerances {} mm, \
         {:.2} deg, {} mm",
        on.distance * 1e3,
        on.angle.to_degrees(),
        on.outside * 1e3,
        crate::tol::CONTACT_DISTANCE * 1e3,
        crate::tol::CONTACT_ANGLE.to_degrees(),
        crate::tol::CONTACT_OUTSIDE * 1e3,
    )
}

/// What to do about a contact of segment `k` (from 0) that is not on environment surface `env`
/// where the segment starts: place it in the initial stance, or land it in the segment before.
pub fn landing_fix(k: usize, env: &str) -> String {
    if k == 0 {
        format!("place it on {env:?} in initial.standing.contacts")
    } else {
        format!("land it there in the segment before (a move with onto = {env:?})")
    }
}

/// The polygon of a shape (a rectangle's four corners; a point as one vertex when
/// `allow_point`), validated as a contact would be.
///
/// ```
/// use stance_contact::Shape;
/// let r = Shape::Rectangle { half_length: 0.1, half_width: 0.05 };
/// assert_eq!(stance_motion::environment::polygon_of(&r, "test", false).unwrap().len(), 4);
/// assert!(stance_motion::environment::polygon_of(&Shape::Point, "test", false).is_err());
/// ```
pub fn polygon_of(
    shape: &Shape,
    what: &str,
    allow_point: bool,
) -> Result<Vec<[f64; 2]>, StanceError> {
    if *shape == Shape::Point && !allow_point {
        return Err(StanceError::BadMotion(format!(
            "{what} is a point; give a rectangle or polygon"
        )));
    }
    let shape = shape.clone();
    let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let c = Contact::new(what, [0.0; 3], eye, shape, 0.0, &Default::default())
        .map_err(|e| StanceError::BadMotion(format!("{what}: {e}")))?;
    Ok(c.vertices_local().to_vec())
}

fn rotation_matrix(m: &nalgebra::Matrix3<f64>) -> [[f64; 3]; 3] {
    [
        [m[(0, 0)], m[(0, 1)], m[(0, 2)]],
        [m[(1, 0)], m[(1, 1)], m[(1, 2)]],
        [m[(2, 0)], m[(2, 1)], m[(2, 2)]],
    ]
}

impl EnvSurface {
    /// Validates an environment surface of a motion file.
    ///
    /// ```
    /// use stance_motion::{environment::EnvSurface, spec::EnvironmentSurfaceSpec};
    /// use stance_contact::Shape;
    /// let spec = EnvironmentSurfaceSpec { name: "floor".into(), position: [0.0; 3], rpy: None,
    ///     rotation: None, shape: Shape::Rectangle { half_length: 1.0, half_width: 1.0 },
    ///     friction: 0.9, thickness: None };
    /// assert_eq!(EnvSurface::new(&spec).unwrap().polygon.len(), 4);
    /// ```
    pub fn new(spec: &EnvironmentSurfaceSpec) -> Result<Self, StanceError> {
        let what = format!("environment surface {:?}", spec.name);
        let pose = match (spec.rpy, spec.rotation) {
            (Some(_), Some(_)) => {
                return Err(StanceError::BadMotion(format!(
                    "{what}: give rpy or rotation, not both"
                )))
            }
            (Some(rpy), None) => {
                if rpy.iter().any(|x| !x.is_finite()) {
                    return Err(StanceError::BadMotion(format!(
                        "{what}: rpy must be finite"
                    )));
                }
                Pose::from_xyz_rpy(spec.position, rpy)
            }
            (None, Some(r)) => Pose {
                rotation: nalgebra::Matrix3::from_row_slice(r.as_flattened()),
                translation: spec.position.into(),
            },
            (None, None) => Pose::from_xyz_rpy(spec.position, [0.0; 3]),
        };
        let polygon = polygon_of(&spec.shape, &what, false)?;
        let extent = polygon
            .iter()
            .map(|v| v[0].hypot(v[1]))
            .fold(0.0f64, f64::max);
        if extent > crate::tol::MAX_SURFACE_EXTENT {
            return Err(StanceError::BadMotion(format!(
                "{what}: its polygon reaches {extent:.3e} m from its origin; the supported size \
                 is up to {:.0e} m: give its shape in metres, within that",
                crate::tol::MAX_SURFACE_EXTENT
            )));
        }
        if !(spec.friction.is_finite() && spec.friction >= 0.0) {
            return Err(StanceError::BadMotion(format!(
                "{what}: friction is {}; give Coulomb's coefficient, >= 0 (e.g. 0.9)",
                spec.friction
            )));
        }
        // validates the position and the rotation as a contact would be
        Contact::new(
            &what,
            spec.position,
            rotation_matrix(&pose.rotation),
            Shape::Point,
            spec.friction,
            &Default::default(),
        )
        .map_err(|e| StanceError::BadMotion(format!("{what}: {e}")))?;
        // (hypot: the squares of a position near f64::MAX overflow)
        let distance = spec.position.iter().fold(0.0f64, |d, v| d.hypot(*v));
        if distance > crate::tol::MAX_SCENE_DISTANCE {
            return Err(StanceError::BadMotion(format!(
                "{what}: its position is {distance:.3e} m from the world origin; the supported \
                 scene is within {:.0e} m of it (double precision leaves too few digits below \
                 the millimetre farther away): put the world origin near the scene",
                crate::tol::MAX_SCENE_DISTANCE
            )));
        }
        let thickness = match spec.thickness {
            None => super::collision::MIN_SOLID_THICKNESS,
            Some(t) if t.is_finite() && t > 0.0 && t <= crate::tol::MAX_SOLID_THICKNESS => t,
            Some(t) => {
                return Err(StanceError::BadMotion(format!(
                    "{what}: thickness is {t}; give the depth of its solid in metres, in (0, {}]",
                    crate::tol::MAX_SOLID_THICKNESS
                )))
            }
        };
        Ok(Self {
            name: spec.name.clone(),
            pose,
            polygon,
            shape: spec.shape.clone(),
            friction: spec.friction,
            thickness,
        })
    }

    /// `world_from_robot_surface` for a robot surface placed at `(x, y)` with yaw `yaw`.
    ///
    /// ```
    /// # use stance_motion::{environment::EnvSurface, spec::EnvironmentSurfaceSpec};
    /// # use stance_contact::Shape;
    /// # let spec = EnvironmentSurfaceSpec { name: "step".into(), position: [0.3, 0.0, 0.24],
    /// #     rpy: None, rotation: None, friction: 0.9, thickness: None,
    /// #     shape: Shape::Rectangle { half_length: 0.15, half_width: 0.5 } };
    /// let step = EnvSurface::new(&spec).unwrap();
    /// let p = step.placement([0.0, -0.1], 0.0);
    /// assert!((p.translation - nalgebra::Vector3::new(0.3, -0.1, 0.24)).norm() < 1e-15);
    /// ```
    pub fn placement(&self, at: [f64; 2], yaw: f64) -> Pose {
        self.pose
            .compose(&Pose::from_xyz_rpy([at[0], at[1], 0.0], [0.0, 0.0, yaw]))
    }

    /// The placement on this surface closest to `world_from_robot`: its origin projected onto
    /// the surface's plane, its normal along the surface's, its yaw kept. A robot surface found
    /// within the contact tolerances of a surface is in contact there, at this placement: two
    /// feet on one floor are then exactly coplanar (the IK's tracking residual, micrometres, would
    /// otherwise make their GIWC degenerate at the scale of its tolerances).
    ///
    /// ```
    /// # use stance_motion::{environment::EnvSurface, spec::EnvironmentSurfaceSpec};
    /// # use stance_contact::Shape;
    /// # let spec = EnvironmentSurfaceSpec { name: "floor".into(), position: [0.0; 3],
    /// #     rpy: None, rotation: None, friction: 0.9, thickness: None,
    /// #     shape: Shape::Rectangle { half_length: 1.0, half_width: 1.0 } };
    /// let floor = EnvSurface::new(&spec).unwrap();
    /// let foot = stance_robot::Pose::from_xyz_rpy([0.1, 0.2, 3e-5], [1e-5, -2e-5, 0.3]);
    /// let on = floor.snap(&foot);
    /// assert_eq!(on.translation.z, 0.0);
    /// assert!((on.translation.xy() - foot.translation.xy()).norm() < 1e-9);
    /// assert!((on.rotation - stance_robot::Pose::from_xyz_rpy([0.0; 3], [0.0, 0.0, 0.3]).rotation).norm() < 1e-9);
    /// ```
    pub fn snap(&self, world_from_robot: &Pose) -> Pose {
        let local = self.pose.inverse().compose(world_from_robot);
        let x_axis = local.rotation.column(0);
        let yaw = x_axis.y.atan2(x_axis.x);
        self.placement([local.translation.x, local.translation.y], yaw)
    }

    /// How well a robot surface (its frame `world_from_robot` and polygon) lies on this surface.
    ///
    /// ```
    /// # use stance_motion::{environment::EnvSurface, spec::EnvironmentSurfaceSpec};
    /// # use stance_contact::Shape;
    /// # let spec = EnvironmentSurfaceSpec { name: "floor".into(), position: [0.0; 3],
    /// #     rpy: None, rotation: None, friction: 0.9, thickness: None,
    /// #     shape: Shape::Rectangle { half_length: 1.0, half_width: 1.0 } };
    /// let floor = EnvSurface::new(&spec).unwrap();
    /// let sole = [[0.1, 0.05], [-0.1, 0.05], [-0.1, -0.05], [0.1, -0.05]];
    /// let on = floor.check(&floor.placement([0.2, 0.0], 0.3), &sole);
    /// assert!(on.holds() && on.distance < 1e-15);
    /// let off = floor.check(&floor.placement([0.95, 0.0], 0.0), &sole);
    /// assert!((off.outside - 0.05).abs() < 1e-12 && !off.holds());
    /// ```
    pub fn check(&self, world_from_robot: &Pose, robot_polygon: &[[f64; 2]]) -> OnSurface {
        let rt = self.pose.rotation.transpose();
        let mut out = OnSurface {
            distance: 0.0,
            angle: 0.0,
            outside: 0.0,
        };
        let n_env = self.pose.rotation.column(2);
        let n_rob = world_from_robot.rotation.column(2);
        out.angle = n_env.dot(&n_rob).clamp(-1.0, 1.0).acos();
        for v in robot_polygon {
            let x = world_from_robot.transform_point(&nalgebra::Vector3::new(v[0], v[1], 0.0));
            let y = rt * (x - self.pose.translation);
            out.distance = out.distance.max(y.z.abs());
            out.outside = out.outside.max(outside_distance(&self.polygon, [y.x, y.y]));
        }
        out
    }
}

/// Distance of `p` outside the convex polygon (0 inside), for either vertex order.
fn outside_distance(poly: &[[f64; 2]], p: [f64; 2]) -> f64 {
    let n = poly.len();
    let area: f64 = (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum();
    let sign = if area >= 0.0 { 1.0 } else { -1.0 };
    let mut worst = 0.0f64;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
        let len = ex.hypot(ey);
        // outward distance: to the right of a counter-clockwise edge
        let d = sign * (ex * (p[1] - a[1]) - ey * (p[0] - a[0])) / len;
        worst = worst.max(-d);
    }
    worst
}
