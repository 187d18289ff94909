use super::*;
use std::time::Instant;

fn median_us<F: FnMut()>(mut f: F) -> f64 {
    let mut t: Vec<f64> = (0..5000)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64() * 1e6
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

/// Whitening time (warm buffers) on the golden stances:
/// `cargo test --release -p polycone --lib whitening_time -- --ignored --nocapture`.
#[test]
#[ignore]
fn whitening_time() {
    let tol = Tolerances::default();
    for case in [
        "single_support_flat",
        "surface_cwc_foot",
        "double_support_flat",
        "double_support_stairs",
        "tilted_foot_hand_ledge",
        "opposing_walls_frictionless",
        "opposing_walls_friction",
    ] {
        let v = super::alloc_count::golden_for_tests(case);
        let (mut out, mut scratch) = (Whitened::default(), WhitenScratch::default());
        let mut best = f64::INFINITY;
        // The best median of 3 rounds.
        for _ in 0..3 {
            best = best.min(median_us(|| {
                whiten_into(std::hint::black_box(&v), &tol, &mut out, &mut scratch);
                std::hint::black_box(&out);
            }));
        }
        eprintln!(
            "{case:30} {:3} generators: {best:5.2} us, rank {}, {} distinct",
            v.nrows(),
            out.r,
            out.distinct.len()
        );
    }
}
