//! Time-optimal path parameterization: `topp` on rows `a u + b x + c <= 0` (eq. 13), and
//! `retime`, a stance and a CoM path through `U_stance` and eq. 14.

use numpy::{PyArray1, PyArray2, PyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use stance::retime::{AngularSpec, ComMotionSpec, Interpolation, PathSpec, SceneRef};
use stance::stance_topp::{CanonicalConstraints, Discretization, Row, SolveOptions, Workspace};

use crate::contact::Stance;
use crate::{arrays, errors, json};

fn discretization(name: &str) -> PyResult<Discretization> {
    match name {
        "interpolation" => Ok(Discretization::Interpolation),
        "collocation" => Ok(Discretization::Collocation),
        other => Err(errors::input(format!(
            "discretization must be \"interpolation\" (rows also at the end of each interval, \
             the default) or \"collocation\", got {other:?}"
        ))),
    }
}

/// A `(N + 1, m)` array of coefficients (or `(N + 1,)`: one row per point) and its `m`.
fn coefficients<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    points: usize,
) -> PyResult<(Bound<'py, PyArrayDyn<f64>>, usize)> {
    let a = arrays::float_array(obj, name)?;
    let m = match a.shape() {
        [n] if *n == points => 1,
        [n, m] if *n == points => *m,
        shape => {
            return Err(errors::input(format!(
                "{name} must have shape ({points}, m) (one row of coefficients per grid point of \
                 s), got shape {shape:?}"
            )))
        }
    };
    Ok((a, m))
}

/// The rows `a u + b x + c <= 0` from the three coefficient arrays (one pass, no copy of the
/// arrays when they are C-contiguous), finite.
fn rows_of(arrays3: [&Bound<'_, PyArrayDyn<f64>>; 3], m: usize) -> PyResult<Vec<Row>> {
    let [a, b, c] = arrays3.map(arrays::flat);
    let mut rows = Vec::with_capacity(a.len());
    for k in 0..a.len() {
        let r = Row {
            a: a[k],
            b: b[k],
            c: c[k],
        };
        if !(r.a.is_finite() && r.b.is_finite() && r.c.is_finite()) {
            let (name, v) = [("a", r.a), ("b", r.b), ("c", r.c)]
                .into_iter()
                .find(|(_, v)| !v.is_finite())
                .unwrap_or(("a", r.a));
            return Err(errors::input(format!(
                "{name}[{}, {}] is {v}: give finite coefficients",
                k / m,
                k % m
            )));
        }
        rows.push(r);
    }
    Ok(rows)
}

/// The result of `topp`.
#[pyclass(frozen, module = "stance._stance")]
pub struct ToppResult {
    /// `"optimal"`, or why there is no profile (`"controllable_set_empty"`, ...).
    #[pyo3(get)]
    pub status: &'static str,
    /// The grid index where it failed (None when optimal).
    #[pyo3(get)]
    pub index: Option<usize>,
    /// `"interpolation"` or `"collocation"`.
    #[pyo3(get)]
    pub discretization: &'static str,
    /// Duration (s), None without a profile.
    #[pyo3(get)]
    pub duration: Option<f64>,
    /// The grid `(N + 1,)`.
    #[pyo3(get)]
    pub s: Py<PyArray1<f64>>,
    /// Path speeds `s'` at the grid points `(N + 1,)` (None without a profile).
    #[pyo3(get)]
    pub sd: Option<Py<PyArray1<f64>>>,
    /// Path accelerations `s''` on each interval `(N,)`.
    #[pyo3(get)]
    pub sdd: Option<Py<PyArray1<f64>>>,
    /// Times at the grid points `(N + 1,)`.
    #[pyo3(get)]
    pub t: Option<Py<PyArray1<f64>>>,
    /// Controllable sets `[lo, hi]` of `x = s'^2` per grid point `(N + 1, 2)`; NaN where empty.
    #[pyo3(get)]
    pub controllable: Py<PyArray2<f64>>,
    /// Whether the solver's box bounded `u` or `x` (rows that leave them free).
    #[pyo3(get)]
    pub hit_box: bool,
}

#[pymethods]
impl ToppResult {
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let state = PyDict::new(py);
        state.set_item("status", self.status)?;
        state.set_item("index", self.index)?;
        state.set_item("discretization", self.discretization)?;
        state.set_item("duration", self.duration)?;
        state.set_item("s", self.s.clone_ref(py))?;
        state.set_item("sd", self.sd.as_ref().map(|a| a.clone_ref(py)))?;
        state.set_item("sdd", self.sdd.as_ref().map(|a| a.clone_ref(py)))?;
        state.set_item("t", self.t.as_ref().map(|a| a.clone_ref(py)))?;
        state.set_item("controllable", self.controllable.clone_ref(py))?;
        state.set_item("hit_box", self.hit_box)?;
        json::reduce_state(py, "ToppResult", state.into_any())
    }

    fn __repr__(&self) -> String {
        match self.duration {
            Some(d) => format!("ToppResult({}, duration={d:.6})", self.status),
            None => format!("ToppResult({}, index={:?})", self.status, self.index),
        }
    }
}

