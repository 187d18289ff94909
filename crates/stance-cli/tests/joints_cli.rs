//! `stance retime-joints` through the binary: the output's keys, the plot, and one-line errors
//! with exit code 2 for bad input.

use std::process::Command;

use stance_test_support::cli;

fn arm() -> String {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../models/three_link_arm.urdf")
        .display()
        .to_string()
}

fn file(name: &str, limits: &str, waypoints: &str) -> std::path::PathBuf {
    cli::temp_file(
        "joints-cli",
        name,
        &format!(
            "urdf = {:?}\nwaypoints = {waypoints}\ndt = 0.005\n[limits]\n{limits}\n",
            arm()
        ),
    )
}

const PATH: &str = "[[0.0, 0.3, 0.5, 0.0], [1.0, -0.5, 1.2, 2.0], [2.0, 0.4, 0.3, 4.0]]";

#[test]
fn retime_joints_writes_the_trajectory_checks_and_binding() {
    let f = file(
        "ok.toml",
        "acceleration = { default = 6.0, wrist = 20.0 }",
        PATH,
    );
    let (out, svg) = (
        cli::temp_dir("joints-cli").join("out.json"),
        cli::temp_dir("joints-cli").join("phase.svg"),
    );
    let st = Command::new(env!("CARGO_BIN_EXE_stance"))
        .arg("retime-joints")
        .arg(&f)
        .arg("--plot")
        .arg(&svg)
        .arg("-o")
        .arg(&out)
        .status()
        .unwrap();
    assert!(st.success());
    assert!(std::fs::metadata(&svg).unwrap().len() > 1000);
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(v["status"], "optimal");
    assert!(v["duration"].as_f64().unwrap() > 0.0);
    let t = &v["trajectory"];
    assert_eq!(t["joint_names"].as_array().unwrap().len(), 4);
    assert_eq!(
        t["q"].as_array().unwrap().len(),
        t["t"].as_array().unwrap().len()
    );
    for key in [
        "max_velocity_ratio",
        "max_acceleration_ratio",
        "max_torque_ratio",
    ] {
        let r = v["checks"][key].as_f64().unwrap();
        assert!(r <= 1.0 + 1e-3, "{key} {r}");
    }
    assert!(v["binding"]["acceleration"].as_u64().unwrap() > 0);
    let wrist = v["limits"]
        .as_array()
        .unwrap()
        .iter()
        .find(|j| j["name"] == "wrist")
        .unwrap();
    assert_eq!(wrist["acceleration"], 20.0);
}

#[test]
fn bad_joint_files_get_one_line_and_exit_2() {
    let bin = env!("CARGO_BIN_EXE_stance");
    for (name, limits, waypoints, expect) in [
        (
            "unknown.toml",
            "acceleration = { elbw = 3.0 }",
            PATH,
            "did you mean \"elbow\"",
        ),
        (
            "negative.toml",
            "acceleration = -2.0",
            PATH,
            "limits.acceleration is -2",
        ),
        ("nan.toml", "torque = nan", PATH, "limits.torque is NaN"),
        (
            "short.toml",
            "",
            "[[0.0, 0.3, 0.5, 0.0], [1.0, -0.5, 1.2]]",
            "waypoint 1 has 3 value(s)",
        ),
        (
            "one.toml",
            "",
            "[[0.0, 0.3, 0.5, 0.0]]",
            "at least 2 waypoints",
        ),
        (
            "true.toml",
            "velocity = true",
            PATH,
            "true is not a fraction",
        ),
    ] {
        let r = cli::run(
            bin,
            [
                "retime-joints",
                file(name, limits, waypoints).to_str().unwrap(),
            ],
        );
        assert_eq!(r.code, 2, "{name}: {}", r.stderr);
        assert_eq!(r.stderr.trim().lines().count(), 1, "{name}: {}", r.stderr);
        assert!(r.stderr.contains(expect), "{name}: {}", r.stderr);
    }
}
