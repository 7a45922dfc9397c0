//! `pushlab labels compare TRUTH OTHER`: how well one labels file (proposals, a person's labels)
//! agrees with a reference (the simulator's truth, an expert's labels), per label and frame.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::Context;
use clap::Args;
use pushlab_core::atomic_file::write_atomically;
use pushlab_core::labels::compare::{CompareError, Comparison, compare};
use pushlab_core::labels::file;

/// Arguments of `pushlab labels compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The reference labels file: it decides which recordings, frames and labels are judged.
    truth: PathBuf,
    /// The labels file judged against it.
    other: PathBuf,
    /// Also write `{"labels": [{"label", "precision", "recall", "f1", "frames_truth",
    /// "frames_other"}, …]}` here (null where a ratio has no frames to count).
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
}

/// Runs the command: the table on stdout, the JSON file written atomically.
pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    let truth = file::read(&args.truth)?;
    let other = file::read(&args.other)?;
    // Each error is about one of the two files: name it, as a file's own errors do.
    let result = compare(&truth, &other).map_err(|e| {
        let about = match e {
            CompareError::EmptyReference => &args.truth,
            CompareError::NoSharedRecording { .. } => &args.other,
        };
        anyhow::anyhow!("{}: {e}", about.display())
    })?;
    print!("{}", table(&result));
    if let Some(path) = &args.json {
        let mut json =
            serde_json::to_vec_pretty(&result).context("cannot encode the comparison")?;
        json.push(b'\n');
        write_atomically(path, &json)
            .with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// One row per label, then which recordings were judged and which left out.
fn table(result: &Comparison) -> String {
    let ratio = |r: Option<f64>| r.map_or_else(|| "-".to_owned(), |v| format!("{v:.3}"));
    let mut out = format!(
        "{:<14} {:>9} {:>9} {:>9} {:>12} {:>12}\n",
        "label", "precision", "recall", "F1", "frames truth", "frames other"
    );
    for l in &result.labels {
        let _ = writeln!(
            out,
            "{:<14} {:>9} {:>9} {:>9} {:>12} {:>12}",
            l.label,
            ratio(l.precision),
            ratio(l.recall),
            ratio(l.f1),
            l.frames_truth,
            l.frames_other
        );
    }
    let _ = write!(out, "{} recording(s) compared", result.recordings);
    if !result.left_out.is_empty() {
        let _ = write!(
            out,
            "; {} only in the other file, not judged",
            result.left_out.len()
        );
    }
    out.push('\n');
    out
}
