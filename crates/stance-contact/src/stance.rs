//! Stances and the gravito-inertial wrench cone (paper Sections III-B, III-C).
//!
//! For contact `i` with pose `(R_i, p_i)` and wrench `w_i = (f_i, tau_i)` in its own frame
//! (at its origin), Newton-Euler (8)-(9) read
//!
//! ```text
//! w_GI = sum_i [ -R_i          0   ] w_i  =  A_stance w_all,
//!              [ -[p_i]x R_i  -R_i ]
//! ```
//!
//! with the gravito-inertial wrench at the world origin `w_GI = (m (g - p''), p x m (g - p'') -
//! L')` (6)-(7). Hence `GIWC = span(A_stance V_all)` (`V_all` the block diagonal of the
//! `V_surf` of each contact) and its face form `U_stance = (A_stance V_all)^F`:
//! the contacts can hold the motion iff `U_stance w_GI <= 0` (and `E w_GI = 0` when the GIWC
//! is not full-dimensional). `U_stance` depends only on the contacts: compute it once per
//! stance. The net contact wrench `w_c = -w_GI` lies in `CWC = -GIWC`.

use nalgebra::{DMatrix, Matrix3};

use crate::{Contact, ContactError, FrictionModel};

/// A set of contacts sharing one friction model. Build it with [`Stance::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct Stance {
    contacts: Vec<Contact>,
    friction_model: FrictionModel,
}

/// The cross-product matrix `[p]x` (`[p]x q = p x q`).
pub(crate) fn skew(p: [f64; 3]) -> Matrix3<f64> {
    Matrix3::new(0.0, -p[2], p[1], p[2], 0.0, -p[0], -p[1], p[0], 0.0)
}

impl Stance {
    /// Builds a stance from validated contacts (at least one) and a friction model.
    ///
    /// ```
    /// use stance_contact::{Contact, FrictionModel, Shape, Stance};
    /// let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let foot = Contact::new("LF", [0.0; 3], eye,
    ///     Shape::Rectangle { half_length: 0.11, half_width: 0.065 }, 0.7, &Default::default()).unwrap();
    /// let stance = Stance::new(vec![foot], FrictionModel::default()).unwrap();
    /// assert_eq!(stance.contacts().len(), 1);
    /// assert!(Stance::new(vec![], FrictionModel::default()).is_err());
    /// ```
    pub fn new(
        contacts: Vec<Contact>,
        friction_model: FrictionModel,
    ) -> Result<Self, ContactError> {
        friction_model.validate()?;
        if contacts.is_empty() {
            return Err(ContactError::BadStance(
                "a stance needs at least one contact".into(),
            ));
        }
        Ok(Self {
            contacts,
            friction_model,
        })
    }

    /// The contacts.
    ///
    /// ```
    /// # use stance_contact::examples;
    /// assert_eq!(examples::double_support_flat().stance().unwrap().contacts().len(), 2);
    /// ```
    pub fn contacts(&self) -> &[Contact] {
        &self.contacts
    }

    /// The same friction model with other contacts (crate-internal: no validation).
    pub(crate) fn with_contacts(&self, contacts: Vec<Contact>) -> Stance {
        Self {
            contacts,
            friction_model: self.friction_model,
        }
    }

    /// This stance with `contact` appended (same friction model).
    ///
    /// ```
    /// use stance_contact::examples;
    /// let s = examples::double_support_flat().stance().unwrap();
    /// let one = stance_contact::Stance::new(vec![s.contacts()[0].clone()], *s.friction_model()).unwrap();
    /// assert_eq!(one.with_contact(s.contacts()[1].clone()), s);
    /// ```
    pub fn with_contact(&self, contact: Contact) -> Stance {
        let mut contacts = self.contacts.clone();
        contacts.push(contact);
        Self {
            contacts,
            friction_model: self.friction_model,
        }
    }

    /// The friction model.
    ///
    /// ```
    /// # use stance_contact::{examples, FrictionModel};
    /// let s = examples::double_support_flat().stance().unwrap();
    /// assert_eq!(s.friction_model(), &FrictionModel::default());
    /// ```
    pub fn friction_model(&self) -> &FrictionModel {
        &self.friction_model
    }

