//! The passes of an experiment, as the paper's tables report them: a trained model on the offline
//! data, and on each online recording with `θ_online` fixed at `θ_online(0)` ("Fixed") and learned
//! online from `θ_online(0)` ("Online"); the same for the physics-only model; and the mean loss per
//! label. `pushlab eval`, the suite and the app compute every number through these functions.

use std::sync::Arc;

use super::com_truth::{ComSummary, ComTruth};
use super::data::{Skipped, UsedRecording};
use crate::geometry::OutlineError;
use crate::labels::pipeline::{LabelMean, PerLabelMeans, key_of};
use crate::learn::{
    Loss, LossScale, Nmse, OnlineConfig, OnlineModel, OnlineState, OnlineStep, Posterior,
    learn_step,
};
use crate::model::{
    CombinedModel, OnlineParams, PhysicsOnlyModel, PureNnModel, Sample, samples_from_trajectory,
};
use crate::recording::Recording;

/// How to evaluate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EvalOptions {
    /// The online update rule (the paper: 5 steps at 0.005).
    pub online: OnlineConfig,
    /// With `Some(tolerance)`, also the physics-only model with this contact tolerance, metres.
    pub physics: Option<f64>,
}

/// The learner of a trained model on one recording: `θ_online(0)`, step sizes and predictions for
/// its object.
pub fn learner_for(
    model: &CombinedModel,
    used: &UsedRecording,
) -> Result<Arc<dyn OnlineModel + Send + Sync>, crate::model::LearnerError> {
    model.learner(used.geometry.as_ref().ok())
}

/// The physics-only model of a recording's object and pusher, its losses normalised by `loss_scale`.
pub fn physics_model(
    recording: &Recording,
    loss_scale: LossScale,
    contact_tolerance: f64,
) -> Result<PhysicsOnlyModel, OutlineError> {
    Ok(PhysicsOnlyModel::new(
        recording.setting.object.outline()?,
        recording.setting.pusher_radius,
        contact_tolerance,
        loss_scale,
    ))
}

/// The σ that normalise losses shown next to a model: its offline data's, or, with no trained model
/// (the app on physics alone), the recording's own motion at `horizon`, floored at a millimetre and a
/// milliradian so that an axis without motion does not divide by zero.
pub fn loss_scale_for(
    model: Option<&CombinedModel>,
    recording: &Recording,
    horizon: usize,
) -> LossScale {
    if let Some(model) = model {
        return model.loss_scale();
    }
    let samples = samples_from_trajectory(&recording.trajectory, horizon);
    let mut scale = LossScale::from_samples(&samples);
    for s in &mut scale.sigma_pos {
        *s = s.max(1e-3);
    }
    scale.sigma_rot = scale.sigma_rot.max(1e-3);
    scale
}

/// Every sample predicted and scored with `θ_online(0)`, never updated: the "Fixed" run.
pub fn fixed_pass(learner: &dyn OnlineModel, samples: &[Sample]) -> Vec<OnlineStep> {
    let theta0 = learner.theta0();
    samples
        .iter()
        .map(|s| learner.online_step(s, &theta0, &OnlineConfig::fixed()))
        .collect()
}

/// Online learning along one trajectory from `θ_online(0)` (Algorithm 1, with the configured
/// optimiser): the "Online" run, and the posterior of `θ_online` after its last frame.
pub fn online_pass(
    learner: &dyn OnlineModel,
    samples: &[Sample],
    config: &OnlineConfig,
) -> (Vec<OnlineStep>, Posterior) {
    let mut state = OnlineState::start(learner);
    let steps = samples
        .iter()
        .map(|s| {
            let (step, next) = learn_step(learner, s, &state, config);
            state = next;
            step
        })
        .collect();
    (steps, state.posterior)
}

/// One online recording's runs.
#[derive(Clone, Debug)]
pub struct TrajectoryRun {
    /// Index of the recording among the online recordings.
    pub recording: usize,
    /// The frame each sample starts at.
    pub frames: Vec<usize>,
    pub fixed: Vec<Loss>,
    pub online: Vec<Loss>,
    pub theta0: OnlineParams,
    /// `θ_online` after the last online step.
    pub theta_end: OnlineParams,
    /// Its posterior given every frame learned from (see `learn::uncertainty`).
    pub posterior_end: Posterior,
    /// The COM estimate against the recording's true COM, when it has one (simulated sets).
    pub com_truth: Option<ComTruth>,
}

/// The physics-only model's NMSE.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PhysicsNmse {
    pub offline: Nmse,
    pub fixed: Nmse,
    pub online: Nmse,
}

/// Mean total loss ℓ per label over the online data ("all" first).
#[derive(Clone, Debug, PartialEq)]
pub struct PerLabel {
    pub fixed: Vec<LabelMean>,
    pub online: Vec<LabelMean>,
}

/// Means of the offline per-sample losses, for figures.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OfflineMeans {
    pub total: f64,
    pub pos: f64,
    pub rot: f64,
}

/// What an experiment measured.
#[derive(Clone, Debug)]
pub struct Evaluation {
    /// The pure network on the offline data, when there is one.
    pub offline_nn: Option<Nmse>,
    /// The combined model on the offline data at `θ_online(0)`.
    pub offline: Nmse,
    pub offline_means: OfflineMeans,
    pub fixed: Nmse,
    pub online: Nmse,
    pub trajectories: Vec<TrajectoryRun>,
    pub physics: Option<PhysicsNmse>,
    /// When the online recordings carry range labels.
    pub per_label: Option<PerLabel>,
    /// Recordings a model could not be evaluated on (the contact-frame model without an outline).
    pub left_out: Vec<Skipped>,
    /// How well online learning found the COM, over the online pushes with a known COM.
    pub com_summary: Option<ComSummary>,
}

