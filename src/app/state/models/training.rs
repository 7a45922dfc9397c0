//! Offline training from the app: runs pushlab-core's `experiment::train_combined` (the same rules
//! as `pushlab train`) off the UI thread — a worker thread on the desktop, a slice of each frame in
//! a page — with progress, a loss history and cancel. The UI thread only polls.

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError, channel};

use pushlab_core::experiment::{
    UsedRecording, train_baseline_in_slices, train_calibrated_in_slices, training_metadata,
};
use pushlab_core::learn::{
    TrainConfig, TrainError, TrainProgress, TrainStage, Trained, TrainingEnding, TrainingReport,
};
use pushlab_core::model::{CombinedModel, ModelKind, PureNnModel};
use pushlab_core::model_file::{ModelFile, TrainingMetadata};

use crate::app::state::recordings::session::RecordingId;

enum Message {
    Progress(TrainProgress),
    /// The combined model is trained; the pure-network baseline is next.
    Baseline,
    /// Boxed: a trained model is kilobytes, progress a few words, and both travel one channel.
    Done(Box<Result<TrainedPair, TrainError>>),
}

/// What one run trains: the combined model, and for a run trained for folders its pure-network
/// baseline, so that the app's pure-NN layer comes from a model of the same data.
struct TrainedPair {
    combined: Trained<CombinedModel>,
    pure_nn: Option<Trained<PureNnModel>>,
}

struct Job {
    receiver: Receiver<Message>,
    cancel: Arc<AtomicBool>,
    metadata: TrainingMetadata,
    for_folders: Vec<PathBuf>,
}

/// A change of the recordings chosen for training (the Train tab's list).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrainingChoice {
    /// Every open recording.
    All,
    /// None.
    None,
    /// The recordings the browser shows under its filter, in place of the choice.
    ShownInBrowser,
    /// Choose one recording (`true`) or leave it out.
    Set(RecordingId, bool),
}

/// A run that finished with a model.
pub struct Finished {
    /// The combined model, its pure-network baseline (runs for folders, unless cancelled first) and
    /// its sources and domain with the training reports filled in.
    pub file: ModelFile,
    /// The folders it was trained for ("Train for these recordings"): the model is remembered for
    /// them. Empty for a run started from the Train tab.
    pub for_folders: Vec<PathBuf>,
}

/// How the last run ended, for the Train tab's bar.
#[derive(Clone, Debug)]
pub enum RunEnd {
    /// A model came out of it.
    Trained {
        /// How the combined model's training went: its epochs, the one kept and why it stopped
        /// (cancelled also while its COM misfit was being measured: see `train_calibrated`).
        report: TrainingReport,
    },
    /// No model: why.
    Failed(String),
}

/// Why a run ended, in the words of the status line and the Train tab's bar (the rule is the
/// core's [`TrainingReport::ending`]).
pub fn why_it_ended(report: &TrainingReport) -> &'static str {
    match report.ending() {
        TrainingEnding::Cancelled => "cancelled",
        TrainingEnding::StoppedEarly => "stopped early",
        TrainingEnding::Finished => "finished",
    }
}

/// Training state: what to train on, the running job, and its history.
#[derive(Default)]
pub struct Training {
    /// Recordings chosen for training.
    pub chosen: BTreeSet<RecordingId>,
    /// Which combined model to train.
    pub kind: ModelKind,
    /// Epochs, learning rate, horizon….
    pub config: TrainConfig,
    /// Progress reported after every epoch of the current or last run's combined model.
    pub history: Vec<TrainProgress>,
    /// Progress of the pure-network baseline, trained after the combined model for folders.
    pub baseline_history: Vec<TrainProgress>,
    /// Whether the running job is training the baseline now.
    training_baseline: bool,
    /// The last epoch of a model trained to measure the COM misfit, while the job trains those
    /// (kept apart from `history`: they are not the model's loss curve).
    calibrating: Option<TrainProgress>,
    /// A model that finished training and has not been taken into use yet.
    finished: Option<Finished>,
    /// How the last run ended: which epoch it kept and why it stopped, or why it failed, for the
    /// Train tab (its history alone shows where it stopped, not what it kept).
    last_end: Option<RunEnd>,
    /// Whether the user ever set the kind or the horizon: then a model taken into use no longer
    /// resets them (see [`Training::follow_model`]).
    edited: bool,
    job: Option<Job>,
}

