//! Reading inputs and writing outputs, shared by every command.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use serde::de::DeserializeOwned;
use serde::Serialize;

/// Options every computational command shares.
#[derive(clap::Args, Debug, Clone)]
pub struct Common {
    /// Write the JSON result to this file instead of standard output.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Repeat the computation N times in the same process after reading the input (for timing
    /// from outside), 1 to 1000000; the result is still printed once.
    #[arg(long, default_value_t = 1, value_name = "N", allow_negative_numbers = true,
          value_parser = clap::value_parser!(i64).range(1..=MAX_REPEAT))]
    pub repeat: i64,
}

impl Common {
    /// Runs `f` `--repeat` times (at least once) and returns its last result; the first error
    /// stops. The one place `--repeat` is honoured.
    pub fn repeated<T, E>(&self, mut f: impl FnMut() -> Result<T, E>) -> Result<T, E> {
        let mut out = f()?;
        for _ in 1..self.repeat {
            out = f()?;
        }
        Ok(out)
    }
}

/// Largest `--repeat`: a million repetitions of the fastest command take seconds; more is a
/// typing mistake that would keep the process busy for hours.
pub const MAX_REPEAT: i64 = 1_000_000;

/// Reads a JSON file, or a TOML file when its extension is `.toml`, into `T`. Unknown keys are
/// rejected by the `T` types themselves (`#[serde(deny_unknown_fields)]`).
pub fn read_input<T: DeserializeOwned>(path: &Path) -> Result<T> {
    Ok(stance::input::read_file(path)?)
}

/// Writes `value` as pretty JSON to the output file of `common`, or to standard output.
pub fn write_output<T: Serialize>(common: &Common, value: &T) -> Result<()> {
    let text = serde_json::to_string_pretty(value).context("cannot serialize the result")?;
    match &common.output {
        Some(path) => std::fs::write(path, text + "\n")
            .with_context(|| format!("cannot write output file {}", path.display())),
        None => print_text(&(text + "\n")),
    }
}

/// Writes `text` to standard output. A closed pipe (`stance ... | head`) is the reader's choice,
/// not an error: the rest is dropped silently. A standard output that was closed when the
/// process started (`stance ... >&-`) is an error: the result would be lost.
pub fn print_text(text: &str) -> Result<()> {
    use std::io::Write;
    if stdout_closed_at_start() {
        anyhow::bail!(
            "standard output is closed, so the result would be lost: write it to a file with \
             -o FILE, or redirect standard output"
        );
    }
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        r => r.context("cannot write the result to standard output"),
    }
}

/// Whether file descriptor 1 was closed when the process started. Rust's runtime reopens a
/// closed standard output on `/dev/null` before `main` (so that later writes cannot land in a
/// file opened on descriptor 1), after which a closed output cannot be told from an intended
/// `> /dev/null`; a constructor in `.init_array`, run by the C runtime before that, records it.
#[cfg(target_os = "linux")]
fn stdout_closed_at_start() -> bool {
    stdout_state::CLOSED.load(std::sync::atomic::Ordering::Relaxed)
}

#[cfg(not(target_os = "linux"))]
fn stdout_closed_at_start() -> bool {
    false
}

#[cfg(target_os = "linux")]
mod stdout_state {
    use std::sync::atomic::{AtomicBool, Ordering};

    pub static CLOSED: AtomicBool = AtomicBool::new(false);

    extern "C" fn record() {
        // SAFETY: `fcntl(F_GETFD)` on a descriptor number only queries its flags; it fails
        // with EBADF when the descriptor is not open.
        let flags = unsafe { libc::fcntl(1, libc::F_GETFD) };
        CLOSED.store(flags == -1, Ordering::Relaxed);
    }

    #[used]
    #[link_section = ".init_array"]
    static RECORD: extern "C" fn() = record;
}

/// One warning line naming the URDF elements the model ignored (`--quiet-urdf` silences it).
pub fn warn_unknown_urdf_elements(urdf: &Path, unknown: &[(String, usize)]) {
    if unknown.is_empty() {
        return;
    }
    let list: Vec<String> = unknown
        .iter()
        .map(|(name, line)| format!("<{name}> (line {line})"))
        .collect();
    eprintln!(
        "warning: {} has elements the model does not use: {}; --quiet-urdf silences this",
        urdf.display(),
        list.join(", ")
    );
}
