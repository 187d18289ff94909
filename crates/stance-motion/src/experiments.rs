//! Built-in motions, by name: the paper's experiments on JVRC-1 (`stair-climbing`,
//! `box-climbing`), the same written as footholds only for the footholds planner
//! (`stair-climbing-footholds`, `box-climbing-footholds`), a footholds-only walk up three steps
//! (`staircase-walk`), and a small test motion on the project's small humanoid (`small-sway`). Their
//! motion files are in the crate's `motions/` folder (documented there, copied by users as
//! templates).

use super::spec::MotionSpec;
use crate::StanceError;

/// The names of the built-in motions.
pub const NAMES: [&str; 6] = [
    "stair-climbing",
    "box-climbing",
    "small-sway",
    "stair-climbing-footholds",
    "box-climbing-footholds",
    "staircase-walk",
];

fn text(name: &str) -> Option<&'static str> {
    match name {
        "stair-climbing" => Some(include_str!("../motions/stair-climbing.toml")),
        "box-climbing" => Some(include_str!("../motions/box-climbing.toml")),
        "small-sway" => Some(include_str!("../motions/small-sway.toml")),
        "stair-climbing-footholds" => {
            Some(include_str!("../motions/stair-climbing-footholds.toml"))
        }
        "box-climbing-footholds" => Some(include_str!("../motions/box-climbing-footholds.toml")),
        "staircase-walk" => Some(include_str!("../motions/staircase-walk.toml")),
        _ => None,
    }
}

/// A built-in motion by name, or an error listing the names.
///
/// ```
/// assert!(stance_motion::experiments::by_name("small-sway").is_ok());
/// assert!(stance_motion::experiments::by_name("moonwalk").is_err());
/// ```
pub fn by_name(name: &str) -> Result<MotionSpec, StanceError> {
    let t = text(name).ok_or_else(|| StanceError::unknown_name(name, "motion", &NAMES, false))?;
    toml::from_str(t).map_err(|e| StanceError::BadMotion(format!("built-in motion {name}: {e}")))
}
