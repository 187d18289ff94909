//! The face form of the GIWC, `U_stance` (paper eq. 11), with its equations and lineality.
//!
//! Convention (the paper's): rows `u` are unit vectors and `u . w_GI <= 0` on the cone, for the
//! gravito-inertial wrench at the **world origin**; equations `e . w_GI = 0` (the GIWC is
//! lower-dimensional, e.g. two point contacts give a 5-D cone); `lineality` is a basis of the
//! largest linear subspace in the cone (non-pointed GIWC, e.g. opposing walls). For the net
//! contact wrench `w_c = -w_GI` use [`Giwc::net_contact_wrench_face`].

use nalgebra::DMatrix;

use crate::ContactError;

/// The face form of a gravito-inertial wrench cone. Build it with [`crate::Stance::u_stance`]
/// or, from a known face matrix, [`Giwc::from_face`].
#[derive(Debug, Clone, PartialEq)]
pub struct Giwc {
    /// `U_stance`: unit rows, `U w_GI <= 0` (paper's convention, world origin).
    pub facets: DMatrix<f64>,
    /// Equations `E w_GI = 0` (unit rows; zero rows when the cone is full-dimensional).
    pub equations: DMatrix<f64>,
    /// Basis of the lineality space, one vector per row (zero rows when pointed).
    pub lineality: DMatrix<f64>,
    /// Whether the cone conversion certified its result.
    pub certified: bool,
    /// The conversion's certificate: which arithmetic and route gave the rows (tolerance,
    /// exact, or exact fallback and why) and what was merged ([`polycone::Certificate::route`],
    /// [`polycone::Certificate::merged_rows`]). `None` for a cone built from a face form.
    pub certificate: Option<polycone::Certificate>,
}

fn unit_rows(m: &DMatrix<f64>, what: &str) -> Result<DMatrix<f64>, ContactError> {
    if m.ncols() != 6 && m.nrows() > 0 {
        return Err(ContactError::BadShape(format!(
            "{what} must have 6 columns (force, torque), got {}",
            m.ncols()
        )));
    }
    if m.iter().any(|x| !x.is_finite()) {
        return Err(ContactError::NonFinite { what: what.into() });
    }
    let rows: Vec<_> = m
        .row_iter()
        .filter(|r| r.norm() > 0.0)
        .map(|r| r / r.norm())
        .collect();
    let out = if rows.is_empty() {
        DMatrix::zeros(0, 6)
    } else {
        DMatrix::from_rows(&rows)
    };
    Ok(out)
}

impl Giwc {
    /// The facets `U` as an array of rows (the layout of the retiming's factored rows).
    ///
    /// ```
    /// # use stance_contact::examples;
    /// let giwc = examples::single_support_flat().stance().unwrap().u_stance(&Default::default()).unwrap();
    /// let rows = giwc.facet_rows();
    /// assert_eq!(rows.len(), 16);
    /// assert_eq!(rows[3][5], giwc.facets[(3, 5)]);
    /// ```
    pub fn facet_rows(&self) -> Vec<[f64; 6]> {
        self.facets
            .row_iter()
            .map(|r| [r[0], r[1], r[2], r[3], r[4], r[5]])
            .collect()
    }

    /// Builds a GIWC from a face matrix `U` (rows `u . w_GI <= 0`) and equations `E` (rows
    /// `e . w_GI = 0`), both with 6 columns; rows are normalized and zero rows dropped.
    /// The lineality is left empty (unknown) and `certified` false.
    ///
    /// ```
    /// use nalgebra::DMatrix;
    /// use stance_contact::Giwc;
    /// let u = DMatrix::from_row_slice(1, 6, &[0.0, 0.0, 2.0, 0.0, 0.0, 0.0]); // f_z <= 0
    /// let g = Giwc::from_face(&u, &DMatrix::zeros(0, 6)).unwrap();
    /// assert!(g.contains(&[0.0, 0.0, -9.81, 0.0, 0.0, 0.0], 1e-9));
    /// assert!(!g.contains(&[0.0, 0.0, 1.0, 0.0, 0.0, 0.0], 1e-9));
    /// ```
    pub fn from_face(
        facets: &DMatrix<f64>,
        equations: &DMatrix<f64>,
    ) -> Result<Self, ContactError> {
        Ok(Self {
            facets: unit_rows(facets, "the face matrix U")?,
            equations: unit_rows(equations, "the equation matrix E")?,
            lineality: DMatrix::zeros(0, 6),
            certified: false,
            certificate: None,
        })
    }

    /// Largest constraint value `max(max_i u_i . w, max_j |e_j . w|)` (0 for the whole space);
    /// `<= 0` inside the cone.
    ///
    /// ```
    /// use nalgebra::DMatrix;
    /// use stance_contact::Giwc;
    /// let u = DMatrix::from_row_slice(1, 6, &[0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
    /// let g = Giwc::from_face(&u, &DMatrix::zeros(0, 6)).unwrap();
    /// assert_eq!(g.max_violation(&[0.0, 0.0, -2.0, 0.0, 0.0, 0.0]), -2.0);
    /// ```
    pub fn max_violation(&self, w: &[f64; 6]) -> f64 {
        let mut worst = f64::NEG_INFINITY;
        // (Rows are zipped with w: a malformed matrix cannot index out of bounds.)
        for r in self.facets.row_iter() {
            let v: f64 = r.iter().zip(w).map(|(a, b)| a * b).sum();
            worst = worst.max(v);
        }
        for r in self.equations.row_iter() {
            let v: f64 = r.iter().zip(w).map(|(a, b)| a * b).sum();
            worst = worst.max(v.abs());
        }
        if worst == f64::NEG_INFINITY {
            0.0
        } else {
            worst
        }
    }

    /// Face-form membership `U w <= tol |w|`, `|E w| <= tol |w|` (the relative band of
    /// [`crate::tol::DEFAULT_FACE_TOL`]).
    ///
    /// ```
    /// # use stance_contact::{examples, w_gi_static};
    /// let scene = examples::single_support_flat();
    /// let giwc = scene.stance().unwrap().u_stance(&Default::default()).unwrap();
    /// assert!(giwc.contains(&w_gi_static(1.0, [0.0, 0.0, -9.81], [0.0, 0.0, 0.8]), 1e-9));
    /// assert!(!giwc.contains(&w_gi_static(1.0, [0.0, 0.0, -9.81], [0.2, 0.0, 0.8]), 1e-9));
    /// ```
    pub fn contains(&self, w: &[f64; 6], tol: f64) -> bool {
        let n = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        self.max_violation(w) <= tol * n
    }

    /// The same cone in the net-contact-wrench convention: `CWC = -GIWC`, i.e. the rows
    /// `-U` with `(-U) w_c <= 0` for `w_c = -w_GI` (world origin). Returns `(facets,
    /// equations)`; the equations are unchanged (`E w = 0` is symmetric).
    ///
    /// ```
    /// use nalgebra::DMatrix;
    /// use stance_contact::Giwc;
    /// let u = DMatrix::from_row_slice(1, 6, &[0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
    /// let g = Giwc::from_face(&u, &DMatrix::zeros(0, 6)).unwrap();
    /// let (cwc, _) = g.net_contact_wrench_face();
    /// assert_eq!(cwc[(0, 2)], -1.0);
    /// ```
    pub fn net_contact_wrench_face(&self) -> (DMatrix<f64>, DMatrix<f64>) {
        (-&self.facets, self.equations.clone())
    }
}
