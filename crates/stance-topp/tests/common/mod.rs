//! Shared helpers of the integration tests: loading the retiming instances of `testdata/topp/`.
#![allow(dead_code)]

pub mod lp;

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
