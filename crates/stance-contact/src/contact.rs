//! Contacts: a pose `world_from_contact = (R, p)`, a shape and a friction coefficient, and their
//! surface contact wrench cone (paper Proposition 1, Section III-A).
//!
//! The contact frame has its origin `p` on the surface and its z axis along the surface normal
//! pointing into the robot; `R` maps contact-frame vectors to world vectors. A wrench is valid
//! iff it is the sum of valid point forces `f_j` at the vertices `v_j` of the (convex) shape:
//! `w = (sum f_j, sum v_j x f_j)` at the contact origin, in the contact frame. Hence the span form
//! `V_surf = A_surf V_point`: one generator `(e, v_j x e)` per vertex `v_j` and pyramid edge `e`.

use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};

use crate::tol::ContactTolerances;
use crate::{ContactError, FrictionModel};

pub use crate::tol::MAX_FRICTION;

/// Shape of a contact surface, in the contact frame (the plane z = 0): the one shape type of
/// contacts, scene and motion files (their `shape` key: `"point"`, `{"rectangle":
/// {"half_length": X, "half_width": Y}}` or `{"polygon": [[x, y], ...]}`), the simulator and
/// the page.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum Shape {
    /// A point contact at the frame origin.
    Point,
    /// The rectangle `[-half_length, half_length] x [-half_width, half_width]`.
    Rectangle {
        /// Half size along the contact x axis (m).
        half_length: f64,
        /// Half size along the contact y axis (m).
        half_width: f64,
    },
    /// A convex polygon, vertices `[x, y]` in order (either orientation).
    Polygon(#[serde(deserialize_with = "crate::scene::strict::points2")] Vec<[f64; 2]>),
}

impl Shape {
    /// The shape scaled by `k` about the contact origin (the rectangle's half sizes and the
    /// polygon's vertices multiplied by `k`; `k = 1`: as given).
    ///
    /// ```
    /// use stance_contact::Shape;
    /// let r = Shape::Rectangle { half_length: 0.1, half_width: 0.05 };
    /// assert_eq!(r.scaled(2.0), Shape::Rectangle { half_length: 0.2, half_width: 0.1 });
    /// ```
    pub fn scaled(&self, k: f64) -> Shape {
        match self {
            Shape::Point => Shape::Point,
            Shape::Rectangle {
                half_length,
                half_width,
            } => Shape::Rectangle {
                half_length: half_length * k,
                half_width: half_width * k,
            },
            Shape::Polygon(v) => Shape::Polygon(v.iter().map(|p| [p[0] * k, p[1] * k]).collect()),
        }
    }

    /// The largest distance of the shape from the contact origin (m; 0 for a point).
    ///
    /// ```
    /// use stance_contact::Shape;
    /// let r = Shape::Rectangle { half_length: 0.3, half_width: 0.4 };
    /// assert!((r.radius() - 0.5).abs() < 1e-15);
    /// ```
    pub fn radius(&self) -> f64 {
        match self {
            Shape::Point => 0.0,
            Shape::Rectangle {
                half_length,
                half_width,
            } => half_length.hypot(*half_width),
            Shape::Polygon(v) => v.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max),
        }
    }
}

/// A validated contact. Build it with [`Contact::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    name: String,
    position: [f64; 3],
    rotation: Matrix3<f64>,
    shape: Shape,
    friction: f64,
    vertices: Vec<[f64; 2]>,
}

fn finite(what: impl Fn() -> String, xs: &[f64]) -> Result<(), ContactError> {
    if xs.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(ContactError::NonFinite { what: what() })
    }
}

impl Contact {
    /// Validates and builds a contact: finite numbers, `0 <= friction <= MAX_FRICTION`, `rotation` (row-major,
    /// contact frame -> world) orthonormal with determinant +1, rectangle half sizes > 0, polygon
    /// convex with at least 3 vertices and area above [`ContactTolerances::min_area`].
    ///
    /// ```
    /// use stance_contact::{Contact, Shape};
    /// let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let foot = Contact::new("LF", [0.0, 0.1, 0.0], eye,
    ///     Shape::Rectangle { half_length: 0.11, half_width: 0.065 }, 0.7, &Default::default()).unwrap();
    /// assert_eq!(foot.vertices_local().len(), 4);
    /// assert!(Contact::new("bad", [0.0; 3], eye, Shape::Point, -0.1, &Default::default()).is_err());
    /// assert!(Contact::new("glue", [0.0; 3], eye, Shape::Point, 1e9, &Default::default()).is_err());
    /// ```
    pub fn new(
        name: &str,
        position: [f64; 3],
        rotation: [[f64; 3]; 3],
        shape: Shape,
        friction: f64,
        tol: &ContactTolerances,
    ) -> Result<Self, ContactError> {
        let what = |w: &str| format!("contact `{name}`: {w}");
        finite(|| what("position"), &position)?;
        finite(|| what("rotation"), rotation.as_flattened())?;
        finite(|| what("friction"), &[friction])?;
        if friction < 0.0 {
            return Err(ContactError::NegativeFriction {
                contact: name.into(),
                mu: friction,
            });
        }
        if friction > MAX_FRICTION {
            return Err(ContactError::FrictionTooLarge {
                contact: name.into(),
                mu: friction,
                max: MAX_FRICTION,
            });
        }
        let r = Matrix3::from_row_slice(rotation.as_flattened());
        let err = (r.transpose() * r - Matrix3::identity())
            .abs()
            .max()
            .max((r.determinant() - 1.0).abs());
        if err > tol.rotation {
            return Err(ContactError::NotARotation {
                contact: name.into(),
                error: err,
                tol: tol.rotation,
            });
        }
        let vertices = match &shape {
            Shape::Point => vec![[0.0, 0.0]],
            Shape::Rectangle {
                half_length,
                half_width,
            } => {
                let (x, y) = (*half_length, *half_width);
                finite(|| what("rectangle"), &[x, y])?;
                if x <= 0.0 || y <= 0.0 {
                    return Err(ContactError::BadRectangle {
                        contact: name.into(),
                        half_length: x,
                        half_width: y,
                    });
                }
                vec![[x, y], [-x, y], [-x, -y], [x, -y]]
            }
            Shape::Polygon(v) => {
                finite(|| what("polygon"), v.as_flattened())?;
                convex_polygon(name, v, tol)?
            }
        };
        Ok(Self {
            name: name.into(),
            position,
            rotation: r,
            shape,
            friction,
            vertices,
        })
    }

