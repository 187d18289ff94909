//! Scene files (JSON or TOML): mass, gravity, contacts, friction model. The format is the
//! project's command-line contract:
//!
//! ```text
//! {"mass": kg, "gravity": [gx, gy, gz], "contacts": [{"name", "position": [x, y, z],
//!   "rotation": [[3x3 row-major, contact frame -> world]], "shape": {"rectangle":
//!   {"half_length": X, "half_width": Y}} | {"polygon": [[x, y], ...]} | "point",
//!   "friction": mu}], "friction_model": {"sides": 4, "approximation": "outer" | "inner"}}
//! ```
//!
//! `gravity` defaults to `[0, 0, -9.81]`, `rotation` to the identity, `friction_model` to the
//! paper's outer 4-sided pyramid. Unknown keys are rejected.

use serde::{Deserialize, Serialize};

use crate::tol::ContactTolerances;
use crate::{Contact, ContactError, FrictionModel, Shape, Stance};

/// Standard gravity (m/s^2), pointing down the world z axis.
pub const STANDARD_GRAVITY: [f64; 3] = [0.0, 0.0, -9.81];

fn default_gravity() -> [f64; 3] {
    STANDARD_GRAVITY
}
fn identity() -> [[f64; 3]; 3] {
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
}

/// Shape of a contact in a scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum ShapeSpec {
    /// A point contact.
    Point,
    /// A rectangle centred on the contact origin.
    Rectangle {
        /// Half size along x (m).
        half_length: f64,
        /// Half size along y (m).
        half_width: f64,
    },
    /// A convex polygon, vertices `[x, y]` in the contact frame.
    Polygon(Vec<[f64; 2]>),
}

/// One contact of a scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Name (for messages and outputs).
    pub name: String,
    /// Contact frame origin, world coordinates (m).
    pub position: [f64; 3],
    /// Rotation, row-major, contact frame -> world (default identity).
    #[serde(default = "identity")]
    pub rotation: [[f64; 3]; 3],
    /// Contact shape.
    pub shape: ShapeSpec,
    /// Friction coefficient mu (>= 0).
    pub friction: f64,
}

/// A scene: the robot's mass, gravity, contacts and friction model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Total mass (kg, > 0).
    pub mass: f64,
    /// Gravity (m/s^2; default `[0, 0, -9.81]`).
    #[serde(default = "default_gravity")]
    pub gravity: [f64; 3],
    /// Contacts (at least one).
    pub contacts: Vec<ContactSpec>,
    /// Friction model (default: outer 4-sided pyramid).
    #[serde(default)]
    pub friction_model: FrictionModel,
}

impl Scene {
    /// Validates the scene (mass > 0, finite gravity, every contact) and builds its stance.
    ///
    /// ```
    /// use stance_contact::Scene;
    /// let scene: Scene = serde_json::from_str(r#"{"mass": 40, "contacts": [
    ///     {"name": "LF", "position": [0, 0, 0], "shape": {"rectangle": {"half_length": 0.11, "half_width": 0.065}}, "friction": 0.7}]}"#).unwrap();
    /// assert_eq!(scene.stance().unwrap().contacts().len(), 1);
    /// ```
    pub fn stance(&self) -> Result<Stance, ContactError> {
        self.stance_with(&ContactTolerances::default())
    }

    /// [`Scene::stance`] with explicit tolerances.
    ///
    /// ```
    /// # use stance_contact::examples;
    /// let s = examples::box_climbing().stance_with(&Default::default()).unwrap();
    /// assert_eq!(s.contacts().len(), 2);
    /// ```
    pub fn stance_with(&self, tol: &ContactTolerances) -> Result<Stance, ContactError> {
        if !self.mass.is_finite() || self.mass <= 0.0 {
            return Err(ContactError::BadMass(self.mass));
        }
        if self.gravity.iter().any(|x| !x.is_finite()) {
            return Err(ContactError::NonFinite {
                what: "gravity".into(),
            });
        }
        let contacts = self
            .contacts
            .iter()
            .map(|c| {
                let shape = match &c.shape {
                    ShapeSpec::Point => Shape::Point,
                    ShapeSpec::Rectangle {
                        half_length,
                        half_width,
                    } => Shape::Rectangle {
                        half_length: *half_length,
                        half_width: *half_width,
                    },
                    ShapeSpec::Polygon(v) => Shape::Polygon(v.clone()),
                };
                Contact::new(&c.name, c.position, c.rotation, shape, c.friction, tol)
            })
            .collect::<Result<Vec<_>, _>>()?;
        Stance::new(contacts, self.friction_model)
    }
}
