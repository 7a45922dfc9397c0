//! `pushlab validate PATH...`: load recordings the way the app does and say, one line per recording,
//! whether each is fine, has recoverable defects, or cannot be used and why.
//!
//! Lines (stdout), then a summary line:
//! - `ok: PATH (N frames, D s)`
//! - `N warning(s): PATH: first; second; …`
//! - `error: PATH[ line L]: what is wrong, expected what`
//!
//! Exit code 0 when every recording loaded (warnings allowed), 1 when any did not, 2 for wrong
//! arguments (handled by clap before this runs).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use pushlab_core::recording::load_paths;

/// Arguments of `pushlab validate`.
#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// Set folders, CSV files inside a set, MIT Push Dataset .json/.h5 files, or folders of them.
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
}

/// Runs the command; see the module documentation for the output and exit codes.
pub fn run(args: &ValidateArgs) -> ExitCode {
    let report = load_paths(&args.paths);
    let mut with_warnings = 0;
    for set in &report.sets {
        for recording in &set.recordings {
            let path = recording.source.display();
            if recording.warnings.is_empty() {
                println!(
                    "ok: {path} ({} frames, {:.2} s)",
                    recording.trajectory.len(),
                    recording.trajectory.duration()
                );
            } else {
                with_warnings += 1;
                let n = recording.warnings.len();
                let plural = if n == 1 { "warning" } else { "warnings" };
                println!("{n} {plural}: {path}: {}", recording.warnings.join("; "));
            }
        }
    }
    for error in &report.errors {
        println!("error: {error}");
    }
    println!(
        "{} recording(s) loaded ({with_warnings} with warnings), {} error(s)",
        report.recording_count(),
        report.errors.len()
    );
    if report.errors.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