    /// The contact's name.
    ///
    /// ```
    /// use stance_contact::{Contact, Shape};
    /// let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let c = Contact::new("hand", [0.0; 3], eye, Shape::Point, 0.5, &Default::default()).unwrap();
    /// assert_eq!(c.name(), "hand");
    /// ```
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Origin `p` of the contact frame in world coordinates (m).
    ///
    /// ```
    /// use stance_contact::{Contact, Shape};
    /// let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let c = Contact::new("c", [1.0, 2.0, 3.0], eye, Shape::Point, 0.5, &Default::default()).unwrap();
    /// assert_eq!(c.position(), [1.0, 2.0, 3.0]);
    /// ```
    pub fn position(&self) -> [f64; 3] {
        self.position
    }

    /// Rotation `R` of `world_from_contact` (contact-frame vectors -> world vectors).
    ///
    /// ```
    /// use stance_contact::{Contact, Shape};
    /// let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let c = Contact::new("c", [0.0; 3], eye, Shape::Point, 0.5, &Default::default()).unwrap();
    /// assert_eq!(c.rotation(), nalgebra::Matrix3::identity());
    /// ```
    pub fn rotation(&self) -> Matrix3<f64> {
        self.rotation
    }

    /// The shape as given.
    ///
    /// ```
    /// use stance_contact::{Contact, Shape};
    /// let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let c = Contact::new("c", [0.0; 3], eye, Shape::Point, 0.5, &Default::default()).unwrap();
    /// assert_eq!(c.shape(), &Shape::Point);
    /// ```
    pub fn shape(&self) -> &Shape {
        &self.shape
    }

    /// Friction coefficient mu.
    ///
    /// ```
    /// use stance_contact::{Contact, Shape};
    /// let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let c = Contact::new("c", [0.0; 3], eye, Shape::Point, 0.5, &Default::default()).unwrap();
    /// assert_eq!(c.friction(), 0.5);
    /// ```
    pub fn friction(&self) -> f64 {
        self.friction
    }

    /// The same contact at `position` with `shape`, its local vertices multiplied by `k`
    /// (exact for a power of two): the contact in a length frame
    /// (`crate::equilibrium::frame`), without re-validating what a scaling keeps valid.
    pub(crate) fn rescaled(&self, position: [f64; 3], shape: Shape, k: f64) -> Contact {
        Contact {
            name: self.name.clone(),
            position,
            rotation: self.rotation,
            shape,
            friction: self.friction,
            vertices: self.vertices.iter().map(|v| [v[0] * k, v[1] * k]).collect(),
        }
    }

    /// Vertices of the contact shape in the contact frame (`[x, y]`, z = 0), counter-clockwise;
    /// a single `[0, 0]` for a point contact.
    ///
    /// ```
    /// use stance_contact::{Contact, Shape};
    /// let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let c = Contact::new("c", [0.0; 3], eye, Shape::Point, 0.5, &Default::default()).unwrap();
    /// assert_eq!(c.vertices_local(), &[[0.0, 0.0]]);
    /// ```
    pub fn vertices_local(&self) -> &[[f64; 2]] {
        &self.vertices
    }

    /// Vertices of the contact shape in world coordinates.
    ///
    /// ```
    /// use stance_contact::{Contact, Shape};
    /// let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let c = Contact::new("c", [1.0, 0.0, 0.5], eye,
    ///     Shape::Rectangle { half_length: 0.1, half_width: 0.05 }, 0.5, &Default::default()).unwrap();
    /// assert_eq!(c.vertices_world()[0], [1.1, 0.05, 0.5]);
    /// ```
    pub fn vertices_world(&self) -> Vec<[f64; 3]> {
        self.vertices
            .iter()
            .map(|v| self.world_from_contact_point([v[0], v[1], 0.0]))
            .collect()
    }

