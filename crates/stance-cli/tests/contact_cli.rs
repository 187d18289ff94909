//! The contact commands of the contract: `stance giwc`, `stance equilibrium polygon|region|test`.

use stance_test_support::cli;

fn stance(args: &[&str]) -> (i32, String, String) {
    let r = cli::run(env!("CARGO_BIN_EXE_stance"), args);
    (r.code, r.stdout, r.stderr)
}

fn tmp(name: &str, text: &str) -> std::path::PathBuf {
    cli::temp_file("contact-cli", name, text)
}

const SCENE: &str = r#"{"mass": 39, "gravity": [0, 0, -9.81], "contacts": [
  {"name": "LF", "position": [0, 0, 0], "rotation": [[1,0,0],[0,1,0],[0,0,1]],
   "shape": {"rectangle": {"half_length": 0.11, "half_width": 0.065}}, "friction": 0.7}]}"#;

#[test]
fn giwc_of_a_scene_file_has_16_facets() {
    let f = tmp("foot.json", SCENE);
    let (code, out, _) = stance(&["giwc", f.to_str().unwrap()]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["giwc"]["facets"].as_array().unwrap().len(), 16);
    assert_eq!(v["span"].as_array().unwrap().len(), 16);
    assert_eq!(v["certified"], true);
    // Exact mode gives the same 16 facets here (axis-aligned foot: the generators are exact).
    let (code, out2, err) = stance(&["giwc", f.to_str().unwrap(), "--exact", "--repeat", "2"]);
    assert_eq!(code, 0, "{err}");
    let w: serde_json::Value = serde_json::from_str(&out2).unwrap();
    let rows = |x: &serde_json::Value| -> Vec<Vec<f64>> {
        serde_json::from_value(x["giwc"]["facets"].clone()).unwrap()
    };
    let (a, b) = (rows(&v), rows(&w));
    assert_eq!(a.len(), b.len());
    for r in &a {
        assert!(b
            .iter()
            .any(|s| r.iter().zip(s).all(|(x, y)| (x - y).abs() < 1e-9)));
    }
}

