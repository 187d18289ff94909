//! `stance cone span-to-face FILE` and `stance cone face-to-span FILE`.

use std::path::PathBuf;

use anyhow::{bail, Result};

use super::io::Common;

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
    #[command(flatten)]
    pub common: Common,
}

pub fn run(_cmd: ConeCommand) -> Result<()> {
    bail!("the cone commands are not available in this build yet")
}
