//! `stance robot centroidal` end to end (the binary, through `std::process::Command`), checked
//! against the Pinocchio fixtures of `testdata/robot/` (1e-9 relative, as the library tests).

use serde_json::Value;
use stance_test_support::cli;
use std::path::{Path, PathBuf};

const REL_TOL: f64 = 1e-9;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn stance(args: &[String]) -> (i32, String, String) {
    let r = cli::run(env!("CARGO_BIN_EXE_stance"), args);
    (r.code, r.stdout, r.stderr)
}

fn load(name: &str) -> Value {
    let path = root().join("testdata/robot").join(name);
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn join(v: &Value) -> String {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| format!("{:?}", x.as_f64().unwrap()))
        .collect::<Vec<_>>()
        .join(",")
}

fn flat(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().flat_map(flat).collect(),
        Value::Number(n) => vec![n.as_f64().unwrap()],
        _ => panic!("not numeric: {v}"),
    }
}

fn assert_close(what: &str, got: &Value, reference: &Value) {
    let (g, r) = (flat(got), flat(reference));
    assert_eq!(g.len(), r.len(), "{what}: size");
    let scale = r.iter().fold(1.0f64, |a, x| a.max(x.abs()));
    for (i, (a, b)) in g.iter().zip(&r).enumerate() {
        assert!(
            (a - b).abs() <= REL_TOL * scale,
            "{what}[{i}]: stance {a}, Pinocchio {b}"
        );
    }
}

fn check_case(urdf: &Path, fx: &Value, case: usize, lock: &[String]) {
    let c = &fx["cases"][case];
    let mut args: Vec<String> = vec![
        "robot".into(),
        "centroidal".into(),
        "--urdf".into(),
        urdf.display().to_string(),
        format!("--q={}", join(&c["q"])),
        format!("--v={}", join(&c["v"])),
    ];
    if !lock.is_empty() {
        args.push("--lock".into());
        args.extend(lock.iter().cloned());
    }
    let (code, out, err) = stance(&args);
    assert_eq!(code, 0, "stderr: {err}");
    let got: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(got["nq"], fx["nq"]);
    assert_eq!(got["nv"], fx["nv"]);
    assert_eq!(got["joint_names"], fx["joint_names"]);
    for key in [
        "mass",
        "com",
        "com_jacobian",
        "centroidal_map",
        "centroidal_map_dot_v",
    ] {
        assert_close(key, &got[key], &c[key]);
    }
}

#[test]
fn centroidal_matches_pinocchio_on_the_small_humanoid() {
    let fx = load("small_humanoid.json");
    let urdf = root().join("models/small_humanoid.urdf");
    for case in [0, 1, 2] {
        check_case(&urdf, &fx, case, &[]);
    }
}

#[test]
fn centroidal_with_locked_joints_at_values_matches_pinocchio() {
    let fx = load("small_humanoid_locked.json");
    let urdf = root().join("models/small_humanoid.urdf");
    let lock: Vec<String> = ["r_elbow=-0.7", "neck=0.4", "torso_lift=0.02"]
        .map(String::from)
        .to_vec();
    check_case(&urdf, &fx, 0, &lock);
}

#[test]
fn centroidal_matches_pinocchio_on_jvrc1() {
    let urdf = match stance::stance_robot::jvrc1::locate_urdf(Some(&root())) {
        Ok(p) => p,
        Err(why) => {
            eprintln!("SKIPPED centroidal_matches_pinocchio_on_jvrc1: {why}");
            return;
        }
    };
    let fx = load("jvrc1.json");
    let fingers: Vec<String> = stance::stance_robot::jvrc1::FINGER_JOINTS
        .iter()
        .map(|s| s.to_string())
        .collect();
    check_case(&urdf, &fx, 0, &fingers);
}

