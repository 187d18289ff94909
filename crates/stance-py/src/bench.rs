//! `_bench_rust`: the Rust side of `bench/peers/python_api.py`. It times, inside Rust and on
//! the inputs the benchmark passes, the very call a binding makes, so that one run gives the
//! Rust time, the Python call's time (whose difference is what the binding adds) and the
//! peer's time on the same inputs. Not part of the API.

use std::time::Instant;

use pyo3::prelude::*;

use stance::polycone::{self, DdOptions};
use stance::stance_contact::equilibrium::{EquilibriumOptions, PolygonWorkspace};
use stance::stance_robot::{centroidal_map, Data};
use stance::stance_topp::{CanonicalConstraints, Discretization, Row, SolveOptions, Workspace};

use crate::{arrays, contact, errors};

/// Seconds per call: the mean of each of 7 blocks of `repeats` calls (the estimator of the
/// Python side, `per_call` in the benchmark).
fn times(repeats: usize, mut f: impl FnMut()) -> Vec<f64> {
    let n = repeats.max(1);
    (0..7)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..n {
                f();
            }
            t.elapsed().as_secs_f64() / n as f64
        })
        .collect()
}

/// Seconds per call of one operation (7 block means of `repeats` calls), timed in Rust:
///
/// - `("span_to_face", V)`;
/// - `("static_polygon", stance)`;
/// - `("robust_batch", stance, gravities, coms)` (the region computed once, outside the timing);
/// - `("topp", s, a, b, c, discretization)` with `a`, `b`, `c` of shape `(N + 1, m)`;
/// - `("centroidal_map", model, q)`.
#[pyfunction]
#[pyo3(signature = (op, args, repeats))]
pub fn _bench_rust(
    py: Python<'_>,
    op: &str,
    args: &Bound<'_, pyo3::types::PyTuple>,
    repeats: usize,
) -> PyResult<Vec<f64>> {
    let arg = |i: usize| args.get_item(i);
    match op {
        "span_to_face" => {
            let v = arrays::matrix(&arg(0)?, "V", None, "generators")?;
            let opts = DdOptions::default();
            Ok(py.detach(|| {
                times(repeats, || {
                    std::hint::black_box(polycone::span_to_face(&v, &opts).ok());
                })
            }))
        }
        "static_polygon" => {
            let st = arg(0)?;
            let st = st.cast::<contact::Stance>()?.get();
            let g = st.scene.gravity;
            Ok(py.detach(|| {
                times(repeats, || {
                    std::hint::black_box(
                        PolygonWorkspace::new()
                            .static_polygon(&st.stance, g, 0.0, &EquilibriumOptions::default())
                            .ok(),
                    );
                })
            }))
        }
        "robust_batch" => {
            let st = arg(0)?;
            let st = st.cast::<contact::Stance>()?.get();
            let region = st.robust_region(py, &arg(1)?)?;
            let (v, _) = arrays::with_points3(&arg(2)?, "coms", |p| p.to_vec())?;
            let mut out = vec![false; v.len()];
            Ok(py.detach(|| {
                times(repeats, || {
                    region.contains_batch(&v, &mut out).ok();
                    std::hint::black_box(&out);
                })
            }))
        }
        "topp" => {
            let s = arrays::vector(&arg(0)?, "s", None, "grid")?;
            let [a, b, c] = [1, 2, 3].map(|i| arrays::matrix(&arg(i)?, "rows", None, "rows"));
            let (a, b, c) = (a?, b?, c?);
            let disc = match arg(4)?.extract::<String>()?.as_str() {
                "collocation" => Discretization::Collocation,
                _ => Discretization::Interpolation,
            };
            let m = a.ncols();
            let rows: Vec<Row> = (0..s.len())
                .flat_map(|i| (0..m).map(move |j| (i, j)))
                .map(|(i, j)| Row {
                    a: a[(i, j)],
                    b: b[(i, j)],
                    c: c[(i, j)],
                })
                .collect();
            let offsets: Vec<usize> = (0..=s.len()).map(|i| i * m).collect();
            let opts = SolveOptions::new(disc);
            Ok(py.detach(|| {
                times(repeats, || {
                    // What `stance.topp` does per call: the constraints, a workspace, the solve.
                    let k = CanonicalConstraints::new(s.clone(), offsets.clone(), rows.clone());
                    if let Ok(k) = k {
                        std::hint::black_box(Workspace::new().solve(&k, &opts).ok());
                    }
                })
            }))
        }
        "centroidal_map" => {
            let m = arg(0)?;
            let m = m.cast::<crate::robot::Model>()?.get();
            let q = arrays::vector(&arg(1)?, "q", None, "configuration")?;
            let model = m.model();
            let mut data = Data::new(model);
            Ok(py.detach(|| {
                times(repeats, || {
                    std::hint::black_box(centroidal_map(model, &mut data, &q).ok());
                })
            }))
        }
        other => Err(errors::input(format!("no benchmark {other}"))),
    }
}
