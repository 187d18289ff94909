//! Contacts, stances and their stability sets: `Contact`, `Stance` (the GIWC `U_stance`,
//! static and robust static equilibrium, supporting forces) and their results.

use std::sync::{Arc, Mutex, OnceLock};

use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

use stance::stance_contact::equilibrium::{
    EquilibriumOptions, PolygonWorkspace, RobustRegion as RustRobust, StaticEquilibrium,
    StaticPolygon,
};
use stance::stance_contact::{
    self as sc, Approximation, ContactSpec, ForcesOutcome, FrictionModel, Giwc as RustGiwc, Scene,
    Shape,
};

use crate::{arrays, errors, json};

const EYE: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// One contact: a pose `world_from_contact` (the z axis is the surface normal, pointing into the
/// robot), a convex shape in the contact frame and a friction coefficient.
#[pyclass(frozen, module = "stance._stance")]
pub struct Contact {
    pub spec: ContactSpec,
    pub contact: sc::Contact,
    /// Whether the user named it (an unnamed contact is `"contact"` until a stance numbers it).
    pub named: bool,
}

impl Contact {
    pub fn from_spec(spec: ContactSpec) -> PyResult<Self> {
        let contact = sc::Contact::new(
            &spec.name,
            spec.position,
            spec.rotation,
            spec.shape.clone(),
            spec.friction,
            &Default::default(),
        )
        .map_err(errors::contact)?;
        Ok(Self {
            spec,
            contact,
            named: true,
        })
    }

    fn build(
        name: Option<String>,
        position: &Bound<'_, PyAny>,
        rotation: Option<&Bound<'_, PyAny>>,
        shape: Shape,
        friction: f64,
    ) -> PyResult<Self> {
        let position = arrays::vec3(position, "position", "contact origin in the world, m")?;
        let rotation = match rotation {
            Some(r) if !r.is_none() => arrays::mat3(
                r,
                "rotation",
                "world_from_contact rotation, columns = contact axes",
            )?,
            _ => EYE,
        };
        let named = name.is_some();
        let mut c = Self::from_spec(ContactSpec {
            name: name.unwrap_or_else(|| "contact".into()),
            position,
            rotation,
            shape,
            friction,
        })?;
        c.named = named;
        Ok(c)
    }
}

#[pymethods]
impl Contact {
    /// A rectangular surface contact `[-half_length, half_length] x [-half_width, half_width]`
    /// in the contact frame (m).
    #[staticmethod]
    #[pyo3(signature = (position, rotation, half_length, half_width, friction, name = None))]
    fn rectangle(
        position: &Bound<'_, PyAny>,
        rotation: Option<&Bound<'_, PyAny>>,
        half_length: f64,
        half_width: f64,
        friction: f64,
        name: Option<String>,
    ) -> PyResult<Self> {
        Self::build(
            name,
            position,
            rotation,
            Shape::Rectangle {
                half_length,
                half_width,
            },
            friction,
        )
    }

    /// A point contact at `position`.
    #[staticmethod]
    #[pyo3(signature = (position, rotation = None, friction = 0.7, name = None))]
    fn point(
        position: &Bound<'_, PyAny>,
        rotation: Option<&Bound<'_, PyAny>>,
        friction: f64,
        name: Option<String>,
    ) -> PyResult<Self> {
        Self::build(name, position, rotation, Shape::Point, friction)
    }

    /// A convex polygonal contact, `vertices` `(n, 2)` in the contact frame (m), either
    /// orientation.
    #[staticmethod]
    #[pyo3(signature = (position, rotation, vertices, friction, name = None))]
    fn polygon(
        position: &Bound<'_, PyAny>,
        rotation: Option<&Bound<'_, PyAny>>,
        vertices: &Bound<'_, PyAny>,
        friction: f64,
        name: Option<String>,
    ) -> PyResult<Self> {
        let v = arrays::matrix(
            vertices,
            "vertices",
            Some(2),
            "polygon vertices in the contact frame, m",
        )?;
        let pts = (0..v.nrows()).map(|i| [v[(i, 0)], v[(i, 1)]]).collect();
        Self::build(name, position, rotation, Shape::Polygon(pts), friction)
    }

    /// The contact's name.
    #[getter]
    fn name(&self) -> &str {
        &self.spec.name
    }

