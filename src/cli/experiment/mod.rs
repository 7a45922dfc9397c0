//! `pushlab train` and `pushlab eval`: the paper's experiments from the command line, on any
//! recordings the importer reads, with the same core code the app uses.
//!
//! Which recordings, samples and models an experiment uses, and how they are trained and evaluated,
//! is `pushlab_core::experiment`; these modules parse the command line and present the results:
//! - [`data`]: the summary of the recordings used;
//! - [`training`]: offline training with a progress bar and Ctrl-C;
//! - [`train`]: the `train` command;
//! - [`eval`]: the `eval` command, its table and its JSON report;
//! - [`suite`]: the `suite` command, many experiments in parallel into one table;
//! - [`plot`]: the paper-style figure.
//!
//! Exit codes: 0 done, 1 nothing usable / a file could not be written, 2 wrong arguments.

pub mod data;
pub mod eval;
pub mod plot;
pub mod suite;
pub mod train;
pub mod training;

use std::process::ExitCode;

use clap::Args;
use pushlab_core::model::ModelKind;

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
            ExitCode::from(super::EXIT_USAGE)
        }
        Err(Failure::Failed(e)) => {
            eprintln!("pushlab: {e:#}");
            ExitCode::from(1)
        }
    }
}

/// Options shared by `train` and `eval`.
#[derive(Clone, Debug, Args)]
pub struct TrainingArgs {
    /// Prediction horizon in frames: each sample predicts the motion from frame t to t+K
    /// [default: 1, or the horizon of --model].
    #[arg(long, value_name = "K", value_parser = positive)]
    pub horizon: Option<usize>,
    /// Most epochs of offline training (it stops early when the validation loss stops improving).
    #[arg(long, value_name = "N", default_value_t = 100, value_parser = positive)]
    pub epochs: usize,
    /// Seeds the weights, the validation split and the shuffling: same seed, same model.
    #[arg(long, value_name = "S", default_value_t = 0)]
    pub seed: u64,
    /// Stop after this many epochs without a better validation loss; 0 never stops early.
    #[arg(long, value_name = "N", default_value_t = 15)]
    pub patience: usize,
    /// Take from the given paths only the recordings whose split (in their folder's labels file, or
    /// else in setting.json) matches the role: offline for --data and --offline, online for --online.
    #[arg(long)]
    pub split_from_labels: bool,
    /// Which combined model: `contact` (the push seen in a frame at the contact, correcting a
    /// friction-cone prior; carries over to other faces, objects and real data) or `paper` (the
    /// paper's Fig. 4 exactly) [default: contact, or the kind of --model].
    #[arg(long, value_name = "KIND", value_parser = model_kind)]
    pub model_kind: Option<ModelKind>,
}

/// A model kind by name.
pub fn model_kind(text: &str) -> Result<ModelKind, String> {
    ModelKind::from_name(text.trim()).ok_or_else(|| {
        let names: Vec<&str> = ModelKind::ALL.iter().map(|k| k.name()).collect();
        format!(
            "unknown model kind {text:?}; expected one of {}",
            names.join(", ")
        )
    })
}

/// A whole number of at least 1.
pub fn positive(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        Ok(_) => Err("must be at least 1".into()),
        Err(_) => Err(format!(
            "expected a whole number of at least 1, got {text:?}"
        )),
    }
}

/// A finite number above 0.
/// An online optimiser by name: `gd` or `gauss-newton`.
pub fn optimizer(text: &str) -> Result<pushlab_core::learn::Optimizer, String> {
    pushlab_core::learn::Optimizer::from_name(text.trim())
        .ok_or_else(|| format!("expected gd or gauss-newton, got {text:?}"))
}

pub fn positive_real(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        Ok(_) => Err(format!("must be a finite number above 0, got {text:?}")),
        Err(_) => Err(format!("expected a number, got {text:?}")),
    }
}
