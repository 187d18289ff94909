//! `stance cone span-to-face FILE` and `stance cone face-to-span FILE`.
//!
//! Input (JSON, or TOML for a `.toml` file):
//! - span-to-face: `{"generators": [[...], ...], "dim": d}` (`dim` optional, needed only when
//!   there is no generator: the zero cone of `R^d`);
//! - face-to-span: `{"facets": [[...], ...], "equations": [[...], ...], "dim": d}` (`equations`
//!   and `dim` optional).
//!
//! Output: the other form, `certified`, and `arithmetic`: `"tolerance"` (the floating-point
//! conversion and its certificate), `"exact"` (`--exact`), or `"exact_fallback"` (the
//! floating-point answer failed its certificate, `fallback_reason` says how, and the exact
//! conversion of the input as given replaced it). No decision depends on the scale of a row.
//!
//! `--wrench` (6-D wrench cones): the conversion runs on generators re-centred on their
//! contacts and scaled by their lever arm, so that a stance written about a far reference
//! point, or in millimetres, gets the same cone (see `polycone::wrench`).

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use serde::Deserialize;
use stance::polycone::{self, nalgebra::DMatrix, Arithmetic, DdOptions, FaceForm, Workspace};
use stance::report::{FaceToSpanReport, SpanToFaceReport};

use super::io::{read_input, write_output, Common};

#[derive(clap::Subcommand)]
pub enum ConeCommand {
    /// Generators (one per row) -> facets, equations, lineality, extreme generators.
    SpanToFace(ConvertArgs),
    /// Facets and equations -> generators and lineality.
    FaceToSpan(ConvertArgs),
}

#[derive(clap::Args)]
pub struct ConvertArgs {
    /// Input JSON file.
    pub file: PathBuf,
    /// Certified exact combinatorics for the input as given (slower).
    #[arg(long)]
    pub exact: bool,
    /// 6-D wrench cones (rows f_x, f_y, f_z, tau_x, tau_y, tau_z) only: re-centre the torques
    /// on the generators (or facets) and scale them by their lever arm before converting, so
    /// that the answer does not depend on the reference point or the unit of length; the
    /// answer is mapped back to the input's coordinates. Not with --exact.
    #[arg(long)]
    pub wrench: bool,
    #[command(flatten)]
    pub common: Common,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SpanInput {
    generators: Vec<Vec<f64>>,
    #[serde(default)]
    dim: Option<usize>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FaceInput {
    facets: Vec<Vec<f64>>,
    #[serde(default)]
    equations: Vec<Vec<f64>>,
    #[serde(default)]
    dim: Option<usize>,
}

/// Rows -> matrix, checking the row lengths and finiteness; `dim` from the rows or the option.
fn to_matrix(what: &str, rows: &[Vec<f64>], dim: Option<usize>) -> Result<DMatrix<f64>> {
    let d = match (rows.first(), dim) {
        (Some(r), Some(d)) if r.len() != d => {
            bail!("{what}: row 0 has {} entries but \"dim\" is {d}", r.len())
        }
        (Some(r), _) => r.len(),
        (None, Some(d)) => d,
        (None, None) => bail!("{what} is empty: give at least one row, or \"dim\""),
    };
    if d == 0 {
        bail!("{what}: the dimension is 0; rows need at least one entry");
    }
    let most = polycone::tol::MAX_COMMAND_ROWS;
    if rows.len() > most {
        bail!(
            "{what}: {} rows, more than the {most} the command converts (the double \
             description's work grows with rows times facets: 20,000 generators on a circle took \
             4 minutes); thin the input, or call the library's conversion",
            rows.len()
        );
    }
    for (i, r) in rows.iter().enumerate() {
        if r.len() != d {
            bail!(
                "{what}: row {i} has {} entries but row 0 has {d} (ragged rows)",
                r.len()
            );
        }
        if let Some((j, v)) = r.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            bail!("{what}: row {i}, column {j} is {v}; every entry must be a finite number");
        }
    }
    Ok(DMatrix::from_fn(rows.len(), d, |i, j| rows[i][j]))
}

fn options(exact: bool, wrench: bool) -> DdOptions {
    DdOptions {
        wrench,
        arithmetic: if exact {
            Arithmetic::Exact
        } else {
            Arithmetic::Tolerance
        },
        ..DdOptions::default()
    }
}

pub fn run(cmd: ConeCommand) -> Result<()> {
    match cmd {
        ConeCommand::SpanToFace(a) => {
            let input: SpanInput = read_input(&a.file)?;
            let v = to_matrix("generators", &input.generators, input.dim)?;
            let opts = options(a.exact, a.wrench);
            let mut ws = Workspace::new();
            let r = a
                .common
                .repeated(|| ws.span_to_face(&v, &opts))
                .context("span-to-face")?;
            write_output(&a.common, &SpanToFaceReport::new(&r))
        }
        ConeCommand::FaceToSpan(a) => {
            let input: FaceInput = read_input(&a.file)?;
            let dim = input
                .dim
                .or_else(|| input.facets.first().map(Vec::len))
                .or_else(|| input.equations.first().map(Vec::len));
            if input.facets.is_empty() && input.equations.is_empty() && dim.is_none() {
                bail!("facets and equations are both empty: give at least one row, or \"dim\"");
            }
            let u = to_matrix("facets", &input.facets, dim)?;
            let e = to_matrix("equations", &input.equations, dim)?;
            let face = FaceForm::new(u, e).map_err(polycone_error)?;
            let opts = options(a.exact, a.wrench);
            let mut ws = Workspace::new();
            let r = a
                .common
                .repeated(|| ws.face_to_span(&face, &opts))
                .context("face-to-span")?;
            write_output(&a.common, &FaceToSpanReport::new(&r))
        }
    }
}

fn polycone_error(e: polycone::ConeError) -> anyhow::Error {
    anyhow::Error::new(e)
}
