//! `retime_joints`: a fixed-base robot's joint path retimed under its joint velocity,
//! acceleration and torque limits (`stance retime-joints`, toppra's problem).

use pyo3::prelude::*;
use pyo3::types::PyDict;

use stance::joints::{retime_joints as retime, JointPathSpec};

use crate::{errors, json};

/// Retimes the path through `waypoints` (one row per waypoint, one column per joint of
/// `joints`) of the fixed-base robot of `urdf` and returns the result of `stance
/// retime-joints` as a `stance.Result`. The keywords are the file format's keys
/// (`stance::joints::spec`); `limits` is the `[limits]` section as a dict
/// (`{"velocity": 1.0, "acceleration": 5.0 or {"default": 5.0, "elbow": 8.0}, "torque": 1.0}`,
/// `False` for none of a kind); `max_violation_fraction=None` solves on the grid as given.
#[pyfunction]
#[pyo3(signature = (urdf, waypoints, *, joints = None, locked = None, knots = None,
    interpolation = "spline", spline = "not-a-knot", gravity = None, grid_points = 101,
    sd_start = 0.0, sd_end = 0.0, discretization = "interpolation",
    max_violation_fraction = Some(1e-3), samples_per_interval = 10, dt = 0.01, limits = None),
    text_signature = "(urdf, waypoints, *, joints=None, locked=None, knots=None, \
    interpolation='spline', spline='not-a-knot', gravity=None, grid_points=101, sd_start=0.0, \
    sd_end=0.0, discretization='interpolation', max_violation_fraction=0.001, \
    samples_per_interval=10, dt=0.01, limits=None)")]
#[allow(clippy::too_many_arguments)]
pub fn retime_joints<'py>(
    py: Python<'py>,
    urdf: std::path::PathBuf,
    waypoints: &Bound<'py, PyAny>,
    joints: Option<&Bound<'py, PyAny>>,
    locked: Option<&Bound<'py, PyAny>>,
    knots: Option<&Bound<'py, PyAny>>,
    interpolation: &str,
    spline: &str,
    gravity: Option<&Bound<'py, PyAny>>,
    grid_points: usize,
    sd_start: f64,
    sd_end: f64,
    discretization: &str,
    max_violation_fraction: Option<f64>,
    samples_per_interval: usize,
    dt: f64,
    limits: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let d = PyDict::new(py);
    d.set_item("urdf", urdf.to_string_lossy().into_owned())?;
    d.set_item("waypoints", waypoints)?;
    for (key, value) in [
        ("joints", joints),
        ("locked", locked),
        ("knots", knots),
        ("gravity", gravity),
        ("limits", limits),
    ] {
        if let Some(v) = value.filter(|v| !v.is_none()) {
            d.set_item(key, v)?;
        }
    }
    d.set_item("interpolation", interpolation)?;
    d.set_item("spline", spline)?;
    d.set_item("grid_points", grid_points)?;
    d.set_item("sd_start", sd_start)?;
    d.set_item("sd_end", sd_end)?;
    d.set_item("discretization", discretization)?;
    match max_violation_fraction {
        Some(f) => d.set_item("max_violation_fraction", f)?,
        None => d.set_item("max_violation_fraction", false)?,
    }
    d.set_item("samples_per_interval", samples_per_interval)?;
    d.set_item("dt", dt)?;
    let spec: JointPathSpec = json::from_python(py, d.as_any(), "joint path")?;
    let r = py.detach(|| retime(&spec, None)).map_err(errors::facade)?;
    let out = json::to_python(py, &r)?;
    py.import("stance._convert")?
        .getattr("Result")?
        .call1((out,))
}