    /// Contact frame origin in the world (m).
    #[getter]
    fn position<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arrays::to_array1(py, &self.spec.position)
    }

    /// `world_from_contact` rotation `(3, 3)` (its third column is the surface normal).
    #[getter]
    fn rotation<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        arrays::rows_to_array2(py, &self.spec.rotation)
    }

    /// Friction coefficient.
    #[getter]
    fn friction(&self) -> f64 {
        self.spec.friction
    }

    /// Vertices of the shape in the world `(n, 3)` (m).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        arrays::rows_to_array2(py, &self.contact.vertices_world())
    }

    /// The contact as a dict of the scene-file format.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json::to_python(py, &self.spec)
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        json::reduce(py, "Contact", &self.spec)
    }

    fn __repr__(&self) -> String {
        let p = self.spec.position;
        format!(
            "Contact({:?}, position=[{}, {}, {}], {}, friction={})",
            self.spec.name,
            p[0],
            p[1],
            p[2],
            match &self.spec.shape {
                Shape::Point => "point".to_string(),
                Shape::Rectangle {
                    half_length,
                    half_width,
                } => format!("rectangle {half_length} x {half_width}"),
                Shape::Polygon(v) => format!("polygon of {} vertices", v.len()),
            },
            self.spec.friction
        )
    }
}

/// The face form of a gravito-inertial wrench cone `U_stance` (the paper's convention:
/// `facets @ w_GI <= 0` for a wrench `w_GI = (f, tau)` at the world origin that the contacts
/// can hold; the net contact wrench is `-w_GI`).
#[pyclass(frozen, module = "stance._stance")]
pub struct Giwc {
    pub giwc: Arc<RustGiwc>,
    /// The certificate's route (`None`: built from a face form), kept through pickling.
    arithmetic: Option<&'static str>,
    /// The certificate's merged rows, kept through pickling.
    merged_rows: usize,
}

impl Giwc {
    /// Wraps a cone, its route read from its certificate.
    pub fn wrap(giwc: Arc<RustGiwc>) -> Self {
        let c = giwc.certificate.as_ref();
        Self {
            arithmetic: c.map(|c| c.route()),
            merged_rows: c.map_or(0, |c| c.merged_rows),
            giwc,
        }
    }
}

#[pymethods]
impl Giwc {
    /// Build from a known face form: `facets` `(m, 6)`, `equations` `(e, 6)`.
    #[new]
    #[pyo3(signature = (facets, equations = None))]
    fn new(facets: &Bound<'_, PyAny>, equations: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        let u = arrays::matrix(facets, "facets", Some(6), "GIWC facet rows (force, torque)")?;
        let e = match equations {
            Some(e) if !e.is_none() => arrays::matrix(e, "equations", Some(6), "equation rows")?,
            _ => stance::polycone::nalgebra::DMatrix::zeros(0, 6),
        };
        let giwc = RustGiwc::from_face(&u, &e).map_err(errors::contact)?;
        Ok(Self::wrap(Arc::new(giwc)))
    }

    /// `U_stance`, `(m, 6)` unit rows.
    #[getter]
    fn facets<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        arrays::to_array2(py, &self.giwc.facets)
    }

    /// Equations `(e, 6)` (`e = 0` when the cone is full-dimensional).
    #[getter]
    fn equations<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        arrays::to_array2(py, &self.giwc.equations)
    }

    /// Lineality basis `(l, 6)` (`l = 0` when pointed).
    #[getter]
    fn lineality<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        arrays::to_array2(py, &self.giwc.lineality)
    }

    /// Whether the cone conversion certified its result.
    #[getter]
    fn certified(&self) -> bool {
        self.giwc.certified
    }

    /// Which arithmetic gave the rows: `"tolerance"`, `"exact"` or `"exact_fallback"` (the
    /// floating-point answer failed its certificate); `None` for a cone built from a face form
    /// (the route, not the rest of the certificate, is kept through pickling).
    #[getter]
    fn arithmetic(&self) -> Option<&'static str> {
        self.arithmetic
    }

    /// Rows of an exact fallback's answer dropped as slivers of the rounded input (0 otherwise);
    /// no unit wrench the rows admit violates a dropped row by more than the tolerance `1e-8`.
    #[getter]
    fn merged_rows(&self) -> usize {
        self.merged_rows
    }

    /// Largest `U w / |w|` (and equation residual) of a wrench `w` `(6,)` at the world origin:
    /// `<= 0` inside the cone.
    fn max_violation(&self, w: &Bound<'_, PyAny>) -> PyResult<f64> {
        let v = arrays::vector(
            w,
            "w",
            Some(6),
            "wrench (force, torque) at the world origin",
        )?;
        Ok(self
            .giwc
            .max_violation(&[v[0], v[1], v[2], v[3], v[4], v[5]]))
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let state = PyDict::new(py);
        state.set_item("facets", arrays::to_array2(py, &self.giwc.facets))?;
        state.set_item("equations", arrays::to_array2(py, &self.giwc.equations))?;
        state.set_item("lineality", arrays::to_array2(py, &self.giwc.lineality))?;
        state.set_item("certified", self.giwc.certified)?;
        state.set_item("arithmetic", self.arithmetic)?;
        state.set_item("merged_rows", self.merged_rows)?;
        json::reduce_state(py, "Giwc", state.into_any())
    }

    fn __repr__(&self) -> String {
        format!(
            "Giwc({} facets, {} equations, {} lineality, certified={})",
            self.giwc.facets.nrows(),
            self.giwc.equations.nrows(),
            self.giwc.lineality.nrows(),
            if self.giwc.certified { "True" } else { "False" }
        )
    }
}