#[test]
fn polygon_of_a_flat_foot_is_its_rectangle() {
    let f = tmp("foot2.json", SCENE);
    let (code, out, _) = stance(&["equilibrium", "polygon", f.to_str().unwrap()]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let verts: Vec<[f64; 2]> = serde_json::from_value(v["vertices"].clone()).unwrap();
    assert_eq!(verts.len(), 4);
    for c in [
        [0.11, 0.065],
        [-0.11, 0.065],
        [-0.11, -0.065],
        [0.11, -0.065],
    ] {
        assert!(verts
            .iter()
            .any(|p| (p[0] - c[0]).abs() < 1e-9 && (p[1] - c[1]).abs() < 1e-9));
    }
    // Counter-clockwise.
    let area: f64 = (0..4)
        .map(|i| verts[i][0] * verts[(i + 1) % 4][1] - verts[i][1] * verts[(i + 1) % 4][0])
        .sum();
    assert!(area > 0.0);
    assert_eq!(v["dim"], 2);
    assert_eq!(v["route"], "direct");
    // The same polygon through U_stance.
    let (code, out, _) = stance(&[
        "equilibrium",
        "polygon",
        f.to_str().unwrap(),
        "--via-u-stance",
    ]);
    assert_eq!(code, 0);
    let w: serde_json::Value = serde_json::from_str(&out).unwrap();
    let verts2: Vec<[f64; 2]> = serde_json::from_value(w["vertices"].clone()).unwrap();
    assert_eq!(verts2.len(), 4);
    assert!(verts2.iter().all(|p| verts
        .iter()
        .any(|q| (p[0] - q[0]).abs() < 1e-9 && (p[1] - q[1]).abs() < 1e-9)));
}

#[test]
fn region_and_test_accept_negative_gravity_values() {
    let (code, out, err) = stance(&[
        "equilibrium",
        "region",
        "box-climbing",
        "--gravity=-0.15,0,-9.81",
        "--gravity",
        "0.15,0,-9.81",
        "--gravity",
        "0,0.15,-9.81",
        "--gravity",
        "0,-0.15,-9.81",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["status"], "bounded");
    let hs: Vec<[f64; 4]> = serde_json::from_value(v["halfspaces"].clone()).unwrap();
    let verts: Vec<[f64; 3]> = serde_json::from_value(v["vertices"].clone()).unwrap();
    for p in &verts {
        for h in &hs {
            assert!(h[0] * p[0] + h[1] * p[1] + h[2] * p[2] <= h[3] + 1e-7);
        }
    }
    let pts = tmp(
        "pts.json",
        r#"{"points": [[0.3, 0.0, 0.8], [1.0, 1.0, 1.0]]}"#,
    );
    let (code, out, _) = stance(&[
        "equilibrium",
        "test",
        "box-climbing",
        "--points",
        pts.to_str().unwrap(),
        "--gravity=-0.15,0,-9.81",
        "--gravity=0.15,0,-9.81",
    ]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["stable"], serde_json::json!([true, false]));
}

#[test]
fn plots_are_written() {
    let dir = std::env::temp_dir().join(format!("stance-contact-plots-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for name in ["p.svg", "p.png"] {
        let path = dir.join(name);
        let (code, _, err) = stance(&[
            "equilibrium",
            "polygon",
            "stairs",
            "--plot",
            path.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(std::fs::metadata(&path).unwrap().len() > 1000);
    }
    let path = dir.join("r.svg");
    let (code, _, err) = stance(&[
        "equilibrium",
        "region",
        "single-support",
        "--gravity=0.15,0,-9.81",
        "--gravity=-0.15,0,-9.81",
        "--gravity=0,0.15,-9.81",
        "--gravity=0,-0.15,-9.81",
        "--plot",
        path.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::read_to_string(&path).unwrap().contains("<svg"));
    // An unbounded region (one gravity: a vertical prism) is plotted too.
    let path = dir.join("prism.png");
    let (code, _, err) = stance(&[
        "equilibrium",
        "region",
        "single-support",
        "--plot",
        path.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::metadata(&path).unwrap().len() > 1000);
}

#[test]
fn bad_input_exits_2_with_one_line() {
    let bad = tmp(
        "bad.json",
        r#"{"mass": 39, "contacts": [], "colour": "red"}"#,
    );
    let neg = tmp(
        "neg.json",
        &SCENE.replace("\"friction\": 0.7", "\"friction\": -0.7"),
    );
    for args in [
        vec!["giwc", bad.to_str().unwrap()],
        vec!["giwc", neg.to_str().unwrap()],
        vec!["giwc", "no-such-scene"],
        vec!["equilibrium", "polygon", "stairs", "--plot", "x.gif"],
    ] {
        let (code, _, err) = stance(&args);
        assert_eq!(code, 2, "{args:?}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
    }
    // Argument errors come from clap (exit 2, the message first, then clap's hint line).
    let (code, _, err) = stance(&["equilibrium", "polygon", "stairs", "--gravity", "1,2"]);
    assert_eq!(code, 2);
    assert!(
        err.starts_with("error:") && err.contains("gx,gy,gz"),
        "{err}"
    );
}

/// Review of issue 3: ragged rows in TOML inputs were silently truncated (a point
/// `[x, y, z, w]` tested as `[x, y, z]`, a 4-number position read as its first 3).
#[test]
fn ragged_rows_in_toml_inputs_exit_2() {
    let pts = tmp(
        "ragged.toml",
        "points = [[0.0, 0.0, 0.8, 9.0], [0.2, 0.0, 0.8]]\n",
    );
    let short = tmp("short.json", r#"{"points": [[0.0, 0.0]]}"#);
    let scene = tmp(
        "ragged_scene.toml",
        "mass = 39.0\n[[contacts]]\nname = \"LF\"\nposition = [0.0, 0.0, 0.0, 5.0]\n\
         shape = \"point\"\nfriction = 0.5\n",
    );
    for (args, want) in [
        (
            vec![
                "equilibrium",
                "test",
                "single-support",
                "--points",
                pts.to_str().unwrap(),
            ],
            "invalid length 4, expected a point [x, y, z]",
        ),
        (
            vec![
                "equilibrium",
                "test",
                "single-support",
                "--points",
                short.to_str().unwrap(),
            ],
            "invalid length 2, expected a point [x, y, z]",
        ),
        (
            vec!["equilibrium", "polygon", scene.to_str().unwrap()],
            "invalid length 4",
        ),
    ] {
        let (code, _, err) = stance(&args);
        assert_eq!(code, 2, "{args:?}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
    }
}
