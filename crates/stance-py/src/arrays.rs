//! NumPy in and out. Inputs are anything `numpy.asarray(x, dtype=float64)` accepts (arrays of
//! any dtype that casts to float, any strides, lists, tuples); a C-contiguous float64 array is
//! read in place, without a copy. Shapes and finiteness are checked here, and a bad input is an
//! `InputError` naming the argument, the expected shape and what was given.

use numpy::{
    PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;

use stance::polycone::nalgebra::DMatrix;

use crate::errors;

static ASARRAY: PyOnceLock<Py<PyAny>> = PyOnceLock::new();

/// `numpy.asarray(obj, dtype=float64)` as a float64 array (no copy when `obj` already is one).
pub fn float_array<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let py = obj.py();
    let arr = match obj.cast::<PyArrayDyn<f64>>() {
        Ok(a) => a.clone(),
        Err(_) => {
            if obj.is_none() {
                return Err(errors::input(format!(
                    "{name} is None: give an array of numbers"
                )));
            }
            if obj.is_instance_of::<pyo3::types::PyString>()
                || obj.is_instance_of::<pyo3::types::PyBytes>()
            {
                return Err(errors::input(format!(
                    "{name} must be an array of numbers, got a string"
                )));
            }
            let asarray = ASARRAY.get_or_try_init(py, || -> PyResult<_> {
                Ok(py.import("numpy")?.getattr("asarray")?.unbind())
            })?;
            let kwargs = pyo3::types::PyDict::new(py);
            kwargs.set_item("dtype", "float64")?;
            let converted = asarray.bind(py).call((obj,), Some(&kwargs)).map_err(|e| {
                errors::input(format!(
                    "{name} must be an array of numbers ({}): {}",
                    type_name(obj),
                    e.value(py)
                ))
            })?;
            converted
                .cast_into::<PyArrayDyn<f64>>()
                .map_err(|_| errors::input(format!("{name} must be an array of numbers")))?
        }
    };
    Ok(arr)
}

/// [`float_array`], borrowed read-only (NumPy's borrow flags): for data read with the GIL
/// released.
pub fn readonly_array<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<PyReadonlyArrayDyn<'py, f64>> {
    float_array(obj, name)?
        .try_readonly()
        .map_err(|e| errors::input(format!("{name} is being written elsewhere: {e}")))
}

fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "?".into())
}

