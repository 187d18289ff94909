//! `stance view`: the page is written where asked, from a scene file, a built-in name or a
//! motion's result; bad input is one clear line and exit code 2. (The page in a browser:
//! scripts/test-view.sh.)

use stance_test_support::cli;

fn stance(args: &[&str]) -> (i32, String) {
    let r = cli::run(env!("CARGO_BIN_EXE_stance"), args);
    (r.code, r.stderr)
}

fn dir() -> std::path::PathBuf {
    cli::temp_dir("view-cli")
}

#[test]
fn view_writes_one_self_contained_page_for_a_scene_file_and_a_motion_result() {
    let d = dir();
    let scene = d.join("foot.toml");
    std::fs::write(
        &scene,
        "mass = 40\n[[contacts]]\nname = \"LF\"\nposition = [0, 0, 0]\nfriction = 0.7\n\
         shape = { rectangle = { half_length = 0.11, half_width = 0.065 } }\n",
    )
    .unwrap();
    let page = d.join("foot.html");
    let (code, err) = stance(&[
        "view",
        scene.to_str().unwrap(),
        "-o",
        page.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("needs no network"), "{err}");
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(html.contains("\"kind\":\"scene\"") && html.contains("\"LF\""));
    // A motion's result, as `stance motion` wrote it.
    let result = d.join("sway.json");
    let (code, err) = stance(&[
        "motion",
        "small-sway",
        "--no-checks",
        "-o",
        result.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let page = d.join("sway.html");
    let (code, err) = stance(&[
        "view",
        result.to_str().unwrap(),
        "-o",
        page.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(html.contains("\"kind\":\"motion\"") && html.contains("\"bones\""));
}

#[test]
fn view_rejects_bad_input_in_one_line() {
    let d = dir();
    let out = d.join("x.html");
    let out = out.to_str().unwrap();
    for (args, needle) in [
        (vec!["view", "moonwalk", "-o", out], "small-sway"),
        (
            vec!["view", "double-support", "-o", "/nonexistent-dir/x.html"],
            "/nonexistent-dir/x.html",
        ),
        (
            vec!["view", "double-support", "--com-height", "nan", "-o", out],
            "--com-height",
        ),
        (
            vec!["view", "double-support", "--scene", "--motion"],
            "cannot be used with",
        ),
    ] {
        let (code, err) = stance(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
    }
}
