//! The crate's error type: bad input, with what to fix.

/// Errors of `stance-contact`. Negative outcomes (an unstable CoM, an empty region, infeasible
/// forces) are values, not errors.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ContactError {
    /// A number is NaN or infinite.
    #[error("{what} has a non-finite value (NaN or infinity): give finite numbers")]
    NonFinite {
        /// Which input.
        what: String,
    },
    /// Negative friction coefficient.
    #[error("contact `{contact}` has friction coefficient {mu} < 0: mu must be >= 0")]
    NegativeFriction {
        /// Contact name.
        contact: String,
        /// The value given.
        mu: f64,
    },
    /// Friction coefficient above [`crate::contact::MAX_FRICTION`].
    #[error("contact `{contact}` has friction coefficient {mu:e} > {max:e}: so large a mu makes the friction cone numerically lose its normal force; use a mu up to {max:e} (1e3 already means a contact that does not slip)")]
    FrictionTooLarge {
        /// Contact name.
        contact: String,
        /// The value given.
        mu: f64,
        /// The largest accepted value.
        max: f64,
    },
    /// A rotation matrix that is not orthonormal with determinant +1.
    #[error("contact `{contact}`: the rotation is not a rotation matrix (R^T R - I or det R - 1 is {error:.3e} > {tol:.0e}); give an orthonormal, right-handed 3x3 matrix, row-major, contact frame -> world")]
    NotARotation {
        /// Contact name.
        contact: String,
        /// Largest deviation found.
        error: f64,
        /// Accepted deviation.
        tol: f64,
    },
    /// A rectangle with a non-positive half size.
    #[error("contact `{contact}`: rectangle half sizes must be > 0 (got {half_length}, {half_width}); use a point contact for a point")]
    BadRectangle {
        /// Contact name.
        contact: String,
        /// Half length (along x).
        half_length: f64,
        /// Half width (along y).
        half_width: f64,
    },
    /// A polygon that is not convex, has fewer than 3 vertices or (near) zero area.
    #[error("contact `{contact}`: {reason}; give the vertices of a convex polygon with non-zero area, in order (either orientation)")]
    BadPolygon {
        /// Contact name.
        contact: String,
        /// What is wrong.
        reason: String,
    },
    /// A stance without contacts, or similar structural problem.
    #[error("{0}")]
    BadStance(String),
    /// Mass zero or negative.
    #[error("mass must be > 0 kg (got {0})")]
    BadMass(f64),
    /// Gravity (or a gravity-like vector) unusable for the requested computation.
    #[error("gravity {gravity:?}: {reason}")]
    BadGravity {
        /// The vector given.
        gravity: [f64; 3],
        /// What is wrong.
        reason: String,
    },
    /// Friction model out of range.
    #[error("friction model: {0}")]
    BadFrictionModel(String),
    /// A face matrix with the wrong number of columns, or similar.
    #[error("{0}")]
    BadShape(String),
    /// The cone conversion failed (reported by polycone).
    #[error("cone conversion failed: {0}")]
    Cone(polycone::ConeError),
    /// A polytope routine rejected its input (a bug here if it happens; please report).
    #[error("polytope routine failed: {0}")]
    Polytope(#[from] polycone::polytope::PolytopeError),
}
