//! Errors of the library: bad input, with what to fix.

/// Bad input (a negative outcome, such as an infeasible retiming, is a
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
    /// A name that is none of the built-in scenes or motions (nor, where a path is accepted
    /// too, a file): one message for every lookup ([`StanceError::unknown_name`]).
    #[error("{}", unknown_name_message(name, what, known, *file_too))]
    UnknownName {
        /// The name asked for.
        name: String,
        /// What was looked up: "scene", "motion", "motion or scene".
        what: &'static str,
        /// The built-in names.
        known: Vec<String>,
        /// Whether a file path is accepted in its place.
        file_too: bool,
    },
}

impl StanceError {
    /// The error of a lookup by name that found nothing, naming the built-in names (and the file
    /// alternative where a path is accepted too).
    ///
    /// ```
    /// use stance_motion::StanceError;
    /// let e = StanceError::unknown_name("moon", "scene", &["stairs"], true);
    /// assert_eq!(e.to_string(),
    ///     "\"moon\" is neither a file nor a built-in scene: use one of stairs, or the path of a \
    ///      scene file");
    /// let e = StanceError::unknown_name("moon", "scene", &["stairs"], false);
    /// assert_eq!(e.to_string(), "unknown scene \"moon\": use one of stairs");
    /// ```
    pub fn unknown_name(name: &str, what: &'static str, known: &[&str], file_too: bool) -> Self {
        StanceError::UnknownName {
            name: name.into(),
            what,
            known: known.iter().map(|s| s.to_string()).collect(),
            file_too,
        }
    }
}

fn unknown_name_message(name: &str, what: &str, known: &[String], file_too: bool) -> String {
    if file_too {
        format!(
            "{name:?} is neither a file nor a built-in {what}: use one of {}, or the path of a \
             {what} file",
            known.join(", ")
        )
    } else {
        format!("unknown {what} {name:?}: use one of {}", known.join(", "))
    }
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
