//! `Model`: a floating-base robot from URDF and its centroidal quantities, with Pinocchio's
//! conventions (`q = (x, y, z, qx, qy, qz, qw, joints)`, `v = (v_base, w_base, joints)` with
//! the base twist in the base frame, `h_G = A_g(q) v = (m c_dot, L_G)` linear first).

use std::sync::Mutex;

use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use serde::{Deserialize, Serialize};

use stance::stance_robot::{
    self as sr, center_of_mass, centroidal_map, centroidal_map_dot_v, Data, RootJoint, UrdfOptions,
};

use crate::{arrays, errors, json};

/// `(rotation (3, 3), translation (3,))` of a frame.
type Placement<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>);

/// What a model is built from (its pickled state).
#[derive(Serialize, Deserialize, Clone)]
pub struct ModelSource {
    urdf: String,
    locked: Vec<(String, f64)>,
    free_flyer: bool,
}

/// A robot model.
#[pyclass(frozen, module = "stance._stance")]
pub struct Model {
    source: ModelSource,
    model: sr::Model,
    data: Mutex<Data>,
}

impl Model {
    fn build(source: ModelSource) -> PyResult<Self> {
        let options = UrdfOptions {
            root: if source.free_flyer {
                RootJoint::FreeFlyer
            } else {
                RootJoint::Fixed
            },
            locked: source.locked.clone(),
            ..Default::default()
        };
        let model = sr::Model::from_urdf_str(&source.urdf, &options).map_err(errors::robot)?;
        let data = Mutex::new(Data::new(&model));
        Ok(Self {
            source,
            model,
            data,
        })
    }

    pub fn from_state(text: &str) -> PyResult<Self> {
        let source: ModelSource = serde_json::from_str(text)
            .map_err(|e| errors::input(format!("invalid pickled Model: {e}")))?;
        Self::build(source)
    }

    /// The Rust model.
    pub fn model(&self) -> &sr::Model {
        &self.model
    }

    fn q(&self, q: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
        arrays::vector(
            q,
            "q",
            Some(self.model.nq),
            "configuration (Pinocchio's layout)",
        )
    }

    fn v(&self, v: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
        arrays::vector(v, "v", Some(self.model.nv), "velocity (Pinocchio's layout)")
    }

    /// Runs `f` with the model's workspace (a fresh one when another thread holds it).
    fn with_data<R>(&self, f: impl FnOnce(&mut Data) -> R) -> R {
        match self.data.try_lock() {
            Ok(mut d) => f(&mut d),
            Err(_) => f(&mut Data::new(&self.model)),
        }
    }
}

