//! Integration tests of `stance cone span-to-face` and `stance cone face-to-span`.

use std::path::PathBuf;
use std::process::{Command, Output};

use stance_test_support::cli;

fn stance(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_stance"))
        .args(args)
        .output()
        .expect("run stance")
}

/// A fresh file in the temporary directory with `content`.
fn temp_file(name: &str, content: &str) -> PathBuf {
    cli::temp_file("cone-cli", name, content)
}

fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

fn assert_bad_input(out: &Output, needle: &str) {
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    assert!(err.contains(needle), "{err} should mention {needle}");
}

#[test]
fn span_to_face_of_the_quadrant_and_back() {
    let f = temp_file(
        "quadrant.json",
        r#"{"generators": [[1, 0, 0], [0, 1, 0], [1, 1, 0]]}"#,
    );
    let out = json(&stance(&["cone", "span-to-face", f.to_str().unwrap()]));
    assert_eq!(out["dim"], 3);
    assert_eq!(out["facets"].as_array().unwrap().len(), 2);
    assert_eq!(out["equations"].as_array().unwrap().len(), 1);
    assert_eq!(out["lineality"].as_array().unwrap().len(), 0);
    assert_eq!(out["extreme_generators"], serde_json::json!([0, 1]));
    assert_eq!(out["certified"], true);
    // Back to span form.
    let face = serde_json::json!({"facets": out["facets"], "equations": out["equations"]});
    let g = temp_file("quadrant_face.json", &face.to_string());
    let back = json(&stance(&["cone", "face-to-span", g.to_str().unwrap()]));
    assert_eq!(back["generators"].as_array().unwrap().len(), 2);
    assert_eq!(back["lineality"].as_array().unwrap().len(), 0);
    assert_eq!(back["certified"], true);
}

#[test]
fn golden_stance_exact_toml_repeat_and_output_file() {
    // Single support (16 generators -> 16 facets), from the project's fixtures.
    let path = format!(
        "{}/../../testdata/cones/single_support_flat.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let input = serde_json::json!({"generators": j["generators"]["float64"]});
    let f = temp_file("single.json", &input.to_string());
    let out = json(&stance(&[
        "cone",
        "span-to-face",
        f.to_str().unwrap(),
        "--repeat",
        "3",
    ]));
    assert_eq!(out["facets"].as_array().unwrap().len(), 16);
    let exact = json(&stance(&[
        "cone",
        "span-to-face",
        f.to_str().unwrap(),
        "--exact",
    ]));
    assert_eq!(exact["facets"].as_array().unwrap().len(), 16);
    assert_eq!(exact["certified"], true);
    // -o writes the file and nothing on stdout.
    let o = std::env::temp_dir().join(format!("stance-cone-cli-{}/out.json", std::process::id()));
    let run = stance(&[
        "cone",
        "span-to-face",
        f.to_str().unwrap(),
        "-o",
        o.to_str().unwrap(),
    ]);
    assert!(run.status.success());
    assert!(run.stdout.is_empty());
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&o).unwrap()).unwrap();
    assert_eq!(written["facets"].as_array().unwrap().len(), 16);
    // TOML input.
    let t = temp_file(
        "half.toml",
        "generators = [[1.0, 0.0], [0.0, 1.0], [0.0, -1.0]]\n",
    );
    let out = json(&stance(&["cone", "span-to-face", t.to_str().unwrap()]));
    assert_eq!(out["facets"].as_array().unwrap().len(), 1);
    assert_eq!(out["lineality"].as_array().unwrap().len(), 1);
}