impl Training {
    /// Whether a training run is going on.
    pub fn is_running(&self) -> bool {
        self.job.is_some()
    }

    /// Starts training on the recordings on a worker thread; `for_folders` are remembered with the
    /// result (see [`Finished::for_folders`]).
    pub fn start(&mut self, recordings: Vec<UsedRecording>, for_folders: Vec<PathBuf>) {
        if self.is_running() {
            return;
        }
        let metadata = training_metadata(&recordings, self.config.horizon);
        self.history.clear();
        self.baseline_history.clear();
        self.training_baseline = false;
        self.calibrating = None;
        self.last_end = None;
        let with_baseline = !for_folders.is_empty();
        let (sender, receiver) = channel();
        let cancel = Arc::new(AtomicBool::new(false));
        let (kind, config) = (self.kind, self.config);
        let worker_cancel = cancel.clone();
        // In slices: a page polls the training a slice of each frame (`platform`).
        crate::app::platform::spawn_in_slices(move || async move {
            let progress_sender = sender.clone();
            let mut progress = |p: &TrainProgress| {
                let _ = progress_sender.send(Message::Progress(*p));
            };
            let combined = train_calibrated_in_slices(
                kind,
                &recordings,
                &config,
                true,
                &mut progress,
                &worker_cancel,
            )
            .await;
            let result = match combined {
                Ok(combined) => {
                    // Not after a cancel; and a baseline cancelled before its first epoch ended
                    // is random weights, not a baseline.
                    let cancelled =
                        worker_cancel.load(Ordering::Relaxed) || combined.report.cancelled;
                    let pure_nn = if with_baseline && !cancelled {
                        let _ = progress_sender.send(Message::Baseline);
                        train_baseline_in_slices(
                            &recordings,
                            &config,
                            &mut progress,
                            &worker_cancel,
                        )
                        .await
                        .map(|baseline| Some(baseline).filter(|b| b.report.kept_an_epoch()))
                    } else {
                        Ok(None)
                    };
                    pure_nn.map(|pure_nn| TrainedPair { combined, pure_nn })
                }
                Err(e) => Err(e),
            };
            // The receiver is gone only when the app closed.
            let _ = sender.send(Message::Done(Box::new(result)));
        });
        self.job = Some(Job {
            receiver,
            cancel,
            metadata,
            for_folders,
        });
    }

    /// Starts the Train tab from the model in use: its kind and its horizon, as `pushlab eval`
    /// takes the horizon of `--model`. Why: the tab used to start at horizon 1 whatever the model,
    /// so pressing Train with its defaults beside the bundled model (horizon 10) made a model that
    /// predicts a tenth as far, from motions of a frame that are mostly tracking noise, and online
    /// learning switched to it. A running job keeps the settings it started with, and a kind or
    /// horizon the user set stays until the user changes it (a folder's remembered model reopened
    /// with the folder does not reset it).
    pub fn follow_model(&mut self, kind: Option<ModelKind>, horizon: usize) {
        if self.is_running() || self.edited {
            return;
        }
        if let Some(kind) = kind {
            self.kind = kind;
        }
        self.config.horizon = horizon;
    }

    /// Asks the running job to stop after the current batch; it still delivers its best model if
    /// an epoch has ended (before that there is none, and the model in use stays).
    pub fn cancel(&self) {
        if let Some(job) = &self.job {
            job.cancel.store(true, Ordering::Relaxed);
        }
    }

    /// Collects progress; returns a status message when the run ended.
    pub fn poll(&mut self) -> Option<String> {
        loop {
            let message = self.job.as_ref()?.receiver.try_recv();
            match message {
                Ok(Message::Progress(p)) if self.training_baseline => self.baseline_history.push(p),
                Ok(Message::Progress(p)) if p.stage != TrainStage::Model => {
                    self.calibrating = Some(p);
                }
                Ok(Message::Progress(p)) => self.history.push(p),
                Ok(Message::Baseline) => {
                    self.training_baseline = true;
                    self.calibrating = None;
                }
                Ok(Message::Done(result)) => {
                    let job = self.job.take()?;
                    self.training_baseline = false;
                    self.calibrating = None;
                    return Some(self.take_result(job, *result));
                }
                Err(TryRecvError::Empty) => return None,
                Err(TryRecvError::Disconnected) => {
                    self.job = None;
                    return Some(self.no_model("training stopped unexpectedly".to_owned()));
                }
            }
        }
    }

