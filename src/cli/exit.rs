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
            eprintln!("pushlab: {}", said_once(&e));
            ExitCode::from(EXIT_USAGE)
        }
        Err(Failure::Failed(e)) => {
            eprintln!("pushlab: {}", said_once(&e));
            ExitCode::from(1)
        }
    }
}

/// The error and its causes, outermost first, each said once. pushlab's errors name their cause in
/// their own message (`"{path}: cannot read: {source}"`) and keep it as their source too, so
/// anyhow's `{:#}` said it twice ("No such file or directory (os error 2): No such file or
/// directory (os error 2)"); a cause already in the message before it is left out.
fn said_once(error: &anyhow::Error) -> String {
    let mut text = error.to_string();
    for cause in error.chain().skip(1) {
        let cause = cause.to_string();
        if !text.contains(&cause) {
            text.push_str(": ");
            text.push_str(&cause);
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use std::io;
    use std::path::PathBuf;

    use anyhow::Context;
    use pushlab_core::labels::file::LabelFileError;

    use super::*;

    #[test]
    fn each_cause_is_said_once() {
        let missing = || io::Error::new(io::ErrorKind::NotFound, "No such file or directory");
        let read: anyhow::Result<()> = Err(LabelFileError::Read {
            path: PathBuf::from("/set/pushlab-labels.json"),
            source: missing(),
        }
        .into());
        let error = read.context("showing /set").expect_err("failed");
        assert_eq!(
            said_once(&error),
            "showing /set: cannot read labels file /set/pushlab-labels.json: No such file or \
             directory"
        );
        // A cause its error does not name is still said.
        let plain = Err::<(), _>(missing()).context("reading /set/a.csv");
        assert_eq!(
            said_once(&plain.expect_err("failed")),
            "reading /set/a.csv: No such file or directory"
        );
    }
}
