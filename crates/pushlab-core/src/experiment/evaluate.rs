//! The passes of an experiment, as the paper's tables report them: a trained model on the offline
//! data, and on each online recording with `θ_online` fixed at `θ_online(0)` ("Fixed") and learned
//! online from `θ_online(0)` ("Online"); the same for the physics-only model; and the mean loss per
//! label. `pushlab eval`, the suite and the app compute every number through these functions, and
//! every online pass is the one [`OnlineRun`] the app plays.

use super::best_fit::{BestFit, ObjectBestFit};
use super::com_truth::{ComSummary, ComTruth};
use super::data::{Skipped, UsedRecording};
use super::runs::carried_from;
pub use super::runs::{
    TrajectoryRun, fixed_pass, loss_scale_for, model_on, online_run, physics_model, start_state,
};
use crate::labels::pipeline::{LabelMean, PerLabelMeans, key_of};
use crate::learn::{ModelWeight, Nmse, OnlineConfig, WeightConfig, Weights};
use crate::model::{CombinedModel, FrameLoss, Loss, LossScale, OnlineParams, PureNnModel};

/// How to evaluate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EvalOptions {
    /// The online update rule (the paper: 5 steps at 0.005).
    pub online: OnlineConfig,
    /// With `Some(tolerance)`, also the physics-only model with this contact tolerance, metres.
    pub physics: Option<f64>,
    /// Each online recording goes on from where the one before it ended when both push the same
    /// object ([`UsedRecording::same_object_as`]): θ and the posterior carried from push to push, as
    /// a robot pushing one object again would. Without it, every push starts from `θ_online(0)` (the
    /// paper's protocol).
    pub carry: bool,
    /// Every push that does not go on from another starts believing the COM this far (object
    /// frame, metres) from `θ_online(0)`'s, the prior centred there
    /// ([`OnlineState::start_with_com_shift`]); `None`: from `θ_online(0)`. The fixed run still
    /// predicts with `θ_online(0)`.
    pub start_com_shift: Option<[f64; 2]>,
    /// With the physics-only model: how its online run and the combined model's are weighed into
    /// the "weighted" prediction (`learn::ModelWeight`).
    pub weighting: WeightConfig,
}

/// The physics-only model's NMSE.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PhysicsNmse {
    /// `None` without offline recordings (a loaded model evaluated on new pushes alone).
    pub offline: Option<Nmse>,
    pub fixed: Nmse,
    pub online: Nmse,
    /// The combined model and this one weighed online, over the pushes both ran on.
    pub weighted: Option<Nmse>,
}

/// Mean total loss ℓ per label over the online data ("all" first).
#[derive(Clone, Debug, PartialEq)]
pub struct PerLabel {
    pub fixed: Vec<LabelMean>,
    pub online: Vec<LabelMean>,
}

/// Where the physics-only model's online run on one recording left θ: its COM beside the combined
/// model's on the same push, to tell what the network adds to finding the COM from what Lynch's
/// model alone finds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhysicsPush {
    /// Index of the recording among the online recordings.
    pub recording: usize,
    /// NMSE of this push, the physics-only model at `θ_online(0)` and learning online: where the
    /// combined model loses to Lynch's model alone, push by push.
    pub fixed: Nmse,
    pub online: Nmse,
    /// The combined model and this one weighed online (`learn::ModelWeight`), over the frames both
    /// learned from; `None` where the combined model could not run.
    pub weighted: Option<Nmse>,
    /// The combined model's weights after the last frame.
    pub weight_end: Option<Weights>,
    /// `θ_online` after the last frame.
    pub theta_end: OnlineParams,
    /// The final posterior's COM offset covariance (m², object frame).
    pub com_covariance: [[f64; 2]; 2],
    /// With a known COM: the final error, whether the 95 % ellipse holds it, frames to settle.
    pub com_truth: Option<ComTruth>,
    /// The `θ_online` that fits the whole push best, once [`Evaluation::find_best_fits`] ran.
    pub best_fit: Option<BestFit>,
}

/// Means of the offline per-sample losses, for figures.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OfflineMeans {
    pub total: f64,
    pub pos: f64,
    pub rot: f64,
}

