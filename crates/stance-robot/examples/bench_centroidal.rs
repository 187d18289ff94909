//! Benchmark runner for `bench/peers/robot.py`: forward kinematics + CoM + A_g per configuration.
//!
//! Usage: `bench_centroidal INPUT.json OUTPUT.json` with INPUT
//! `{"urdf": path, "locked": [[name, value], ...], "configurations": [[q...], ...],
//! "velocities": [[v...], ...], "repeat": R, "chunk": C}`. It computes `centroidal_map`
//! (forward kinematics, CoM, CoM Jacobian and A_g in one pass) for every configuration, and
//! `centroidal_map_dot_v` (the same plus velocities and dA_g/dt v) for every (q, v), writes the
//! answers (for the peer comparison), then times R rounds over all configurations, each round in
//! chunks of C configurations (short timed sections, so that the scheduler's preemptions on a
//! shared machine spoil few of them), and reports the median and minimum over all chunks of the
//! time per configuration in nanoseconds, for both.

use std::time::Instant;

use serde_json::{json, Value};
use stance_robot::{centroidal_map, centroidal_map_dot_v, Data, Model, UrdfOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    if args.len() != 3 {
        return Err("usage: bench_centroidal INPUT.json OUTPUT.json".into());
    }
    let input: Value = serde_json::from_str(&std::fs::read_to_string(&args[1])?)?;
    let urdf = input["urdf"].as_str().ok_or("missing urdf")?;
    let locked = input["locked"]
        .as_array()
        .ok_or("missing locked")?
        .iter()
        .map(|p| {
            (
                p[0].as_str().unwrap_or_default().to_string(),
                p[1].as_f64().unwrap_or(0.0),
            )
        })
        .collect();
    let configurations: Vec<Vec<f64>> = serde_json::from_value(input["configurations"].clone())?;
    let velocities: Vec<Vec<f64>> = serde_json::from_value(input["velocities"].clone())?;
    if velocities.len() != configurations.len() {
        return Err("as many velocities as configurations are needed".into());
    }
    let repeat = input["repeat"].as_u64().unwrap_or(10).max(1) as usize;
    let chunk = input["chunk"].as_u64().unwrap_or(100).max(1) as usize;
    let model = Model::from_urdf_file(
        urdf,
        &UrdfOptions {
            locked,
            ..Default::default()
        },
    )?;
    let mut data = Data::new(&model);

    let mut results = Vec::with_capacity(configurations.len());
    for q in &configurations {
        centroidal_map(&model, &mut data, q)?;
        let ag: Vec<Vec<f64>> = (0..6)
            .map(|i| (0..model.nv).map(|j| data.centroidal_map[(i, j)]).collect())
            .collect();
        results.push(json!({"com": data.com.as_slice(), "centroidal_map": ag}));
    }
    let mut drifts = Vec::with_capacity(configurations.len());
    for (q, v) in configurations.iter().zip(&velocities) {
        let dh = centroidal_map_dot_v(&model, &mut data, q, v)?;
        drifts.push(dh.as_slice().to_vec());
    }

    let mut per_config_ns = Vec::with_capacity(repeat);
    let mut sink = 0.0;
    for _ in 0..repeat {
        for part in configurations.chunks(chunk) {
            let start = Instant::now();
            for q in part {
                centroidal_map(&model, &mut data, q)?;
                sink += std::hint::black_box(data.centroidal_map[(3, 7)] + data.com[0]);
            }
            per_config_ns.push(start.elapsed().as_nanos() as f64 / part.len() as f64);
        }
    }
    per_config_ns.sort_by(f64::total_cmp);
    let pairs: Vec<(&Vec<f64>, &Vec<f64>)> = configurations.iter().zip(&velocities).collect();
    let mut drift_ns = Vec::with_capacity(repeat);
    for _ in 0..repeat {
        for part in pairs.chunks(chunk) {
            let start = Instant::now();
            for (q, v) in part {
                let dh = centroidal_map_dot_v(&model, &mut data, q, v)?;
                sink += std::hint::black_box(data.centroidal_map[(3, 7)] + dh[4]);
            }
            drift_ns.push(start.elapsed().as_nanos() as f64 / part.len() as f64);
        }
    }
    drift_ns.sort_by(f64::total_cmp);
    let out = json!({
        "nq": model.nq,
        "nv": model.nv,
        "results": results,
        "median_ns": per_config_ns[per_config_ns.len() / 2],
        "min_ns": per_config_ns[0],
        "centroidal_map_dot_v": drifts,
        "dot_v_median_ns": drift_ns[drift_ns.len() / 2],
        "dot_v_min_ns": drift_ns[0],
        "checksum": sink,
    });
    std::fs::write(&args[2], serde_json::to_string(&out)?)?;
    Ok(())
}