/// Rebuilds a pickled `Giwc` (the arrays and the certificate's verdict as computed).
pub fn giwc_from_state(state: &Bound<'_, PyDict>) -> PyResult<Giwc> {
    let get = |k: &str| json::state_item(state, "Giwc", k);
    let m = |k: &str| arrays::matrix(&get(k)?, k, Some(6), "GIWC rows");
    let arithmetic: Option<String> = get("arithmetic")?.extract()?;
    let arithmetic = match arithmetic.as_deref() {
        None => None,
        Some("tolerance") => Some("tolerance"),
        Some("exact") => Some("exact"),
        Some("exact_fallback") => Some("exact_fallback"),
        Some(other) => {
            return Err(errors::input(format!(
            "pickled Giwc with arithmetic {other:?}: expected tolerance, exact or exact_fallback"
        )))
        }
    };
    Ok(Giwc {
        giwc: Arc::new(RustGiwc {
            facets: m("facets")?,
            equations: m("equations")?,
            lineality: m("lineality")?,
            certified: get("certified")?.extract()?,
            // The certificate's details are not pickled: its verdict and route are.
            certificate: None,
        }),
        arithmetic,
        merged_rows: get("merged_rows")?.extract()?,
    })
}

/// The static-equilibrium polygon: the CoM positions `(x, y)` (at height `height`) where the
/// contacts can hold the robot at rest.
#[pyclass(frozen, module = "stance._stance")]
pub struct Polygon {
    /// `"bounded"`, `"empty"` or `"unbounded"` (clipped to a far box).
    #[pyo3(get)]
    pub status: &'static str,
    /// 2 for a proper polygon, 1 or 0 when degenerate.
    #[pyo3(get)]
    pub dim: usize,
    /// Vertices `(n, 2)`, counter-clockwise (m).
    #[pyo3(get)]
    pub vertices: Py<PyArray2<f64>>,
    /// Half-planes `A @ (x, y) <= b`, unit rows `(k, 2)`.
    #[pyo3(get, name = "A")]
    pub a: Py<PyArray2<f64>>,
    /// Offsets `(k,)` (m).
    #[pyo3(get)]
    pub b: Py<PyArray1<f64>>,
    /// Height of the cross-section (m).
    #[pyo3(get)]
    pub height: f64,
    /// Whether it was computed by the direct route (support-function LPs over the contact
    /// forces) or through `U_stance`.
    #[pyo3(get)]
    pub route: &'static str,
}

impl Polygon {
    fn from_rust(py: Python<'_>, p: &StaticPolygon, route: &'static str) -> Self {
        let a: Vec<[f64; 2]> = p.halfplanes.iter().map(|h| h.0).collect();
        let b: Vec<f64> = p.halfplanes.iter().map(|h| h.1).collect();
        Polygon {
            status: p.status.name(),
            dim: p.dim,
            vertices: arrays::rows_to_array2(py, &p.vertices).unbind(),
            a: arrays::rows_to_array2(py, &a).unbind(),
            b: arrays::to_array1(py, &b).unbind(),
            height: p.height,
            route,
        }
    }
}

#[pymethods]
impl Polygon {
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let state = PyDict::new(py);
        state.set_item("status", self.status)?;
        state.set_item("dim", self.dim)?;
        state.set_item("vertices", self.vertices.clone_ref(py))?;
        state.set_item("A", self.a.clone_ref(py))?;
        state.set_item("b", self.b.clone_ref(py))?;
        state.set_item("height", self.height)?;
        state.set_item("route", self.route)?;
        json::reduce_state(py, "Polygon", state.into_any())
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        use numpy::PyUntypedArrayMethods;
        format!(
            "Polygon({}, {} vertices)",
            self.status,
            self.vertices.bind(py).shape()[0]
        )
    }
}

/// The name, among a fixed set, that equals `s` (pickled states carry strings).
fn known(s: &str) -> &'static str {
    [
        "bounded",
        "empty",
        "unbounded",
        "direct",
        "via U_stance",
        "feasible",
        "infeasible",
    ]
    .into_iter()
    .find(|k| *k == s)
    .unwrap_or("unknown")
}

