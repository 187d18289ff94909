//! Robots from PyPI in the project virtualenv, for the tests that run motions written for them.

use std::path::{Path, PathBuf};

/// Talos's URDF in the project virtualenv's `example-robot-data` (`scripts/setup-venv.sh
/// --peers`; the virtualenv at `$STANCE_VENV`, else `.venv` under `root`), or why not.
pub fn talos_urdf(root: &Path) -> Result<PathBuf, String> {
    let venv = std::env::var_os("STANCE_VENV").map_or_else(|| root.join(".venv"), PathBuf::from);
    let lib = std::fs::read_dir(venv.join("lib")).map_err(|e| {
        format!(
            "no virtualenv at {} ({e}): run scripts/setup-venv.sh --peers",
            venv.display()
        )
    })?;
    lib.flatten()
        .map(|d| {
            d.path().join(
                "site-packages/cmeel.prefix/share/example-robot-data/robots/talos_data/robots/\
                 talos_reduced.urdf",
            )
        })
        .find(|p| p.is_file())
        .ok_or_else(|| {
            "example-robot-data is not in the virtualenv (scripts/setup-venv.sh --peers)".into()
        })
}
