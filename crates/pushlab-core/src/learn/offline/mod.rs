//! Offline training (eq. 12): Adam on the network's weights over pre-recorded pushes, with
//! `θ_online` fixed at `θ_online(0)` (or, optionally, trained too), seeded shuffling, a validation
//! split by trajectory and early stopping.
//!
//! One loop ([`run`]) trains every model: [`paper`] (the paper's combined model), [`contact`] (the
//! contact-frame combined model) and [`pure_nn`] (the "Offline NN" baseline) each only say how a
//! batch's gradient and the validation loss are computed ([`Trainee`]); the two combined models run
//! each network layer for a whole batch at once (`model/*/batch.rs`).

mod contact;
mod paper;
mod pure_nn;

pub use self::contact::{ContactTrajectory, train_contact, train_contact_in_slices};
pub use self::paper::{paper_theta0, train_paper, train_paper_in_slices};
pub use self::pure_nn::{train_pure_nn, train_pure_nn_in_slices};

use std::sync::atomic::{AtomicBool, Ordering};

use serde::{Deserialize, Serialize};

use super::adam::Adam;
use crate::model::LossScale;
use crate::model::{Mlp, Network, OnlineParams, Sample, loss_weights};
use crate::real::Real;
use crate::rng::SplitMix64;
#[cfg(target_arch = "x86_64")]
use crate::simd::Fused;
use crate::simd::{MulAdd, Unfused};

/// How to train.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct TrainConfig {
    /// Passes over the training data at most.
    pub epochs: usize,
    /// Adam's learning rate (the paper: 0.005).
    pub learning_rate: f64,
    /// Samples per gradient step (the paper: 32).
    pub batch_size: usize,
    /// Seeds the weights, the validation split and the shuffling: same seed, same model, bit for bit.
    pub seed: u64,
    /// Fraction of the trajectories held out for validation (whole trajectories, so that neighbouring
    /// frames of one push never sit on both sides). Zero disables validation and early stopping.
    pub validation_fraction: f64,
    /// Stop after this many epochs without a better validation loss; zero never stops early.
    pub patience: usize,
    /// Also train `θ_online(0)` offline (the paper's optional scheme; the paper model only).
    pub train_online_params: bool,
    /// The paper model's `θ_online(0)`. `None` puts the COM at the centre and takes half the mean
    /// distance of the pusher from the centre as `h` — a rough guess; [`paper_theta0`] is the rule
    /// `train` and `eval` use. The contact-frame model takes each object's own `θ_online(0)`.
    pub theta0: Option<OnlineParams>,
    /// The prediction horizon in frames the samples were made with (stored in the model).
    pub horizon: usize,
    /// The contact-frame model's parts (its ablations turn one off; see `ContactOptions`).
    pub contact: crate::model::contact::ContactOptions,
    /// The paper model only: add to the offline pushes their images under the symmetries of the
    /// object's outline (mirrors and quarter turns that map it onto itself).
    pub augment_symmetries: bool,
    /// The σ that weight and normalise the losses; `None` takes them from the training samples.
    /// Given when the training samples are not the data the losses should be measured against
    /// (augmented with images whose motions spread wider).
    #[serde(skip)]
    pub loss_scale: Option<LossScale>,
}

impl Default for TrainConfig {
    fn default() -> Self {
        Self {
            epochs: 100,
            learning_rate: 0.005,
            batch_size: 32,
            seed: 0,
            validation_fraction: 0.2,
            patience: 15,
            train_online_params: false,
            theta0: None,
            horizon: 1,
            contact: Default::default(),
            augment_symmetries: false,
            loss_scale: None,
        }
    }
}

/// Which training an epoch belongs to: the model asked for, or one of the models trained to
/// measure its COM misfit (`experiment::calibrate_com_misfit_in_slices`), which a progress bar or a loss
/// curve of the model must not take for its own.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TrainStage {
    /// The model asked for.
    #[default]
    Model,
    /// The model trained without the `fold`-th object (from 1) of `folds`.
    MisfitFold { fold: usize, folds: usize },
}

/// Reported after every epoch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrainProgress {
    /// Which training this epoch belongs to.
    pub stage: TrainStage,
    /// The epoch just finished, from 1.
    pub epoch: usize,
    /// The most epochs this run will take.
    pub epochs: usize,
    /// Mean loss ℓ over the epoch's training samples.
    pub train_loss: f64,
    /// Mean loss ℓ on the validation trajectories.
    pub validation_loss: Option<f64>,
    /// The best validation loss so far (the model that will be kept).
    pub best_validation_loss: Option<f64>,
}

