//! The hostile-input sweep (`scripts/sweep.py`): nearly a thousand generated inputs across every
//! command, each classified ok / unclear / wrong / panic / crash / slow against its oracle (the
//! exact conversion, an invariance, a closed form, or the error it must give) and a work bound
//! (20 s, 3 GB). Fails on any wrong answer, panic, crash or slow case, on any unclear message,
//! and on an open finding of the script's `KNOWN` list that passes now (`fixed`: take it off);
//! the open findings themselves are listed (`known`).

use std::process::Command;

#[test]
fn hostile_input_sweep() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let out = Command::new("python3")
        .arg(format!("{root}/scripts/sweep.py"))
        .args(["--stance", env!("CARGO_BIN_EXE_stance"), "--check"])
        .output()
        .expect("python3 runs the sweep (Python 3.8+, standard library only)");
    let text = String::from_utf8_lossy(&out.stdout);
    eprintln!("{text}");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary = text
        .lines()
        .find(|l| l.contains(" cases: "))
        .expect("a summary line");
    assert!(summary.contains("unclear 0,"), "{summary}");
}