#[test]
fn negative_values_work_with_and_without_equals_sign_and_output_file_and_repeat() {
    let urdf = root().join("models/small_humanoid.urdf");
    let mut q = vec!["-0.2".to_string(), "0".into(), "0".into()];
    q.extend(["0", "0", "0", "1"].map(String::from));
    // 12 leg joints, torso_lift, chest_p, 3 left arm joints, the neck (cos, sin), 3 right arm
    // joints (Pinocchio's order: siblings by joint name)
    q.extend(std::iter::repeat_n("-0.1".to_string(), 17));
    q.extend(["1", "0"].map(String::from));
    q.extend(std::iter::repeat_n("-0.1".to_string(), 3));
    let q = q.join(",");
    let dir = std::env::temp_dir().join(format!("stance-robot-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out_file = dir.join("out.json");
    let base = |q_arg: Vec<String>| {
        let mut a: Vec<String> = vec![
            "robot".into(),
            "centroidal".into(),
            "--urdf".into(),
            urdf.display().to_string(),
        ];
        a.extend(q_arg);
        a
    };
    let (c1, o1, e1) = stance(&base(vec![format!("--q={q}")]));
    assert_eq!(c1, 0, "{e1}");
    let (c2, o2, e2) = stance(&base(vec![
        "--q".into(),
        q.clone(),
        "--repeat".into(),
        "3".into(),
    ]));
    assert_eq!(c2, 0, "{e2}");
    assert_eq!(o1, o2);
    let (c3, o3, e3) = stance(&base(vec![
        format!("--q={q}"),
        "-o".into(),
        out_file.display().to_string(),
    ]));
    assert_eq!(c3, 0, "{e3}");
    assert!(o3.is_empty());
    let written = std::fs::read_to_string(&out_file).unwrap();
    assert_eq!(written.trim(), o1.trim());
    let v: Value = serde_json::from_str(&o1).unwrap();
    // the base is at x = -0.2: the CoM x is negative-shifted accordingly (pure translation)
    assert!(v["com"][0].as_f64().unwrap() < 0.0);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_input_exits_2_with_one_line() {
    let urdf = root()
        .join("models/small_humanoid.urdf")
        .display()
        .to_string();
    let neutral = {
        let mut q = vec!["0"; 29];
        q[6] = "1";
        q[24] = "1"; // neck cos (after 7 base entries and 17 joints)
        q.join(",")
    };
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec!["--urdf".into(), urdf.clone(), "--q=0,0,0".into()],
            "expected 29",
        ),
        (
            vec![
                "--urdf".into(),
                urdf.clone(),
                format!("--q={neutral}"),
                "--lock".into(),
                "nope".into(),
            ],
            "nope",
        ),
        (
            vec![
                "--urdf".into(),
                urdf.clone(),
                format!("--q={neutral}"),
                "--v=1,2".into(),
            ],
            "expected 27",
        ),
        (
            vec!["--urdf".into(), urdf.clone(), "--q=0,x".into()],
            "not a finite number",
        ),
        (
            vec![
                "--urdf".into(),
                "no/such.urdf".into(),
                format!("--q={neutral}"),
            ],
            "cannot read",
        ),
    ];
    for (args, needle) in cases {
        let mut a: Vec<String> = vec!["robot".into(), "centroidal".into()];
        a.extend(args);
        let (code, out, err) = stance(&a);
        assert_eq!(code, 2, "{a:?}: {err}");
        assert!(out.is_empty());
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(needle), "{err} should mention {needle}");
    }
    // a malformed URDF
    let dir = std::env::temp_dir().join(format!("stance-robot-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.urdf");
    std::fs::write(&bad, "<robot name=\"x\"><link name=\"a\"></robot>").unwrap();
    let (code, _, err) = stance(&[
        "robot".into(),
        "centroidal".into(),
        "--urdf".into(),
        bad.display().to_string(),
        "--q=0,0,0,0,0,0,1".into(),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("malformed URDF"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Joint velocities beyond the supported range are refused naming `--v` and the range (they
/// wrote `null`s, exit 0); within it every number of the answer is finite.
#[test]
fn joint_velocities_out_of_range_are_refused_naming_the_option() {
    let urdf = root().join("models/small_humanoid.urdf");
    let q = format!(
        "--q={}",
        (0..29)
            .map(|i| if i == 6 || i == 24 { "1" } else { "0" })
            .collect::<Vec<_>>()
            .join(",")
    );
    let v = |x: f64| format!("--v={}", vec![format!("{x:e}"); 27].join(","));
    for (x, ok) in [
        (1.0, true),
        (1e100, true),
        (1e150, true),
        (1e151, false),
        (1e300, false),
    ] {
        let args: Vec<String> = vec![
            "robot".into(),
            "centroidal".into(),
            "--urdf".into(),
            urdf.display().to_string(),
            q.clone(),
            v(x),
        ];
        let (code, stdout, stderr) = stance(&args);
        if ok {
            assert_eq!(code, 0, "{x:e}: {stderr}");
            assert!(!stdout.contains("null"), "{x:e}: {stdout}");
        } else {
            assert_eq!(code, 2, "{x:e}: {stdout}");
            assert!(
                stderr.contains("--v") && stderr.contains("1e150"),
                "{stderr}"
            );
        }
    }
}
