//! The two descriptions of a polyhedral cone.
//!
//! - face form `{x : U x <= 0, E x = 0}` ([`FaceForm`]): rows of `U` are outward facet normals,
//!   rows of `E` equations;
//! - span form `{V^T z + L^T y : z >= 0}` ([`SpanForm`]): rows of `V` are generators, rows of `L`
//!   a basis of the lineality space.

use nalgebra::DMatrix;

use crate::ConeError;

/// Face form: `{x : facets x <= 0, equations x = 0}`; rows are unit-norm, facet rows are
/// outward normals.
#[derive(Clone, Debug, PartialEq)]
pub struct FaceForm {
    /// Ambient dimension `d`.
    pub dim: usize,
    /// `m x d`, one facet normal per row.
    pub facets: DMatrix<f64>,
    /// `k x d`, one equation per row.
    pub equations: DMatrix<f64>,
}

/// Span form: `{generators^T z + lineality^T y : z >= 0}` (generators and lineality basis as
/// rows).
#[derive(Clone, Debug, PartialEq)]
pub struct SpanForm {
    /// Ambient dimension `d`.
    pub dim: usize,
    /// `n x d`, one generator per row.
    pub generators: DMatrix<f64>,
    /// `l x d`, a basis of the lineality space (rows).
    pub lineality: DMatrix<f64>,
}

fn finite(what: &'static str, m: &DMatrix<f64>) -> Result<(), ConeError> {
    for i in 0..m.nrows() {
        for j in 0..m.ncols() {
            if !m[(i, j)].is_finite() {
                return Err(ConeError::NonFinite {
                    what,
                    row: i,
                    col: j,
                    value: m[(i, j)],
                });
            }
        }
    }
    Ok(())
}

impl FaceForm {
    /// Builds a face form; the dimension is the number of columns of `facets` (or of
    /// `equations` when `facets` has no row and no column).
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, FaceForm};
    /// let f = FaceForm::new(DMatrix::from_row_slice(1, 2, &[0.0, -1.0]), DMatrix::zeros(0, 2)).unwrap();
    /// assert_eq!(f.dim, 2);
    /// assert!(FaceForm::new(DMatrix::from_row_slice(1, 1, &[f64::NAN]), DMatrix::zeros(0, 1)).is_err());
    /// ```
    pub fn new(facets: DMatrix<f64>, equations: DMatrix<f64>) -> Result<Self, ConeError> {
        let dim = if facets.ncols() > 0 || facets.nrows() > 0 {
            facets.ncols()
        } else {
            equations.ncols()
        };
        let f = Self {
            dim,
            facets,
            equations,
        };
        f.validate()?;
        Ok(f)
    }

    /// Checks dimensions and finiteness. A matrix with no row may have any number of columns.
    ///
    /// ```
    /// use polycone::{nalgebra::DMatrix, FaceForm};
    /// let f = FaceForm { dim: 3, facets: DMatrix::zeros(1, 2), equations: DMatrix::zeros(0, 3) };
    /// assert!(f.validate().is_err());
    /// ```
    pub fn validate(&self) -> Result<(), ConeError> {
        check_dimension(self.dim)?;
        for (what, m) in [("facets", &self.facets), ("equations", &self.equations)] {
            if m.nrows() > 0 && m.ncols() != self.dim {
                return Err(ConeError::DimensionMismatch {
                    what,
                    got: m.ncols(),
                    expected: self.dim,
                });
            }
            finite(what, m)?;
        }
        Ok(())
    }

    /// Is `x` in the cone, within `eps` (`u . x <= eps |x|`, `|e . x| <= eps |x|` for unit rows)?
    ///
    /// ```
    /// use polycone::{nalgebra::{DMatrix, DVector}, FaceForm};
    /// let f = FaceForm::new(DMatrix::from_row_slice(1, 2, &[0.0, -1.0]), DMatrix::zeros(0, 2)).unwrap();
    /// assert!(f.contains(&DVector::from_vec(vec![5.0, 1.0]), 1e-12));
    /// assert!(!f.contains(&DVector::from_vec(vec![5.0, -1.0]), 1e-12));
    /// ```
    pub fn contains(&self, x: &nalgebra::DVector<f64>, eps: f64) -> bool {
        let n = x.norm();
        let fr = (0..self.facets.nrows()).all(|i| {
            let row = self.facets.row(i);
            row.transpose().dot(x) <= eps * n * row.norm()
        });
        let er = (0..self.equations.nrows()).all(|i| {
            let row = self.equations.row(i);
            row.transpose().dot(x).abs() <= eps * n * row.norm()
        });
        fr && er
    }
}

/// The ambient dimension `d` is at least 1 and at most [`crate::tol::MAX_DIMENSION`].
pub(crate) fn check_dimension(d: usize) -> Result<(), ConeError> {
    if d == 0 {
        Err(ConeError::ZeroDimension)
    } else if d > crate::tol::MAX_DIMENSION {
        Err(ConeError::DimensionTooLarge {
            got: d,
            max: crate::tol::MAX_DIMENSION,
        })
    } else {
        Ok(())
    }
}
