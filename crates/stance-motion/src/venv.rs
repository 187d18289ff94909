//! The Python virtualenv that holds what stance takes from PyPI at run time: JVRC-1's
//! description (`jvrc-description`, the paper's robot) and MuJoCo (`mujoco`, the simulator's
//! Python bindings).
//!
//! One rule, wherever the binary is installed and whatever the working directory:
//!
//! 1. `$STANCE_VENV` when it is set (the project's own builds set it to the source tree's
//!    `.venv` through `.cargo/config.toml`, so `cargo run` and `cargo test` use the virtualenv
//!    that `scripts/setup-venv.sh` makes);
//! 2. else `.venv` in the per-user data directory of the platform (on Linux
//!    `$XDG_DATA_HOME/stance/.venv`, by default `~/.local/share/stance/.venv`; on macOS
//!    `~/Library/Application Support/stance/.venv`), which `stance setup` creates.
//!
//! No path of the machine that built the binary is read at run time.

use std::path::{Path, PathBuf};

use crate::StanceError;

/// What [`setup`] installs from PyPI, pinned (the versions the project tests with; the same
/// pins as `bench/peers/requirements-tests.txt`).
pub const REQUIREMENTS: [&str; 2] = ["jvrc-description==1.1.1", "mujoco==4.0.0"];

/// The per-user data directory of stance (`None` when the platform gives no home directory).
pub fn data_dir() -> Option<PathBuf> {
    directories::ProjectDirs::from("", "", "stance").map(|d| d.data_dir().to_path_buf())
}

/// The virtualenv's folder: `$STANCE_VENV`, else `.venv` in [`data_dir`].
///
/// # Errors
///
/// Neither is available (no `STANCE_VENV` and no home directory).
pub fn dir() -> Result<PathBuf, StanceError> {
    if let Some(v) = std::env::var_os("STANCE_VENV") {
        return Ok(PathBuf::from(v));
    }
    data_dir().map(|d| d.join(".venv")).ok_or_else(|| {
        StanceError::NotInstalled(
            "no home directory for stance's virtualenv: set STANCE_VENV to a folder".into(),
        )
    })
}

/// The folder that contains the virtualenv as `.venv` (what [`stance_robot::jvrc1::locate_urdf`]
/// calls the project root), or `None` when `$STANCE_VENV` names it (which that function reads
/// itself).
pub fn root() -> Option<PathBuf> {
    match std::env::var_os("STANCE_VENV") {
        Some(_) => None,
        None => data_dir(),
    }
}

/// The virtualenv's Python interpreter (which may not exist yet).
pub fn python(venv: &Path) -> PathBuf {
    if cfg!(windows) {
        venv.join("Scripts").join("python.exe")
    } else {
        venv.join("bin").join("python")
    }
}

/// What to run when the virtualenv is missing, for error messages.
pub fn how_to_install() -> String {
    match std::env::var_os("STANCE_VENV") {
        Some(v) => format!(
            "run `stance setup` (it creates the virtualenv STANCE_VENV={} and installs {} from \
             PyPI)",
            PathBuf::from(v).display(),
            REQUIREMENTS.join(" and ")
        ),
        None => format!(
            "run `stance setup` (it installs {} from PyPI into a per-user virtualenv), or set \
             STANCE_VENV to a virtualenv that has them",
            REQUIREMENTS.join(" and ")
        ),
    }
}

/// Creates the virtualenv at [`dir`] when missing (with `python`, e.g. `python3`) and installs
/// [`REQUIREMENTS`] into it from PyPI; returns the virtualenv's folder. Idempotent: what is
/// installed already is kept. Progress goes to standard error (pip's own output).
///
/// # Errors
///
/// No Python with `venv`, or pip failing (no network access to PyPI, a platform without wheels).
pub fn setup(python_cmd: &str) -> Result<PathBuf, StanceError> {
    let venv = dir()?;
    let run = |cmd: &mut std::process::Command, what: &str| -> Result<(), StanceError> {
        let status = cmd.status().map_err(|e| {
            StanceError::NotInstalled(format!("cannot run {what}: {e} (is Python 3 installed?)"))
        })?;
        if status.success() {
            Ok(())
        } else {
            Err(StanceError::NotInstalled(format!(
                "{what} failed ({status})"
            )))
        }
    };
    let py = python(&venv);
    if !py.is_file() {
        if let Some(parent) = venv.parent() {
            std::fs::create_dir_all(parent).map_err(|e| {
                StanceError::NotInstalled(format!("cannot create {}: {e}", parent.display()))
            })?;
        }
        eprintln!("stance setup: creating the virtualenv {}", venv.display());
        run(
            std::process::Command::new(python_cmd)
                .args(["-m", "venv"])
                .arg(&venv),
            &format!("`{python_cmd} -m venv {}`", venv.display()),
        )?;
    }
    eprintln!(
        "stance setup: installing {} from PyPI into {}",
        REQUIREMENTS.join(", "),
        venv.display()
    );
    run(
        std::process::Command::new(&py)
            .args([
                "-m",
                "pip",
                "install",
                "--quiet",
                "--disable-pip-version-check",
            ])
            .args(REQUIREMENTS),
        &format!(
            "pip install {} (with {})",
            REQUIREMENTS.join(" "),
            py.display()
        ),
    )?;
    Ok(venv)
}