/// Rebuilds a pickled `Polygon`.
pub fn polygon_from_state(state: &Bound<'_, PyDict>) -> PyResult<Polygon> {
    let get = |k: &str| json::state_item(state, "Polygon", k);
    let status: String = get("status")?.extract()?;
    let route: String = get("route")?.extract()?;
    Ok(Polygon {
        status: known(&status),
        dim: get("dim")?.extract()?,
        vertices: get("vertices")?.cast_into::<PyArray2<f64>>()?.unbind(),
        a: get("A")?.cast_into::<PyArray2<f64>>()?.unbind(),
        b: get("b")?.cast_into::<PyArray1<f64>>()?.unbind(),
        height: get("height")?.extract()?,
        route: known(&route),
    })
}

/// The robust static-equilibrium region `M` (eq. 12): CoM positions where the contacts hold
/// the robot at rest for every gravity-like vector of a set (e.g. to absorb accelerations).
#[pyclass(frozen, module = "stance._stance")]
pub struct RobustRegion {
    pub region: Arc<RustRobust>,
    /// The cone it was computed from (for pickling).
    pub giwc: Arc<RustGiwc>,
}

/// Rebuilds a pickled `RobustRegion` (recomputed from its cone and gravities: deterministic).
pub fn robust_from_state(state: &Bound<'_, PyDict>) -> PyResult<RobustRegion> {
    let get = |k: &str| json::state_item(state, "RobustRegion", k);
    let u = arrays::matrix(&get("facets")?, "facets", Some(6), "GIWC rows")?;
    let e = arrays::matrix(&get("equations")?, "equations", Some(6), "GIWC equations")?;
    let g = arrays::matrix(&get("gravities")?, "gravities", Some(3), "gravities")?;
    let gs: Vec<[f64; 3]> = (0..g.nrows())
        .map(|i| [g[(i, 0)], g[(i, 1)], g[(i, 2)]])
        .collect();
    // The cone as computed (not re-normalized): the region is recomputed bit for bit.
    let giwc = Arc::new(RustGiwc {
        facets: u,
        equations: e,
        lineality: stance::polycone::nalgebra::DMatrix::zeros(0, 6),
        certified: true,
        certificate: None,
    });
    let region =
        RustRobust::new(&giwc, &gs, &EquilibriumOptions::default()).map_err(errors::contact)?;
    Ok(RobustRegion {
        region: Arc::new(region),
        giwc,
    })
}

#[pymethods]
impl RobustRegion {
    /// `"bounded"`, `"empty"` or `"unbounded"`.
    #[getter]
    fn status(&self) -> &'static str {
        self.region.polyhedron.status.name()
    }

    /// Dimension of the region (3 for a solid).
    #[getter]
    fn dim(&self) -> usize {
        self.region.polyhedron.dim
    }

    /// The gravity-like vectors `(K, 3)` (m/s^2).
    #[getter]
    fn gravities<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        arrays::rows_to_array2(py, &self.region.gravities)
    }

    /// Vertices `(n, 3)` (m).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        arrays::rows_to_array2(py, &self.region.polyhedron.vertices)
    }

    /// Faces: vertex indices, counter-clockwise seen from outside.
    #[getter]
    fn faces(&self) -> Vec<Vec<usize>> {
        self.region.polyhedron.faces.clone()
    }

    /// Half-spaces `A @ p <= b` (unit rows `(k, 3)`).
    #[getter(A)]
    fn a<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        arrays::rows_to_array2(py, &self.region.halfspaces.normals)
    }

    /// Offsets `(k,)` (m).
    #[getter]
    fn b<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arrays::to_array1(py, &self.region.halfspaces.offsets)
    }

    /// Whether each CoM of `coms` `(n, 3)` is in the region (GIL released, parallel).
    fn contains<'py>(
        &self,
        py: Python<'py>,
        coms: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let r = self.region.clone();
        batch(py, coms, move |p, out| r.contains_batch(p, out))
    }

    /// Signed margin (m) of one CoM: distance to the boundary inside; outside, minus the largest
    /// plane violation.
    fn margin(&self, com: &Bound<'_, PyAny>) -> PyResult<f64> {
        Ok(self.region.margin(arrays::vec3(com, "com", "CoM, m")?))
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let state = PyDict::new(py);
        state.set_item("facets", arrays::to_array2(py, &self.giwc.facets))?;
        state.set_item("equations", arrays::to_array2(py, &self.giwc.equations))?;
        state.set_item(
            "gravities",
            arrays::rows_to_array2(py, &self.region.gravities),
        )?;
        json::reduce_state(py, "RobustRegion", state.into_any())
    }

    fn __repr__(&self) -> String {
        format!(
            "RobustRegion({}, {} vertices, {} faces)",
            self.status(),
            self.region.polyhedron.vertices.len(),
            self.region.polyhedron.faces.len()
        )
    }
}