/// What an experiment measured.
///
/// The offline rows are `None` when no offline recordings were given: a model loaded from a file
/// is evaluated on new pushes without the data it was trained on, and a row of zeros would read as
/// a perfect fit.
#[derive(Clone, Debug)]
pub struct Evaluation {
    /// The pure network on the offline data, when there is one and offline data.
    pub offline_nn: Option<Nmse>,
    /// The combined model on the offline data at `θ_online(0)`, when there is offline data.
    pub offline: Option<Nmse>,
    pub offline_means: Option<OfflineMeans>,
    /// The pure network on the online data, when there is one: over the same frames as `fixed`
    /// and `online`, what the combined model's physics and online learning add to the network alone
    /// on new pushes.
    pub online_nn: Option<Nmse>,
    pub fixed: Nmse,
    pub online: Nmse,
    pub trajectories: Vec<TrajectoryRun>,
    pub physics: Option<PhysicsNmse>,
    /// The physics-only model's online runs, when evaluated: one per online recording it could run.
    pub physics_pushes: Vec<PhysicsPush>,
    /// How well the physics-only model found the COM, over the same pushes with a known COM.
    pub physics_com_summary: Option<ComSummary>,
    /// When the online recordings carry range labels.
    pub per_label: Option<PerLabel>,
    /// Recordings a model could not be evaluated on (the contact-frame model without an outline).
    pub left_out: Vec<Skipped>,
    /// How well online learning found the COM, over the online pushes with a known COM.
    pub com_summary: Option<ComSummary>,
    /// With θ carried from push to push, the best θ over all the pushes of each object at once,
    /// once [`Evaluation::find_best_fits`] ran.
    pub object_best_fits: Vec<ObjectBestFit>,
}

/// Evaluates a trained model (and the pure network, when given) on offline and online recordings.
/// Every loss is normalised by the model's offline σ (kept in the model), so that every row is
/// comparable. `offline` may be empty: the offline rows are then `None` and every other row is the
/// same, to the bit, as with it (nothing online depends on the offline recordings).
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
    let mut learner = |u: &UsedRecording| match model_on(model, u) {
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
            offline_losses.extend(fixed_pass(learner.as_ref(), &samples));
        }
        if let Some(nn) = pure_nn {
            offline_nn.extend(
                samples
                    .iter()
                    .map(|s| Loss::of(&nn.predict(&s.input).motion, &s.target, &scale)),
            );
        }
    }

    let mut trajectories: Vec<TrajectoryRun> = Vec::new();
    for (index, u) in online.iter().enumerate() {
        let carried = carried_from(options.carry, online, index, trajectories.last());
        let run = TrajectoryRun::learn_from(
            model,
            u,
            index,
            &options.online,
            carried.as_ref(),
            options.start_com_shift,
        );
        match run {
            Ok(run) => trajectories.push(run),
            Err(e) => left_out.push(Skipped {
                path: u.source(),
                reason: format!("{} model: {e}", model.kind()),
            }),
        }
    }

    let (physics, physics_pushes) = match options.physics {
        Some(tolerance) => {
            let (nmse, pushes) = physics_nmse(
                (offline, online),
                &trajectories,
                horizon,
                scale,
                tolerance,
                options,
            );
            (Some(nmse), pushes)
        }
        None => (None, Vec::new()),
    };
    let mean = |f: fn(&Loss) -> f64| {
        offline_losses.iter().map(f).sum::<f64>() / offline_losses.len().max(1) as f64
    };
    let has_offline = !offline.is_empty();
    Evaluation {
        offline_nn: pure_nn
            .filter(|_| has_offline)
            .map(|_| Nmse::of(&offline_nn)),
        offline: has_offline.then(|| Nmse::of(&offline_losses)),
        offline_means: has_offline.then(|| OfflineMeans {
            total: mean(Loss::total),
            pos: mean(Loss::pos),
            rot: mean(|l| l.rot),
        }),
        online_nn: pure_nn.map(|nn| pure_nn_online(nn, &trajectories, scale)),
        fixed: Nmse::of_frames(trajectories.iter().flat_map(TrajectoryRun::fixed)),
        online: Nmse::of_frames(trajectories.iter().flat_map(TrajectoryRun::online)),
        per_label: per_label(online, &trajectories),
        com_summary: ComSummary::of(trajectories.iter().filter_map(|r| r.com_truth.as_ref())),
        trajectories,
        physics,
        physics_com_summary: ComSummary::of(
            physics_pushes.iter().filter_map(|p| p.com_truth.as_ref()),
        ),
        physics_pushes,
        left_out,
        object_best_fits: Vec::new(),
    }
}

