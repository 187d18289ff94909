//! Polyhedral friction cones (paper Definition 1).
//!
//! The Coulomb cone `{f : sqrt(f_x^2 + f_y^2) <= mu f_z}` (contact frame, z = surface normal) is
//! approximated by a k-sided pyramid. Its face normals point at angles `phi_s = 2 pi s / k`
//! (so for k = 4 the faces are `|f_x| <= mu' f_z`, `|f_y| <= mu' f_z`, aligned with the contact
//! x/y axes), and its edges at angles `(2 s + 1) pi / k`:
//!
//! - outer (circumscribed, the paper's choice): apothem `mu' = mu`, edge radius `mu / cos(pi/k)`;
//!   for k = 4 the edges are `(+-mu, +-mu, 1)`;
//! - inner (inscribed): edge radius `mu`, apothem `mu' = mu cos(pi/k)` (`mu / sqrt 2` for k = 4).
//!
//! Span form: the k edges `(r cos, r sin, 1)`; face form: rows
//! `(cos phi_s, sin phi_s, -mu')` with `u . f <= 0`, and `(0, 0, -1)` (`f_z >= 0`) when
//! `mu = 0`, where the side faces alone leave `f_z` free.

use serde::{Deserialize, Serialize};

use crate::ContactError;

/// Outer (circumscribed, contains the Coulomb cone) or inner (inscribed) pyramid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Approximation {
    /// Circumscribed pyramid: the paper's choice (may accept slightly too much friction).
    #[default]
    Outer,
    /// Inscribed pyramid: conservative.
    Inner,
}

/// The polyhedral friction model shared by all contacts of a stance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionModel {
    /// Number of pyramid sides k (>= 3; default 4).
    #[serde(default = "default_sides")]
    pub sides: usize,
    /// Outer or inner approximation (default outer).
    #[serde(default)]
    pub approximation: Approximation,
}

fn default_sides() -> usize {
    4
}

impl Default for FrictionModel {
    fn default() -> Self {
        Self {
            sides: 4,
            approximation: Approximation::Outer,
        }
    }
}

/// Largest accepted number of pyramid sides (more is never useful and costs cone size).
pub const MAX_SIDES: usize = 64;

impl FrictionModel {
    /// Checks `3 <= sides <= 64`.
    ///
    /// ```
    /// use stance_contact::FrictionModel;
    /// assert!(FrictionModel::default().validate().is_ok());
    /// assert!(FrictionModel { sides: 2, ..Default::default() }.validate().is_err());
    /// ```
    pub fn validate(&self) -> Result<(), ContactError> {
        if !(3..=MAX_SIDES).contains(&self.sides) {
            return Err(ContactError::BadFrictionModel(format!(
                "sides = {} is out of range: use 3 to {MAX_SIDES} (4 is the paper's pyramid)",
                self.sides
            )));
        }
        Ok(())
    }

    /// Apothem `mu'` of the pyramid for the friction coefficient `mu`.
    fn apothem(&self, mu: f64) -> f64 {
        match self.approximation {
            Approximation::Outer => mu,
            Approximation::Inner => mu * (std::f64::consts::PI / self.sides as f64).cos(),
        }
    }

    /// The k edges (span form) in the contact frame, one per entry.
    ///
    /// ```
    /// use stance_contact::FrictionModel;
    /// let e = FrictionModel::default().edges(0.5);
    /// assert_eq!(e.len(), 4);
    /// // The paper's pyramid has exact edges (+-mu, +-mu, 1).
    /// for v in &e { assert!(v[0].abs() == 0.5 && v[1].abs() == 0.5 && v[2] == 1.0); }
    /// ```
    pub fn edges(&self, mu: f64) -> Vec<[f64; 3]> {
        if self.sides == 4 {
            // Exact values for the paper's pyramid (no trigonometric rounding): (+-a, +-a, 1).
            let a = self.apothem(mu);
            return vec![[a, a, 1.0], [-a, a, 1.0], [-a, -a, 1.0], [a, -a, 1.0]];
        }
        let k = self.sides as f64;
        let r = self.apothem(mu) / (std::f64::consts::PI / k).cos();
        (0..self.sides)
            .map(|s| {
                let t = (2.0 * s as f64 + 1.0) * std::f64::consts::PI / k;
                [r * t.cos(), r * t.sin(), 1.0]
            })
            .collect()
    }

    /// The face rows `u` (contact frame) with `u . f <= 0` on the pyramid: the k side faces,
    /// plus the unilateral row `(0, 0, -1)` (`f_z >= 0`) when the apothem is zero (`mu = 0`).
    /// For `mu > 0` the side faces imply `f_z >= 0`; for `mu = 0` they only say
    /// `f_x = f_y = 0` and would let the contact pull.
    ///
    /// ```
    /// use stance_contact::FrictionModel;
    /// let m = FrictionModel::default();
    /// for u in m.faces(0.7) {
    ///     for e in m.edges(0.7) {
    ///         assert!(u[0] * e[0] + u[1] * e[1] + u[2] * e[2] <= 1e-12);
    ///     }
    /// }
    /// // Frictionless: the ray f_z >= 0 of the normal, never a pull.
    /// let pull = [0.0, 0.0, -1.0];
    /// assert_eq!(m.faces(0.0).len(), 5);
    /// assert!(m.faces(0.0).iter().any(|u| u[0] * pull[0] + u[1] * pull[1] + u[2] * pull[2] > 0.0));
    /// ```
    pub fn faces(&self, mu: f64) -> Vec<[f64; 3]> {
        let a = self.apothem(mu);
        let mut out: Vec<[f64; 3]> = if self.sides == 4 {
            vec![
                [1.0, 0.0, -a],
                [0.0, 1.0, -a],
                [-1.0, 0.0, -a],
                [0.0, -1.0, -a],
            ]
        } else {
            let k = self.sides as f64;
            (0..self.sides)
                .map(|s| {
                    let t = 2.0 * s as f64 * std::f64::consts::PI / k;
                    [t.cos(), t.sin(), -a]
                })
                .collect()
        };
        if a <= 0.0 {
            out.push([0.0, 0.0, -1.0]);
        }
        out
    }
}
