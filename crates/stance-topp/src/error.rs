//! Errors for bad input. Negative outcomes (an infeasible retiming) are values of
//! [`crate::Status`], never errors.

/// Bad input to the crate: each message says what to fix.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ToppError {
    /// The grid has fewer than two points.
    #[error("the path grid needs at least 2 points (got {got}); give s_0 < s_1 < ... < s_N")]
    GridTooShort {
        /// Number of grid points given.
        got: usize,
    },
    /// The grid is not strictly increasing or not finite.
    #[error("the path grid must be finite and strictly increasing: s[{index}] = {value} after s[{prev_index}] = {prev}; fix or remove that point")]
    GridNotIncreasing {
        /// Index of the offending point.
        index: usize,
        /// Its value.
        value: f64,
        /// Index of the point before it.
        prev_index: usize,
        /// The value before it.
        prev: f64,
    },
    /// Array lengths do not match.
    #[error("shape mismatch in {what}: expected {expected}, got {got}")]
    Shape {
        /// Which array is wrong.
        what: String,
        /// What was expected.
        expected: usize,
        /// What was given.
        got: usize,
    },
    /// A coefficient is NaN or infinite.
    #[error("{what} at grid point {point}, row {row} is not finite ({value}); every coefficient must be a finite number")]
    NotFinite {
        /// Which array.
        what: &'static str,
        /// Grid point index.
        point: usize,
        /// Row index within the grid point (0 for bounds and speeds).
        row: usize,
        /// The value.
        value: f64,
    },
    /// A bound interval is empty or a speed is negative.
    #[error("invalid {what}: {detail}")]
    InvalidValue {
        /// Which value.
        what: &'static str,
        /// What is wrong and how to fix it.
        detail: String,
    },
}