/// Batches from this size run with the GIL released.
const DETACH_FROM: usize = 256;

/// Runs a batch CoM test with the GIL released (large batches); a single point `(3,)` gives a bool, `(n, 3)` an
/// array of bools.
fn batch<'py>(
    py: Python<'py>,
    coms: &Bound<'py, PyAny>,
    test: impl Fn(&[[f64; 3]], &mut [bool]) -> Result<(), sc::ContactError> + Send + Sync,
) -> PyResult<Bound<'py, PyAny>> {
    // One CoM: no borrow, no allocation, no thread.
    if let Ok(a) = coms.cast::<numpy::PyArray1<f64>>() {
        if let Some(p) = arrays::as_vec3(a) {
            let mut out = [false];
            test(&[p], &mut out).map_err(errors::contact)?;
            return Ok(pyo3::types::PyBool::new(py, out[0]).to_owned().into_any());
        }
    }
    let (out, single) = arrays::with_points3(coms, "coms", |points| {
        let mut out = vec![false; points.len()];
        // Releasing the GIL costs more than testing a few CoMs.
        if points.len() < DETACH_FROM {
            test(points, &mut out).map(|()| out)
        } else {
            py.detach(|| test(points, &mut out)).map(|()| out)
        }
    })?;
    let out = out.map_err(errors::contact)?;
    if single {
        return Ok(pyo3::types::PyBool::new(py, out[0]).to_owned().into_any());
    }
    Ok(PyArray1::from_vec(py, out).into_any())
}

/// A set of contacts, the robot's mass and gravity. Contacts made without a name are named by
/// their place in the list (`contact0`, `contact1`, ...); two contacts given the same name are
/// an error.
#[pyclass(frozen, module = "stance._stance")]
pub struct Stance {
    pub scene: Scene,
    pub stance: sc::Stance,
    contacts: Vec<Py<Contact>>,
    giwc: OnceLock<Arc<RustGiwc>>,
    statics: OnceLock<Arc<StaticEquilibrium>>,
    robust: Mutex<Option<Arc<RustRobust>>>,
}

impl Stance {
    pub fn from_scene_struct(py: Python<'_>, scene: Scene) -> PyResult<Self> {
        let stance = scene.stance().map_err(errors::contact)?;
        let contacts = scene
            .contacts
            .iter()
            .map(|c| Py::new(py, Contact::from_spec(c.clone())?))
            .collect::<PyResult<_>>()?;
        Ok(Self {
            scene,
            stance,
            contacts,
            giwc: OnceLock::new(),
            statics: OnceLock::new(),
            robust: Mutex::new(None),
        })
    }

    /// `U_stance`, computed once (GIL released).
    pub fn giwc_arc(&self, py: Python<'_>) -> PyResult<Arc<RustGiwc>> {
        if let Some(g) = self.giwc.get() {
            return Ok(g.clone());
        }
        let g = py
            .detach(|| self.stance.u_stance(&Default::default()))
            .map_err(errors::contact)?;
        Ok(self.giwc.get_or_init(|| Arc::new(g)).clone())
    }

    fn statics_for(
        &self,
        py: Python<'_>,
        gravity: Option<[f64; 3]>,
    ) -> PyResult<Arc<StaticEquilibrium>> {
        let giwc = self.giwc_arc(py)?;
        match gravity {
            Some(g) if g != self.scene.gravity => Ok(Arc::new(
                StaticEquilibrium::new(&giwc, g, &EquilibriumOptions::default())
                    .map_err(errors::contact)?,
            )),
            _ => {
                if let Some(s) = self.statics.get() {
                    return Ok(s.clone());
                }
                let s = StaticEquilibrium::new(
                    &giwc,
                    self.scene.gravity,
                    &EquilibriumOptions::default(),
                )
                .map_err(errors::contact)?;
                Ok(self.statics.get_or_init(|| Arc::new(s)).clone())
            }
        }
    }

    pub fn robust_region(
        &self,
        py: Python<'_>,
        gravities: &Bound<'_, PyAny>,
    ) -> PyResult<Arc<RustRobust>> {
        let g = arrays::matrix(
            gravities,
            "gravities",
            Some(3),
            "gravity-like vectors, m/s^2",
        )?;
        let gs: Vec<[f64; 3]> = (0..g.nrows())
            .map(|i| [g[(i, 0)], g[(i, 1)], g[(i, 2)]])
            .collect();
        if let Some(r) = self.robust.lock().unwrap().as_ref() {
            if r.gravities == gs {
                return Ok(r.clone());
            }
        }
        let giwc = self.giwc_arc(py)?;
        let r = py
            .detach(|| RustRobust::new(&giwc, &gs, &EquilibriumOptions::default()))
            .map_err(errors::contact)?;
        let r = Arc::new(r);
        *self.robust.lock().unwrap() = Some(r.clone());
        Ok(r)
    }
}