fn shape_text(shape: &[usize]) -> String {
    match shape.len() {
        0 => "a scalar".into(),
        1 => format!("shape ({},)", shape[0]),
        _ => format!(
            "shape ({})",
            shape
                .iter()
                .map(|s| s.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// The entries in C (row-major) order, read while the GIL is held (no Python code runs
/// meanwhile, and this crate never writes into its inputs): the array's own memory when it is
/// C-contiguous.
pub fn flat<'a>(a: &'a Bound<'_, PyArrayDyn<f64>>) -> std::borrow::Cow<'a, [f64]> {
    // (`as_slice` also accepts Fortran order, whose memory is not in C order.)
    if a.is_c_contiguous() {
        // SAFETY: see above; the slice does not outlive the borrow of `a` and is only read.
        if let Ok(s) = unsafe { a.as_slice() } {
            return std::borrow::Cow::Borrowed(s);
        }
    }
    std::borrow::Cow::Owned(a.to_owned_array().iter().copied().collect())
}

/// [`flat`] of a read-only borrow (for data read with the GIL released).
pub fn flat_borrowed<'a>(a: &'a PyReadonlyArrayDyn<'_, f64>) -> std::borrow::Cow<'a, [f64]> {
    if a.is_c_contiguous() {
        if let Ok(s) = a.as_slice() {
            return std::borrow::Cow::Borrowed(s);
        }
    }
    std::borrow::Cow::Owned(a.as_array().iter().copied().collect())
}

/// The first non-finite entry, as an error naming its index.
fn check_finite<'a>(
    name: &str,
    shape: &[usize],
    values: impl Iterator<Item = &'a f64>,
) -> PyResult<()> {
    for (k, v) in values.enumerate() {
        if !v.is_finite() {
            let mut idx = Vec::with_capacity(shape.len());
            let mut rest = k;
            for d in shape.iter().rev() {
                idx.push(rest % d.max(&1));
                rest /= d.max(&1);
            }
            idx.reverse();
            let idx = idx
                .iter()
                .map(|i| i.to_string())
                .collect::<Vec<_>>()
                .join(", ");
            return Err(errors::input(format!(
                "{name}[{idx}] is {v}: give finite numbers"
            )));
        }
    }
    Ok(())
}

/// A 2-D array `(n, cols)` (any `n`, `cols` when given) as a matrix, finite.
pub fn matrix(
    obj: &Bound<'_, PyAny>,
    name: &str,
    cols: Option<usize>,
    what: &str,
) -> PyResult<DMatrix<f64>> {
    let a = float_array(obj, name)?;
    let shape = a.shape().to_vec();
    let ok = shape.len() == 2 && cols.is_none_or(|c| shape[1] == c);
    if !ok {
        let want = match cols {
            Some(c) => format!("(n, {c})"),
            None => "(n, d)".into(),
        };
        return Err(errors::input(format!(
            "{name} must be a 2-D array of shape {want} ({what}), got {}",
            shape_text(&shape)
        )));
    }
    let values = flat(&a);
    check_finite(name, &shape, values.iter())?;
    let cols = shape[1];
    Ok(DMatrix::from_fn(shape[0], cols, |i, j| {
        values[i * cols + j]
    }))
}

/// A 1-D array of length `len` (when given), finite.
pub fn vector(
    obj: &Bound<'_, PyAny>,
    name: &str,
    len: Option<usize>,
    what: &str,
) -> PyResult<Vec<f64>> {
    let a = float_array(obj, name)?;
    let shape = a.shape().to_vec();
    let ok = shape.len() == 1 && len.is_none_or(|n| shape[0] == n);
    if !ok {
        let want = match len {
            Some(n) => format!("({n},)"),
            None => "(n,)".into(),
        };
        return Err(errors::input(format!(
            "{name} must be a 1-D array of shape {want} ({what}), got {}",
            shape_text(&shape)
        )));
    }
    let values = flat(&a);
    check_finite(name, &shape, values.iter())?;
    Ok(values.into_owned())
}

/// A 3-vector, finite.
pub fn vec3(obj: &Bound<'_, PyAny>, name: &str, what: &str) -> PyResult<[f64; 3]> {
    let v = vector(obj, name, Some(3), what)?;
    Ok([v[0], v[1], v[2]])
}

/// A C-contiguous float64 array of 3 finite numbers, read directly (the fast path of one
/// CoM); None for anything else (which then takes the general path and its messages).
pub fn as_vec3(a: &Bound<'_, PyArray1<f64>>) -> Option<[f64; 3]> {
    if !a.is_c_contiguous() {
        return None;
    }
    // SAFETY: read with the GIL held, as in `flat`.
    let s = unsafe { a.as_slice() }.ok()?;
    match s {
        [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => Some([*x, *y, *z]),
        _ => None,
    }
}

/// Runs `f` with the GIL released when `big` (releasing and taking it back costs about
/// 0.2 us: not worth it for tiny problems, which then block other threads for as little).
pub fn detach_if<T: Send>(py: Python<'_>, big: bool, f: impl FnOnce() -> T + Send) -> T {
    if big {
        py.detach(f)
    } else {
        f()
    }
}

/// A `(3, 3)` matrix as rows, finite.
pub fn mat3(obj: &Bound<'_, PyAny>, name: &str, what: &str) -> PyResult<[[f64; 3]; 3]> {
    let m = matrix(obj, name, Some(3), what)?;
    if m.nrows() != 3 {
        return Err(errors::input(format!(
            "{name} must be a 3x3 array ({what}), got shape ({}, 3)",
            m.nrows()
        )));
    }
    Ok([0, 1, 2].map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]]))
}

/// Points `(n, 3)` (or one point `(3,)`, as `n = 1`) read in place when the input is a
/// C-contiguous float64 array: `f` runs on them; also says whether the input was one point.
/// Non-finite points are an error.
pub fn with_points3<R>(
    obj: &Bound<'_, PyAny>,
    name: &str,
    f: impl FnOnce(&[[f64; 3]]) -> R,
) -> PyResult<(R, bool)> {
    let a = readonly_array(obj, name)?;
    let shape = a.shape().to_vec();
    let ok = (shape.len() == 2 && shape[1] == 3) || (shape.len() == 1 && shape[0] == 3);
    if !ok {
        return Err(errors::input(format!(
            "{name} must be an array of shape (n, 3) (points, m), got {}",
            shape_text(&shape)
        )));
    }
    let values = flat_borrowed(&a);
    check_finite(name, &shape, values.iter())?;
    let (points, _) = values.as_chunks::<3>();
    Ok((f(points), shape.len() == 1))
}

/// A new C-contiguous `(rows, cols)` array with entries `f(i, j)`, written in place (one
/// allocation, by NumPy).
pub fn array2_from_fn<'py>(
    py: Python<'py>,
    rows: usize,
    cols: usize,
    f: impl Fn(usize, usize) -> f64,
) -> Bound<'py, PyArray2<f64>> {
    // SAFETY: the array is fresh (no other reference to it) and C-contiguous; every entry is
    // written below before it is returned.
    let a = unsafe { PyArray2::<f64>::new(py, [rows, cols], false) };
    let data = unsafe { a.as_slice_mut() }.expect("a new array is contiguous");
    for i in 0..rows {
        for j in 0..cols {
            data[i * cols + j] = f(i, j);
        }
    }
    a
}

/// A matrix as a new `(rows, cols)` array.
pub fn to_array2<'py>(py: Python<'py>, m: &DMatrix<f64>) -> Bound<'py, PyArray2<f64>> {
    array2_from_fn(py, m.nrows(), m.ncols(), |i, j| m[(i, j)])
}

/// Rows of `N` numbers as a new `(n, N)` array.
pub fn rows_to_array2<'py, const N: usize>(
    py: Python<'py>,
    rows: &[[f64; N]],
) -> Bound<'py, PyArray2<f64>> {
    array2_from_fn(py, rows.len(), N, |i, j| rows[i][j])
}

/// A vector as a new `(n,)` array.
pub fn to_array1<'py>(py: Python<'py>, v: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v)
}

/// A readonly copy of an input array as an owned array of the pyclass (for `__new__`).
pub fn owned2(
    obj: &Bound<'_, PyAny>,
    name: &str,
    cols: Option<usize>,
) -> PyResult<Py<PyArray2<f64>>> {
    let m = matrix(obj, name, cols, "rows")?;
    Ok(to_array2(obj.py(), &m).unbind())
}