    /// Keeps what an ended run delivered (a model waits in `finished` to be taken into use);
    /// returns the status line.
    fn take_result(&mut self, job: Job, result: Result<TrainedPair, TrainError>) -> String {
        let TrainedPair {
            combined: trained,
            pure_nn,
        } = match result {
            Ok(pair) if pair.combined.report.kept_an_epoch() => pair,
            Ok(_) => {
                return self.no_model(
                    "training cancelled before its first epoch ended: no model; the one in use \
                     is kept"
                        .to_owned(),
                );
            }
            Err(e) => return self.no_model(format!("training failed: {e}")),
        };
        let r = &trained.report;
        self.last_end = Some(RunEnd::Trained { report: r.clone() });
        let message = format!(
            "training the {} model {} after {} epochs (kept epoch {}): train loss {:.4}{}",
            trained.model.kind(),
            why_it_ended(r),
            r.epochs_run,
            r.best_epoch,
            r.train_loss,
            r.validation_loss
                .map(|v| format!(", validation loss {v:.4}"))
                .unwrap_or_default()
        );
        let message = match &pure_nn {
            Some(baseline) => format!(
                "{message}; its pure-NN baseline {}after {} epochs",
                if baseline.report.cancelled {
                    "cancelled "
                } else {
                    ""
                },
                baseline.report.epochs_run
            ),
            None => message,
        };
        self.finished = Some(Finished {
            file: ModelFile::from_training(trained, pure_nn, job.metadata),
            for_folders: job.for_folders,
        });
        message
    }

    /// Records a run that left no model (the one in use stays); returns the status line: why.
    fn no_model(&mut self, why: String) -> String {
        self.last_end = Some(RunEnd::Failed(why.clone()));
        why
    }

    /// How the last run ended, until the next starts.
    pub fn last_end(&self) -> Option<&RunEnd> {
        self.last_end.as_ref()
    }

    /// Sets the kind to train, as the user chose it.
    pub fn set_kind(&mut self, kind: ModelKind) {
        self.edited |= kind != self.kind;
        self.kind = kind;
    }

    /// Sets the training settings, as the user chose them (not while a run uses them).
    pub fn set_config(&mut self, config: TrainConfig) {
        if self.is_running() {
            return;
        }
        self.edited |= config.horizon != self.config.horizon;
        self.config = config;
    }

    /// The model of a finished run, once.
    pub fn take_finished(&mut self) -> Option<Finished> {
        self.finished.take()
    }

    /// Fraction of epochs done, for the progress bar; a run that trains the baseline too counts
    /// the combined model as the first half and the baseline as the second.
    pub fn progress(&self) -> f32 {
        let fraction = |history: &[TrainProgress]| match history.last() {
            Some(p) if p.epochs > 0 => p.epoch as f32 / p.epochs as f32,
            _ => 0.0,
        };
        if self.training_baseline {
            0.5 + 0.5 * fraction(&self.baseline_history)
        } else if let Some(TrainProgress {
            stage: TrainStage::MisfitFold { fold, folds },
            epoch,
            epochs,
            ..
        }) = self.calibrating
        {
            // The misfit's folds, one after the other, each from 0 to 1 of its epochs.
            let within = epoch as f32 / epochs.max(1) as f32;
            ((fold - 1) as f32 + within) / folds.max(1) as f32
        } else {
            fraction(&self.history)
        }
    }

