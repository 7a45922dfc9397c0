//! `pushlab train --data PATH... --out MODEL.json`: offline training of a combined model (and, with
//! `--baseline`, the pure network) on any recordings the importer reads; writes a model file the app
//! and `pushlab eval --model` open.

use std::path::PathBuf;

use anyhow::{Context, anyhow};
use clap::Args;
use pushlab_core::experiment::{self, DEFAULT_HORIZON, UsedRecording, paper_theta0_for};
use pushlab_core::labels::Split;
use pushlab_core::learn::TrainConfig;
use pushlab_core::model::ModelKind;
use pushlab_core::model_file::ModelFile;

use super::args::TrainingArgs;
use super::data;
use super::train_progress::{self, TrainedModels};
use crate::cli::exit::Failure;

/// Arguments of `pushlab train`.
#[derive(Debug, Args)]
pub struct TrainArgs {
    /// Recordings to train on: set folders, CSV files inside a set, MIT Push Dataset .json/.h5
    /// files, or folders of them (searched recursively).
    #[arg(long, required = true, num_args = 1.., value_name = "PATH")]
    pub data: Vec<PathBuf>,
    /// Where to write the model file (JSON; written atomically).
    #[arg(long, value_name = "MODEL.json")]
    pub out: PathBuf,
    #[command(flatten)]
    pub training: TrainingArgs,
    /// Also train the pure-network baseline (the paper's "Offline NN") into the same file.
    #[arg(long)]
    pub baseline: bool,
}

/// Runs `pushlab train`.
pub fn run(args: &TrainArgs) -> Result<(), Failure> {
    // Ctrl-C from here on stops training cleanly instead of killing the process.
    train_progress::cancel_flag();
    let horizon = args.training.horizon.unwrap_or(DEFAULT_HORIZON);
    let kind = args.training.model_kind.unwrap_or_default();
    let split = args.training.split_from_labels.then_some(Split::Offline);
    let loaded = experiment::load(&args.data, split, horizon);
    data::print_summary("data", &loaded, horizon);
    if loaded.used.is_empty() {
        return Err(Failure::Failed(anyhow!(
            "nothing to train on in --data: {}",
            loaded.why_nothing(horizon)
        )));
    }
    let config = train_config(&args.training, horizon, kind, &loaded.used);
    let TrainedModels { combined, pure_nn } = train_progress::train_models(
        kind,
        &loaded.used,
        &config,
        !args.training.no_com_calibration,
        args.baseline,
    )?;
    if !combined.report.kept_an_epoch() {
        return Err(Failure::Failed(anyhow!(
            "stopped by Ctrl-C before the first epoch ended: no model written to {}",
            args.out.display()
        )));
    }
    let file = ModelFile::from_training(
        combined,
        pure_nn,
        experiment::training_metadata(&loaded.used, horizon),
    );
    file.save(&args.out)
        .with_context(|| format!("cannot save the model to {}", args.out.display()))?;
    if args.baseline && file.pure_nn.is_none() {
        println!("the pure network was not trained (stopped by Ctrl-C)");
    }
    println!("wrote {} ({kind} model)", args.out.display());
    Ok(())
}

/// The training configuration: the paper's (Adam, learning rate 0.005, batch 32) with the user's
/// epochs, seed and horizon; says which `θ_online(0)` the model starts from.
pub fn train_config(
    args: &TrainingArgs,
    horizon: usize,
    kind: ModelKind,
    used: &[UsedRecording],
) -> TrainConfig {
    match kind {
        ModelKind::Contact => println!(
            "θ_online(0): per object, COM at the centre and h of a uniform pressure over its outline"
        ),
        ModelKind::Paper => match paper_theta0_for(used) {
            Some(t) => println!(
                "θ_online(0): COM offset ({:.4}, {:.4}) m, h {:.4} m (from the object's outline)",
                t.com_offset[0], t.com_offset[1], t.h
            ),
            None => println!(
                "θ_online(0): COM at the centre, h from the pusher distances (the recordings do not share one object outline)"
            ),
        },
    }
    TrainConfig {
        epochs: args.epochs,
        seed: args.seed,
        patience: args.patience,
        learning_rate: args.adam_lr,
        horizon,
        ..TrainConfig::default()
    }
}
