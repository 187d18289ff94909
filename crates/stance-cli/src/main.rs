//! The `stance` program: see the `stance_cli` library for the commands.

fn main() -> std::process::ExitCode {
    stance_cli::main()
}
