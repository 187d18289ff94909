//! Test inputs shared by the double description's unit tests.

/// A small deterministic generator (64-bit LCG), enough for test inputs.
pub(super) struct Lcg(pub u64);

impl Lcg {
    /// A value in `[-1, 1)`.
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// `m x k` unit rows, row-major; with `degenerate`, coordinates are rounded to a coarse grid
/// first so that many rays are tight on more than `k - 1` rows (the blocker test matters then).
pub(super) fn unit_rows(rng: &mut Lcg, m: usize, k: usize, degenerate: bool) -> Vec<f64> {
    let mut a = Vec::with_capacity(m * k);
    for _ in 0..m {
        let start = a.len();
        for _ in 0..k {
            let v = rng.next();
            a.push(if degenerate { (v * 2.0).round() } else { v });
        }
        if a[start..].iter().all(|&x| x == 0.0) {
            a[start] = 1.0;
        }
        let inv = 1.0 / a[start..].iter().map(|x| x * x).sum::<f64>().sqrt();
        a[start..].iter_mut().for_each(|x| *x *= inv);
    }
    a
}