/// The pure network's NMSE on the online recordings, over the frames each trajectory's online run
/// learned from (the frames of the "Fixed" and "Online" rows).
fn pure_nn_online(nn: &PureNnModel, runs: &[TrajectoryRun], scale: LossScale) -> Nmse {
    let losses: Vec<Loss> = (runs.iter())
        .flat_map(|r| r.frames().filter_map(|frame| r.run.sample(frame)))
        .map(|s| Loss::of(&nn.predict(&s.input).motion, &s.target, &scale))
        .collect();
    Nmse::of(&losses)
}

/// The physics-only model on the offline data (fixed) and on each online recording, fixed and learning
/// online, one model per recording's own outline and pusher, with where each online push's θ ended.
/// Recordings with an unusable outline are left out.
fn physics_nmse(
    (offline, online): (&[UsedRecording], &[UsedRecording]),
    combined: &[TrajectoryRun],
    horizon: usize,
    scale: LossScale,
    tolerance: f64,
    options: &EvalOptions,
) -> (PhysicsNmse, Vec<PhysicsPush>) {
    let model = |u: &UsedRecording| physics_model(&u.recording, scale, tolerance).ok();
    let mut offline_losses = Vec::new();
    for u in offline {
        if let Some(m) = model(u) {
            offline_losses.extend(fixed_pass(&m, &u.samples(horizon)));
        }
    }
    let (mut fixed, mut learned, mut pushes) = (Vec::new(), Vec::new(), Vec::new());
    let mut weighted = Vec::new();
    let mut previous: Option<TrajectoryRun> = None;
    let mut previous_weight: Option<ModelWeight> = None;
    for (index, u) in online.iter().enumerate() {
        if let Some(m) = model(u) {
            let carried = carried_from(options.carry, online, index, previous.as_ref());
            let run = TrajectoryRun::learn_physics(
                m,
                u,
                index,
                horizon,
                &options.online,
                carried.as_ref(),
                options.start_com_shift,
            );
            fixed.extend(run.fixed());
            learned.extend(run.online());
            // The weight goes on from the push before when θ does.
            let paired = combined.iter().find(|c| c.recording == index);
            let weight = paired.map(|c| {
                let mut weight = match (&carried, &previous_weight) {
                    (Some(_), Some(before)) => ModelWeight::continuing(before),
                    _ => ModelWeight::new(options.weighting),
                };
                c.run.weigh_against(&run.run, &mut weight);
                weight
            });
            let push_weighted = weight.as_ref().map(|w| {
                let losses: Vec<FrameLoss> = w.frames().iter().map(|f| f.loss).collect();
                weighted.extend(losses.iter().copied());
                Nmse::of_frames(losses)
            });
            pushes.push(PhysicsPush {
                recording: index,
                fixed: run.fixed_nmse(),
                online: run.online_nmse(),
                weighted: push_weighted,
                weight_end: weight.as_ref().map(ModelWeight::weight),
                theta_end: run.theta_end(),
                com_covariance: run.posterior_end().com_covariance(),
                com_truth: run.com_truth,
                best_fit: None,
            });
            previous = Some(run);
            previous_weight = weight;
        }
    }
    let nmse = PhysicsNmse {
        offline: (!offline.is_empty()).then(|| Nmse::of(&offline_losses)),
        fixed: Nmse::of_frames(fixed),
        online: Nmse::of_frames(learned),
        weighted: (!weighted.is_empty()).then(|| Nmse::of_frames(weighted)),
    };
    (nmse, pushes)
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
        let frames: Vec<usize> = r.frames().collect();
        let totals =
            |l: &mut dyn Iterator<Item = FrameLoss>| l.map(|l| l.total()).collect::<Vec<_>>();
        // Lengths match by construction (one frame per loss), so adding cannot fail.
        let _ = fixed.add(&key, labels, &frames, &totals(&mut r.fixed()));
        let _ = learned.add(&key, labels, &frames, &totals(&mut r.online()));
    }
    let list = |m: &PerLabelMeans| std::iter::once(m.all()).chain(m.by_label()).collect();
    Some(PerLabel {
        fixed: list(&fixed),
        online: list(&learned),
    })
}