fn friction_model(sides: usize, approximation: &str) -> PyResult<FrictionModel> {
    let approximation = match approximation {
        "outer" => Approximation::Outer,
        "inner" => Approximation::Inner,
        other => {
            return Err(errors::input(format!(
                "friction_approximation must be \"outer\" (the paper's circumscribed pyramid) or \
                 \"inner\" (inscribed), got {other:?}"
            )))
        }
    };
    let m = FrictionModel {
        sides,
        approximation,
    };
    m.validate().map_err(errors::contact)?;
    Ok(m)
}

#[pymethods]
impl Stance {
    #[new]
    #[pyo3(signature = (contacts, mass, gravity = None, *, friction_sides = 4, friction_approximation = "outer"))]
    fn new(
        py: Python<'_>,
        contacts: &Bound<'_, PyAny>,
        mass: f64,
        gravity: Option<&Bound<'_, PyAny>>,
        friction_sides: usize,
        friction_approximation: &str,
    ) -> PyResult<Self> {
        let mut specs = Vec::new();
        let mut unnamed = Vec::new();
        let iter = contacts.try_iter().map_err(|_| {
            errors::input("contacts must be a list of stance.Contact (Contact.rectangle, ...)")
        })?;
        for (i, c) in iter.enumerate() {
            let c = c?;
            let c = c.cast::<Contact>().map_err(|_| {
                errors::input(format!(
                    "contacts[{i}] is not a stance.Contact: build it with Contact.rectangle, \
                     Contact.point or Contact.polygon"
                ))
            })?;
            if !c.get().named {
                unnamed.push(i);
            }
            specs.push(c.get().spec.clone());
        }
        // contacts made without a name are numbered by their place in the list (`contact0`,
        // `contact1`, ...), after any name the user gave; explicit duplicates stay an error
        let mut taken: std::collections::HashSet<String> = specs
            .iter()
            .enumerate()
            .filter(|(i, _)| !unnamed.contains(i))
            .map(|(_, s)| s.name.clone())
            .collect();
        for &i in &unnamed {
            let mut name = format!("contact{i}");
            let mut n = 1;
            while taken.contains(&name) {
                name = format!("contact{i}_{n}");
                n += 1;
            }
            taken.insert(name.clone());
            specs[i].name = name;
        }
        let gravity = match gravity {
            Some(g) if !g.is_none() => arrays::vec3(g, "gravity", "gravity vector, m/s^2")?,
            _ => [0.0, 0.0, -9.81],
        };
        let scene = Scene {
            mass,
            gravity,
            contacts: specs,
            friction_model: friction_model(friction_sides, friction_approximation)?,
        };
        Self::from_scene_struct(py, scene)
    }

    /// A stance from a scene: a file path (JSON or TOML), a dict of the scene-file format, or a
    /// built-in example name (`"stairs"`, `"box-climbing"`, ...).
    #[staticmethod]
    fn from_scene(py: Python<'_>, source: &Bound<'_, PyAny>) -> PyResult<Self> {
        let scene: Scene = if source.is_instance_of::<PyDict>() {
            json::from_python(py, source, "scene")?
        } else if let Ok(path) = source.extract::<std::path::PathBuf>() {
            stance::input::scene(&path.to_string_lossy()).map_err(errors::facade)?
        } else {
            return Err(errors::input(
                "from_scene takes a path, a dict of the scene format or an example name",
            ));
        };
        Self::from_scene_struct(py, scene)
    }

