//! Errors of the facade: bad input, with what to fix.

/// Bad input to the facade's glue (a negative outcome, such as an infeasible retiming, is a
/// value, not an error).
#[derive(Debug, thiserror::Error)]
pub enum StanceError {
    /// The scene or its contacts are invalid. (The inner error is part of the message and is not
    /// reported again as a `source`, so that an error chain prints it once.)
    #[error("invalid scene: {0}")]
    Contact(stance_contact::ContactError),
    /// The path, grid or rows are invalid (the inner error is in the message, not a `source`).
    #[error("invalid retiming input: {0}")]
    Topp(stance_topp::ToppError),
    /// A motion file field is invalid.
    #[error("invalid motion: {0}")]
    BadMotion(String),
    /// The robot model is invalid (the inner error is in the message, not a `source`).
    #[error("robot model: {0}")]
    Robot(stance_robot::RobotError),
    /// An optional resource is not installed (JVRC-1's URDF): what to install.
    #[error("{0}")]
    NotInstalled(String),
    /// An input file that cannot be read or parsed (the path and the parser's message).
    #[error("{0}")]
    File(String),
    /// An unknown built-in example or motion name.
    #[error("unknown example {name:?}: use one of {known}")]
    UnknownExample {
        /// The name asked for.
        name: String,
        /// The known names.
        known: String,
    },
}

impl From<stance_contact::ContactError> for StanceError {
    fn from(e: stance_contact::ContactError) -> Self {
        StanceError::Contact(e)
    }
}

impl From<stance_topp::ToppError> for StanceError {
    fn from(e: stance_topp::ToppError) -> Self {
        StanceError::Topp(e)
    }
}
