//! Offline training as `train` and `eval` run it: a progress bar per epoch showing the current loss,
//! and Ctrl-C stopping cleanly with the best model so far.

use std::sync::atomic::AtomicBool;

use anyhow::Context;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pushlab_core::experiment::{UsedRecording, train_baseline, train_calibrated};
use pushlab_core::learn::{
    TrainConfig, TrainProgress, TrainStage, Trained, TrainingEnding, TrainingReport,
};
use pushlab_core::model::{CombinedModel, ModelKind, PureNnModel};

// Ctrl-C: training checks the flag between batches and keeps the best model so far.
pub use crate::cli::interrupt::{cancel_flag, cancelled};

/// The trained models of one run.
pub struct TrainedModels {
    pub combined: Trained<CombinedModel>,
    pub pure_nn: Option<Trained<PureNnModel>>,
}

/// Trains the combined model of `kind` (calibrating its COM misfit when `calibrate`) and, when
/// `baseline`, the pure network, one progress bar each. When Ctrl-C stops the combined model's
/// training, the pure network is not started.
pub fn train_models(
    kind: ModelKind,
    used: &[UsedRecording],
    config: &TrainConfig,
    calibrate: bool,
    baseline: bool,
) -> anyhow::Result<TrainedModels> {
    let cancel = cancel_flag();
    let name = format!("{kind} model");
    let combined = with_progress(&name, config, |progress| {
        train_calibrated(kind, used, config, calibrate, progress, cancel)
    })
    .with_context(|| format!("cannot train the {name}"))?;
    println!("{}", summary(&name, &combined.report));
    let misfit = combined.model.com_misfit();
    if misfit.is_calibrated() {
        println!(
            "COM misfit, from {} pushes on {} objects each left out of training: {:.3} h with \
             gradient descent, {:.3} h with Gauss–Newton (added to the COM ellipse)",
            misfit.pushes, misfit.objects, misfit.gd_per_h, misfit.gauss_newton_per_h
        );
    }
    // Not after a Ctrl-C; and a baseline stopped before its first epoch ended is random weights,
    // not a baseline.
    let pure_nn = if baseline && !combined.report.cancelled && !cancelled() {
        Some(train_pure_nn(used, config, cancel_flag())?).filter(|t| t.report.kept_an_epoch())
    } else {
        None
    };
    Ok(TrainedModels { combined, pure_nn })
}

/// Trains the pure network alone (when a loaded model file has none), stopping when `cancel` is
/// set.
pub fn train_pure_nn(
    used: &[UsedRecording],
    config: &TrainConfig,
    cancel: &AtomicBool,
) -> anyhow::Result<Trained<PureNnModel>> {
    let trained = with_progress("pure NN", config, |progress| {
        train_baseline(used, config, progress, cancel)
    })
    .context("cannot train the pure network")?;
    println!("{}", summary("pure NN", &trained.report));
    Ok(trained)
}

/// Runs `train` with a progress bar on stderr (hidden when stderr is not a terminal).
fn with_progress<T, E>(
    name: &str,
    config: &TrainConfig,
    train: impl FnOnce(&mut dyn FnMut(&TrainProgress)) -> Result<T, E>,
) -> Result<T, E> {
    let bar =
        ProgressBar::with_draw_target(Some(config.epochs as u64), ProgressDrawTarget::stderr());
    if let Ok(style) =
        ProgressStyle::with_template("{prefix:>13} [{bar:30}] epoch {pos}/{len} {msg} ({elapsed})")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix(name.to_owned());
    let result = train(&mut |p: &TrainProgress| {
        // The models trained to measure the COM misfit say which object they leave out.
        bar.set_prefix(match p.stage {
            TrainStage::Model => name.to_owned(),
            TrainStage::MisfitFold { fold, folds } => format!("misfit {fold}/{folds}"),
        });
        bar.set_position(p.epoch as u64);
        bar.set_message(match p.validation_loss {
            Some(v) => format!("loss {:.4}, validation {v:.4}", p.train_loss),
            None => format!("loss {:.4}", p.train_loss),
        });
    });
    bar.finish_and_clear();
    result
}

/// One line saying how training went.
pub fn summary(name: &str, report: &TrainingReport) -> String {
    let how = match report.ending() {
        TrainingEnding::Cancelled => " (stopped by Ctrl-C; best model so far kept)",
        TrainingEnding::StoppedEarly => " (stopped early: validation loss no longer improving)",
        TrainingEnding::Finished => "",
    };
    let validation = report
        .validation_loss
        .map(|v| format!(", validation loss {v:.4}"))
        .unwrap_or_default();
    format!(
        "{name}: {} epoch(s) run, kept epoch {}: training loss {:.4}{validation}; {} training / {} validation samples{how}",
        report.epochs_run,
        report.best_epoch,
        report.train_loss,
        report.training_samples,
        report.validation_samples,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(epochs_run: usize, cancelled: bool, stopped_early: bool) -> TrainingReport {
        TrainingReport {
            config: TrainConfig {
                epochs: 100,
                ..TrainConfig::default()
            },
            epochs_run,
            best_epoch: 22,
            train_loss: 0.5,
            validation_loss: Some(0.75),
            training_samples: 900,
            validation_samples: 100,
            cancelled,
            stopped_early,
            history: Vec::new(),
        }
    }

    #[test]
    fn the_summary_says_why_training_stopped() {
        assert_eq!(
            summary("combined", &report(37, false, true)),
            "combined: 37 epoch(s) run, kept epoch 22: training loss 0.5000, validation loss \
             0.7500; 900 training / 100 validation samples (stopped early: validation loss no \
             longer improving)"
        );
        assert!(
            summary("combined", &report(12, true, false))
                .ends_with("(stopped by Ctrl-C; best model so far kept)")
        );
        // Patience that ran out on the last epoch ran every epoch: nothing stopped early.
        assert!(summary("combined", &report(100, false, true)).ends_with("validation samples"));
    }
}
