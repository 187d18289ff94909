//! The command line's argument parser on arbitrary arguments: the input split at NUL bytes into
//! arguments (any bytes, not only UTF-8), after the program name. Never a panic (clap's own
//! checks of the command definitions run too: debug assertions are on); a usage error is one
//! non-empty line, as `stance` prints it; help and version render. Commands are not run: what
//! they read is fuzzed by the file targets (cone, scene, motion, topp, urdf).
#![no_main]

use std::ffi::OsString;
use std::os::unix::ffi::OsStringExt;

use libfuzzer_sys::fuzz_target;
use stance_cli::{parse_args, Args};

fuzz_target!(|data: &[u8]| {
    let args: Vec<OsString> = std::iter::once(OsString::from("stance"))
        .chain(
            data.split(|&b| b == 0)
                .take(32)
                .map(|a| OsString::from_vec(a.to_vec())),
        )
        .collect();
    match parse_args(args) {
        Args::Command(_) => {}
        Args::Info(e) => assert!(!e.to_string().is_empty()),
        Args::Usage(line) => {
            assert!(!line.trim().is_empty(), "empty usage message");
            assert!(!line.contains('\n'), "usage message on several lines: {line:?}");
        }
    }
});
