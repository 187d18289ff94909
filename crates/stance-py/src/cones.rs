//! `span_to_face` and `face_to_span`: polyhedral cones between their two descriptions.

use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use stance::polycone::{self, nalgebra::DMatrix, Arithmetic, DdOptions};

use crate::{arrays, errors};

fn options(exact: bool) -> DdOptions {
    DdOptions {
        arithmetic: if exact {
            Arithmetic::Exact
        } else {
            Arithmetic::Tolerance
        },
        ..DdOptions::default()
    }
}

/// The face form `{x : facets @ x <= 0, equations @ x = 0}` of a cone, with its lineality
/// space (rows of `lineality` span the largest linear subspace in the cone).
///
/// Rows of `facets` and `equations` have unit norm. `certified` is whether the engine's
/// certificate (soundness, support, lineality, completeness) proved the answer; an answer that
/// cannot be certified raises `UncertifiedError` instead.
#[pyclass(frozen, module = "stance._stance")]
pub struct FaceForm {
    /// `(m, d)` unit outward facet normals (`facets @ x <= 0` on the cone).
    #[pyo3(get)]
    pub facets: Py<PyArray2<f64>>,
    /// `(e, d)` orthonormal equations (`equations @ x = 0`; `e = 0` for a full-dimensional cone).
    #[pyo3(get)]
    pub equations: Py<PyArray2<f64>>,
    /// `(l, d)` basis of the lineality space (`l = 0` for a pointed cone).
    #[pyo3(get)]
    pub lineality: Py<PyArray2<f64>>,
    /// Whether the answer is certified.
    #[pyo3(get)]
    pub certified: bool,
    /// Indices of the generators that are extreme rays (the irredundant ones).
    #[pyo3(get)]
    pub extreme_generators: Vec<usize>,
}

#[pymethods]
impl FaceForm {
    #[new]
    #[pyo3(signature = (facets, equations, lineality, certified, extreme_generators))]
    fn new(
        facets: &Bound<'_, PyAny>,
        equations: &Bound<'_, PyAny>,
        lineality: &Bound<'_, PyAny>,
        certified: bool,
        extreme_generators: Vec<usize>,
    ) -> PyResult<Self> {
        Ok(Self {
            facets: arrays::owned2(facets, "facets", None)?,
            equations: arrays::owned2(equations, "equations", None)?,
            lineality: arrays::owned2(lineality, "lineality", None)?,
            certified,
            extreme_generators,
        })
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let s = slf.get();
        let args = (
            s.facets.clone_ref(py),
            s.equations.clone_ref(py),
            s.lineality.clone_ref(py),
            s.certified,
            s.extreme_generators.clone(),
        );
        PyTuple::new(
            py,
            [
                slf.get_type().into_any(),
                args.into_pyobject(py)?.into_any(),
            ],
        )
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "FaceForm(facets: {}, equations: {}, lineality: {}, certified={})",
            rows(py, &self.facets),
            rows(py, &self.equations),
            rows(py, &self.lineality),
            if self.certified { "True" } else { "False" }
        )
    }
}

fn rows(py: Python<'_>, a: &Py<PyArray2<f64>>) -> String {
    use numpy::PyUntypedArrayMethods;
    let s = a.bind(py).shape().to_vec();
    format!("{}x{}", s[0], s[1])
}

/// The span form `{generators.T @ z + lineality.T @ y : z >= 0}` of a cone.
#[pyclass(frozen, module = "stance._stance")]
pub struct SpanForm {
    /// `(k, d)` generators (extreme rays), one per row.
    #[pyo3(get)]
    pub generators: Py<PyArray2<f64>>,
    /// `(l, d)` basis of the lineality space.
    #[pyo3(get)]
    pub lineality: Py<PyArray2<f64>>,
    /// Whether the answer is certified.
    #[pyo3(get)]
    pub certified: bool,
    /// Indices of the input facets that are irredundant.
    #[pyo3(get)]
    pub irredundant_facets: Vec<usize>,
}

#[pymethods]
impl SpanForm {
    #[new]
    #[pyo3(signature = (generators, lineality, certified, irredundant_facets))]
    fn new(
        generators: &Bound<'_, PyAny>,
        lineality: &Bound<'_, PyAny>,
        certified: bool,
        irredundant_facets: Vec<usize>,
    ) -> PyResult<Self> {
        Ok(Self {
            generators: arrays::owned2(generators, "generators", None)?,
            lineality: arrays::owned2(lineality, "lineality", None)?,
            certified,
            irredundant_facets,
        })
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let s = slf.get();
        let args = (
            s.generators.clone_ref(py),
            s.lineality.clone_ref(py),
            s.certified,
            s.irredundant_facets.clone(),
        );
        PyTuple::new(
            py,
            [
                slf.get_type().into_any(),
                args.into_pyobject(py)?.into_any(),
            ],
        )
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "SpanForm(generators: {}, lineality: {}, certified={})",
            rows(py, &self.generators),
            rows(py, &self.lineality),
            if self.certified { "True" } else { "False" }
        )
    }
}

/// Face form of the cone spanned by the rows of `generators`.
#[pyfunction]
#[pyo3(signature = (generators, *, exact = false))]
pub fn span_to_face(
    py: Python<'_>,
    generators: &Bound<'_, PyAny>,
    exact: bool,
) -> PyResult<FaceForm> {
    let v = arrays::matrix(generators, "generators", None, "one generator per row")?;
    let out = py
        .detach(|| polycone::span_to_face(&v, &options(exact)))
        .map_err(errors::cone)?;
    Ok(FaceForm {
        facets: arrays::to_array2(py, &out.face.facets).unbind(),
        equations: arrays::to_array2(py, &out.face.equations).unbind(),
        lineality: arrays::to_array2(py, &out.lineality).unbind(),
        certified: out.certificate.certified,
        extreme_generators: out.extreme_generators,
    })
}

/// Span form of the cone `{x : facets @ x <= 0, equations @ x = 0}`.
#[pyfunction]
#[pyo3(signature = (facets, equations = None, *, exact = false))]
pub fn face_to_span(
    py: Python<'_>,
    facets: &Bound<'_, PyAny>,
    equations: Option<&Bound<'_, PyAny>>,
    exact: bool,
) -> PyResult<SpanForm> {
    let u = arrays::matrix(facets, "facets", None, "one facet normal per row")?;
    let e = match equations {
        Some(e) => arrays::matrix(e, "equations", Some(u.ncols()), "one equation per row")?,
        None => DMatrix::zeros(0, u.ncols()),
    };
    let face = polycone::FaceForm::new(u, e).map_err(errors::cone)?;
    let out = py
        .detach(|| polycone::face_to_span(&face, &options(exact)))
        .map_err(errors::cone)?;
    Ok(SpanForm {
        generators: arrays::to_array2(py, &out.span.generators).unbind(),
        lineality: arrays::to_array2(py, &out.span.lineality).unbind(),
        certified: out.certificate.certified,
        irredundant_facets: out.irredundant_facets,
    })
}
