//! Serde values to and from Python (through the `json` module: the same text as the command
//! line's files and outputs, so a dict means what a file means), and pickling.
//!
//! Every class pickles as `_restore(kind, state)`: the scene-file text for inputs (`Contact`,
//! `Stance`, `Model`), a dict of arrays for results. `serde_json`'s `float_roundtrip` makes
//! the text exact.

use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple};
use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::errors;

static LOADS: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
static DUMPS: PyOnceLock<Py<PyAny>> = PyOnceLock::new();

fn json_fn<'py>(
    py: Python<'py>,
    cell: &'static PyOnceLock<Py<PyAny>>,
    name: &str,
) -> PyResult<Bound<'py, PyAny>> {
    Ok(cell
        .get_or_try_init(py, || -> PyResult<_> {
            Ok(py.import("json")?.getattr(name)?.unbind())
        })?
        .bind(py)
        .clone())
}

/// A serde value as Python objects (dicts, lists, floats, strings).
pub fn to_python<'py, T: Serialize>(py: Python<'py>, value: &T) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| errors::input(format!("cannot serialize the value: {e}")))?;
    json_fn(py, &LOADS, "loads")?.call1((text,))
}

/// Python objects (a dict of the file format) as a serde value; `what` names it in errors.
pub fn from_python<T: DeserializeOwned>(
    py: Python<'_>,
    obj: &Bound<'_, PyAny>,
    what: &str,
) -> PyResult<T> {
    let kwargs = PyDict::new(py);
    // numpy scalars and arrays as plain numbers and lists.
    kwargs.set_item(
        "default",
        py.import("stance._convert")?.getattr("to_builtin")?,
    )?;
    let text: String = json_fn(py, &DUMPS, "dumps")?
        .call((obj,), Some(&kwargs))
        .map_err(|e| errors::input(format!("{what} cannot be read: {}", e.value(py))))?
        .extract()?;
    stance::input::from_json_str(&text).map_err(|e| errors::input(format!("invalid {what}: {e}")))
}

/// `(_restore, (kind, json_text))`.
pub fn reduce<'py, T: Serialize>(
    py: Python<'py>,
    kind: &str,
    value: &T,
) -> PyResult<Bound<'py, PyTuple>> {
    let text = serde_json::to_string(value)
        .map_err(|e| errors::input(format!("cannot serialize the {kind}: {e}")))?;
    let text = pyo3::types::PyString::new(py, &text).into_any();
    reduce_state(py, kind, text)
}

/// `(_restore, (kind, state))`.
pub fn reduce_state<'py>(
    py: Python<'py>,
    kind: &str,
    state: Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyTuple>> {
    let f = py.import("stance._stance")?.getattr("_restore")?;
    let args = PyTuple::new(py, [pyo3::types::PyString::new(py, kind).into_any(), state])?;
    PyTuple::new(py, [f, args.into_any()])
}

/// `state[key]`, or an error naming the class.
pub fn state_item<'py>(
    state: &Bound<'py, PyDict>,
    kind: &str,
    key: &str,
) -> PyResult<Bound<'py, PyAny>> {
    state
        .get_item(key)?
        .ok_or_else(|| errors::input(format!("pickled {kind} without {key}")))
}