    /// `A_stance` (6 x 6n, eq. 8-9): maps the stacked contact wrenches (each in its contact
    /// frame, at its origin) to `w_GI` at the world origin.
    ///
    /// ```
    /// # use stance_contact::examples;
    /// let s = examples::double_support_flat().stance().unwrap();
    /// assert_eq!(s.a_stance().shape(), (6, 12));
    /// ```
    pub fn a_stance(&self) -> DMatrix<f64> {
        let mut a = DMatrix::zeros(6, 6 * self.contacts.len());
        for (i, c) in self.contacts.iter().enumerate() {
            let r = c.rotation();
            let pr = skew(c.position()) * r;
            for row in 0..3 {
                for col in 0..3 {
                    a[(row, 6 * i + col)] = -r[(row, col)];
                    a[(3 + row, 6 * i + col)] = -pr[(row, col)];
                    a[(3 + row, 6 * i + 3 + col)] = -r[(row, col)];
                }
            }
        }
        a
    }

    /// `V_all` with one generator per **row** (N x 6n, the project's layout): row `g` holds
    /// generator `g` of contact `i`'s surface cone in columns `6i..6i + 6`, so that
    /// `V_all A_stance^T` spans the GIWC (the paper writes `A_stance V_all` with generators as
    /// columns).
    ///
    /// ```
    /// # use stance_contact::examples;
    /// let s = examples::double_support_flat().stance().unwrap();
    /// let v = s.v_all_rows();
    /// assert_eq!(v.shape(), (32, 12));
    /// assert!((s.giwc_span() - &v * s.a_stance().transpose()).amax() < 1e-12);
    /// ```
    pub fn v_all_rows(&self) -> DMatrix<f64> {
        let blocks: Vec<DMatrix<f64>> = self
            .contacts
            .iter()
            .map(|c| c.v_surf(&self.friction_model))
            .collect();
        let n: usize = blocks.iter().map(|b| b.nrows()).sum();
        let mut v = DMatrix::zeros(n, 6 * self.contacts.len());
        let mut row = 0;
        for (i, b) in blocks.iter().enumerate() {
            v.view_mut((row, 6 * i), (b.nrows(), 6)).copy_from(b);
            row += b.nrows();
        }
        v
    }

    /// Span form of the GIWC, one generator per **row** (`V_all A_stance^T`, the layout of
    /// polycone): for each contact vertex `q` (world) and pyramid edge `e` (world), the row
    /// `-(e, q x e)`. Wrench at the world origin, paper's convention.
    ///
    /// ```
    /// # use stance_contact::examples;
    /// let s = examples::double_support_flat().stance().unwrap();
    /// let span = s.giwc_span();
    /// assert_eq!(span.shape(), (32, 6));
    /// assert!((span - s.v_all_rows() * s.a_stance().transpose()).amax() < 1e-12);
    /// ```
    pub fn giwc_span(&self) -> DMatrix<f64> {
        let n: usize = self
            .contacts
            .iter()
            .map(|c| c.vertices_local().len() * self.friction_model.sides)
            .sum();
        let mut out = DMatrix::zeros(n, 6);
        let mut row = 0;
        for c in &self.contacts {
            let r = c.rotation();
            let edges: Vec<nalgebra::Vector3<f64>> = self
                .friction_model
                .edges(c.friction())
                .iter()
                .map(|e| r * nalgebra::Vector3::from(*e))
                .collect();
            for q in c.vertices_world() {
                for e in &edges {
                    let f = [e[0], e[1], e[2]];
                    let t = crate::cross(q, f);
                    for k in 0..3 {
                        out[(row, k)] = -f[k];
                        out[(row, 3 + k)] = -t[k];
                    }
                    row += 1;
                }
            }
        }
        out
    }
}

/// Gravito-inertial wrench at the world origin for a static CoM (eq. 6-7 with `p'' = 0`,
/// `L' = 0`): `w_GI = (m g, m p x g)`.
///
/// ```
/// use stance_contact::w_gi_static;
/// let w = w_gi_static(2.0, [0.0, 0.0, -9.81], [0.1, 0.0, 1.0]);
/// assert_eq!(w[2], -19.62);
/// assert!((w[4] - 1.962).abs() < 1e-12); // (p x g)_y = p_z g_x - p_x g_z
/// ```
pub fn w_gi_static(mass: f64, gravity: [f64; 3], com: [f64; 3]) -> [f64; 6] {
    let t = crate::cross(com, gravity);
    [
        mass * gravity[0],
        mass * gravity[1],
        mass * gravity[2],
        mass * t[0],
        mass * t[1],
        mass * t[2],
    ]
}
