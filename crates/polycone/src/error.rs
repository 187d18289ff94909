//! The errors of `polycone`: bad input, each message saying what to fix.

/// Why a conversion could not be done. Every variant is caused by the input or the options, or
/// (for [`ConeError::Uncertified`]) reports that the engine could not certify its own answer;
/// a wrong cone is never returned as certified.
#[derive(thiserror::Error, Debug, Clone, PartialEq)]
pub enum ConeError {
    /// The ambient dimension is 0.
    #[error("the ambient dimension is 0: give at least one column (one coordinate) per row")]
    ZeroDimension,
    /// An input entry is NaN or infinite.
    #[error("{what} has a non-finite entry ({value}) at row {row}, column {col}: every entry must be a finite number")]
    NonFinite {
        /// Which matrix ("generators", "facets", "equations").
        what: &'static str,
        /// Row of the bad entry.
        row: usize,
        /// Column of the bad entry.
        col: usize,
        /// The bad value.
        value: f64,
    },
    /// Two matrices that must share the ambient dimension do not.
    #[error("{what} has {got} columns but the ambient dimension is {expected}: give rows of length {expected}")]
    DimensionMismatch {
        /// Which matrix.
        what: &'static str,
        /// Its number of columns.
        got: usize,
        /// The expected number.
        expected: usize,
    },
    /// A tolerance is negative or not finite.
    #[error("tolerance `{name}` = {value} is invalid: use a finite, non-negative number")]
    BadTolerance {
        /// The field of [`crate::tol::Tolerances`].
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// [`crate::DdOptions::wrench`] was set for a cone that is not 6-D.
    #[error("the wrench preconditioning needs 6 columns (f_x, f_y, f_z, tau_x, tau_y, tau_z) but the dimension is {dim}: turn the `wrench` option off for other cones")]
    NotAWrench {
        /// The ambient dimension given.
        dim: usize,
    },
    /// Two options that cannot be used together.
    #[error("incompatible options: {0}")]
    IncompatibleOptions(&'static str),
    /// The ambient dimension exceeds [`crate::tol::MAX_DIMENSION`].
    #[error("the ambient dimension is {got}, above the limit of {max}: cones of larger dimension are not supported (check \"dim\" or the row length)")]
    DimensionTooLarge {
        /// The dimension given.
        got: usize,
        /// [`crate::tol::MAX_DIMENSION`].
        max: usize,
    },
    /// The dimension of the cone's linear span is decided by the rank tolerance alone: a
    /// singular value between the rounding level and [`crate::tol::Tolerances::rank`] (see
    /// there). Neither answer can be given as certain in floating point.
    #[error("the dimension of the cone is undecided: a singular value {ratio:.1e} times the largest is above the rounding level ({noise:.0e}) and within the rank tolerance ({rank:.0e}); dropping it would drop a direction of the cone. For a wrench cone written about a far reference point, use the wrench preconditioning (--wrench); for the cone of the input exactly as given, exact arithmetic (--exact); or rescale the coordinates that are that small")]
    RankUndecided {
        /// The largest dropped singular value over the largest.
        ratio: f64,
        /// The rounding level it was compared with.
        noise: f64,
        /// The rank tolerance.
        rank: f64,
    },
    /// The input is beyond what the engine supports (dimension too large for the bitsets, ...).
    #[error("unsupported input: {0}")]
    Unsupported(String),
    /// The engine computed an answer it could not certify (in tolerance mode: the input is
    /// degenerate at the scale of the tolerances in a way the engine cannot resolve; try
    /// [`crate::Arithmetic::Exact`] or larger tolerances).
    #[error("the conversion could not be certified ({0}); retry with exact arithmetic or larger tolerances")]
    Uncertified(String),
}