    /// The contacts.
    #[getter]
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        PyList::new(py, self.contacts.iter().map(|c| c.clone_ref(py)))
    }

    /// Total mass (kg).
    #[getter]
    fn mass(&self) -> f64 {
        self.scene.mass
    }

    /// Gravity (m/s^2).
    #[getter]
    fn gravity<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arrays::to_array1(py, &self.scene.gravity)
    }

    /// The stance as a dict of the scene-file format.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json::to_python(py, &self.scene)
    }

    /// The gravito-inertial wrench cone `U_stance` (computed once per stance; GIL released).
    fn giwc(&self, py: Python<'_>) -> PyResult<Giwc> {
        Ok(Giwc::wrap(self.giwc_arc(py)?))
    }

    /// The static-equilibrium polygon at height `height` (m) for `gravity` (default: the
    /// stance's), computed from the contact forces directly (support-function LPs), through
    /// `U_stance` when that route cannot conclude.
    #[pyo3(signature = (gravity = None, height = 0.0))]
    fn static_equilibrium_polygon(
        &self,
        py: Python<'_>,
        gravity: Option<&Bound<'_, PyAny>>,
        height: f64,
    ) -> PyResult<Polygon> {
        let g = match gravity {
            Some(g) if !g.is_none() => arrays::vec3(g, "gravity", "gravity vector, m/s^2")?,
            _ => self.scene.gravity,
        };
        let r = py
            .detach(|| {
                PolygonWorkspace::new().static_polygon(
                    &self.stance,
                    g,
                    height,
                    &EquilibriumOptions::default(),
                )
            })
            .map_err(errors::contact)?;
        let route = match r.route {
            sc::equilibrium::PolygonRoute::Direct => "direct",
            sc::equilibrium::PolygonRoute::ViaUStance(_) => "via U_stance",
        };
        Ok(Polygon::from_rust(py, &r.polygon, route))
    }

    /// Whether the contacts can hold the robot at rest with its CoM at each row of `coms`
    /// `(n, 3)` (m): `U_stance (m g, m p x g) <= 0`. A single CoM `(3,)` gives a bool.
    /// Batches run with the GIL released, in parallel.
    #[pyo3(signature = (coms, gravity = None))]
    fn is_static_equilibrium<'py>(
        &self,
        py: Python<'py>,
        coms: &Bound<'py, PyAny>,
        gravity: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let g = match gravity {
            Some(g) if !g.is_none() => Some(arrays::vec3(g, "gravity", "gravity vector, m/s^2")?),
            _ => None,
        };
        let eq = self.statics_for(py, g)?;
        batch(py, coms, move |p, out| eq.contains_batch(p, out))
    }

    /// The robust static-equilibrium region for the gravity-like vectors `gravities` `(K, 3)`.
    fn robust_static_region(
        &self,
        py: Python<'_>,
        gravities: &Bound<'_, PyAny>,
    ) -> PyResult<RobustRegion> {
        Ok(RobustRegion {
            region: self.robust_region(py, gravities)?,
            giwc: self.giwc_arc(py)?,
        })
    }

    /// Whether each CoM of `coms` `(n, 3)` is robustly statically stable for every vector of
    /// `gravities` `(K, 3)` (the region is computed once and kept for the same gravities).
    fn is_robust_static_equilibrium<'py>(
        &self,
        py: Python<'py>,
        coms: &Bound<'py, PyAny>,
        gravities: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let r = self.robust_region(py, gravities)?;
        batch(py, coms, move |p, out| r.contains_batch(p, out))
    }

    /// Contact forces (minimal sum of squares, on the shape vertices) that hold the robot with
    /// its CoM at `com` (m), CoM acceleration `com_acceleration` (m/s^2) and rate of angular
    /// momentum about the CoM `angular_momentum_rate` (N m), or a certificate that none exist:
    /// the independent check of every face-form answer (a QP over the forces, no double
    /// description).
    #[pyo3(signature = (com, com_acceleration = None, angular_momentum_rate = None))]
    fn supporting_forces(
        &self,
        py: Python<'_>,
        com: &Bound<'_, PyAny>,
        com_acceleration: Option<&Bound<'_, PyAny>>,
        angular_momentum_rate: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<SupportingForces> {
        let p = arrays::vec3(com, "com", "CoM, m")?;
        let opt3 = |x: Option<&Bound<'_, PyAny>>, name: &str, what: &str| -> PyResult<[f64; 3]> {
            match x {
                Some(x) if !x.is_none() => arrays::vec3(x, name, what),
                _ => Ok([0.0; 3]),
            }
        };
        let pdd = opt3(
            com_acceleration,
            "com_acceleration",
            "CoM acceleration, m/s^2",
        )?;
        let ld = opt3(
            angular_momentum_rate,
            "angular_momentum_rate",
            "rate of angular momentum about the CoM, N m",
        )?;
        let (m, g) = (self.scene.mass, self.scene.gravity);
        let f = [0, 1, 2].map(|k| m * (g[k] - pdd[k]));
        let w = [
            f[0],
            f[1],
            f[2],
            p[1] * f[2] - p[2] * f[1] - ld[0],
            p[2] * f[0] - p[0] * f[2] - ld[1],
            p[0] * f[1] - p[1] * f[0] - ld[2],
        ];
        let r = py
            .detach(|| sc::supporting_forces(&self.stance, &w, &Default::default()))
            .map_err(errors::contact)?;
        SupportingForces::from_rust(py, &r, w)
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        json::reduce(py, "Stance", &self.scene)
    }

    fn __repr__(&self) -> String {
        format!(
            "Stance([{}], mass={})",
            self.scene
                .contacts
                .iter()
                .map(|c| c.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            self.scene.mass
        )
    }
}

