//! `pushlab`: the desktop app (no subcommand, or `open`) and the headless commands.

mod cli;

fn main() -> std::process::ExitCode {
    cli::run()
}
