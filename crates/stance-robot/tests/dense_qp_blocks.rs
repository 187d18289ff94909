//! The dense solver with `P` declared block diagonal (`DenseQpWorkspace::set_blocks`, the force
//! check's per-vertex blocks) against the same solver with `P` dense: random block-diagonal
//! QPs with equations and bounds, the same status and the same answer to round-off.

use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;
use stance_robot::ik::{DenseQpOptions, DenseQpStatus, DenseQpWorkspace};

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn blocks_give_the_dense_answer(
        sizes in prop::collection::vec(1usize..6, 1..8),
        seed in prop::collection::vec(-1.0f64..1.0, 600),
        m in 0usize..4,
    ) {
        let n: usize = sizes.iter().sum();
        prop_assume!(m < n);
        let mut k = 0;
        let mut next = || { k += 1; seed[k % seed.len()] };
        // P = B^T B + I per block: definite, zero outside the blocks
        let mut p = DMatrix::<f64>::zeros(n, n);
        let mut start = 0;
        for &s in &sizes {
            let b = DMatrix::from_fn(s, s, |_, _| next());
            let blk = b.transpose() * &b + DMatrix::identity(s, s);
            p.view_mut((start, start), (s, s)).copy_from(&blk);
            start += s;
        }
        let c = DVector::from_fn(n, |_, _| next());
        let a = DMatrix::from_fn(m, n, |_, _| next());
        let b = DVector::from_fn(m, |_, _| 0.3 * next());
        // nonnegative weights, some with upper bounds
        let lo = vec![0.0; n];
        let hi: Vec<f64> = (0..n).map(|i| if i % 3 == 0 { 0.5 } else { f64::INFINITY }).collect();
        let opts = DenseQpOptions::default();
        let mut dense = DenseQpWorkspace::new();
        let rd = dense.solve(&p, &c, &a, &b, &lo, &hi, &opts);
        let mut blocked = DenseQpWorkspace::new();
        blocked.set_blocks(&sizes);
        let rb = blocked.solve(&p, &c, &a, &b, &lo, &hi, &opts);
        prop_assert_eq!(rd.status, rb.status);
        if rd.status == DenseQpStatus::Optimal {
            let scale = 1.0 + dense.solution().iter().fold(0.0f64, |s, x| s.max(x.abs()));
            for (x, y) in dense.solution().iter().zip(blocked.solution()) {
                prop_assert!((x - y).abs() <= 1e-9 * scale, "{} vs {}", x, y);
            }
        }
    }
}