fn locked_list(locked: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<(String, f64)>> {
    let Some(locked) = locked.filter(|l| !l.is_none()) else {
        return Ok(vec![]);
    };
    if let Ok(d) = locked.cast::<PyDict>() {
        let mut out = Vec::new();
        for (k, v) in d.iter() {
            out.push((
                k.extract::<String>()?,
                v.extract::<f64>().map_err(|_| {
                    errors::input(format!("locked[{k}] must be a joint position (number)"))
                })?,
            ));
        }
        return Ok(out);
    }
    let names: Vec<String> = locked.extract().map_err(|_| {
        errors::input(
            "locked must be a dict {joint name: position} or a list of joint names (locked at 0)",
        )
    })?;
    Ok(names.into_iter().map(|n| (n, 0.0)).collect())
}

#[pymethods]
impl Model {
    /// A model from a URDF file. `locked`: joints fixed at a position (`{name: value}`, or a
    /// list of names fixed at 0), removed from `q` and `v` as Pinocchio's `buildReducedModel`;
    /// `free_flyer`: a floating base (default) or a root fixed to the world.
    #[staticmethod]
    #[pyo3(signature = (path, locked = None, free_flyer = true))]
    fn from_urdf(
        path: std::path::PathBuf,
        locked: Option<&Bound<'_, PyAny>>,
        free_flyer: bool,
    ) -> PyResult<Self> {
        let urdf = std::fs::read_to_string(&path)
            .map_err(|e| errors::input(format!("cannot read URDF {}: {e}", path.display())))?;
        Self::build(ModelSource {
            urdf,
            locked: locked_list(locked)?,
            free_flyer,
        })
    }

    /// A model from URDF text.
    #[staticmethod]
    #[pyo3(signature = (text, locked = None, free_flyer = true))]
    fn from_urdf_string(
        text: String,
        locked: Option<&Bound<'_, PyAny>>,
        free_flyer: bool,
    ) -> PyResult<Self> {
        Self::build(ModelSource {
            urdf: text,
            locked: locked_list(locked)?,
            free_flyer,
        })
    }

    /// The project's small humanoid (shipped with the package).
    #[staticmethod]
    fn small_humanoid() -> PyResult<Self> {
        Self::build(ModelSource {
            urdf: sr::SMALL_HUMANOID_URDF.to_string(),
            locked: vec![],
            free_flyer: true,
        })
    }

    /// JVRC-1 (PyPI `jvrc-description`, installed in the same environment, or the file named
    /// by `STANCE_JVRC1_URDF`) with the project's options: free flyer, fingers locked at 0.
    #[staticmethod]
    fn jvrc1(py: Python<'_>) -> PyResult<Self> {
        let found = py
            .import("stance._convert")?
            .getattr("jvrc1_urdf")?
            .call0()?;
        if found.is_none() {
            return Err(errors::not_installed(
                "JVRC-1's URDF is not installed: pip install jvrc-description==1.1.1 (or set \
                 STANCE_JVRC1_URDF to the file)",
            ));
        }
        let path: std::path::PathBuf = found.extract()?;
        let urdf = std::fs::read_to_string(&path)
            .map_err(|e| errors::input(format!("cannot read URDF {}: {e}", path.display())))?;
        Self::build(ModelSource {
            urdf,
            locked: sr::jvrc1::urdf_options().locked,
            free_flyer: true,
        })
    }

    /// The robot's name (from the URDF).
    #[getter]
    fn name(&self) -> &str {
        &self.model.name
    }

    /// Configuration size.
    #[getter]
    fn nq(&self) -> usize {
        self.model.nq
    }

    /// Velocity size.
    #[getter]
    fn nv(&self) -> usize {
        self.model.nv
    }

    /// Total mass (kg).
    #[getter]
    fn mass(&self) -> f64 {
        self.model.total_mass()
    }

    /// Joint names in `q` order (the root first for a free flyer).
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.model.joint_names()
    }

    /// The neutral configuration (identity base orientation, joints at 0).
    fn neutral<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arrays::to_array1(py, &self.model.neutral())
    }

    /// The centre of mass `c(q)` (m, world).
    fn center_of_mass<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let q = self.q(q)?;
        let c = self
            .with_data(|d| center_of_mass(&self.model, d, &q))
            .map_err(errors::robot)?;
        Ok(arrays::to_array1(py, c.as_slice()))
    }

    /// The centroidal momentum matrix `A_g(q)` `(6, nv)` (`h_G = A_g v`, linear first, angular
    /// about the CoM).
    fn centroidal_map<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = self.q(q)?;
        self.with_data(|d| {
            centroidal_map(&self.model, d, &q)?;
            let a = &d.centroidal_map;
            let m =
                stance::polycone::nalgebra::DMatrix::from_fn(6, self.model.nv, |i, k| a[(i, k)]);
            Ok(arrays::to_array2(py, &m))
        })
        .map_err(errors::robot)
    }

    /// The CoM Jacobian `J_com(q)` `(3, nv)`.
    fn com_jacobian<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = self.q(q)?;
        self.with_data(|d| {
            centroidal_map(&self.model, d, &q)?;
            let j = &d.com_jacobian;
            let m =
                stance::polycone::nalgebra::DMatrix::from_fn(3, self.model.nv, |i, k| j[(i, k)]);
            Ok(arrays::to_array2(py, &m))
        })
        .map_err(errors::robot)
    }

    /// The centroidal momentum `h_G = A_g(q) v` `(6,)` (N s, N m s).
    fn centroidal_momentum<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (q, v) = (self.q(q)?, self.v(v)?);
        self.with_data(|d| {
            centroidal_map(&self.model, d, &q)?;
            let h: Vec<f64> = (0..6)
                .map(|i| {
                    (0..self.model.nv)
                        .map(|k| d.centroidal_map[(i, k)] * v[k])
                        .sum()
                })
                .collect();
            Ok(arrays::to_array1(py, &h))
        })
        .map_err(errors::robot)
    }

    /// `(dA_g/dt) v` `(6,)`: the rate of change of `h_G` when `v` is constant.
    fn centroidal_map_dot_v<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (q, v) = (self.q(q)?, self.v(v)?);
        let h = self
            .with_data(|d| centroidal_map_dot_v(&self.model, d, &q, &v))
            .map_err(errors::robot)?;
        Ok(arrays::to_array1(py, h.as_slice()))
    }

    /// The placement of a frame (URDF link or joint) at `q`: `(rotation (3, 3), translation
    /// (3,))`, `world_from_frame`.
    fn frame_placement<'py>(
        &self,
        py: Python<'py>,
        frame: &str,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Placement<'py>> {
        let q = self.q(q)?;
        let id = self.model.frame_id(frame).map_err(errors::robot)?;
        let pose = self
            .with_data(|d| {
                sr::forward_kinematics(&self.model, d, &q)?;
                sr::frame_placement(&self.model, d, id)
            })
            .map_err(errors::robot)?;
        let r = pose.rotation;
        let rows = [0, 1, 2].map(|i| [r[(i, 0)], r[(i, 1)], r[(i, 2)]]);
        Ok((
            arrays::rows_to_array2(py, &rows),
            arrays::to_array1(py, pose.translation.as_slice()),
        ))
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        json::reduce(py, "Model", &self.source)
    }

    fn __repr__(&self) -> String {
        format!(
            "Model({:?}, nq={}, nv={}, mass={:.3} kg)",
            self.model.name,
            self.model.nq,
            self.model.nv,
            self.model.total_mass()
        )
    }
}
