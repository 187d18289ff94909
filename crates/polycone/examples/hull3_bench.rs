//! Rust side of the 3-D hull benchmark (`bench/peers/hull3.py` runs it; see
//! `bench/peers/hull3.md`). Reads a JSON job on standard input:
//! `{"clouds": [{"name": str, "points": [[x, y, z], ...]}, ...]}` and writes JSON with, for
//! each cloud, the hull (vertices, face planes `[n_x, n_y, n_z, d]` meaning `n . p <= d`,
//! faces as vertex loops) and the time of one `hull3` call (median over 7 batches, each at least 20 ms).
//!
//! Run: `cargo run --release -p polycone --example hull3_bench < job.json`.

use std::io::Read;
use std::time::Instant;

use polycone::polytope::{hull3, PolytopeOptions};

fn main() {
    let mut text = String::new();
    std::io::stdin()
        .read_to_string(&mut text)
        .expect("read the job from standard input");
    let job: serde_json::Value = serde_json::from_str(&text).expect("the job is JSON");
    let opts = PolytopeOptions::default();
    let mut out = Vec::new();
    for cloud in job["clouds"].as_array().expect("a list of clouds") {
        let name = cloud["name"].as_str().unwrap_or("?").to_string();
        let pts: Vec<[f64; 3]> =
            serde_json::from_value(cloud["points"].clone()).expect("points are [x, y, z] rows");
        let hull = hull3(&pts, &opts).expect("hull3 succeeds on the benchmark clouds");
        // Calls per batch so that a batch lasts at least 20 ms.
        let t = Instant::now();
        std::hint::black_box(hull3(&pts, &opts).unwrap());
        let once = t.elapsed().as_secs_f64().max(1e-7);
        let reps = ((0.02 / once).ceil() as usize).max(1);
        let mut batches: Vec<f64> = (0..7)
            .map(|_| {
                let t = Instant::now();
                for _ in 0..reps {
                    std::hint::black_box(hull3(&pts, &opts).unwrap());
                }
                t.elapsed().as_secs_f64() / reps as f64
            })
            .collect();
        batches.sort_by(f64::total_cmp);
        out.push(serde_json::json!({
            "name": name,
            "dim": hull.dim,
            "vertices": hull.vertices,
            "planes": hull.planes.iter().map(|(n, d)| [n[0], n[1], n[2], *d]).collect::<Vec<_>>(),
            "faces": hull.faces,
            "us_hull3": batches[3] * 1e6,
        }));
    }
    println!("{}", serde_json::to_string(&out).unwrap());
}