/// What a training run did.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrainingReport {
    pub config: TrainConfig,
    /// Epochs actually run.
    pub epochs_run: usize,
    /// The epoch whose weights were kept (the best validation loss, or the last one without validation).
    pub best_epoch: usize,
    /// Mean training loss ℓ of the kept epoch.
    pub train_loss: f64,
    /// Mean validation loss ℓ of the kept epoch.
    pub validation_loss: Option<f64>,
    pub training_samples: usize,
    pub validation_samples: usize,
    /// Stopped by the cancel flag (the best model so far is kept).
    pub cancelled: bool,
    /// Stopped because the validation loss stopped improving.
    pub stopped_early: bool,
    /// Training and validation loss per epoch.
    pub history: Vec<(f64, Option<f64>)>,
}

impl TrainingReport {
    /// Whether the model holds the weights of a finished epoch. A run cancelled before its first
    /// epoch ended keeps the random initial weights (`best_epoch` 0): that is no trained model, and
    /// the app and `pushlab train` refuse to use or write it.
    pub fn kept_an_epoch(&self) -> bool {
        self.best_epoch > 0
    }

    /// How the run ended, one rule for the app's Train tab and `pushlab train`: a patience that
    /// ran out on the last epoch ran every epoch, so that run finished.
    pub fn ending(&self) -> TrainingEnding {
        if self.cancelled {
            TrainingEnding::Cancelled
        } else if self.stopped_early && self.epochs_run < self.config.epochs {
            TrainingEnding::StoppedEarly
        } else {
            TrainingEnding::Finished
        }
    }
}

/// How a training run ended (see [`TrainingReport::ending`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrainingEnding {
    /// Stopped by the cancel flag; the best model so far is kept.
    Cancelled,
    /// No better validation loss for `patience` epochs, before the last epoch.
    StoppedEarly,
    /// Ran every epoch.
    Finished,
}

/// A trained model and how it was trained.
#[derive(Clone, Debug)]
pub struct Trained<M> {
    pub model: M,
    pub report: TrainingReport,
}

/// Why training could not start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TrainError {
    #[error(
        "no training samples: the recordings are shorter than the horizon ({horizon} frames) or empty"
    )]
    NoSamples { horizon: usize },
    #[error("invalid training configuration: {0}")]
    BadConfig(String),
    #[error("the training data contains a non-finite value (sample at frame {frame})")]
    NonFinite { frame: usize },
    #[error(
        "the contact-frame model needs each object's outline, and none of the recordings has a usable one (train the paper model instead)"
    )]
    NoOutline,
}

/// Checks the training configuration and that every sample is finite.
fn check(trajectories: &[&[Sample]], config: &TrainConfig) -> Result<(), TrainError> {
    // No epoch keeps the random initial weights: that is no model (see `kept_an_epoch`).
    if config.epochs == 0 {
        return Err(TrainError::BadConfig("epochs must be at least 1".into()));
    }
    if config.batch_size == 0 {
        return Err(TrainError::BadConfig(
            "batch size must be at least 1".into(),
        ));
    }
    if !(config.learning_rate.is_finite() && config.learning_rate > 0.0) {
        return Err(TrainError::BadConfig(format!(
            "learning rate must be positive, got {}",
            config.learning_rate
        )));
    }
    if !(0.0..1.0).contains(&config.validation_fraction) {
        return Err(TrainError::BadConfig(format!(
            "validation fraction must be in [0, 1), got {}",
            config.validation_fraction
        )));
    }
    for s in trajectories.iter().copied().flatten() {
        let i = &s.input;
        let t = &s.target;
        let values = [
            i.robot_in_object[0],
            i.robot_in_object[1],
            i.robot_motion_in_object[0],
            i.robot_motion_in_object[1],
            t.translation[0],
            t.translation[1],
            t.rotation,
        ];
        if !values.iter().all(|v| v.is_finite()) {
            return Err(TrainError::NonFinite { frame: s.frame });
        }
    }
    if trajectories.iter().all(|t| t.is_empty()) {
        return Err(TrainError::NoSamples {
            horizon: config.horizon,
        });
    }
    Ok(())
}

