//! `stance retime` and `stance demo` through the binary.

use std::path::PathBuf;
use std::process::Command;

use stance_test_support::cli;

fn tmp(name: &str) -> PathBuf {
    cli::temp_dir("retime-cli").join(name)
}

fn stance() -> Command {
    Command::new(env!("CARGO_BIN_EXE_stance"))
}

#[test]
fn retime_writes_the_trajectory_and_the_phase_plane() {
    let motion = tmp("motion.json");
    std::fs::write(
        &motion,
        r#"{"scene": "double-support",
            "path": {"waypoints": [[0.0, 0.08, 0.8], [0.03, 0.0, 0.78], [0.0, -0.08, 0.8]]},
            "max_violation_fraction": 0.01, "dt": 0.05}"#,
    )
    .unwrap();
    let (out, svg, png) = (tmp("out.json"), tmp("phase.svg"), tmp("phase.png"));
    for plot in [&svg, &png] {
        let st = stance()
            .arg("retime")
            .arg(&motion)
            .arg("--plot")
            .arg(plot)
            .arg("-o")
            .arg(&out)
            .status()
            .unwrap();
        assert!(st.success());
        assert!(std::fs::metadata(plot).unwrap().len() > 1000);
    }
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(v["status"], "optimal");
    let duration = v["duration"].as_f64().unwrap();
    assert!(duration > 0.1 && duration < 10.0, "{duration}");
    let samples = v["samples"].as_array().unwrap();
    // Resampled at 0.05 s: about duration / 0.05 samples, the last at the end of the motion.
    assert!(samples.len() as f64 >= duration / 0.05);
    assert!(v["between"]["fraction_of_weight"].as_f64().unwrap() <= 0.01);
    assert_eq!(
        v["s"].as_array().unwrap().len(),
        v["sd"].as_array().unwrap().len()
    );
}

#[test]
fn retime_rejects_bad_motion_files_with_one_line_and_exit_code_2() {
    for (name, text, needle) in [
        (
            "unknown-key.json",
            r#"{"scene": "stairs", "path": {"waypoints": [[0,0,0.8],[0.1,0,0.8]]}, "speed": 3}"#,
            "speed",
        ),
        (
            "unknown-scene.json",
            r#"{"scene": "moon", "path": {"waypoints": [[0,0,0.8],[0.1,0,0.8]]}}"#,
            "box-climbing",
        ),
        (
            "one-waypoint.json",
            r#"{"scene": "stairs", "path": {"waypoints": [[0,0,0.8]]}}"#,
            "at least 2 CoM waypoints",
        ),
        (
            "tiny-dt.json",
            r#"{"scene": "double-support", "path": {"waypoints": [[0,0.05,0.8],[0,-0.05,0.8]]},
                "dt": 1e-300}"#,
            "give dt >=",
        ),
        (
            "huge-grid.json",
            r#"{"scene": "stairs", "path": {"waypoints": [[0,0,0.8],[0.1,0,0.8]]},
                "grid_points": 1000000000000}"#,
            "grid_points",
        ),
        (
            // A typo inside an inline scene: the scene's own error, not "did not match any
            // variant of untagged enum SceneRef".
            "scene-typo.json",
            r#"{"scene": {"mass": 38, "gravty": [0, 0, -9.81], "contacts": []},
                "path": {"waypoints": [[0,0,0.8],[0.1,0,0.8]]}}"#,
            "gravty",
        ),
        (
            "far-waypoints.json",
            r#"{"scene": "stairs", "path": {"waypoints": [[0,0,1e200],[0,0,-1e200]]}}"#,
            "rescale",
        ),
        (
            "short-angular.json",
            r#"{"scene": "stairs", "path": {"waypoints": [[0,0,0.8],[0.1,0,0.8]]},
                "angular_momentum": {"l1": [[0,0,0],[0,0,0]], "l2": [[0,0,0]]}}"#,
            "l2",
        ),
    ] {
        let f = tmp(name);
        std::fs::write(&f, text).unwrap();
        let out = stance().arg("retime").arg(&f).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{name}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        // Once: the inner error of the facade is not printed again as a source.
        assert_eq!(err.matches(needle).count(), 1, "{name}: {err}");
    }
}

