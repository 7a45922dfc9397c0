//! Offline training of any model kind on the recordings an experiment uses: which samples, which
//! `θ_online(0)`, which objects. `pushlab train`, `pushlab eval`, the suite and the app's Train tab
//! all train through [`train_combined`].

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use super::data::UsedRecording;
use super::variant::{symmetries, transformed};
use crate::domain::Domain;
use crate::learn::{
    ContactTrajectory, TrainConfig, TrainError, TrainProgress, Trained, paper_theta0,
    train_contact_in_slices, train_paper_in_slices, train_pure_nn_in_slices, training_trajectories,
};
use crate::model::{CombinedModel, LossScale, ModelKind, OnlineParams, PureNnModel, Sample};
use crate::model_file::TrainingMetadata;

/// Where a model trained on these recordings at `horizon` comes from — their sources, the pushlab
/// version and the [`Domain`] they span — for its model file; the caller adds the training reports.
pub fn training_metadata(used: &[UsedRecording], horizon: usize) -> TrainingMetadata {
    TrainingMetadata {
        report: None,
        pure_nn_report: None,
        sources: used.iter().map(UsedRecording::source).collect(),
        pushlab_version: env!("CARGO_PKG_VERSION").to_owned(),
        domain: Domain::of(used.iter().map(|u| &u.recording), horizon),
    }
}

/// The paper model's `θ_online(0)` for training on these recordings (see [`paper_theta0`]): from
/// their object's outline when they all share one, else `None` (the generic guess).
pub fn paper_theta0_for(used: &[UsedRecording]) -> Option<OnlineParams> {
    let outlines: Vec<Option<crate::geometry::Outline>> = used
        .iter()
        .map(|u| u.recording.setting.object.outline().ok())
        .collect();
    paper_theta0(outlines.iter().map(Option::as_ref))
}

/// Trains a combined model of `kind` on the recordings' samples at `config.horizon`, leaving out
/// samples that touch frames labelled bad tracking. The paper model's `θ_online(0)` is
/// `config.theta0`, else [`paper_theta0_for`]; the contact-frame model trains each recording on its
/// own object and needs its outline (recordings without a usable one are left out).
pub fn train_combined(
    kind: ModelKind,
    used: &[UsedRecording],
    config: &TrainConfig,
    progress: &mut dyn FnMut(&TrainProgress),
    cancel: &AtomicBool,
) -> Result<Trained<CombinedModel>, TrainError> {
    crate::slices::finish(train_combined_in_slices(
        kind, used, config, progress, cancel,
    ))
}

/// [`train_combined`] in slices (`crate::slices`): what a browser tab polls a slice of each frame.
pub async fn train_combined_in_slices(
    kind: ModelKind,
    used: &[UsedRecording],
    config: &TrainConfig,
    progress: &mut dyn FnMut(&TrainProgress),
    cancel: &AtomicBool,
) -> Result<Trained<CombinedModel>, TrainError> {
    let mut samples: Vec<Vec<Sample>> = used.iter().map(|u| u.samples(config.horizon)).collect();
    match kind {
        ModelKind::Paper => {
            let mut config = *config;
            if config.augment_symmetries {
                // The losses stay normalised by the recorded motions, not by their images': the σ of
                // the same training trajectories the unaugmented model would take them from.
                let kept = training_trajectories(&samples, &config);
                config.loss_scale = Some(LossScale::from_samples(
                    kept.iter().flat_map(|&i| samples[i].iter()),
                ));
                // Each push with its images as one trajectory, so that the validation split keeps
                // them together.
                for (u, trajectory) in used.iter().zip(&mut samples) {
                    if let Ok(outline) = u.recording.setting.object.outline() {
                        let images: Vec<Sample> = symmetries(&outline)
                            .iter()
                            .skip(1)
                            .flat_map(|t| trajectory.iter().map(move |s| transformed(s, t)))
                            .collect();
                        trajectory.extend(images);
                    }
                }
            }
            let config = TrainConfig {
                theta0: config.theta0.or_else(|| paper_theta0_for(used)),
                ..config
            };
            let trained = train_paper_in_slices(&samples, &config, progress, cancel).await?;
            Ok(Trained {
                model: CombinedModel::Paper(Arc::new(trained.model)),
                report: trained.report,
            })
        }
        ModelKind::Contact => {
            let trajectories: Vec<ContactTrajectory> = used
                .iter()
                .zip(&samples)
                .filter_map(|(u, samples)| {
                    Some(ContactTrajectory {
                        geometry: u.geometry.as_ref().ok()?,
                        samples,
                    })
                })
                .collect();
            if trajectories.is_empty() && !used.is_empty() {
                return Err(TrainError::NoOutline);
            }
            let trained = train_contact_in_slices(&trajectories, config, progress, cancel).await?;
            Ok(Trained {
                model: CombinedModel::Contact(Arc::new(trained.model)),
                report: trained.report,
            })
        }
    }
}

/// Trains the pure-network baseline on the recordings' samples.
pub fn train_baseline(
    used: &[UsedRecording],
    config: &TrainConfig,
    progress: &mut dyn FnMut(&TrainProgress),
    cancel: &AtomicBool,
) -> Result<Trained<PureNnModel>, TrainError> {
    crate::slices::finish(train_baseline_in_slices(used, config, progress, cancel))
}

/// [`train_baseline`] in slices (`crate::slices`): what a browser tab polls a slice of each frame.
pub async fn train_baseline_in_slices(
    used: &[UsedRecording],
    config: &TrainConfig,
    progress: &mut dyn FnMut(&TrainProgress),
    cancel: &AtomicBool,
) -> Result<Trained<PureNnModel>, TrainError> {
    let samples: Vec<Vec<Sample>> = used.iter().map(|u| u.samples(config.horizon)).collect();
    train_pure_nn_in_slices(&samples, config, progress, cancel).await
}