    /// What the job is training now, for its progress bar.
    pub fn phase(&self) -> String {
        match self.calibrating {
            _ if self.training_baseline => "the pure-NN baseline".to_owned(),
            Some(TrainProgress {
                stage: TrainStage::MisfitFold { fold, folds },
                ..
            }) => format!("the COM misfit (without object {fold} of {folds})"),
            _ => "the combined model".to_owned(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc::Sender;

    /// A job whose worker is the test: it sends the messages.
    fn training_fed_by_hand() -> (Training, Sender<Message>) {
        let (sender, receiver) = channel();
        let training = Training {
            job: Some(Job {
                receiver,
                cancel: Arc::new(AtomicBool::new(false)),
                metadata: training_metadata(&[], 1),
                for_folders: Vec::new(),
            }),
            ..Training::default()
        };
        (training, sender)
    }

    fn epoch(stage: TrainStage, epoch: usize) -> Message {
        Message::Progress(TrainProgress {
            stage,
            epoch,
            epochs: 10,
            train_loss: 1.0,
            validation_loss: None,
            best_validation_loss: None,
        })
    }

    #[test]
    fn the_misfit_trainings_show_as_their_own_phase_and_stay_out_of_the_loss_curve() {
        let (mut training, sender) = training_fed_by_hand();
        for k in 1..=10 {
            sender.send(epoch(TrainStage::Model, k)).expect("sends");
        }
        training.poll();
        assert_eq!(training.phase(), "the combined model");
        assert_eq!(training.progress(), 1.0);

        let second = TrainStage::MisfitFold { fold: 2, folds: 4 };
        sender.send(epoch(second, 5)).expect("sends");
        training.poll();
        assert_eq!(training.phase(), "the COM misfit (without object 2 of 4)");
        // One fold done and half of the second, of four.
        assert_eq!(training.progress(), 1.5 / 4.0);
        assert_eq!(training.history.len(), 10, "the model's curve only");
    }

    #[test]
    fn a_failed_run_says_why_where_its_bar_was() {
        let (mut training, sender) = training_fed_by_hand();
        sender.send(epoch(TrainStage::Model, 3)).expect("sends");
        let failure = Err(TrainError::NonFinite { frame: 7 });
        sender
            .send(Message::Done(Box::new(failure)))
            .expect("sends");
        let status = training.poll().expect("the run ended");
        assert_eq!(
            status,
            "training failed: the training data contains a non-finite value (sample at frame 7)"
        );
        assert!(matches!(training.last_end(), Some(RunEnd::Failed(why)) if *why == status));
    }

    #[test]
    fn the_words_for_how_a_run_ended() {
        let report = |epochs_run, cancelled, stopped_early| TrainingReport {
            config: TrainConfig {
                epochs: 100,
                ..TrainConfig::default()
            },
            epochs_run,
            best_epoch: 1,
            train_loss: 1.0,
            validation_loss: None,
            training_samples: 1,
            validation_samples: 0,
            cancelled,
            stopped_early,
            history: Vec::new(),
        };
        assert_eq!(why_it_ended(&report(37, false, true)), "stopped early");
        assert_eq!(why_it_ended(&report(100, false, false)), "finished");
        // Patience ran out on the last epoch: it ran them all.
        assert_eq!(why_it_ended(&report(100, false, true)), "finished");
        assert_eq!(why_it_ended(&report(12, true, false)), "cancelled");
    }

    #[test]
    fn the_tab_follows_the_model_in_use_until_the_user_sets_kind_or_horizon() {
        let mut training = Training::default();
        training.follow_model(Some(ModelKind::Paper), 10);
        assert_eq!(
            (training.kind, training.config.horizon),
            (ModelKind::Paper, 10)
        );
        training.set_config(TrainConfig {
            epochs: 3,
            ..training.config
        });
        training.follow_model(Some(ModelKind::Contact), 5);
        assert_eq!(
            (training.kind, training.config.horizon),
            (ModelKind::Contact, 5),
            "changing the epochs is not choosing the horizon"
        );
        training.set_config(TrainConfig {
            horizon: 2,
            ..training.config
        });
        training.follow_model(Some(ModelKind::Paper), 10);
        assert_eq!(
            (training.kind, training.config.horizon),
            (ModelKind::Contact, 2)
        );
    }

    #[test]
    fn a_run_cancelled_before_its_first_epoch_ended_gives_no_model() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("sample-data/box1-paper-center-front/offline_000.csv");
        let loaded = pushlab_core::experiment::load(&[dir], None, 1);
        let cancelled = AtomicBool::new(true);
        let combined = pushlab_core::experiment::train_combined(
            ModelKind::Contact,
            &loaded.used,
            &TrainConfig::default(),
            &mut |_| {},
            &cancelled,
        )
        .expect("the run starts");
        assert_eq!(combined.report.epochs_run, 0);
        let (mut training, sender) = training_fed_by_hand();
        let pair = TrainedPair {
            combined,
            pure_nn: None,
        };
        sender
            .send(Message::Done(Box::new(Ok(pair))))
            .expect("sends");
        let status = training.poll().expect("the run ended");
        assert_eq!(
            status,
            "training cancelled before its first epoch ended: no model; the one in use is kept"
        );
        assert!(
            training.take_finished().is_none(),
            "the random weights are not taken into use"
        );
        assert!(matches!(training.last_end(), Some(RunEnd::Failed(_))));
    }
}
