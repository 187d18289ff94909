//! What the benchmark examples share: the instances `bench/peers/topp.py --write-instances`
//! writes, their CoM path, and a timer.
//!
//! Input: `{"instances": [{"name", "s", "a", "b", "c", "U", "mass", "gravity",
//! "bow": {"p0", "p1", "bow"}}]}` (the CoM path `p0 + s (p1 - p0) + sin(pi s) bow`).

// Each example uses part of this module.
#![allow(dead_code)]

use std::time::Instant;

use stance_topp::path::{PathCurve, PathPoint};

/// The CoM path of an instance: `p0 + s (p1 - p0) + sin(pi s) bow`, `s` in `[0, 1]`.
#[derive(serde::Deserialize, Clone, Copy)]
pub struct Bow {
    pub p0: [f64; 3],
    pub p1: [f64; 3],
    pub bow: [f64; 3],
}

impl PathCurve for Bow {
    fn domain(&self) -> [f64; 2] {
        [0.0, 1.0]
    }
    fn eval(&self, s: f64) -> PathPoint {
        let pi = std::f64::consts::PI;
        let (sn, cs) = (pi * s).sin_cos();
        let mut q = PathPoint::default();
        for d in 0..3 {
            q.p[d] = self.p0[d] + s * (self.p1[d] - self.p0[d]) + sn * self.bow[d];
            q.ps[d] = (self.p1[d] - self.p0[d]) + pi * cs * self.bow[d];
            q.pss[d] = -pi * pi * sn * self.bow[d];
        }
        q
    }
}

/// One instance: the grid, its rows, `U_stance` with mass and gravity, and the CoM path.
#[derive(serde::Deserialize)]
pub struct Instance {
    pub name: String,
    pub s: Vec<f64>,
    pub a: Vec<Vec<f64>>,
    pub b: Vec<Vec<f64>>,
    pub c: Vec<Vec<f64>>,
    #[serde(rename = "U")]
    pub u: Vec<[f64; 6]>,
    pub mass: f64,
    pub gravity: [f64; 3],
    pub bow: Bow,
}

/// The input file.
#[derive(serde::Deserialize)]
pub struct Input {
    pub instances: Vec<Instance>,
}

/// `[median, minimum]` of `reps` timed calls of `f`, in microseconds (after `reps / 10 + 1`
/// warm-up calls). The minimum is the better estimate of the cost on a busy machine.
pub fn timed_us(reps: usize, mut f: impl FnMut()) -> [f64; 2] {
    for _ in 0..reps / 10 + 1 {
        f();
    }
    let mut t: Vec<f64> = (0..reps)
        .map(|_| {
            let t0 = Instant::now();
            f();
            t0.elapsed().as_secs_f64() * 1e6
        })
        .collect();
    t.sort_by(f64::total_cmp);
    [t[reps / 2], t[0]]
}
