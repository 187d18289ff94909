//! `stance demo`: the paper's built-in examples end to end.

use anyhow::{bail, Result};

#[derive(clap::Args)]
pub struct DemoArgs {}

pub fn run(_args: DemoArgs) -> Result<()> {
    bail!("the demo is not available in this build yet")
}
