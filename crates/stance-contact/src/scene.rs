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
//! paper's outer 4-sided pyramid. Unknown keys are rejected, and so are arrays of the wrong
//! length (a 4-number position, a ragged rotation row, a 3-number polygon vertex): the TOML
//! reader would otherwise drop the extra numbers silently.

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

/// Fixed-length arrays that reject extra elements in every format (`deserialize_with`): a
/// TOML `[f64; 3]` would otherwise drop the extra numbers silently. Public for the other crates'
/// file formats.
pub mod strict {
    use serde::de::{Deserialize, Deserializer, Error};

    fn exact<'de, D: Deserializer<'de>, const N: usize>(
        v: Vec<f64>,
        what: &'static str,
    ) -> Result<[f64; N], D::Error> {
        let len = v.len();
        v.try_into()
            .map_err(|_| D::Error::invalid_length(len, &what))
    }

    /// `[x, y, z]`.
    pub fn vec3<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 3], D::Error> {
        exact::<D, 3>(Vec::deserialize(d)?, "3 numbers [x, y, z]")
    }

    /// A 3x3 matrix, row-major.
    pub fn mat3<'de, D: Deserializer<'de>>(d: D) -> Result<[[f64; 3]; 3], D::Error> {
        let rows: Vec<Vec<f64>> = Vec::deserialize(d)?;
        let len = rows.len();
        let rows: [Vec<f64>; 3] = rows
            .try_into()
            .map_err(|_| D::Error::invalid_length(len, &"3 rows (a 3x3 matrix, row-major)"))?;
        let [a, b, c] = rows;
        let row = |r: Vec<f64>| exact::<D, 3>(r, "a matrix row of 3 numbers");
        Ok([row(a)?, row(b)?, row(c)?])
    }

    /// Points `[[x, y, z], ...]`.
    ///
    /// ```
    /// #[derive(serde::Deserialize)]
    /// struct P {
    ///     #[serde(deserialize_with = "stance_contact::scene::strict::points3")]
    ///     p: Vec<[f64; 3]>,
    /// }
    /// assert!(toml::from_str::<P>("p = [[1, 2, 3]]").is_ok());
    /// assert!(toml::from_str::<P>("p = [[1, 2, 3, 4]]").is_err());
    /// ```
    pub fn points3<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<[f64; 3]>, D::Error> {
        let rows: Vec<Vec<f64>> = Vec::deserialize(d)?;
        rows.into_iter()
            .map(|r| exact::<D, 3>(r, "a point of 3 numbers [x, y, z]"))
            .collect()
    }

    /// Polygon vertices `[[x, y], ...]`.
    pub fn points2<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<[f64; 2]>, D::Error> {
        let rows: Vec<Vec<f64>> = Vec::deserialize(d)?;
        rows.into_iter()
            .map(|r| exact::<D, 2>(r, "a vertex of 2 numbers [x, y]"))
            .collect()
    }
}

/// One contact of a scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Name (for messages and outputs).
    pub name: String,
    /// Contact frame origin, world coordinates (m).
    #[serde(deserialize_with = "strict::vec3")]
    pub position: [f64; 3],
    /// Rotation, row-major, contact frame -> world (default identity).
    #[serde(default = "identity", deserialize_with = "strict::mat3")]
    pub rotation: [[f64; 3]; 3],
    /// Contact shape.
    pub shape: Shape,
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
    #[serde(default = "default_gravity", deserialize_with = "strict::vec3")]
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
        // Names identify contacts in results and in motion files: two with one name is a
        // mistake (a copied block), not a second contact.
        for (i, c) in self.contacts.iter().enumerate() {
            if let Some(j) = self.contacts[..i].iter().position(|d| d.name == c.name) {
                return Err(ContactError::BadStance(format!(
                    "duplicate contact name {:?} (contacts {j} and {i}): give each contact its \
                     own name",
                    c.name
                )));
            }
        }
        let contacts = self
            .contacts
            .iter()
            .map(|c| {
                Contact::new(
                    &c.name,
                    c.position,
                    c.rotation,
                    c.shape.clone(),
                    c.friction,
                    tol,
                )
            })
            .collect::<Result<Vec<_>, _>>()?;
        Stance::new(contacts, self.friction_model)
    }
}
