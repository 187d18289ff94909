//! `stance setup`: creates stance's Python virtualenv and installs from PyPI what some commands
//! need at run time (JVRC-1's description for the paper's motions, MuJoCo for `stance
//! simulate`). The virtualenv is `$STANCE_VENV`, else a per-user data folder
//! (`stance::motion::venv`); its path is printed on standard output.

use anyhow::Result;

/// Arguments of `stance setup`.
#[derive(clap::Args)]
pub struct SetupArgs {
    /// The Python 3 that creates the virtualenv (it needs the `venv` module).
    #[arg(long, default_value = "python3")]
    python: String,
    /// Print where the virtualenv is (or would be) and whether it is ready; install nothing.
    #[arg(long)]
    check: bool,
}

/// Runs `stance setup`.
pub fn run(a: SetupArgs) -> Result<()> {
    use stance::motion::venv;
    let dir = venv::dir()?;
    if a.check {
        match venv::check(&dir) {
            Ok(()) => println!("{} (ready)", dir.display()),
            Err(why) => println!("{} ({why}: run `stance setup`)", dir.display()),
        }
        return Ok(());
    }
    let dir = venv::setup(&a.python)?;
    println!("{}", dir.display());
    Ok(())
}
