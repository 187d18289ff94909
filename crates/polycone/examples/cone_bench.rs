//! Bench runner for `bench/peers/cones.py`: times span -> face conversions.
//!
//! Usage: `cargo run --release -p polycone --example cone_bench -- INPUT.json [REPEATS]` with
//! `INPUT.json = {"cases": [{"name": ..., "generators": [[...], ...]}, ...]}` (generators may
//! also be given bit-exactly as `"generators_hex"`, Python `float.hex` strings). Prints one JSON
//! object: per case the facet count, equations, lineality dimension, certified flag, the facets
//! (unit rows) and the median and minimum time per conversion in milliseconds (a warm
//! [`polycone::Workspace`], `REPEATS` runs, default 200). `--exact` uses exact arithmetic,
//! `--no-completeness` skips the completeness check of the certificate (to measure its cost),
//! `--wrench` sets [`DdOptions::wrench`] (6-D wrench cones; measures the re-centring's cost).

use std::time::Instant;

use polycone::nalgebra::DMatrix;
use polycone::{Arithmetic, DdOptions, Workspace};

use stance_test_support::hex::parse_hex;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args
        .get(1)
        .expect("usage: cone_bench INPUT.json [REPEATS] [--exact] [--no-completeness] [--wrench]");
    let repeats: usize = args
        .get(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(200)
        .max(1);
    let exact = args.iter().any(|a| a == "--exact");
    let no_completeness = args.iter().any(|a| a == "--no-completeness");
    let wrench = args.iter().any(|a| a == "--wrench");
    let text = std::fs::read_to_string(path).expect("read input");
    let json: serde_json::Value = serde_json::from_str(&text).expect("parse input");
    let opts = DdOptions {
        arithmetic: if exact {
            Arithmetic::Exact
        } else {
            Arithmetic::Tolerance
        },
        check_completeness: !no_completeness,
        wrench,
        ..DdOptions::default()
    };
    let mut ws = Workspace::new();
    let mut out = Vec::new();
    for case in json["cases"].as_array().expect("cases") {
        let name = case["name"].as_str().expect("name").to_string();
        let rows: Vec<Vec<f64>> = if let Some(h) = case.get("generators_hex") {
            h.as_array()
                .expect("rows")
                .iter()
                .map(|r| {
                    r.as_array()
                        .expect("row")
                        .iter()
                        .map(|x| parse_hex(x.as_str().expect("hex")))
                        .collect()
                })
                .collect()
        } else {
            case["generators"]
                .as_array()
                .expect("rows")
                .iter()
                .map(|r| {
                    r.as_array()
                        .expect("row")
                        .iter()
                        .map(|x| x.as_f64().expect("number"))
                        .collect()
                })
                .collect()
        };
        let d = rows.first().map(Vec::len).unwrap_or(0);
        let v = DMatrix::from_fn(rows.len(), d, |i, j| rows[i][j]);
        let first = ws.span_to_face(&v, &opts);
        let entry = match first {
            Err(e) => serde_json::json!({"name": name, "error": e.to_string()}),
            Ok(r) => {
                let mut times = Vec::with_capacity(repeats);
                for _ in 0..repeats {
                    let t0 = Instant::now();
                    let r = ws.span_to_face(&v, &opts).expect("same input");
                    times.push(t0.elapsed().as_secs_f64() * 1e3);
                    std::hint::black_box(r);
                }
                times.sort_by(f64::total_cmp);
                let facets: Vec<Vec<f64>> = (0..r.face.facets.nrows())
                    .map(|i| r.face.facets.row(i).iter().copied().collect())
                    .collect();
                serde_json::json!({
                    "name": name,
                    "generators": v.nrows(),
                    "facets_count": facets.len(),
                    "equations": r.face.equations.nrows(),
                    "lineality_dim": r.lineality.nrows(),
                    "extreme_generators": r.extreme_generators.len(),
                    "certified": r.certificate.certified,
                    "facets": facets,
                    "median_ms": times[times.len() / 2],
                    "min_ms": times[0],
                })
            }
        };
        out.push(entry);
    }
    println!("{}", serde_json::json!({ "results": out }));
}
