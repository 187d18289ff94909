//! The Python virtualenv that holds what stance takes from PyPI at run time: JVRC-1's
//! description (`jvrc-description`, the paper's robot) and MuJoCo (`mujoco`, the simulator's
//! Python bindings).
//!
//! One rule, wherever the binary is installed and whatever the working directory:
//!
//! 1. `$STANCE_VENV` when it is set and not empty (the project's own builds set it to the source tree's
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

/// The virtualenv's folder: `$STANCE_VENV` when set and not empty (made absolute against the
/// working folder), else `.venv` in [`data_dir`].
///
/// # Errors
///
/// Neither is available (no `STANCE_VENV` and no home directory).
pub fn dir() -> Result<PathBuf, StanceError> {
    match std::env::var_os("STANCE_VENV") {
        Some(v) if !v.is_empty() => std::path::absolute(PathBuf::from(&v)).map_err(|e| {
            StanceError::NotInstalled(format!(
                "STANCE_VENV={}: {e}; set it to a folder",
                PathBuf::from(&v).display()
            ))
        }),
        _ => data_dir().map(|d| d.join(".venv")).ok_or_else(|| {
            StanceError::NotInstalled(
                "no home directory for stance's virtualenv: set STANCE_VENV to a folder".into(),
            )
        }),
    }
}

/// JVRC-1's URDF from the PyPI package `jvrc-description` in the virtualenv ([`dir`]), or
/// `$STANCE_JVRC1_URDF` when set.
///
/// # Errors
///
/// Not installed: the reason and what to run.
pub fn jvrc1_urdf() -> Result<PathBuf, StanceError> {
    let venv = dir()?;
    stance_robot::jvrc1::locate_urdf_in_venv(&venv).map_err(|why| {
        StanceError::NotInstalled(format!(
            "the robot jvrc1 needs JVRC-1's URDF from PyPI ({}): {why}; {}, or set \
             STANCE_JVRC1_URDF to the URDF file",
            REQUIREMENTS[0],
            how_to_install()
        ))
    })
}

/// The virtualenv's Python interpreter (which may not exist yet).
pub fn python(venv: &Path) -> PathBuf {
    if cfg!(windows) {
        venv.join("Scripts").join("python.exe")
    } else {
        venv.join("bin").join("python")
    }
}

/// Whether the virtualenv at `venv` has what [`setup`] installs (its Python imports MuJoCo and
/// JVRC-1's description): `Err` with what is missing.
pub fn check(venv: &Path) -> Result<(), String> {
    let py = python(venv);
    if !py.is_file() {
        return Err("missing".into());
    }
    match std::process::Command::new(&py)
        .args(["-c", "import mujoco, jvrc_description"])
        .output()
    {
        Ok(o) if o.status.success() => Ok(()),
        Ok(o) => Err(format!(
            "incomplete ({})",
            String::from_utf8_lossy(&o.stderr)
                .lines()
                .last()
                .unwrap_or("")
                .trim()
        )),
        Err(e) => Err(format!("its Python does not run ({e})")),
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
    // A virtualenv made without pip (Debian's python3 without python3-venv leaves one) is
    // made again.
    let has_pip = || {
        std::process::Command::new(&py)
            .args(["-m", "pip", "--version"])
            .output()
            .is_ok_and(|o| o.status.success())
    };
    if py.is_file() && !has_pip() {
        eprintln!(
            "stance setup: the virtualenv {} has no pip: making it again",
            venv.display()
        );
        run(
            std::process::Command::new(python_cmd)
                .args(["-m", "venv", "--clear"])
                .arg(&venv),
            &format!("`{python_cmd} -m venv --clear {}`", venv.display()),
        )?;
    }
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

#[cfg(test)]
mod tests {
    /// The pins `stance setup` installs are the ones the project tests with.
    #[test]
    fn the_requirements_are_the_tested_ones() {
        let tested = include_str!("../../../bench/peers/requirements-tests.txt");
        let pins: Vec<&str> = tested
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty() && !l.starts_with('#'))
            .collect();
        assert_eq!(pins, super::REQUIREMENTS);
    }
}
