//! The `stance` command line. Thin by design: it parses arguments and files, calls the library
//! (the `stance` facade crate), and writes JSON, plots and reports. Each command's inputs and
//! outputs are in its `--help` and the README; ARCHITECTURE.md lists the commands and exit codes.
//!
//! Exit codes: 0 on success, including negative outcomes (an unstable CoM, an infeasible
//! retiming), which are reported in the JSON; 2 on bad input or usage, with a one-line message on
//! standard error.
//!
//! The binary is `src/main.rs`; this library holds the commands so that the argument parser can
//! be fuzzed ([`parse_args`], `fuzz/fuzz_targets/args.rs`).

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod cmd;

/// Multi-contact stability of legged robots: cones, contact stability, retiming, robot models.
#[derive(Parser)]
#[command(name = "stance", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Convert polyhedral cones between span form (generators) and face form (inequalities).
    #[command(subcommand)]
    Cone(cmd::cone::ConeCommand),
    /// Time-optimal retiming on raw rows a sdd + b sd^2 + c <= 0 (reachability analysis).
    Topp(cmd::topp::ToppArgs),
    /// The gravito-inertial wrench cone (GIWC) of a scene, in face and span form.
    Giwc(cmd::contact::GiwcArgs),
    /// Static and robust static equilibrium of the CoM: polygon, 3-D region, tests.
    #[command(subcommand)]
    Equilibrium(cmd::contact::EquilibriumCommand),
    /// Retime a CoM motion under contact stability (GIWC -> TOPP), with a phase-plane plot.
    Retime(cmd::retime::RetimeArgs),
    /// Retime a fixed-base robot's joint path under its joint velocity, acceleration and
    /// torque limits (toppra's problem).
    RetimeJoints(cmd::retime_joints::RetimeJointsArgs),
    /// A whole-body motion across stances: IK, GIWC, chained retiming, checks (the paper's
    /// stair and box climbing are built in).
    Motion(cmd::motion::MotionArgs),
    /// A motion retimed, then executed in MuJoCo under PD control: does it hold?
    Simulate(cmd::simulate::SimulateArgs),
    /// Run the built-in examples of the paper end to end and print a summary.
    Demo(cmd::demo::DemoArgs),
    /// One self-contained 3-D page (HTML, opens offline) of a scene, a motion or a motion's
    /// result: contacts, friction pyramids, static polygon, robust region, the robot played back.
    View(cmd::view::ViewArgs),
    /// Robot models from URDF: centroidal quantities (Pinocchio's conventions).
    #[command(subcommand)]
    Robot(cmd::robot::RobotCommand),
    /// Install from PyPI what the paper's robot and the simulator need (JVRC-1's description,
    /// MuJoCo) into stance's virtualenv ($STANCE_VENV, else a per-user folder).
    Setup(cmd::setup::SetupArgs),
}

/// What the arguments ask for.
pub enum Args {
    /// A command to run ([`run`]).
    Command(Cli),
    /// Help or version text: printed on standard output as clap formats it, exit code 0.
    Info(clap::Error),
    /// A usage error: one line for standard error, exit code 2.
    Usage(String),
}

/// Parses a command line (the program name first). Never panics: what it cannot parse is a
/// [`Args::Usage`] line naming what to fix.
pub fn parse_args<I, T>(args: I) -> Args
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    match Cli::try_parse_from(args) {
        Ok(cli) => Args::Command(cli),
        // Help and version requests are not errors.
        Err(e) if !e.use_stderr() => Args::Info(e),
        // A command group without its command (`stance`, `stance cone`): one line naming the
        // commands to choose from.
        Err(e) if e.kind() == clap::error::ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            Args::Usage(format!("error: {}", missing_command(&e.to_string())))
        }
        // A negative number given as its own word (`--grid -1`) reads as an unknown option, and
        // clap's tip (`-- -1`) would make it a positional argument: say what works.
        Err(e) if negative_number_argument(&e).is_some() => {
            let arg = negative_number_argument(&e).unwrap_or_default();
            Args::Usage(format!(
                "error: '{arg}' reads as an option: for an option's value join them with '=' \
                 (OPTION={arg}); for a file, write ./{arg}"
            ))
        }
        // Usage errors: one line (clap's message without its usage and --help hint lines).
        Err(e) => {
            let text = e.to_string();
            let line: Vec<&str> = text
                .lines()
                .map(str::trim)
                .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
                .filter(|l| !l.is_empty())
                .collect();
            Args::Usage(line.join(" "))
        }
    }
}

/// Runs a parsed command: exit code 0 on success (negative outcomes included), 2 with one line
/// on standard error otherwise.
pub fn run(cli: Cli) -> ExitCode {
    let result = match cli.command {
        Command::Cone(c) => cmd::cone::run(c),
        Command::Demo(a) => cmd::demo::run(a),
        Command::Retime(a) => cmd::retime::run(a),
        Command::RetimeJoints(a) => cmd::retime_joints::run(a),
        Command::Motion(a) => cmd::motion::run_cmd(a),
        Command::Simulate(a) => cmd::simulate::run(a),
        Command::Topp(a) => cmd::topp::run(a),
        Command::Robot(c) => cmd::robot::run(c),
        Command::View(a) => cmd::view::run(a),
        Command::Setup(a) => cmd::setup::run(a),
        Command::Giwc(a) => cmd::contact::run_giwc(a),
        Command::Equilibrium(c) => cmd::contact::run_equilibrium(c),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line: the whole chain of causes, separated by colons.
            eprintln!("error: {}", format!("{e:#}").replace('\n', " "));
            ExitCode::from(2)
        }
    }
}

/// The `stance` program: [`parse_args`] on the process's arguments, then [`run`].
pub fn main() -> ExitCode {
    match parse_args(std::env::args_os()) {
        Args::Command(cli) => run(cli),
        Args::Info(e) => {
            let _ = e.print();
            ExitCode::SUCCESS
        }
        Args::Usage(line) => {
            eprintln!("{line}");
            ExitCode::from(2)
        }
    }
}

/// The argument of an "unexpected argument" error when it is a negative number.
fn negative_number_argument(e: &clap::Error) -> Option<String> {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if e.kind() != ErrorKind::UnknownArgument {
        return None;
    }
    match e.get(ContextKind::InvalidArg) {
        Some(ContextValue::String(a)) if a.starts_with('-') && a.parse::<f64>().is_ok() => {
            Some(a.clone())
        }
        _ => None,
    }
}

/// From clap's help of a command group: "`stance cone` needs a command: span-to-face,
/// face-to-span; see `stance cone --help`".
fn missing_command(help: &str) -> String {
    let usage = help
        .lines()
        .find_map(|l| l.trim().strip_prefix("Usage: "))
        .and_then(|u| u.split(" <COMMAND>").next())
        .map(|u| u.trim_end_matches(" [OPTIONS]").to_string())
        .unwrap_or_else(|| "stance".to_string());
    let commands: Vec<String> = help
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| {
            let l = l.trim();
            let name = l.split_whitespace().next()?;
            (name != "help").then(|| name.to_string())
        })
        .collect();
    format!(
        "`{usage}` needs a command: {}; see `{usage} --help`",
        commands.join(", ")
    )
}
