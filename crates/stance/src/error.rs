//! Errors of the facade: bad input, with what to fix.

/// Bad input to the facade's glue (a negative outcome, such as an infeasible retiming, is a
/// value, not an error).
#[derive(Debug, thiserror::Error)]
pub enum StanceError {
    /// The scene or its contacts are invalid.
    #[error("invalid scene: {0}")]
    Contact(#[from] stance_contact::ContactError),
    /// The path, grid or rows are invalid.
    #[error("invalid retiming input: {0}")]
    Topp(#[from] stance_topp::ToppError),
    /// A motion file field is invalid.
    #[error("invalid motion: {0}")]
    BadMotion(String),
    /// A named example does not exist.
    #[error("unknown example scene {name:?}: use one of {known}")]
    UnknownExample {
        /// The name asked for.
        name: String,
        /// The known names.
        known: String,
    },
}
