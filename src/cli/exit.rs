//! How a command ends: the exit codes pushlab documents, and a failure turned into one.

use std::process::ExitCode;

/// Exit code of wrong arguments (clap's usage errors and the commands' own).
pub const EXIT_USAGE: u8 = 2;

/// How a command failed: wrong arguments (exit 2) or a run that could not complete (exit 1).
#[derive(Debug)]
pub enum Failure {
    Usage(anyhow::Error),
    Failed(anyhow::Error),
}

impl From<anyhow::Error> for Failure {
    fn from(e: anyhow::Error) -> Self {
        Failure::Failed(e)
    }
}

/// Prints the failure and turns it into the documented exit code.
pub fn exit_code(result: Result<(), Failure>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Usage(e)) => {
            eprintln!("pushlab: {e:#}");
            ExitCode::from(EXIT_USAGE)
        }
        Err(Failure::Failed(e)) => {
            eprintln!("pushlab: {e:#}");
            ExitCode::from(1)
        }
    }
}
