//! `stance topp FILE`: time-optimal retiming on raw rows `a sdd + b sd^2 + c <= 0`.
//!
//! Input (JSON or TOML): `{"s": [N+1], "a": [[m] x (N+1)], "b": ..., "c": ..., "sd_start",
//! "sd_end", "discretization": "collocation" | "interpolation"}` (`sd_start`, `sd_end` default to
//! 0, the discretization to collocation). Output: `{"status", "duration", "sd", "sdd", "t",
//! "controllable_sets"}` plus `"discretization"` (the one that ran), `"index"` (the grid point of
//! a failure, else null), `"max_residual"` (largest enforced row residual, rows scaled to unit
//! norm) and `"hit_box"` (whether the rows left `sdd` or `sd^2` unbounded somewhere, so that the
//! solver's bounding box decided). Infeasible instances are a status, exit code 0.

use std::path::PathBuf;

use anyhow::Result;
use serde::Deserialize;
use stance::stance_topp::{CanonicalConstraints, Discretization, SolveOptions, Workspace};

use super::io::{read_input, write_output, Common};

#[derive(clap::Args)]
pub struct ToppArgs {
    /// Input JSON (or .toml) file with s, a, b, c, sd_start, sd_end, discretization.
    pub file: PathBuf,
    #[command(flatten)]
    pub common: Common,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ToppInput {
    s: Vec<f64>,
    a: Vec<Vec<f64>>,
    b: Vec<Vec<f64>>,
    c: Vec<Vec<f64>>,
    #[serde(default)]
    sd_start: f64,
    #[serde(default)]
    sd_end: f64,
    #[serde(default)]
    discretization: Discretization,
    /// Metadata of the project's reference instances (`testdata/topp/*.json`: where the rows
    /// came from and the peers' answers), accepted so that those files run as they are, and
    /// ignored by the solver. Any other key is an error.
    #[serde(default, flatten)]
    _reference: ReferenceMetadata,
}

/// The extra keys of `testdata/topp/*.json` (see [`ToppInput`]).
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
#[allow(dead_code, non_snake_case)]
struct ReferenceMetadata {
    instance: Option<String>,
    description: Option<String>,
    constraint: Option<String>,
    mass: Option<f64>,
    gravity: Option<[f64; 3]>,
    U: Option<serde_json::Value>,
    com_path: Option<serde_json::Value>,
    reference: Option<serde_json::Value>,
}

pub fn run(args: ToppArgs) -> Result<()> {
    let input: ToppInput = read_input(&args.file)?;
    let k = CanonicalConstraints::from_dense(&input.s, &input.a, &input.b, &input.c)?;
    let disc = input.discretization;
    let opts = SolveOptions::new(disc)
        .with_start(input.sd_start)
        .with_end(input.sd_end);
    let mut ws = Workspace::new();
    let sol = args.common.repeated(|| ws.solve(&k, &opts))?;
    write_output(&args.common, &sol.report(&k))
}
