//! `motion`: the whole-body pipeline of `stance motion` (IK, `U_stance` per stance, eq. 14 with
//! the real angular momentum, one chained retiming, the independent force check).

use pyo3::prelude::*;

use stance::motion::{plan, run, RunOptions};

use crate::{errors, json};

/// Runs a motion file (TOML or JSON) or a built-in motion (`"stair-climbing"`,
/// `"box-climbing"`, `"small-sway"`) and returns the result of `stance motion` as a
/// `stance.Result` (GIL released while it runs); `limits=False` retimes under contact
/// stability alone (`--no-limits`: the file's limits are still checked); `check_dt` is the step
/// of the independent checks (`--check-dt`, 0.001 s).
#[pyfunction]
#[pyo3(signature = (source, *, rest_to_rest = None, dt = None, grid = None, checks = true,
    time_scale = None, check_friction = None, limits = true, check_dt = None))]
#[allow(clippy::too_many_arguments)]
pub fn motion<'py>(
    py: Python<'py>,
    source: std::path::PathBuf,
    rest_to_rest: Option<bool>,
    dt: Option<f64>,
    grid: Option<usize>,
    checks: bool,
    time_scale: Option<f64>,
    check_friction: Option<f64>,
    limits: bool,
    check_dt: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let (mut spec, base_dir) =
        stance::input::motion(&source.to_string_lossy()).map_err(errors::facade)?;
    if let Some(r) = rest_to_rest {
        spec.retiming.rest_to_rest = r;
    }
    if let Some(dt) = dt {
        spec.retiming.dt = dt;
    }
    if let Some(dt) = check_dt {
        spec.retiming.check_dt = dt;
    }
    if let Some(g) = grid {
        spec.retiming.grid = g;
    }
    plan::check_retiming(&spec.retiming).map_err(errors::facade)?;
    let options = RunOptions {
        base_dir,
        skip_checks: !checks,
        time_scale,
        check_friction,
        no_limits: !limits,
        progress: None,
    };
    let out = py.detach(|| run(spec, &options)).map_err(errors::facade)?;
    let d = json::to_python(py, &out)?;
    py.import("stance._convert")?.getattr("Result")?.call1((d,))
}
