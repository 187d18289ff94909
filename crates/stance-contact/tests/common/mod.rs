//! Shared helpers of the integration tests: fixtures and row-set comparison.
#![allow(dead_code)]

use nalgebra::DMatrix;
use nalgebra::Vector3;
use proptest::prelude::*;
use stance_contact::{Approximation, Contact, FrictionModel, Shape, Stance};

pub fn fixture(name: &str) -> serde_json::Value {
    let path = format!(
        "{}/../../testdata/contact/{name}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

pub fn rows(v: &serde_json::Value) -> DMatrix<f64> {
    let r: Vec<Vec<f64>> = serde_json::from_value(v.clone()).unwrap();
    if r.is_empty() {
        return DMatrix::zeros(0, 6);
    }
    DMatrix::from_row_iterator(r.len(), r[0].len(), r.into_iter().flatten())
}

/// The stance of a fixture (rectangles, outer 4-sided pyramids).
pub fn fixture_stance(v: &serde_json::Value) -> Stance {
    let contacts = v["contacts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let pos: [f64; 3] = serde_json::from_value(c["pos"].clone()).unwrap();
            let rot: [[f64; 3]; 3] = serde_json::from_value(c["R"].clone()).unwrap();
            let hs: [f64; 2] = serde_json::from_value(c["half_size"].clone()).unwrap();
            Contact::new(
                c["name"].as_str().unwrap(),
                pos,
                rot,
                Shape::Rectangle {
                    half_length: hs[0],
                    half_width: hs[1],
                },
                c["mu"].as_f64().unwrap(),
                &Default::default(),
            )
            .unwrap()
        })
        .collect();
    Stance::new(contacts, FrictionModel::default()).unwrap()
}

/// Rows normalized to unit length (zero rows dropped).
pub fn normalized(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    m.row_iter()
        .filter(|r| r.norm() > 0.0)
        .map(|r| (r / r.norm()).iter().copied().collect())
        .collect()
}

/// Same set of unit rows up to `tol` (max-norm), both ways, same count.
pub fn same_rows(a: &DMatrix<f64>, b: &DMatrix<f64>, tol: f64) -> Result<(), String> {
    let (a, b) = (normalized(a), normalized(b));
    if a.len() != b.len() {
        return Err(format!("{} rows vs {} rows", a.len(), b.len()));
    }
    let close = |x: &Vec<f64>, y: &Vec<f64>| x.iter().zip(y).all(|(p, q)| (p - q).abs() <= tol);
    for (i, x) in a.iter().enumerate() {
        if !b.iter().any(|y| close(x, y)) {
            return Err(format!(
                "row {i} {x:?} of the first set is not in the second"
            ));
        }
    }
    for (i, y) in b.iter().enumerate() {
        if !a.iter().any(|x| close(x, y)) {
            return Err(format!(
                "row {i} {y:?} of the second set is not in the first"
            ));
        }
    }
    Ok(())
}

/// Projector onto the row space of `m` (for comparing subspaces).
pub fn projector(m: &DMatrix<f64>, dim: usize) -> DMatrix<f64> {
    if m.nrows() == 0 {
        return DMatrix::zeros(dim, dim);
    }
    let svd = m.clone().svd(false, true);
    let vt = svd.v_t.unwrap();
    let mut p = DMatrix::zeros(dim, dim);
    for (k, s) in svd.singular_values.iter().enumerate() {
        if *s > 1e-9 * svd.singular_values.max() {
            let v = vt.row(k).transpose();
            p += &v * v.transpose();
        }
    }
    p
}

/// A contact for the random-stance property tests: at `p`, rotated by `angle` about `axis`
/// (identity for an axis shorter than 1e-3), a point (`kind` 0), an `x` by `y` half-size
/// rectangle (1) or a triangle (2), friction `mu`.
pub fn test_contact(
    p: [f64; 3],
    axis: nalgebra::Vector3<f64>,
    angle: f64,
    kind: usize,
    (x, y): (f64, f64),
    mu: f64,
) -> Contact {
    let r = if axis.norm() > 1e-3 {
        nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle)
    } else {
        nalgebra::Rotation3::identity()
    };
    let m = r.matrix();
    let rot = [
        [m[(0, 0)], m[(0, 1)], m[(0, 2)]],
        [m[(1, 0)], m[(1, 1)], m[(1, 2)]],
        [m[(2, 0)], m[(2, 1)], m[(2, 2)]],
    ];
    let shape = match kind {
        0 => Shape::Point,
        1 => Shape::Rectangle {
            half_length: x,
            half_width: y,
        },
        _ => Shape::Polygon(vec![[x, 0.0], [-x, y], [-x, -y]]),
    };
    Contact::new("c", p, rot, shape, mu, &Default::default()).unwrap()
}

/// A random contact of the agreement tests: upright (tilted at most ~40 deg) or in any
/// orientation, a point, rectangle or triangle, mu in [0.1, 1.2] or (1 in 7) frictionless.
pub fn contact_strategy() -> impl Strategy<Value = Contact> {
    (
        (-0.4f64..0.4, -0.4f64..0.4, 0.0f64..0.8),
        (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0, 0.0f64..1.0),
        0usize..3,
        (0.02f64..0.15, 0.02f64..0.1),
        // Sometimes frictionless (the pyramid degenerates to the normal ray).
        prop_oneof![6 => 0.1f64..1.2, 1 => Just(0.0)],
        proptest::bool::ANY,
    )
        .prop_map(|(p, (ax, ay, az, t), kind, (x, y), mu, upright)| {
            // Upright contacts tilt at most ~40 deg; others take any orientation.
            let angle = if upright {
                0.7 * t
            } else {
                std::f64::consts::PI * t
            };
            let axis = Vector3::new(ax, ay, if upright { 0.0 } else { az });
            test_contact([p.0, p.1, p.2], axis, angle, kind, (x, y), mu)
        })
}

/// A random stance of 1 to 4 contacts: mostly the paper's pyramid; sometimes k-sided outer or
/// inner pyramids (the QP uses their face form, the GIWC their edges: a consistency check of
/// the two).
pub fn stance_strategy() -> impl Strategy<Value = Stance> {
    (
        prop::collection::vec(contact_strategy(), 1..5),
        prop_oneof![3 => Just(4usize), 1 => 3usize..9],
        proptest::bool::ANY,
    )
        .prop_map(|(c, sides, outer)| {
            let approximation = if outer || sides == 4 {
                Approximation::Outer
            } else {
                Approximation::Inner
            };
            Stance::new(
                c,
                FrictionModel {
                    sides,
                    approximation,
                },
            )
            .unwrap()
        })
}
