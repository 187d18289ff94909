//! # stance (Python)
//!
//! The native half of the Python package `stance`: pyo3 classes and functions over the Rust
//! facade, NumPy in and out. The Python half (`python/stance/`) holds the exception tree, the
//! result dicts, the pypoman drop-ins and the stubs.
//!
//! # Conventions (those of the Rust crates, `docs/math.md`)
//!
//! - Cones: generators and facets as **rows**; `span_to_face(V)` returns `U` with
//!   `{x : U x <= 0, E x = 0} = span(V)`. (`stance.pypoman` has pypoman's column convention.)
//! - Wrenches `(force, torque)`; the GIWC's face form is the paper's, `U_stance w_GI <= 0`
//!   with `w_GI = (m (g - p''), m p x (g - p'') - L')` at the world origin.
//! - Robot quantities with Pinocchio's conventions (quaternion `(x, y, z, w)`, base twist in the
//!   base frame, linear first).
//! - Units: SI (m, kg, s, N); gravity `(0, 0, -9.81)` by default.
//!
//! # Threads
//!
//! Every computation runs with the GIL released (`Python::detach`); batch CoM tests are parallel
//! (rayon). Objects are immutable (`frozen`) and shareable between threads; `Stance` computes
//! `U_stance` once, on first use.
//!
//! # Limitations
//!
//! - Inputs are converted to C-contiguous float64 (a copy unless they already are; a batch of
//!   CoMs in that layout is read in place).
//! - Pickles of `Contact`, `Stance` and `Model` carry their scene-file or URDF text (a `Model`
//!   pickle holds the whole URDF); a `RobustRegion` is recomputed from its cone on unpickling.
//! - `motion` needs JVRC-1's URDF (PyPI `jvrc-description`) for the paper's experiments; the
//!   package finds it when it is installed in the same environment.

mod arrays;
mod bench;
mod cones;
mod contact;
mod errors;
mod joints;
mod json;
mod motion;
mod robot;
mod topp;

use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Rebuilds a pickled object (`kind` and the state written by its `__reduce__`).
#[pyfunction]
fn _restore<'py>(
    py: Python<'py>,
    kind: &str,
    state: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let text = || state.extract::<String>();
    let dict = || state.cast::<PyDict>().map_err(PyErr::from);
    Ok(match kind {
        "Contact" => {
            let spec = serde_json::from_str(&text()?)
                .map_err(|e| errors::input(format!("invalid pickled Contact: {e}")))?;
            Bound::new(py, contact::Contact::from_spec(spec)?)?.into_any()
        }
        "Stance" => {
            let scene = serde_json::from_str(&text()?)
                .map_err(|e| errors::input(format!("invalid pickled Stance: {e}")))?;
            Bound::new(py, contact::Stance::from_scene_struct(py, scene)?)?.into_any()
        }
        "Model" => Bound::new(py, robot::Model::from_state(&text()?)?)?.into_any(),
        "Giwc" => Bound::new(py, contact::giwc_from_state(dict()?)?)?.into_any(),
        "Polygon" => Bound::new(py, contact::polygon_from_state(dict()?)?)?.into_any(),
        "RobustRegion" => Bound::new(py, contact::robust_from_state(dict()?)?)?.into_any(),
        "SupportingForces" => Bound::new(py, contact::forces_from_state(dict()?)?)?.into_any(),
        "ToppResult" => Bound::new(py, topp::topp_from_state(dict()?)?)?.into_any(),
        other => return Err(errors::input(format!("cannot unpickle a {other}"))),
    })
}

#[pymodule]
fn _stance(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(cones::span_to_face, m)?)?;
    m.add_function(wrap_pyfunction!(cones::face_to_span, m)?)?;
    m.add_class::<cones::FaceForm>()?;
    m.add_class::<cones::SpanForm>()?;
    m.add_class::<contact::Contact>()?;
    m.add_class::<contact::Stance>()?;
    m.add_class::<contact::Giwc>()?;
    m.add_class::<contact::Polygon>()?;
    m.add_class::<contact::RobustRegion>()?;
    m.add_class::<contact::SupportingForces>()?;
    m.add_function(wrap_pyfunction!(topp::topp, m)?)?;
    m.add_class::<topp::ToppResult>()?;
    m.add_function(wrap_pyfunction!(topp::retime, m)?)?;
    m.add_class::<robot::Model>()?;
    m.add_function(wrap_pyfunction!(motion::motion, m)?)?;
    m.add_function(wrap_pyfunction!(joints::retime_joints, m)?)?;
    m.add_function(wrap_pyfunction!(_restore, m)?)?;
    m.add_function(wrap_pyfunction!(bench::_bench_rust, m)?)?;
    Ok(())
}
