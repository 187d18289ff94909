//! `stance motion` through the binary (the small humanoid's built-in motion: no Python needed).

use std::path::PathBuf;
use std::process::Command;

use stance_test_support::cli;

fn tmp(name: &str) -> PathBuf {
    cli::temp_dir("motion-cli").join(name)
}

fn stance() -> Command {
    Command::new(env!("CARGO_BIN_EXE_stance"))
}

fn json(args: &[&str]) -> serde_json::Value {
    let out = stance().args(args).output().unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn motion_writes_the_contract_fields_and_plots() {
    let dir = tmp("plots");
    let v = json(&[
        "motion",
        "small-sway",
        "--dt",
        "0.02",
        "--plot",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(v["status"], "optimal");
    let duration = v["duration"].as_f64().unwrap();
    assert!(duration > 0.5 && duration < 10.0, "{duration}");
    assert_eq!(v["robot"]["name"], "small-humanoid");
    assert!((v["robot"]["mass"].as_f64().unwrap() - 43.2).abs() < 1e-9);
    let segs = v["segments"].as_array().unwrap();
    assert_eq!(segs.len(), 3);
    for s in segs {
        for key in [
            "t_start",
            "t_end",
            "u_stance_rows",
            "grid_points",
            "duration",
            "t_ik_ms",
            "t_u_ms",
            "t_abc_ms",
            "t_topp_ms",
        ] {
            assert!(!s[key].is_null(), "{key} in {s}");
        }
        for c in s["contacts"].as_array().unwrap() {
            for key in [
                "name",
                "link",
                "position",
                "rotation",
                "half_length",
                "half_width",
                "friction",
            ] {
                assert!(!c[key].is_null(), "{key} in {c}");
            }
            // planning friction and 70 % of the sole's area, as the file asks
            assert_eq!(c["friction"], 0.7);
            let hl = c["half_length"].as_f64().unwrap();
            assert!((hl - 0.11 * 0.7f64.sqrt()).abs() < 1e-12, "{hl}");
        }
    }
    let checks = &v["checks"];
    for key in [
        "samples",
        "samples_without_forces",
        "max_friction_usage",
        "min_normal_force",
        "max_contact_drift",
        "max_between_violation_fraction",
    ] {
        assert!(!checks[key].is_null(), "{key}");
    }
    assert_eq!(checks["samples_without_forces"], 0);
    let tr = &v["trajectory"];
    let t = tr["t"].as_array().unwrap();
    assert!(t.len() as f64 >= duration / 0.02);
    let nq = v["robot"]["nq"].as_u64().unwrap() as usize;
    let nv = v["robot"]["nv"].as_u64().unwrap() as usize;
    assert_eq!(tr["q"][0].as_array().unwrap().len(), nq);
    assert_eq!(tr["v"][0].as_array().unwrap().len(), nv);
    assert_eq!(tr["a"][0].as_array().unwrap().len(), nv);
    assert_eq!(tr["joint_names"].as_array().unwrap().len(), nv - 6);
    for f in ["motion.svg", "segment-1.svg", "segment-3.svg"] {
        assert!(std::fs::metadata(dir.join(f)).unwrap().len() > 1000, "{f}");
    }
}

#[test]
fn rest_to_rest_is_longer_and_its_boundary_speeds_are_zero() {
    let chained = json(&["motion", "small-sway", "--no-checks"]);
    let r2r = json(&["motion", "small-sway", "--no-checks", "--rest-to-rest"]);
    assert_eq!(r2r["mode"], "rest_to_rest");
    assert!(chained["duration"].as_f64().unwrap() < r2r["duration"].as_f64().unwrap());
    for s in r2r["segments"].as_array().unwrap() {
        assert_eq!(s["sd_boundaries"][0], 0.0);
        assert_eq!(s["sd_boundaries"][1], 0.0);
    }
    assert!(chained["segments"][0]["sd_boundaries"][1].as_f64().unwrap() > 0.0);
}

#[test]
fn played_faster_the_motion_fails_the_force_check() {
    let v = json(&["motion", "small-sway", "--time-scale", "1.3"]);
    assert!(v["checks"]["samples_without_forces"].as_u64().unwrap() > 0);
}

#[test]
fn bad_motion_input_is_one_line_and_exit_code_2() {
    let bad = tmp("bad.toml");
    std::fs::write(&bad, "robot = \"small-humanoid\"\nenvironment = []\n").unwrap();
    for (args, needle) in [
        (vec!["motion", "moonwalk"], "built-in motion"),
        (vec!["motion", bad.to_str().unwrap()], "missing field"),
        (vec!["motion", "small-sway", "--dt", "0"], "retiming.dt"),
        (
            vec!["motion", "small-sway", "--grid", "1"],
            "--grid <N>': 1 is not in 2..=10000",
        ),
        (
            vec!["motion", "small-sway", "--time-scale", "-1"],
            "time scale",
        ),
    ] {
        let out = stance().args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn simulate_without_mujoco_says_how_to_install_it() {
    let out = stance()
        .args(["simulate", "small-sway"])
        .env("STANCE_VENV", tmp("no-such-venv"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("stance setup"), "{err}");
}

/// Without STANCE_VENV the virtualenv is the per-user one (under the platform's data folder),
/// never a path of the machine that built the binary; `stance setup --check` says where.
#[test]
fn the_virtualenv_is_per_user_without_stance_venv() {
    let home = tmp("home");
    let out = stance()
        .args(["setup", "--check"])
        .env_remove("STANCE_VENV")
        .env_remove("XDG_DATA_HOME")
        .env("HOME", &home)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8(out.stdout).unwrap();
    if cfg!(target_os = "linux") {
        let want = home.join(".local/share/stance/.venv");
        assert!(text.starts_with(&want.display().to_string()), "{text}");
    }
    assert!(text.contains("missing: run `stance setup`"), "{text}");
    // and the motions that need it say how to get it
    let out = stance()
        .args(["motion", "stair-climbing"])
        .env_remove("STANCE_VENV")
        .env_remove("XDG_DATA_HOME")
        .env_remove("STANCE_JVRC1_URDF")
        .env("HOME", &home)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("stance setup"), "{err}");
}

#[test]
fn simulate_reports_the_contract_fields() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let has_mujoco = std::process::Command::new(root.join(".venv/bin/python"))
        .args(["-c", "import mujoco"])
        .output()
        .is_ok_and(|o| o.status.success());
    if std::env::var_os("STANCE_VENV").is_none() && !has_mujoco {
        eprintln!("SKIPPED simulate_reports_the_contract_fields: no MuJoCo in .venv");
        return;
    }
    let v = json(&["simulate", "small-sway", "--segments", "1..1"]);
    for key in [
        "held",
        "reason",
        "max_slip_m",
        "contact_losses",
        "fell",
        "max_base_error_m",
        "max_friction_usage",
        "wall_per_sim_s",
    ] {
        assert!(!v[key].is_null(), "{key} in {v}");
    }
    assert_eq!(v["held"], true, "{}", v["reason"]);
    let out = stance()
        .args(["simulate", "small-sway", "--segments", "2..1"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8(out.stderr)
        .unwrap()
        .contains("FIRST..LAST"));
}

/// The parser's advice works: a negative number after a numeric option is read as its value (and
/// refused with the range), and a negative number where none is expected gets advice that works
/// (clap's own tip, `-- -1`, turned it into a positional argument).
#[test]
fn negative_numbers_get_advice_that_works() {
    for (args, needle) in [
        (vec!["motion", "small-sway", "--grid", "-1"], "2..=10000"),
        (vec!["motion", "small-sway", "--grid", "1"], "2..=10000"),
        (vec!["motion", "small-sway", "--dt", "-1"], "retiming.dt"),
        (vec!["cone", "span-to-face", "-5"], "OPTION=-5"),
    ] {
        let out = stance().args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("'-- "), "{args:?}: {err}");
    }
    // the advice, followed, gets past the parser
    let out = stance()
        .args(["cone", "span-to-face", "./-5"])
        .output()
        .unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("./-5") && err.contains("read"), "{err}");
}

/// `--write-plan` writes the complete motion file the footholds planner made, in TOML (or
/// JSON for a .json name, its URDF path kept valid from the plan's folder), and the written
/// file retimes to the same duration without planning again.
#[test]
fn write_plan_writes_a_file_that_retimes_to_the_same_result() {
    let footholds = tmp("steps.toml");
    std::fs::write(
        &footholds,
        r#"
robot = "small-humanoid"
[[environment]]
name = "floor"
position = [0.0, 0.0, 0.0]
shape = { rectangle = { half_length = 2.0, half_width = 2.0 } }
friction = 0.9
[initial.standing]
com_height = 0.9
contacts = { LF = { surface = "floor", at = [0.0, 0.1] }, RF = { surface = "floor", at = [0.0, -0.1] } }
[[segments]]
stance = { LF = "floor", RF = "floor" }
[[segments]]
stance = { LF = "floor" }
moves = [{ links = [{ surface = "RF", onto = "floor", at = [0.12, -0.1] }] }]
[[segments]]
stance = { LF = "floor", RF = "floor" }
"#,
    )
    .unwrap();
    for name in ["plan.toml", "plan.json"] {
        let plan = tmp(name);
        let a = json(&[
            "motion",
            footholds.to_str().unwrap(),
            "--no-checks",
            "--write-plan",
            plan.to_str().unwrap(),
        ]);
        assert_eq!(a["status"], "optimal");
        assert_eq!(a["planning"]["segments"].as_array().unwrap().len(), 3);
        let b = json(&["motion", plan.to_str().unwrap(), "--no-checks"]);
        assert_eq!(a["duration"], b["duration"], "{name}");
        assert!(b["planning"].is_null());
    }
    // a plan that cannot be written names the path
    let out = stance()
        .args([
            "motion",
            footholds.to_str().unwrap(),
            "--write-plan",
            "/nonexistent-folder/plan.toml",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(e.contains("/nonexistent-folder/plan.toml"), "{e}");
}
