//! Random retiming instances shared by the tests.

use stance_topp::{CanonicalConstraints, Row};

/// splitmix64: a tiny deterministic generator driven by proptest's seed.
pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// Random rows that (u, x) = (0, 0) satisfies strictly, plus |u| <= U and x <= X so the sets
/// are bounded. `monotone`: every row has a = 0 or b = 0.
pub fn random_instance(seed: u64, n: usize, m: usize, monotone: bool) -> CanonicalConstraints {
    let mut r = Rng(seed);
    let mut s = vec![0.0];
    for _ in 0..n {
        let last = *s.last().unwrap();
        s.push(last + r.range(0.02, 0.1));
    }
    let mut rows = Vec::new();
    let mut offsets = vec![0];
    for _ in 0..=n {
        let u_max = r.range(0.5, 3.0);
        rows.push(Row {
            a: 1.0,
            b: 0.0,
            c: -u_max,
        });
        rows.push(Row {
            a: -1.0,
            b: 0.0,
            c: -u_max,
        });
        rows.push(Row {
            a: 0.0,
            b: 1.0,
            c: -r.range(1.0, 5.0),
        });
        for _ in 0..m {
            let mut a = r.range(-1.0, 1.0);
            let mut b = r.range(-1.0, 1.0);
            let kind = r.next();
            if kind < 0.2 {
                a = 0.0; // zero-inertia row: a bound on x
            } else if monotone || kind < 0.3 {
                if monotone && kind < 0.6 {
                    a = 0.0;
                } else {
                    b = 0.0;
                }
            }
            rows.push(Row {
                a,
                b,
                c: -r.range(0.2, 2.0),
            });
        }
        offsets.push(rows.len());
    }
    CanonicalConstraints::new(s, offsets, rows).unwrap()
}
