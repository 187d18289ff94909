//! Running the `stance` binary from integration tests (`env!("CARGO_BIN_EXE_stance")` is known
//! only in stance-cli's own tests, so the path is passed in), and temporary files.

use std::ffi::OsStr;
use std::path::PathBuf;
use std::process::Command;

/// What a run of the binary gave.
#[derive(Debug, Clone)]
pub struct Run {
    /// Exit code (-1 when killed by a signal).
    pub code: i32,
    /// Standard output, lossily decoded.
    pub stdout: String,
    /// Standard error, lossily decoded.
    pub stderr: String,
}

/// Runs `bin` with `args` and waits for it.
pub fn run<I, S>(bin: &str, args: I) -> Run
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    let out = Command::new(bin)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {bin}: {e}"));
    Run {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// A directory of this test process under the system's temporary directory, created if needed:
/// `stance-TAG-PID`.
pub fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stance-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("create the temporary directory");
    d
}

/// A file `name` holding `content` in [`temp_dir`]`(tag)`.
pub fn temp_file(tag: &str, name: &str, content: &str) -> PathBuf {
    let p = temp_dir(tag).join(name);
    std::fs::write(&p, content).expect("write the temporary file");
    p
}
