//! Test scaffolding shared by the project's crates (`publish = false`): written once here instead
//! of once per test file.
//!
//! - [`hex`]: the fixtures' exact floats, written as Python's `float.hex()` strings
//!   (`-0x1.8p+3`) by the scripts that regenerate them, read back bit for bit;
//! - [`cli`]: running the `stance` binary from a crate's integration tests, and temporary files;
//! - [`robots`]: robots from PyPI in the project virtualenv (Talos's URDF).
//!
//! It depends on no crate of the project, so that polycone, the lowest crate, can use it too.
//!
//! # Limitations
//!
//! Panics on malformed fixtures: it is for tests, where a panic names the broken fixture.

pub mod cli;
pub mod hex;
pub mod robots;
