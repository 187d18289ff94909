//! Shared helpers of the integration tests: loading the retiming instances of `testdata/topp/`.
#![allow(dead_code)]

pub mod lp;
pub mod random;

use stance_topp::CanonicalConstraints;

#[derive(serde::Deserialize)]
pub struct ComPath {
    pub p: Vec<[f64; 3]>,
    pub ps: Vec<[f64; 3]>,
    pub pss: Vec<[f64; 3]>,
}

#[derive(serde::Deserialize)]
#[allow(non_snake_case)]
pub struct Reference {
    pub duration_collocation: f64,
    pub duration_interpolation: f64,
    pub duration_one_shot_lp_collocation: f64,
    pub duration_collocation_N1000: f64,
    pub duration_interpolation_N1000: f64,
    pub sd_collocation: Vec<f64>,
}

#[derive(serde::Deserialize)]
pub struct Instance {
    pub instance: String,
    pub s: Vec<f64>,
    pub a: Vec<Vec<f64>>,
    pub b: Vec<Vec<f64>>,
    pub c: Vec<Vec<f64>>,
    pub sd_start: f64,
    pub sd_end: f64,
    pub mass: f64,
    pub gravity: [f64; 3],
    #[serde(rename = "U")]
    pub u: Vec<[f64; 6]>,
    pub com_path: ComPath,
    pub reference: Reference,
}

pub fn load(name: &str) -> Instance {
    let path = format!(
        "{}/../../testdata/topp/{name}_N100.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).expect("testdata/topp instance");
    serde_json::from_str(&text).expect("valid instance JSON")
}

impl Instance {
    pub fn constraints(&self) -> CanonicalConstraints {
        CanonicalConstraints::from_dense(&self.s, &self.a, &self.b, &self.c).unwrap()
    }
}

pub const NAMES: [&str; 2] = ["ds_flat", "mc_minvel"];

/// The shared instances' CoM path `p(s) = p0 + s (p1 - p0) + sin(pi s) bow`, recovered from the
/// samples (`p0 = p(0)`, `p1 = p(1)`, `bow = (p_s(0) - (p1 - p0)) / pi`).
#[derive(Clone, Copy)]
pub struct BowPath {
    pub p0: [f64; 3],
    pub p1: [f64; 3],
    pub bow: [f64; 3],
}

impl BowPath {
    pub fn from_instance(inst: &Instance) -> Self {
        let p0 = inst.com_path.p[0];
        let p1 = *inst.com_path.p.last().unwrap();
        let ps0 = inst.com_path.ps[0];
        let bow = std::array::from_fn(|d| (ps0[d] - (p1[d] - p0[d])) / std::f64::consts::PI);
        Self { p0, p1, bow }
    }
}

impl stance_topp::path::PathCurve for BowPath {
    fn domain(&self) -> [f64; 2] {
        [0.0, 1.0]
    }
    fn eval(&self, s: f64) -> stance_topp::path::PathPoint {
        let pi = std::f64::consts::PI;
        let (sn, cs) = (pi * s).sin_cos();
        let mut q = stance_topp::path::PathPoint::default();
        for d in 0..3 {
            q.p[d] = self.p0[d] + s * (self.p1[d] - self.p0[d]) + sn * self.bow[d];
            q.ps[d] = (self.p1[d] - self.p0[d]) + pi * cs * self.bow[d];
            q.pss[d] = -pi * pi * sn * self.bow[d];
        }
        q
    }
}