/// The indices of the trajectories training keeps for training (the others validate), as every model
/// trained with `config` splits them.
pub fn training_trajectories<T: Clone>(
    trajectories: &[Vec<T>],
    config: &TrainConfig,
) -> Vec<usize> {
    let indexed: Vec<Vec<usize>> = trajectories
        .iter()
        .enumerate()
        .map(|(i, t)| if t.is_empty() { Vec::new() } else { vec![i] })
        .collect();
    let mut train = Split::new(&indexed, config).train;
    train.sort_unstable();
    train
}

/// The training and validation items: whole trajectories held out for validation, chosen by the seed
/// (the same trajectories for every model trained with that seed), at least one kept for training.
struct Split<T> {
    train: Vec<T>,
    validation: Vec<T>,
}

impl<T: Clone> Split<T> {
    fn new(trajectories: &[Vec<T>], config: &TrainConfig) -> Self {
        let non_empty: Vec<&Vec<T>> = trajectories.iter().filter(|t| !t.is_empty()).collect();
        let mut order: Vec<usize> = (0..non_empty.len()).collect();
        SplitMix64::new(config.seed ^ 0x5EED_5B17).shuffle(&mut order);
        let held_out = if config.validation_fraction > 0.0 && non_empty.len() >= 2 {
            ((non_empty.len() as f64 * config.validation_fraction).ceil() as usize)
                .clamp(1, non_empty.len() - 1)
        } else {
            0
        };
        let mut train = Vec::new();
        let mut validation = Vec::new();
        for (rank, &i) in order.iter().enumerate() {
            let target = if rank < held_out {
                &mut validation
            } else {
                &mut train
            };
            target.extend_from_slice(non_empty[i]);
        }
        Self { train, validation }
    }
}

/// What the shared training loop needs from a model whose network has `I` inputs.
trait Trainee<const I: usize> {
    type Real: Real;
    /// One training sample as the model consumes it.
    type Item;
    fn network_mut(&mut self) -> &mut Network<Self::Real, I>;
    /// The network and up to three other trained parameters (the paper model's `θ_online(0)`, the
    /// contact model's `μ`), to keep the best epoch's.
    fn snapshot(&self) -> (Network<Self::Real, I>, [Self::Real; 3]);
    fn restore(&mut self, snapshot: (Network<Self::Real, I>, [Self::Real; 3]));
    fn loss_scale(&self) -> LossScale;
    /// Adds the weight gradient of the loss of `samples[i]` for every `i` in `batch` to `grad`
    /// (summed in sample order); returns the summed loss. Implementations are `#[inline(always)]`:
    /// compiled into the epoch's AVX2 + FMA copy. (A method compiled on its own gets the baseline
    /// target, where every fused multiply-add is a call to `fmaf`: that was two thirds of the contact
    /// kind's training time.)
    fn accumulate_batch<A: MulAdd>(
        &mut self,
        samples: &[Self::Item],
        batch: &[usize],
        weights: &[Self::Real; 3],
        grad: &mut Mlp<Self::Real, I>,
    ) -> Self::Real;
    /// The summed loss of `samples` (the validation split), added in order.
    fn total_loss(&mut self, samples: &[Self::Item], weights: &[Self::Real; 3]) -> f64;
    /// Called after each batch with its size: updates any non-network parameters.
    fn after_batch(&mut self, _batch: usize) {}
}

/// Batches trained between two pauses of a run in slices (`crate::slices`): 512 samples at the
/// paper's batch size, about a millisecond of a browser tab's time, so that a page polling the run
/// for a slice of each frame overruns its slice by little.
const BATCHES_PER_SLICE: usize = 16;

