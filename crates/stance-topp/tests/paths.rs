//! CoM path helpers: interpolation of the waypoints, derivatives against finite differences.
#![allow(clippy::needless_range_loop)] // coordinates d = 0..3 index several arrays at once

use proptest::prelude::*;
use stance_topp::path::{CubicSpline, PathCurve, Polyline, SplineEnds};

fn waypoints() -> impl Strategy<Value = (Vec<f64>, Vec<[f64; 3]>)> {
    (2usize..8).prop_flat_map(|n| {
        (
            prop::collection::vec(0.1f64..1.0, n - 1),
            prop::collection::vec(prop::array::uniform3(-1.0f64..1.0), n),
        )
            .prop_map(|(h, p)| {
                let mut s = vec![0.0];
                for d in h {
                    s.push(s.last().unwrap() + d);
                }
                (s, p)
            })
    })
}

proptest! {
    #[test]
    fn spline_interpolates_and_derivatives_match_finite_differences(
        (s, p) in waypoints(),
        clamped in any::<bool>(),
        t0 in prop::array::uniform3(-1.0f64..1.0),
        frac in 0.0f64..1.0,
    ) {
        let ends = if clamped { SplineEnds::Clamped { start: t0, end: [0.0; 3] } } else { SplineEnds::Natural };
        let sp = CubicSpline::new(s.clone(), p.clone(), ends).unwrap();
        for (si, pi) in s.iter().zip(&p) {
            let q = sp.eval(*si);
            for d in 0..3 {
                prop_assert!((q.p[d] - pi[d]).abs() < 1e-9);
            }
        }
        let [a, b] = sp.domain();
        if clamped {
            let (q0, q1) = (sp.eval(a), sp.eval(b));
            for d in 0..3 {
                prop_assert!((q0.ps[d] - t0[d]).abs() < 1e-9);
                prop_assert!(q1.ps[d].abs() < 1e-9);
            }
        } else {
            for d in 0..3 {
                prop_assert!(sp.eval(a).pss[d].abs() < 1e-9 && sp.eval(b).pss[d].abs() < 1e-9);
            }
        }
        // Derivatives by central differences away from the knots' kinks of p_sss. With knot
        // spacing >= 0.1 and |p| <= 1, |p_sss| stays below about 1e4: the tangent's truncation
        // error h^2 |p_sss| / 6 is about 2e-9 and its round-off 1e-10, so FD_TANGENT = 1e-7
        // leaves a margin of 50. The curvature is differentiated across the kinks of p_sss
        // (error up to h |jump of p_sss|), hence its looser bound.
        const FD_TANGENT: f64 = 1e-7;
        let h = 1e-6;
        let x = a + h + (b - a - 2.0 * h) * frac;
        let (qm, q, qp) = (sp.eval(x - h), sp.eval(x), sp.eval(x + h));
        for d in 0..3 {
            prop_assert!((q.ps[d] - (qp.p[d] - qm.p[d]) / (2.0 * h)).abs() < FD_TANGENT * (1.0 + q.ps[d].abs()));
            prop_assert!((q.pss[d] - (qp.ps[d] - qm.ps[d]) / (2.0 * h)).abs() < 1e-4 * (1.0 + q.pss[d].abs()));
        }
        // C1 and C2 continuity at interior knots: across 2e-9 the tangent moves by about
        // 2e-9 |p_ss|, bounded here by 1e-8 (1 + |p_ss|).
        for &k in &s[1..s.len() - 1] {
            let (l, r) = (sp.eval(k - 1e-9), sp.eval(k + 1e-9));
            for d in 0..3 {
                prop_assert!((l.ps[d] - r.ps[d]).abs() < 1e-8 * (1.0 + l.pss[d].abs()));
                prop_assert!((l.pss[d] - r.pss[d]).abs() < 1e-5 * (1.0 + l.pss[d].abs()));
            }
        }
    }

    #[test]
    fn polyline_interpolates_with_piecewise_constant_tangent((s, p) in waypoints(), frac in 0.0f64..1.0) {
        let l = Polyline::new(s.clone(), p.clone()).unwrap();
        for (si, pi) in s.iter().zip(&p) {
            let q = l.eval(*si);
            for d in 0..3 {
                prop_assert!((q.p[d] - pi[d]).abs() < 1e-12);
            }
        }
        let [a, b] = l.domain();
        let x = a + (b - a) * frac;
        let q = l.eval(x);
        prop_assert_eq!(q.pss, [0.0; 3]);
        // Central difference of a straight segment: no truncation error, round-off about
        // EPSILON |p| / h = 2e-9.
        let h = 1e-7;
        if x - h > a && x + h < b && !s.iter().any(|k| (k - x).abs() < 2.0 * h) {
            let (qm, qp) = (l.eval(x - h), l.eval(x + h));
            for d in 0..3 {
                prop_assert!((q.ps[d] - (qp.p[d] - qm.p[d]) / (2.0 * h)).abs() < 1e-7 * (1.0 + q.ps[d].abs()));
            }
        }
    }
}