const STATUSES: [&str; 6] = [
    "optimal",
    "feasible_set_empty",
    "controllable_set_empty",
    "start_outside_controllable_set",
    "forward_pass_failed",
    "stalled",
];

/// Rebuilds a pickled `ToppResult`.
pub fn topp_from_state(state: &Bound<'_, PyDict>) -> PyResult<ToppResult> {
    let get = |k: &str| json::state_item(state, "ToppResult", k);
    let status: String = get("status")?.extract()?;
    let disc: String = get("discretization")?.extract()?;
    let arr = |k: &str| -> PyResult<Option<Py<PyArray1<f64>>>> {
        let v = get(k)?;
        if v.is_none() {
            Ok(None)
        } else {
            Ok(Some(v.cast_into::<PyArray1<f64>>()?.unbind()))
        }
    };
    Ok(ToppResult {
        status: STATUSES
            .into_iter()
            .find(|s| *s == status)
            .unwrap_or("stalled"),
        index: get("index")?.extract()?,
        discretization: discretization(&disc)?.name(),
        duration: get("duration")?.extract()?,
        s: get("s")?.cast_into::<PyArray1<f64>>()?.unbind(),
        sd: arr("sd")?,
        sdd: arr("sdd")?,
        t: arr("t")?,
        controllable: get("controllable")?.cast_into::<PyArray2<f64>>()?.unbind(),
        hit_box: get("hit_box")?.extract()?,
    })
}

/// Time-optimal parameterization of a path under `a[i] u + b[i] x + c[i] <= 0` at every grid
/// point `s[i]` (`u = s''`, `x = s'^2`), by reachability analysis.
#[pyfunction]
#[pyo3(signature = (s, a, b, c, sd_start = 0.0, sd_end = 0.0, discretization = "interpolation"))]
#[allow(clippy::too_many_arguments)]
pub fn topp(
    py: Python<'_>,
    s: &Bound<'_, PyAny>,
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    c: &Bound<'_, PyAny>,
    sd_start: f64,
    sd_end: f64,
    discretization: &str,
) -> PyResult<ToppResult> {
    let grid = arrays::vector(s, "s", None, "path grid, strictly increasing")?;
    let n = grid.len();
    let (av, ma) = coefficients(a, "a", n)?;
    let (bv, mb) = coefficients(b, "b", n)?;
    let (cv, mc) = coefficients(c, "c", n)?;
    if ma != mb || ma != mc {
        return Err(errors::input(format!(
            "a, b and c must have the same number of rows per grid point, got {ma}, {mb} and {mc}"
        )));
    }
    let rows = rows_of([&av, &bv, &cv], ma)?;
    let offsets: Vec<usize> = (0..=n).map(|i| i * ma).collect();
    let disc = self::discretization(discretization)?;
    let opts = SolveOptions::new(disc)
        .with_start(sd_start)
        .with_end(sd_end);
    let k = CanonicalConstraints::new(grid, offsets, rows).map_err(errors::topp)?;
    let sol = arrays::detach_if(py, k.rows().len() > 64, || {
        Workspace::new().solve(&k, &opts)
    })
    .map_err(errors::topp)?;
    let controllable: Vec<[f64; 2]> = sol
        .controllable
        .iter()
        .map(|c| c.unwrap_or([f64::NAN, f64::NAN]))
        .collect();
    let profile = sol.profile.as_ref();
    let one = |v: &[f64]| arrays::to_array1(py, v).unbind();
    Ok(ToppResult {
        status: sol.status.name(),
        index: sol.status.grid_index(),
        discretization: disc.name(),
        duration: profile.map(|p| p.duration()).filter(|d| d.is_finite()),
        s: one(k.grid()),
        sd: profile.map(|p| one(&p.sd())),
        sdd: profile.map(|p| one(p.u())),
        t: profile
            .filter(|p| p.times().iter().all(|t| t.is_finite()))
            .map(|p| one(p.times())),
        controllable: arrays::rows_to_array2(py, &controllable).unbind(),
        hit_box: sol.hit_box,
    })
}