/// The optional angular-momentum samples are read from the motion file and change the answer.
#[test]
fn retime_reads_angular_momentum_terms() {
    let base = r#""scene": "double-support",
        "path": {"waypoints": [[0.0, 0.08, 0.8], [0.03, 0.0, 0.78], [0.0, -0.08, 0.8]]}"#;
    let duration = |extra: &str, name: &str| -> f64 {
        let motion = tmp(name);
        std::fs::write(&motion, format!("{{{base}{extra}}}")).unwrap();
        let out = stance().arg("retime").arg(&motion).output().unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        v["duration"].as_f64().unwrap()
    };
    let d0 = duration("", "point-mass.json");
    let d1 = duration(
        r#", "angular_momentum": {"l1": [[4, 0, 0], [0, 2, 1], [-4, 0, 0]],
            "l2": [[0, 3, 0], [1, 0, 0], [0, -3, 0]]}"#,
        "whole-body.json",
    );
    assert!((d1 - d0).abs() > 1e-3 * d0, "{d0} vs {d1}");
}

/// Motion files in TOML, with the scene by name and in full (the scene reference has its own
/// deserializer, which must work for both formats).
#[test]
fn retime_reads_toml_motions() {
    for (name, scene) in [
        ("named.toml", "scene = \"double-support\"\n".to_string()),
        (
            "inline.toml",
            "[scene]\nmass = 38.0\n[[scene.contacts]]\nname = \"LF\"\nposition = [0.0, 0.0, 0.0]\n\
             friction = 0.7\nshape = { rectangle = { half_length = 0.11, half_width = 0.065 } }\n"
                .to_string(),
        ),
    ] {
        let motion = tmp(name);
        std::fs::write(
            &motion,
            format!("{scene}[path]\nwaypoints = [[0.0, 0.01, 0.8], [0.0, -0.01, 0.8]]\n"),
        )
        .unwrap();
        let out = stance().arg("retime").arg(&motion).output().unwrap();
        assert!(
            out.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["status"], "optimal", "{name}");
    }
}

/// TOML used to drop the extra numbers of a 4-number waypoint or angular-momentum sample.
#[test]
fn retime_rejects_toml_points_of_the_wrong_length() {
    for (name, extra) in [
        (
            "waypoint4.toml",
            "[path]\nwaypoints = [[0.0, 0.01, 0.8, 5.0], [0.0, -0.01, 0.8]]\n",
        ),
        (
            "l1_4.toml",
            "[path]\nwaypoints = [[0.0, 0.01, 0.8], [0.0, -0.01, 0.8]]\n\
             [angular_momentum]\nl1 = [[0, 0, 0, 1], [0, 0, 0]]\nl2 = [[0, 0, 0], [0, 0, 0]]\n",
        ),
    ] {
        let motion = tmp(name);
        std::fs::write(&motion, format!("scene = \"double-support\"\n{extra}")).unwrap();
        let out = stance().arg("retime").arg(&motion).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{name}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert!(err.contains("3 numbers"), "{name}: {err}");
    }
}

#[test]
fn demo_runs_the_built_in_examples() {
    let dir = tmp("demo");
    let out = stance()
        .arg("demo")
        .arg("--out")
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    for scene in ["single-support", "double-support", "stairs", "box-climbing"] {
        assert!(text.contains(scene), "{text}");
        assert!(dir.join(format!("phase-{scene}.svg")).exists());
    }
    assert!(!text.contains("false"), "every GIWC certified:\n{text}");
    assert!(text.contains("optimal"));
    // the paper's whole-body experiments on JVRC-1, beside Tables I and II (the demo installs
    // JVRC-1 when it is missing; it never skips them)
    for (table, motion) in [("Table I", "stair-climbing"), ("Table II", "box-climbing")] {
        assert!(text.contains(table), "{text}");
        assert!(dir.join(motion).join("motion.svg").exists());
    }
    assert_eq!(
        text.matches(", 0 without supporting forces").count(),
        2,
        "{text}"
    );
}

#[test]
fn usage_errors_are_one_line_with_exit_code_2() {
    for args in [
        &["retime"][..],
        &["cone", "span-to-face"],
        &["no-such-command"],
    ] {
        let out = stance().args(args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("error:"), "{err}");
    }
    let out = stance().arg("--help").output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8(out.stdout).unwrap().contains("retime"));
}
