//! The CoM reference through its via-points (`crate::references`), for random via-points,
//! holds, knots and corner placements.

use nalgebra::Vector3;
use proptest::prelude::*;

use crate::references::{ComReference, CornerKernel};

fn vector() -> impl Strategy<Value = Vector3<f64>> {
    prop::array::uniform3(-0.3..0.3f64).prop_map(Vector3::from)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The reference passes through every via-point at its knot, starts and ends at rest,
    /// stays on a held via-point through its hold, and is twice continuously differentiable
    /// (its derivatives match finite differences of its value and first derivative).
    #[test]
    fn the_com_reference_interpolates_its_via_points(
        moves in prop::collection::vec((vector(), 1.0..3.0f64, prop::bool::weighted(0.25), 0..3usize), 1..8),
        blend in 0.05..0.25f64,
    ) {
        let mut knots = vec![0.0];
        let mut points = vec![Vector3::new(0.0, 0.0, 0.9)];
        // where a corner the CoM passes through is rounded (as at stance switches)
        let mut turns = vec![None];
        for (d, t, hold, turn) in &moves {
            let last = points[points.len() - 1];
            points.push(if *hold { last } else { last + d });
            knots.push(knots[knots.len() - 1] + t);
            turns.push([None, Some(CornerKernel::After), Some(CornerKernel::Before)][*turn]);
        }
        let c = ComReference::new(knots.clone(), points.clone(), blend, &turns).unwrap();
        let scale = 1.0 + points.iter().map(|p| p.norm()).fold(0.0, f64::max);
        for (s, p) in knots.iter().zip(&points) {
            prop_assert!((c.at(*s).p - p).norm() <= 1e-12 * scale, "{s}");
        }
        let (start, end) = (c.at(0.0), c.at(knots[knots.len() - 1]));
        prop_assert!(start.p_s.norm() == 0.0 && start.p_ss.norm() == 0.0);
        prop_assert!(end.p_s.norm() <= 1e-12 * scale && end.p_ss.norm() <= 1e-12 * scale);
        prop_assert!((c.at(knots[knots.len() - 1] + 1.0).p - end.p).norm() <= 1e-12 * scale);
        for k in 1..knots.len() {
            let held = points[k] == points[k - 1];
            for j in 0..=20 {
                let s = knots[k - 1] + (knots[k] - knots[k - 1]) * j as f64 / 20.0;
                let r = c.at(s);
                if held {
                    prop_assert!((r.p - points[k]).norm() <= 1e-12 * scale, "hold at {s}");
                }
                let e = 1e-6;
                let (a, b) = (c.at(s - e), c.at(s + e));
                prop_assert!(((b.p - a.p) / (2.0 * e) - r.p_s).norm() <= 1e-6 * scale / blend);
                prop_assert!(((b.p_s - a.p_s) / (2.0 * e) - r.p_ss).norm() <= 1e-4 * scale / (blend * blend));
            }
        }
        // the kernels: leaving a rest, arriving at one, or as asked where the CoM passes through
        prop_assert_eq!(c.corners[0], CornerKernel::After);
        if let Some(k) = (1..knots.len()).rev().find(|&k| points[k] != points[k - 1]) {
            prop_assert_eq!(c.corners[k], CornerKernel::Before);
        }
    }
}

/// Moves shorter than four half-widths are refused, naming `ik.com_blend`.
#[test]
fn a_blend_too_wide_for_its_moves_is_refused() {
    let e = ComReference::new(
        vec![0.0, 0.5],
        vec![Vector3::zeros(), Vector3::x()],
        0.25,
        &[],
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("ik.com_blend") && e.contains("quarter"), "{e}");
}
