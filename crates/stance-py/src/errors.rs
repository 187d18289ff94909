//! Rust errors as Python exceptions. The classes live in `stance/errors.py` (so that
//! `InputError` can be both a `StanceError` and a `ValueError`); they are looked up once.
//!
//! - bad input (every `*Error` of the crates below that names what to fix) -> `InputError`;
//! - a cone conversion whose certificate failed, also in exact arithmetic -> `UncertifiedError`
//!   (never a wrong answer: the engine refuses to return one);
//! - JVRC-1's URDF not installed -> `NotInstalledError`.
//!
//! Negative outcomes (an unstable CoM, an infeasible retiming, an empty polygon) are values.

use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyType;

use stance::polycone::ConeError;
use stance::stance_contact::ContactError;
use stance::StanceError;

static INPUT: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static UNCERTIFIED: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static NOT_INSTALLED: PyOnceLock<Py<PyType>> = PyOnceLock::new();

fn raise(py: Python<'_>, cell: &'static PyOnceLock<Py<PyType>>, name: &str, msg: String) -> PyErr {
    match cell.import(py, "stance.errors", name) {
        Ok(ty) => PyErr::from_type(ty.clone(), msg),
        // The package's Python half is missing (the native module imported on its own).
        Err(_) => pyo3::exceptions::PyValueError::new_err(msg),
    }
}

/// `stance.InputError(msg)`: bad input, with what to fix.
pub fn input(msg: impl Into<String>) -> PyErr {
    Python::attach(|py| raise(py, &INPUT, "InputError", msg.into()))
}

/// `stance.UncertifiedError(msg)`.
pub fn uncertified(msg: impl Into<String>) -> PyErr {
    Python::attach(|py| raise(py, &UNCERTIFIED, "UncertifiedError", msg.into()))
}

/// `stance.NotInstalledError(msg)`.
pub fn not_installed(msg: impl Into<String>) -> PyErr {
    Python::attach(|py| raise(py, &NOT_INSTALLED, "NotInstalledError", msg.into()))
}

/// A cone conversion's error.
pub fn cone(e: ConeError) -> PyErr {
    match e {
        // The engine could not decide (or certify) in floating point: not malformed input.
        ConeError::Uncertified(_) | ConeError::RankUndecided { .. } => uncertified(e.to_string()),
        _ => input(e.to_string()),
    }
}

/// A contact layer's error.
pub fn contact(e: ContactError) -> PyErr {
    match e {
        ContactError::Cone(c) => cone(c),
        _ => input(e.to_string()),
    }
}

/// A facade error.
pub fn facade(e: StanceError) -> PyErr {
    match e {
        StanceError::Contact(ContactError::Cone(
            ConeError::Uncertified(_) | ConeError::RankUndecided { .. },
        )) => uncertified(e.to_string()),
        StanceError::NotInstalled(_) => not_installed(
            "JVRC-1's URDF is not installed: pip install jvrc-description==1.1.1 in this \
             environment (or set STANCE_JVRC1_URDF to the file)",
        ),
        _ => input(e.to_string()),
    }
}

/// A TOPP error (all bad input).
pub fn topp(e: stance::stance_topp::ToppError) -> PyErr {
    input(e.to_string())
}

/// A robot model error (all bad input).
pub fn robot(e: stance::stance_robot::RobotError) -> PyErr {
    input(e.to_string())
}