/// Evaluates a trained model (and the pure network, when given) on offline and online recordings.
/// Every loss is normalised by the model's offline σ, so that every row is comparable.
pub fn evaluate(
    model: &CombinedModel,
    pure_nn: Option<&PureNnModel>,
    offline: &[UsedRecording],
    online: &[UsedRecording],
    options: &EvalOptions,
) -> Evaluation {
    let horizon = model.horizon();
    let scale = model.loss_scale();
    let mut left_out = Vec::new();
    let mut learner = |u: &UsedRecording| match learner_for(model, u) {
        Ok(learner) => Some(learner),
        Err(e) => {
            left_out.push(Skipped {
                path: u.source(),
                reason: format!("{} model: {e}", model.kind()),
            });
            None
        }
    };

    let mut offline_losses = Vec::new();
    let mut offline_nn = Vec::new();
    for u in offline {
        let samples = u.samples(horizon);
        if let Some(learner) = learner(u) {
            offline_losses.extend(
                fixed_pass(learner.as_ref(), &samples)
                    .iter()
                    .map(|s| s.loss),
            );
        }
        if let Some(nn) = pure_nn {
            offline_nn.extend(
                samples
                    .iter()
                    .map(|s| Loss::of(&nn.predict(&s.input).motion, &s.target, &scale)),
            );
        }
    }

    let mut trajectories = Vec::new();
    for (index, u) in online.iter().enumerate() {
        let Some(learner) = learner(u) else {
            continue;
        };
        let samples = u.samples(horizon);
        let fixed = fixed_pass(learner.as_ref(), &samples);
        let (learned, posterior_end) = online_pass(learner.as_ref(), &samples, &options.online);
        trajectories.push(TrajectoryRun {
            recording: index,
            frames: samples.iter().map(|s| s.frame).collect(),
            fixed: fixed.iter().map(|s| s.loss).collect(),
            online: learned.iter().map(|s| s.loss).collect(),
            theta0: learner.theta0(),
            theta_end: learned.last().map_or(learner.theta0(), |s| s.theta_after),
            com_truth: u
                .recording
                .setting
                .com_offset
                .and_then(|truth| ComTruth::of(&learned, &posterior_end, truth)),
            posterior_end,
        });
    }

    let physics = options
        .physics
        .map(|tolerance| physics_nmse(offline, online, horizon, scale, tolerance, &options.online));
    let mean = |f: fn(&Loss) -> f64| {
        offline_losses.iter().map(f).sum::<f64>() / offline_losses.len().max(1) as f64
    };
    Evaluation {
        offline_nn: pure_nn.map(|_| Nmse::of(&offline_nn)),
        offline: Nmse::of(&offline_losses),
        offline_means: OfflineMeans {
            total: mean(Loss::total),
            pos: mean(Loss::pos),
            rot: mean(|l| l.rot),
        },
        fixed: Nmse::of(trajectories.iter().flat_map(|r| r.fixed.iter())),
        online: Nmse::of(trajectories.iter().flat_map(|r| r.online.iter())),
        per_label: per_label(online, &trajectories),
        com_summary: ComSummary::of(trajectories.iter().filter_map(|r| r.com_truth.as_ref())),
        trajectories,
        physics,
        left_out,
    }
}

/// The physics-only model on the offline data (fixed) and on each online recording, fixed and learning
/// online, one model per recording's own outline and pusher. Recordings with an unusable outline are
/// left out.
fn physics_nmse(
    offline: &[UsedRecording],
    online: &[UsedRecording],
    horizon: usize,
    scale: LossScale,
    tolerance: f64,
    config: &OnlineConfig,
) -> PhysicsNmse {
    let model = |u: &UsedRecording| physics_model(&u.recording, scale, tolerance).ok();
    let mut offline_losses = Vec::new();
    for u in offline {
        if let Some(m) = model(u) {
            offline_losses.extend(fixed_pass(&m, &u.samples(horizon)).iter().map(|s| s.loss));
        }
    }
    let (mut fixed, mut learned) = (Vec::new(), Vec::new());
    for u in online {
        if let Some(m) = model(u) {
            let samples = u.samples(horizon);
            fixed.extend(fixed_pass(&m, &samples).iter().map(|s| s.loss));
            learned.extend(online_pass(&m, &samples, config).0.iter().map(|s| s.loss));
        }
    }
    PhysicsNmse {
        offline: Nmse::of(&offline_losses),
        fixed: Nmse::of(&fixed),
        online: Nmse::of(&learned),
    }
}

/// Mean total loss per range label, when any online recording has labels.
fn per_label(online: &[UsedRecording], runs: &[TrajectoryRun]) -> Option<PerLabel> {
    if !online
        .iter()
        .any(|u| u.labels.as_ref().is_some_and(|l| !l.segments.is_empty()))
    {
        return None;
    }
    let mut fixed = PerLabelMeans::new();
    let mut learned = PerLabelMeans::new();
    for r in runs {
        let u = &online[r.recording];
        let key = key_of(&u.recording.source).unwrap_or_default();
        let labels = u.labels.as_ref();
        let totals = |l: &[Loss]| l.iter().map(Loss::total).collect::<Vec<_>>();
        // Lengths match by construction (one frame per loss), so adding cannot fail.
        let _ = fixed.add(&key, labels, &r.frames, &totals(&r.fixed));
        let _ = learned.add(&key, labels, &r.frames, &totals(&r.online));
    }
    let list = |m: &PerLabelMeans| std::iter::once(m.all()).chain(m.by_label()).collect();
    Some(PerLabel {
        fixed: list(&fixed),
        online: list(&learned),
    })
}