/// The training loop shared by every model, in slices: it pauses every [`BATCHES_PER_SLICE`]
/// batches and after each epoch's validation. The batches and the sum of their losses are the same
/// as in one piece, bit for bit: a slice is a run of whole batches, added to one running sum.
async fn run<const I: usize, M: Trainee<I>>(
    trainee: &mut M,
    split: &Split<M::Item>,
    config: &TrainConfig,
    rng: &mut SplitMix64,
    progress: &mut dyn FnMut(&TrainProgress),
    cancel: &AtomicBool,
) -> TrainingReport {
    let (train, validation) = (&split.train, &split.validation);
    let weights = loss_weights::<M::Real>(&trainee.loss_scale());
    let mut adam = Adam::<M::Real, I>::new(config.learning_rate);
    let mut grad = Mlp::<M::Real, I>::zeros();
    let mut order: Vec<usize> = (0..train.len()).collect();
    let mut history = Vec::new();
    let mut best: Option<(f64, usize, f64)> = None; // (validation loss, epoch, train loss)
    let mut best_snapshot = trainee.snapshot();
    let (mut cancelled, mut stopped_early) = (false, false);
    let mut last_train_loss = f64::NAN;

    'epochs: for epoch in 1..=config.epochs {
        rng.shuffle(&mut order);
        let mut epoch_loss = 0.0f64;
        for slice in order.chunks(config.batch_size.saturating_mul(BATCHES_PER_SLICE)) {
            let mut batches = Batches {
                trainee: &mut *trainee,
                train,
                order: slice,
                weights: &weights,
                adam: &mut adam,
                grad: &mut grad,
                batch_size: config.batch_size,
                cancel,
            };
            if !batches.run(&mut epoch_loss) {
                cancelled = true;
                break 'epochs;
            }
            crate::slices::pause().await;
        }
        last_train_loss = epoch_loss / train.len().max(1) as f64;
        let validation_loss = (!validation.is_empty())
            .then(|| trainee.total_loss(validation, &weights) / validation.len() as f64);
        history.push((last_train_loss, validation_loss));
        let improved = match (validation_loss, best) {
            (Some(v), Some((b, _, _))) => v < b,
            (Some(_), None) => true,
            (None, _) => true,
        };
        if improved {
            best = Some((
                validation_loss.unwrap_or(last_train_loss),
                epoch,
                last_train_loss,
            ));
            best_snapshot = trainee.snapshot();
        }
        progress(&TrainProgress {
            stage: TrainStage::Model,
            epoch,
            epochs: config.epochs,
            train_loss: last_train_loss,
            validation_loss,
            best_validation_loss: validation_loss.and(best.map(|b| b.0)),
        });
        crate::slices::pause().await;
        if let (Some(_), Some((_, best_epoch, _))) = (validation_loss, best)
            && config.patience > 0
            && epoch - best_epoch >= config.patience
        {
            stopped_early = true;
            break;
        }
    }
    trainee.restore(best_snapshot);
    let (validation_loss, best_epoch, train_loss) = match best {
        Some((v, e, t)) => ((!validation.is_empty()).then_some(v), e, t),
        None => (None, 0, last_train_loss),
    };
    TrainingReport {
        config: *config,
        epochs_run: history.len(),
        best_epoch,
        train_loss,
        validation_loss,
        training_samples: train.len(),
        validation_samples: validation.len(),
        cancelled,
        stopped_early,
        history,
    }
}

/// Consecutive batches of an epoch, in the order given: the hot loop of training.
struct Batches<'a, const I: usize, M: Trainee<I>> {
    trainee: &'a mut M,
    train: &'a [M::Item],
    order: &'a [usize],
    weights: &'a [M::Real; 3],
    adam: &'a mut Adam<M::Real, I>,
    grad: &'a mut Mlp<M::Real, I>,
    batch_size: usize,
    cancel: &'a AtomicBool,
}

impl<const I: usize, M: Trainee<I>> Batches<'_, I, M> {
    /// Trains the batches in the widest SIMD available, adding their losses to `epoch_loss`;
    /// `false` when cancelled.
    fn run(&mut self, epoch_loss: &mut f64) -> bool {
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx2_fma_available() {
            #[allow(unsafe_code)]
            // SAFETY: `run_avx2` only requires AVX2 and FMA, and the CPU was just checked to have them.
            return unsafe { self.run_avx2(epoch_loss) };
        }
        self.run_portable::<Unfused>(epoch_loss)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn run_avx2(&mut self, epoch_loss: &mut f64) -> bool {
        self.run_portable::<Fused>(epoch_loss)
    }

    #[inline(always)]
    fn run_portable<A: MulAdd>(&mut self, epoch_loss: &mut f64) -> bool {
        for batch in self.order.chunks(self.batch_size) {
            if self.cancel.load(Ordering::Relaxed) {
                return false;
            }
            self.grad.fill_zero();
            let batch_loss =
                self.trainee
                    .accumulate_batch::<A>(self.train, batch, self.weights, self.grad);
            *epoch_loss += batch_loss.as_f64();
            self.grad.scale(M::Real::of(1.0 / batch.len() as f64));
            let (adam, grad) = (&mut *self.adam, &*self.grad);
            self.trainee
                .network_mut()
                .update(|params| adam.step(params, grad));
            self.trainee.after_batch(batch.len());
        }
        true
    }
}