    /// Maps a contact-frame point to world coordinates: `p + R x`.
    ///
    /// ```
    /// use stance_contact::{Contact, Shape};
    /// let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let c = Contact::new("c", [1.0, 0.0, 0.0], eye, Shape::Point, 0.5, &Default::default()).unwrap();
    /// assert_eq!(c.world_from_contact_point([0.0, 1.0, 0.0]), [1.0, 1.0, 0.0]);
    /// ```
    pub fn world_from_contact_point(&self, x: [f64; 3]) -> [f64; 3] {
        let w = self.rotation * nalgebra::Vector3::from(x);
        [
            self.position[0] + w[0],
            self.position[1] + w[1],
            self.position[2] + w[2],
        ]
    }

    /// Span form of the surface contact wrench cone, `V_surf = A_surf V_point`: one row
    /// `(e, v_j x e)` per vertex `v_j` and pyramid edge `e` (contact frame, wrench at the
    /// contact origin, force first).
    ///
    /// ```
    /// use stance_contact::{Contact, FrictionModel, Shape};
    /// let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let c = Contact::new("c", [0.0; 3], eye,
    ///     Shape::Rectangle { half_length: 0.1, half_width: 0.05 }, 0.5, &Default::default()).unwrap();
    /// let v = c.v_surf(&FrictionModel::default());
    /// assert_eq!((v.nrows(), v.ncols()), (16, 6));
    /// ```
    pub fn v_surf(&self, model: &FrictionModel) -> nalgebra::DMatrix<f64> {
        let edges = model.edges(self.friction);
        let mut v = nalgebra::DMatrix::zeros(self.vertices.len() * edges.len(), 6);
        let mut row = 0;
        for p in &self.vertices {
            for e in &edges {
                let t = crate::cross([p[0], p[1], 0.0], *e);
                for k in 0..3 {
                    v[(row, k)] = e[k];
                    v[(row, 3 + k)] = t[k];
                }
                row += 1;
            }
        }
        v
    }
}

/// Checks convexity and area; returns the vertices counter-clockwise.
fn convex_polygon(
    name: &str,
    v: &[[f64; 2]],
    tol: &ContactTolerances,
) -> Result<Vec<[f64; 2]>, ContactError> {
    let bad = |reason: String| ContactError::BadPolygon {
        contact: name.into(),
        reason,
    };
    if v.len() < 3 {
        return Err(bad(format!(
            "{} vertices given, at least 3 needed",
            v.len()
        )));
    }
    if v.len() > crate::tol::MAX_POLYGON_VERTICES {
        return Err(bad(format!(
            "{} vertices given, at most {} are supported (the cone's size and its conversion's \
             time grow with them): simplify the polygon",
            v.len(),
            crate::tol::MAX_POLYGON_VERTICES
        )));
    }
    let n = v.len();
    let area: f64 = 0.5
        * (0..n)
            .map(|i| {
                let (p, q) = (v[i], v[(i + 1) % n]);
                p[0] * q[1] - p[1] * q[0]
            })
            .sum::<f64>();
    if area.abs() <= tol.min_area {
        return Err(bad(format!("area {:.3e} m^2 is (near) zero", area.abs())));
    }
    let mut out = v.to_vec();
    if area < 0.0 {
        out.reverse();
    }
    for i in 0..n {
        let (p, q, r) = (out[(i + n - 1) % n], out[i], out[(i + 1) % n]);
        let (dx, dy) = (r[0] - p[0], r[1] - p[1]);
        let len = dx.hypot(dy);
        if len == 0.0 {
            return Err(bad(format!("vertices {} and {} coincide", i, (i + 1) % n)));
        }
        // Signed distance of q from the line p -> r, positive to the left: a reflex vertex
        // of a counter-clockwise polygon (convex vertices lie to the right).
        let left = -((q[0] - p[0]) * dy - (q[1] - p[1]) * dx) / len;
        if left > tol.convexity {
            return Err(bad(format!("the polygon is not convex at vertex {i}")));
        }
    }
    // Also reject self-intersecting "star" orders: a convex polygon turns by exactly 2 pi.
    let mut turn = 0.0;
    for i in 0..n {
        let (p, q, r) = (out[(i + n - 1) % n], out[i], out[(i + 1) % n]);
        let a1 = (q[1] - p[1]).atan2(q[0] - p[0]);
        let a2 = (r[1] - q[1]).atan2(r[0] - q[0]);
        let mut d = a2 - a1;
        while d <= -std::f64::consts::PI {
            d += std::f64::consts::TAU;
        }
        while d > std::f64::consts::PI {
            d -= std::f64::consts::TAU;
        }
        turn += d;
    }
    if (turn - std::f64::consts::TAU).abs() > crate::tol::WINDING_TOL {
        return Err(bad("the vertices wind around more than once".into()));
    }
    Ok(out)
}
