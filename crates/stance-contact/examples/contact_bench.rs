//! Rust side of the contact benchmark (`bench/peers/contact.py` runs it; see
//! `bench/peers/contact.md`). Reads a JSON job on standard input:
//! `{"scenes": [built-in example names], "gravities": [[gx, gy, gz], ...],
//!   "sample_points": [[x, y, z], ...], "n_batch": N}` and writes JSON with each scene, the
//! answers (for the peer comparison) and timings (median over 7 batches of repeated calls).
//!
//! Run: `cargo run --release -p stance-contact --example contact_bench < job.json`.

use std::io::Read;
use std::time::Instant;

use serde::{Deserialize, Serialize};
use stance_contact::equilibrium::{PolygonWorkspace, RobustRegion, StaticEquilibrium};
use stance_contact::Scene;

#[derive(Deserialize)]
struct Job {
    scenes: Vec<String>,
    gravities: Vec<[f64; 3]>,
    sample_points: Vec<[f64; 3]>,
    n_batch: usize,
}

#[derive(Serialize)]
struct Out {
    name: String,
    scene: Scene,
    facets: Vec<Vec<f64>>,
    equations: usize,
    polygon: Vec<[f64; 2]>,
    polygon_direct: Vec<[f64; 2]>,
    polygon_route: String,
    region_vertices: usize,
    region_halfspaces: usize,
    sample_stable: Vec<bool>,
    us_u_stance: f64,
    us_polygon_from_u: f64,
    us_polygon_total: f64,
    us_polygon_direct: f64,
    us_polygon_direct_fresh: f64,
    us_region_from_u: f64,
    ns_robust_test_serial: f64,
    ns_static_test_serial: f64,
    ns_robust_test_batch_1core: f64,
    ns_robust_test_batch_all_cores: f64,
    ms_batch_all_cores: f64,
    n_batch: usize,
    threads: usize,
}

/// Median seconds per call over 7 batches, each batch at least 20 ms.
fn time<F: FnMut()>(mut f: F) -> f64 {
    let mut reps = 1usize;
    loop {
        let t = Instant::now();
        for _ in 0..reps {
            f();
        }
        if t.elapsed().as_secs_f64() >= 0.02 {
            break;
        }
        reps *= 2;
    }
    let mut v: Vec<f64> = (0..7)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..reps {
                f();
            }
            t.elapsed().as_secs_f64() / reps as f64
        })
        .collect();
    v.sort_by(f64::total_cmp);
    v[3]
}

/// Deterministic points in the box [-0.5, 0.8] x [-0.6, 0.5] x [0.3, 1.3] (xorshift).
fn points(n: usize) -> Vec<[f64; 3]> {
    let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut u = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| [-0.5 + 1.3 * u(), -0.6 + 1.1 * u(), 0.3 + 1.0 * u()])
        .collect()
}

fn main() {
    let mut text = String::new();
    std::io::stdin().read_to_string(&mut text).unwrap();
    let job: Job = serde_json::from_str(&text).expect("bad job JSON");
    let opts = Default::default();
    let batch = points(job.n_batch);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let mut outs = Vec::new();
    for name in &job.scenes {
        let scene = &stance_contact::examples::by_name(name).expect("unknown example");
        let stance = scene.stance().unwrap();
        let giwc = stance.u_stance(&Default::default()).unwrap();
        let g = scene.gravity;
        let eq = StaticEquilibrium::new(&giwc, g, &opts).unwrap();
        let poly = eq.polygon(0.0).unwrap();
        let region = RobustRegion::new(&giwc, &job.gravities, &opts).unwrap();
        let us_u_stance = 1e6
            * time(|| {
                std::hint::black_box(stance.u_stance(&Default::default()).unwrap());
            });
        let us_polygon_from_u = 1e6
            * time(|| {
                let eq = StaticEquilibrium::new(&giwc, g, &opts).unwrap();
                std::hint::black_box(eq.polygon(0.0).unwrap());
            });
        let us_polygon_total = 1e6
            * time(|| {
                let giwc = stance.u_stance(&Default::default()).unwrap();
                let eq = StaticEquilibrium::new(&giwc, g, &opts).unwrap();
                std::hint::black_box(eq.polygon(0.0).unwrap());
            });
        // The direct route (contact forces, no U_stance): reused buffers, and a fresh workspace
        // per call.
        let mut ws = PolygonWorkspace::new();
        let direct = ws.static_polygon(&stance, g, 0.0, &opts).unwrap();
        let us_polygon_direct = 1e6
            * time(|| {
                std::hint::black_box(ws.static_polygon(&stance, g, 0.0, &opts).unwrap());
            });
        let us_polygon_direct_fresh = 1e6
            * time(|| {
                std::hint::black_box(
                    PolygonWorkspace::new()
                        .static_polygon(&stance, g, 0.0, &opts)
                        .unwrap(),
                );
            });
        let us_region_from_u = 1e6
            * time(|| {
                std::hint::black_box(RobustRegion::new(&giwc, &job.gravities, &opts).unwrap());
            });
        let serial = &batch[..batch.len().min(100_000)];
        let ns_robust_test_serial =
            1e9 * time(|| {
                let mut k = 0usize;
                for p in serial {
                    k += region.contains(std::hint::black_box(*p)) as usize;
                }
                std::hint::black_box(k);
            }) / serial.len() as f64;
        let ns_static_test_serial =
            1e9 * time(|| {
                let mut k = 0usize;
                for p in serial {
                    k += eq.contains(std::hint::black_box(*p)) as usize;
                }
                std::hint::black_box(k);
            }) / serial.len() as f64;
        let mut out = vec![false; batch.len()];
        let ns_robust_test_batch_1core = 1e9
            * one.install(|| time(|| region.contains_batch(&batch, &mut out).unwrap()))
            / batch.len() as f64;
        let t_all = time(|| region.contains_batch(&batch, &mut out).unwrap());
        let mut sample_stable = vec![false; job.sample_points.len()];
        region
            .contains_batch(&job.sample_points, &mut sample_stable)
            .unwrap();
        outs.push(Out {
            name: name.clone(),
            scene: scene.clone(),
            facets: giwc
                .facets
                .row_iter()
                .map(|r| r.iter().copied().collect())
                .collect(),
            equations: giwc.equations.nrows(),
            polygon: poly.vertices.clone(),
            polygon_direct: direct.polygon.vertices.clone(),
            polygon_route: format!("{:?}", direct.route),
            region_vertices: region.polyhedron.vertices.len(),
            region_halfspaces: region.halfspaces.normals.len(),
            sample_stable,
            us_u_stance,
            us_polygon_from_u,
            us_polygon_total,
            us_polygon_direct,
            us_polygon_direct_fresh,
            us_region_from_u,
            ns_robust_test_serial,
            ns_static_test_serial,
            ns_robust_test_batch_1core,
            ns_robust_test_batch_all_cores: 1e9 * t_all / batch.len() as f64,
            ms_batch_all_cores: 1e3 * t_all,
            n_batch: batch.len(),
            threads: rayon::current_num_threads(),
        });
    }
    println!("{}", serde_json::to_string(&outs).unwrap());
}