#[test]
fn zero_cone_and_whole_space() {
    let f = temp_file("zero.json", r#"{"generators": [], "dim": 3}"#);
    let out = json(&stance(&["cone", "span-to-face", f.to_str().unwrap()]));
    assert_eq!(out["equations"].as_array().unwrap().len(), 3);
    let g = temp_file("whole.json", r#"{"facets": [], "dim": 2}"#);
    let out = json(&stance(&["cone", "face-to-span", g.to_str().unwrap()]));
    assert_eq!(out["lineality"].as_array().unwrap().len(), 2);
    assert_eq!(out["generators"].as_array().unwrap().len(), 0);
}

#[test]
fn bad_inputs_exit_2_with_one_line() {
    let ragged = temp_file("ragged.json", r#"{"generators": [[1, 0], [1]]}"#);
    assert_bad_input(
        &stance(&["cone", "span-to-face", ragged.to_str().unwrap()]),
        "ragged",
    );
    let empty = temp_file("empty.json", r#"{"generators": []}"#);
    assert_bad_input(
        &stance(&["cone", "span-to-face", empty.to_str().unwrap()]),
        "empty",
    );
    let unknown = temp_file("unknown.json", r#"{"generators": [[1]], "gens": 1}"#);
    assert_bad_input(
        &stance(&["cone", "span-to-face", unknown.to_str().unwrap()]),
        "unknown field",
    );
    let nan = temp_file("nan.toml", "generators = [[1.0, nan]]\n");
    assert_bad_input(
        &stance(&["cone", "span-to-face", nan.to_str().unwrap()]),
        "finite",
    );
    let huge = temp_file("huge.json", r#"{"generators": [[1e999, 0]]}"#);
    assert_eq!(
        stance(&["cone", "span-to-face", huge.to_str().unwrap()])
            .status
            .code(),
        Some(2)
    );
    let blank = temp_file("blank.json", "  \n");
    assert_bad_input(
        &stance(&["cone", "span-to-face", blank.to_str().unwrap()]),
        "empty",
    );
    let missing = stance(&["cone", "span-to-face", "/nonexistent/x.json"]);
    assert_eq!(missing.status.code(), Some(2));
    let wrong_keys = temp_file("wrong.json", r#"{"generators": [[1, 0]]}"#);
    assert_bad_input(
        &stance(&["cone", "face-to-span", wrong_keys.to_str().unwrap()]),
        "unknown field",
    );
    let dims = temp_file(
        "dims.json",
        r#"{"facets": [[1, 0]], "equations": [[1, 0, 0]]}"#,
    );
    assert_bad_input(
        &stance(&["cone", "face-to-span", dims.to_str().unwrap()]),
        "entries",
    );
}

/// `--wrench`: the stairs stance written about a point 30 km away keeps its 176 facets; without
/// the flag the rank decision makes it 5-D. face -> span with the flag gives back the extreme
/// rays of the stance written 1 km away (facets written farther than a few km carry too much
/// rounding for face -> span: the `wrench` module docs of polycone). Misuse exits 2.
#[test]
fn wrench_flag_far_from_the_origin() {
    let path = format!(
        "{}/../../testdata/cones/double_support_stairs.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let shifted = |s: [f64; 3]| -> Vec<Vec<f64>> {
        j["generators"]["float64"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| {
                let x: Vec<f64> = r
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_f64().unwrap())
                    .collect();
                // (f, t) -> (f, t + s x f)
                let sf = [
                    s[1] * x[2] - s[2] * x[1],
                    s[2] * x[0] - s[0] * x[2],
                    s[0] * x[1] - s[1] * x[0],
                ];
                vec![x[0], x[1], x[2], x[3] + sf[0], x[4] + sf[1], x[5] + sf[2]]
            })
            .collect()
    };
    let f = temp_file(
        "stairs_far.json",
        &serde_json::json!({ "generators": shifted([21213.2, 21213.2, 0.0]) }).to_string(),
    );
    let file = f.to_str().unwrap();
    let out = json(&stance(&["cone", "span-to-face", file, "--wrench"]));
    assert_eq!(out["facets"].as_array().unwrap().len(), 176);
    assert_eq!(out["equations"].as_array().unwrap().len(), 0);
    assert_eq!(out["certified"], true);
    // Without the flag the dimension is undecided in floating point (it was a certified 5-D
    // cone, a direction lost): an error that names the flag.
    assert_bad_input(&stance(&["cone", "span-to-face", file]), "--wrench");
    // face -> span with the flag gives back the 32 extreme rays, 1 km away.
    let near = temp_file(
        "stairs_1km.json",
        &serde_json::json!({ "generators": shifted([707.1, -707.1, 30.0]) }).to_string(),
    );
    let out = json(&stance(&[
        "cone",
        "span-to-face",
        near.to_str().unwrap(),
        "--wrench",
    ]));
    assert_eq!(out["facets"].as_array().unwrap().len(), 176);
    let face = serde_json::json!({"facets": out["facets"], "equations": out["equations"]});
    let g = temp_file("stairs_1km_face.json", &face.to_string());
    let back = json(&stance(&[
        "cone",
        "face-to-span",
        g.to_str().unwrap(),
        "--wrench",
    ]));
    assert_eq!(
        back["generators"].as_array().unwrap().len(),
        out["extreme_generators"].as_array().unwrap().len()
    );
    assert_eq!(back["generators"].as_array().unwrap().len(), 32);
    assert_eq!(back["certified"], true);
    // Misuse.
    assert_bad_input(
        &stance(&["cone", "span-to-face", file, "--wrench", "--exact"]),
        "incompatible options",
    );
    let q = temp_file("plane.json", r#"{"generators": [[1, 0, 0], [0, 1, 0]]}"#);
    assert_bad_input(
        &stance(&["cone", "span-to-face", q.to_str().unwrap(), "--wrench"]),
        "6 columns",
    );
}

/// Inputs of the robustness sweep that were silently wrong, panicked or were unclear.
#[test]
fn hostile_inputs_from_the_sweep() {
    // A generator 1e-11 times the others is a generator: the orthant, not two facets and x = 0.
    let f = temp_file(
        "tiny_generator.json",
        r#"{"generators": [[1e-11, 0, 0], [0, 1, 0], [0, 0, 1]]}"#,
    );
    let out = json(&stance(&["cone", "span-to-face", f.to_str().unwrap()]));
    assert_eq!(out["facets"].as_array().unwrap().len(), 3);
    assert_eq!(out["equations"].as_array().unwrap().len(), 0);
    // A facet row 1e-11 times the others is a facet: x <= 0 is kept.
    let f = temp_file(
        "tiny_facet.json",
        r#"{"facets": [[1e-11, 0, 0], [0, -1, 0]]}"#,
    );
    let out = json(&stance(&["cone", "face-to-span", f.to_str().unwrap()]));
    assert_eq!(out["generators"].as_array().unwrap().len(), 2);
    assert_eq!(out["lineality"].as_array().unwrap().len(), 1);
    // Exact mode with tiny entries: unit rows, not all-zero ones.
    let f = temp_file(
        "tiny_exact.json",
        r#"{"generators": [[1e-310, 2e-100, 0], [0, 1e-310, 1], [3, 0, 1e-310], [1e-310, 1e-310, -1e-310]]}"#,
    );
    let out = json(&stance(&[
        "cone",
        "span-to-face",
        "--exact",
        f.to_str().unwrap(),
    ]));
    for row in out["facets"].as_array().unwrap() {
        let n: f64 = row
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap().powi(2))
            .sum();
        assert!((n - 1.0).abs() < 1e-12, "{row}");
    }
    // Dimensions that overflowed or exhausted memory: an error naming the limit.
    for dim in ["4294967296", "100000"] {
        let f = temp_file(
            "huge_dim.json",
            &format!(r#"{{"generators": [], "dim": {dim}}}"#),
        );
        assert_bad_input(
            &stance(&["cone", "span-to-face", f.to_str().unwrap()]),
            "limit of 1024",
        );
        let f = temp_file(
            "huge_dim_face.json",
            &format!(r#"{{"facets": [], "dim": {dim}}}"#),
        );
        assert_bad_input(
            &stance(&["cone", "face-to-span", f.to_str().unwrap()]),
            "limit of 1024",
        );
    }
    // --repeat out of range names the range (it suggested `-- -1`).
    let f = temp_file("repeat.json", r#"{"generators": [[1, 0]]}"#);
    for n in ["-1", "0", "1000001"] {
        let out = stance(&["cone", "span-to-face", "--repeat", n, f.to_str().unwrap()]);
        assert_bad_input(&out, "1..=1000000");
    }
}

/// The output says which arithmetic gave the answer, and a contact wrench cone 1e5 m from the
/// origin without --wrench is a clear error (its two smallest directions are far above rounding
/// but within the rank tolerance: it was a certified cone with two directions lost).
#[test]
fn the_output_names_the_arithmetic() {
    let mut rows = Vec::new();
    for (sx, sy) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
        let r = [1e5 + 0.1 * sx, 3e4 + 0.05 * sy, 0.0];
        for f in [
            [0.7, 0.0, 1.0],
            [-0.7, 0.0, 1.0],
            [0.0, 0.7, 1.0],
            [0.0, -0.7, 1.0],
        ] {
            let t = [
                r[1] * f[2] - r[2] * f[1],
                r[2] * f[0] - r[0] * f[2],
                r[0] * f[1] - r[1] * f[0],
            ];
            rows.push(vec![f[0], f[1], f[2], t[0], t[1], t[2]]);
        }
    }
    let f = temp_file(
        "far_cwc.json",
        &serde_json::json!({ "generators": rows }).to_string(),
    );
    assert_bad_input(
        &stance(&["cone", "span-to-face", f.to_str().unwrap()]),
        "--wrench",
    );
    let out = json(&stance(&[
        "cone",
        "span-to-face",
        "--wrench",
        f.to_str().unwrap(),
    ]));
    assert_eq!(out["facets"].as_array().unwrap().len(), 32);
    assert_eq!(out["equations"].as_array().unwrap().len(), 0);
    assert_eq!(out["arithmetic"], "tolerance");
    assert!(out.get("fallback_reason").is_none());
    let out = json(&stance(&[
        "cone",
        "span-to-face",
        "--exact",
        f.to_str().unwrap(),
    ]));
    assert_eq!(out["facets"].as_array().unwrap().len(), 32);
    assert_eq!(out["arithmetic"], "exact");
}