/// Result of `Stance.supporting_forces`.
#[pyclass(frozen, module = "stance._stance")]
pub struct SupportingForces {
    /// `"feasible"`, `"infeasible"` (certified by the solver) or `"unknown"`.
    #[pyo3(get)]
    pub outcome: &'static str,
    /// The contact of each application point.
    #[pyo3(get)]
    pub contact_names: Vec<String>,
    /// Index into `contact_names` of each point `(n,)`.
    #[pyo3(get)]
    pub contact_index: Vec<usize>,
    /// Application points (the shape vertices) `(n, 3)`, world (m).
    #[pyo3(get)]
    pub points: Py<PyArray2<f64>>,
    /// Forces `(n, 3)`, world (N).
    #[pyo3(get)]
    pub forces: Py<PyArray2<f64>>,
    /// The gravito-inertial wrench `(6,)` at the world origin that the forces balance.
    #[pyo3(get)]
    pub w_gi: Py<PyArray1<f64>>,
    /// Relative wrench residual of the returned forces.
    #[pyo3(get)]
    pub residual: f64,
    /// Largest relative friction-pyramid violation of the returned forces.
    #[pyo3(get)]
    pub friction_violation: f64,
    /// Relative L1 distance from `-w_GI` to the contacts' wrenches (0 when feasible).
    #[pyo3(get)]
    pub distance: f64,
}

impl SupportingForces {
    fn from_rust(py: Python<'_>, r: &sc::SupportingForces, w: [f64; 6]) -> PyResult<Self> {
        let mut names = Vec::new();
        let mut index = Vec::new();
        let mut points = Vec::new();
        let mut forces = Vec::new();
        for (i, c) in r.contacts.iter().enumerate() {
            names.push(c.contact.clone());
            for (p, f) in c.points.iter().zip(&c.forces_world) {
                index.push(i);
                points.push(*p);
                forces.push(*f);
            }
        }
        Ok(Self {
            outcome: match r.outcome {
                ForcesOutcome::Feasible => "feasible",
                ForcesOutcome::Infeasible => "infeasible",
                ForcesOutcome::Unknown => "unknown",
            },
            contact_names: names,
            contact_index: index,
            points: arrays::rows_to_array2(py, &points).unbind(),
            forces: arrays::rows_to_array2(py, &forces).unbind(),
            w_gi: arrays::to_array1(py, &w).unbind(),
            residual: r.residual,
            friction_violation: r.friction_violation,
            distance: r.distance,
        })
    }
}

#[pymethods]
impl SupportingForces {
    /// Whether forces were found.
    #[getter]
    fn feasible(&self) -> bool {
        self.outcome == "feasible"
    }

    fn __bool__(&self) -> bool {
        self.feasible()
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let state = PyDict::new(py);
        state.set_item("outcome", self.outcome)?;
        state.set_item("contact_names", self.contact_names.clone())?;
        state.set_item("contact_index", self.contact_index.clone())?;
        state.set_item("points", self.points.clone_ref(py))?;
        state.set_item("forces", self.forces.clone_ref(py))?;
        state.set_item("w_gi", self.w_gi.clone_ref(py))?;
        state.set_item("residual", self.residual)?;
        state.set_item("friction_violation", self.friction_violation)?;
        state.set_item("distance", self.distance)?;
        json::reduce_state(py, "SupportingForces", state.into_any())
    }

    fn __repr__(&self) -> String {
        format!(
            "SupportingForces({}, {} points, residual={:.1e})",
            self.outcome,
            self.contact_index.len(),
            self.residual
        )
    }
}

/// Rebuilds a pickled `SupportingForces`.
pub fn forces_from_state(state: &Bound<'_, PyDict>) -> PyResult<SupportingForces> {
    let get = |k: &str| json::state_item(state, "SupportingForces", k);
    let outcome: String = get("outcome")?.extract()?;
    Ok(SupportingForces {
        outcome: known(&outcome),
        contact_names: get("contact_names")?.extract()?,
        contact_index: get("contact_index")?.extract()?,
        points: get("points")?.cast_into::<PyArray2<f64>>()?.unbind(),
        forces: get("forces")?.cast_into::<PyArray2<f64>>()?.unbind(),
        w_gi: get("w_gi")?.cast_into::<PyArray1<f64>>()?.unbind(),
        residual: get("residual")?.extract()?,
        friction_violation: get("friction_violation")?.extract()?,
        distance: get("distance")?.extract()?,
    })
}
