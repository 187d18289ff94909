//! `stance topp FILE` end to end, through the built binary.

use std::path::PathBuf;

use serde_json::{json, Value};
use stance_test_support::cli;

fn tmp(name: &str, contents: &str) -> PathBuf {
    cli::temp_file("cli-topp", name, contents)
}

fn run(args: &[&str]) -> (i32, String, String) {
    let r = cli::run(env!("CARGO_BIN_EXE_stance"), args);
    (r.code, r.stdout, r.stderr)
}

/// The shared instance reduced to the contract's keys.
fn instance(name: &str, disc: &str) -> (Value, f64) {
    let path = format!(
        "{}/../../testdata/topp/{name}_N100.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let full: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let reference = full["reference"][format!("duration_{disc}")]
        .as_f64()
        .unwrap();
    let v = json!({
        "s": full["s"], "a": full["a"], "b": full["b"], "c": full["c"],
        "sd_start": full["sd_start"], "sd_end": full["sd_end"], "discretization": disc,
    });
    (v, reference)
}

#[test]
fn topp_solves_the_shared_instances_like_toppra() {
    for name in ["ds_flat", "mc_minvel"] {
        for disc in ["collocation", "interpolation"] {
            let (v, reference) = instance(name, disc);
            let f = tmp(&format!("{name}_{disc}.json"), &v.to_string());
            let (code, stdout, stderr) = run(&["topp", f.to_str().unwrap(), "--repeat", "3"]);
            assert_eq!(code, 0, "{stderr}");
            let out: Value = serde_json::from_str(&stdout).unwrap();
            assert_eq!(out["status"], "optimal");
            assert_eq!(out["discretization"], disc);
            let d = out["duration"].as_f64().unwrap();
            assert!(
                ((d - reference) / reference).abs() < 1e-6,
                "{name} {disc}: {d} vs {reference}"
            );
            assert_eq!(out["sd"].as_array().unwrap().len(), 101);
            assert_eq!(out["t"].as_array().unwrap().len(), 101);
            assert_eq!(out["sdd"].as_array().unwrap().len(), 100);
            assert_eq!(out["controllable_sets"].as_array().unwrap().len(), 101);
            assert!(out["max_residual"].as_f64().unwrap() < 1e-9);
        }
    }
}

#[test]
fn topp_writes_to_a_file_and_reads_toml() {
    let toml = "s = [0.0, 0.5, 1.0]\na = [[1.0, -1.0], [1.0, -1.0], [1.0, -1.0]]\n\
                b = [[0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]\nc = [[-1.0, -1.0], [-1.0, -1.0], [-1.0, -1.0]]\n";
    let f = tmp("bang.toml", toml);
    let o = f.with_extension("out.json");
    let (code, stdout, stderr) = run(&["topp", f.to_str().unwrap(), "-o", o.to_str().unwrap()]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.is_empty());
    let out: Value = serde_json::from_str(&std::fs::read_to_string(&o).unwrap()).unwrap();
    assert!((out["duration"].as_f64().unwrap() - 2.0).abs() < 1e-12);
}

#[test]
fn topp_reports_infeasibility_as_a_status() {
    // x <= -1 at the middle point: no state is feasible there.
    let v = json!({
        "s": [0.0, 1.0, 2.0],
        "a": [[0.0], [0.0], [0.0]], "b": [[1.0], [1.0], [1.0]], "c": [[-1.0], [1.0], [-1.0]],
        "sd_start": 0.0, "sd_end": 0.0, "discretization": "collocation",
    });
    let f = tmp("infeasible.json", &v.to_string());
    let (code, stdout, _) = run(&["topp", f.to_str().unwrap()]);
    assert_eq!(code, 0);
    let out: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(out["status"], "feasible_set_empty");
    assert_eq!(out["index"], 1);
    assert!(out["duration"].is_null());
}

#[test]
fn topp_bad_input_exits_2_with_one_line() {
    let cases = [
        ("shape", json!({"s": [0.0, 1.0], "a": [[1.0]], "b": [[0.0]], "c": [[-1.0]]}).to_string()),
        ("grid", json!({"s": [0.0, 0.0], "a": [[1.0], [1.0]], "b": [[0.0], [0.0]], "c": [[-1.0], [-1.0]]}).to_string()),
        ("speed", json!({"s": [0.0, 1.0], "a": [[1.0], [1.0]], "b": [[0.0], [0.0]], "c": [[-1.0], [-1.0]], "sd_start": -1.0}).to_string()),
        ("disc", json!({"s": [0.0, 1.0], "a": [[1.0], [1.0]], "b": [[0.0], [0.0]], "c": [[-1.0], [-1.0]], "discretization": "spline"}).to_string()),
        ("unknown", json!({"s": [0.0, 1.0], "a": [[1.0], [1.0]], "b": [[0.0], [0.0]], "c": [[-1.0], [-1.0]], "sd_stat": 1.0}).to_string()),
        ("notjson", "{".to_string()),
        // Coefficients that overflow when squared (used to give "optimal" at the LP box).
        ("huge", json!({"s": [0.0, 1.0], "a": [[1e200], [1e200]], "b": [[0.0], [0.0]], "c": [[-1e200], [-1e200]]}).to_string()),
        ("span", json!({"s": [0.0, 1.7e308], "a": [[1.0], [1.0]], "b": [[0.0], [0.0]], "c": [[-1.0], [-1.0]]}).to_string()),
    ];
    for (name, text) in cases {
        let f = tmp(&format!("bad_{name}.json"), &text);
        let (code, stdout, stderr) = run(&["topp", f.to_str().unwrap()]);
        assert_eq!(code, 2, "{name}: {stdout}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{name}: {stderr}");
        assert!(stderr.starts_with("error:"), "{name}: {stderr}");
    }
    let (code, _, _) = run(&["topp", "/nonexistent/file.json"]);
    assert_eq!(code, 2);
}