/// Retimes a CoM path under contact stability of one stance (the paper's Section V with a
/// point mass, or with angular-momentum terms `l1`, `l2`): `U_stance` once, eq. 14's rows on
/// the grid, the TOPP, and the violation between grid points measured (and refined away when
/// `max_violation_fraction` is given). Returns the `stance retime` result as a `stance.Result`.
#[pyfunction]
#[pyo3(signature = (stance, com_waypoints, knots = None, interpolation = "spline",
    grid_points = 101, sd_start = 0.0, sd_end = 0.0, discretization = "interpolation",
    max_violation_fraction = None, dt = None, angular_momentum = None))]
#[allow(clippy::too_many_arguments)]
pub fn retime<'py>(
    py: Python<'py>,
    stance: &Bound<'py, PyAny>,
    com_waypoints: &Bound<'py, PyAny>,
    knots: Option<&Bound<'py, PyAny>>,
    interpolation: &str,
    grid_points: usize,
    sd_start: f64,
    sd_end: f64,
    discretization: &str,
    max_violation_fraction: Option<f64>,
    dt: Option<f64>,
    angular_momentum: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let scene = match stance.cast::<Stance>() {
        Ok(s) => SceneRef::Inline(Box::new(s.get().scene.clone())),
        Err(_) => match stance.extract::<String>() {
            Ok(name) => SceneRef::Named(name),
            Err(_) => {
                return Err(errors::input(
                    "stance must be a stance.Stance or a built-in scene name",
                ))
            }
        },
    };
    let w = arrays::matrix(com_waypoints, "com_waypoints", Some(3), "CoM waypoints, m")?;
    let waypoints = (0..w.nrows())
        .map(|i| [w[(i, 0)], w[(i, 1)], w[(i, 2)]])
        .collect();
    let knots = match knots {
        Some(k) if !k.is_none() => Some(arrays::vector(
            k,
            "knots",
            Some(w.nrows()),
            "path parameter of each waypoint",
        )?),
        _ => None,
    };
    let interpolation = match interpolation {
        "spline" => Interpolation::Spline,
        "polyline" => Interpolation::Polyline,
        other => {
            return Err(errors::input(format!(
                "interpolation must be \"spline\" (C2, rest at both ends) or \"polyline\", got {other:?}"
            )))
        }
    };
    let discretization = self::discretization(discretization)?;
    let angular_momentum = match angular_momentum {
        Some(d) if !d.is_none() => Some(angular(d)?),
        _ => None,
    };
    let spec = ComMotionSpec {
        scene,
        path: PathSpec {
            waypoints,
            knots,
            interpolation,
        },
        grid_points,
        sd_start,
        sd_end,
        discretization,
        max_violation_fraction,
        samples_per_interval: 10,
        dt,
        angular_momentum,
    };
    let r = py
        .detach(|| stance::retime::retime(&spec))
        .map_err(errors::facade)?;
    let d = json::to_python(py, &r)?;
    py.import("stance._convert")?.getattr("Result")?.call1((d,))
}

/// `{"s": (k,), "l1": (k, 3), "l2": (k, 3)}` (`s` optional).
fn angular(d: &Bound<'_, PyAny>) -> PyResult<AngularSpec> {
    let d = d.cast::<PyDict>().map_err(|_| {
        errors::input("angular_momentum must be a dict with l1, l2 (k, 3) and optionally s (k,)")
    })?;
    let item = |k: &str| d.get_item(k);
    let l1 = item("l1")?.ok_or_else(|| errors::input("angular_momentum needs l1 (k, 3)"))?;
    let l2 = item("l2")?.ok_or_else(|| errors::input("angular_momentum needs l2 (k, 3)"))?;
    let l1 = arrays::matrix(
        &l1,
        "angular_momentum['l1']",
        Some(3),
        "N m s per unit of s",
    )?;
    let l2 = arrays::matrix(
        &l2,
        "angular_momentum['l2']",
        Some(3),
        "N m s per unit of s squared",
    )?;
    let s = match item("s")? {
        Some(s) if !s.is_none() => Some(arrays::vector(
            &s,
            "angular_momentum['s']",
            Some(l1.nrows()),
            "path parameters",
        )?),
        _ => None,
    };
    let rows = |m: &stance::polycone::nalgebra::DMatrix<f64>| -> Vec<[f64; 3]> {
        (0..m.nrows())
            .map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]])
            .collect()
    };
    Ok(AngularSpec {
        s,
        l1: rows(&l1),
        l2: rows(&l2),
    })
}