#[test]
fn path_errors() {
    assert!(Polyline::new(vec![0.0, 0.0], vec![[0.0; 3]; 2]).is_err());
    assert!(Polyline::new(vec![0.0, 1.0], vec![[0.0; 3]; 3]).is_err());
    assert!(CubicSpline::new(
        vec![0.0, 1.0],
        vec![[f64::NAN; 3], [0.0; 3]],
        SplineEnds::Natural
    )
    .is_err());
    let bad = SplineEnds::Clamped {
        start: [f64::INFINITY, 0.0, 0.0],
        end: [0.0; 3],
    };
    assert!(CubicSpline::new(vec![0.0, 1.0], vec![[0.0; 3]; 2], bad).is_err());
}

/// The n-D spline against SciPy's `CubicSpline` (testdata/topp/splines.json, made by
/// `make_splines.py`): not-a-knot, natural and clamped ends on 2 to 9 knots, value and both
/// derivatives within 1e-10 relative to the case's largest value.
#[test]
fn waypoint_path_matches_scipy_cubic_spline() {
    use stance_topp::path::{Interpolation, WaypointPath};
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/topp/splines.json");
    let fx: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let vecf = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let rows = |v: &serde_json::Value| -> Vec<Vec<f64>> {
        v.as_array().unwrap().iter().map(vecf).collect()
    };
    for (c, case) in fx["cases"].as_array().unwrap().iter().enumerate() {
        let knots = vecf(&case["knots"]);
        let points = rows(&case["points"]);
        let dim = points[0].len();
        let interpolation = match case["bc_type"].as_str().unwrap() {
            "not-a-knot" => Interpolation::NotAKnot,
            "natural" => Interpolation::Natural,
            "clamped" => Interpolation::Clamped {
                start: vec![0.0; dim],
                end: vec![0.0; dim],
            },
            other => panic!("{other}"),
        };
        let p = WaypointPath::new(knots, points, interpolation).unwrap();
        let (mut q, mut qs, mut qss) = (vec![0.0; dim], vec![0.0; dim], vec![0.0; dim]);
        for (key, k) in [("q", 0), ("q_s", 1), ("q_ss", 2)] {
            let reference = rows(&case[key]);
            let scale = reference
                .iter()
                .flatten()
                .fold(1.0f64, |a, x| a.max(x.abs()));
            for (s, r) in vecf(&case["s"]).iter().zip(&reference) {
                p.eval(*s, &mut q, &mut qs, &mut qss);
                let got = [&q, &qs, &qss][k];
                for d in 0..dim {
                    let e = (got[d] - r[d]).abs() / scale;
                    assert!(
                        e < 1e-10,
                        "case {c} ({}): {key}[{d}] at s = {s}: {} vs SciPy {} ({e:.1e})",
                        case["bc_type"],
                        got[d],
                        r[d]
                    );
                }
            }
        }
    }
}

#[test]
fn waypoint_path_errors() {
    use stance_topp::path::{Interpolation, WaypointPath};
    let ok = || vec![vec![0.0, 1.0], vec![1.0, 2.0]];
    assert!(WaypointPath::new(vec![0.0, 1.0], ok(), Interpolation::NotAKnot).is_ok());
    assert!(WaypointPath::new(vec![1.0, 1.0], ok(), Interpolation::NotAKnot).is_err());
    assert!(WaypointPath::new(
        vec![0.0, 1.0],
        vec![vec![0.0, 1.0], vec![1.0]],
        Interpolation::Polyline
    )
    .is_err());
    assert!(WaypointPath::new(
        vec![0.0, 1.0],
        vec![vec![0.0, f64::NAN], vec![1.0, 1.0]],
        Interpolation::Natural
    )
    .is_err());
    let bad = Interpolation::Clamped {
        start: vec![0.0],
        end: vec![0.0, 0.0],
    };
    assert!(WaypointPath::new(vec![0.0, 1.0], ok(), bad).is_err());
    assert!(
        WaypointPath::new(vec![0.0, 1.0], vec![vec![], vec![]], Interpolation::Natural).is_err()
    );
}
