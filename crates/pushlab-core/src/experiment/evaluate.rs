//! The passes of an experiment, as the paper's tables report them: a trained model on the offline
//! data, and on each online recording with `θ_online` fixed at `θ_online(0)` ("Fixed") and learned
//! online from `θ_online(0)` ("Online"); the same for the physics-only model; and the mean loss per
//! label. `pushlab eval`, the suite and the app compute every number through these functions, and
//! every online pass is the one [`OnlineRun`] the app plays.

use std::sync::Arc;

use super::best_fit::{BestFit, ObjectBestFit};
use super::com_truth::{ComSummary, ComTruth};
use super::data::{Skipped, UsedRecording};
use crate::geometry::OutlineError;
use crate::labels::pipeline::{LabelMean, PerLabelMeans, key_of};
use crate::learn::{
    ModelWeight, Nmse, OnlineConfig, OnlineRun, OnlineState, Posterior, WeightConfig, Weights,
};
use crate::model::{
    CombinedModel, FrameLoss, Loss, LossScale, NoOutline, OnlineModel, OnlineParams,
    PhysicsOnlyModel, PureNnModel, Sample, SharedOnlineModel, samples_from_trajectory,
};
use crate::recording::Recording;

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

/// A trained model bound to one recording's object: `θ_online(0)`, step sizes and predictions for
/// its object.
pub fn model_on(
    model: &CombinedModel,
    used: &UsedRecording,
) -> Result<SharedOnlineModel, NoOutline> {
    model.on_object(used.geometry.as_ref().ok())
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

/// Every sample predicted and scored with `θ_online(0)`, never updated: the "Fixed" run's losses
/// (`OnlineModel::loss_at`: no gradient, which no caller read).
pub fn fixed_pass(learner: &dyn OnlineModel, samples: &[Sample]) -> Vec<Loss> {
    let theta0 = learner.theta0();
    samples
        .iter()
        .map(|s| learner.loss_at(s, &theta0))
        .collect()
}

/// Online learning along a recording from `θ_online(0)`, or from where an earlier push of the same
/// object ended (`from`), with the configured optimiser (Algorithm 1) on samples `horizon` frames
/// long, holding θ over samples on frames labelled bad tracking: the "Online" run.
pub fn online_run(
    model: SharedOnlineModel,
    used: &UsedRecording,
    horizon: usize,
    config: &OnlineConfig,
    from: Option<&OnlineState>,
) -> OnlineRun {
    let trajectory = Arc::clone(&used.recording.trajectory);
    let mut run = match from {
        Some(from) => OnlineRun::continuing(model, trajectory, horizon, *config, from),
        None => OnlineRun::new(model, trajectory, horizon, *config),
    };
    run.learn_all(&used.skip);
    run
}

/// One online recording's runs.
#[derive(Clone, Debug)]
pub struct TrajectoryRun {
    /// Index of the recording among the online recordings.
    pub recording: usize,
    /// The online run over every frame: θ, the online and fixed losses and the spread per frame.
    pub run: OnlineRun,
    /// The COM estimate against the recording's true COM, when it has one (simulated sets).
    pub com_truth: Option<ComTruth>,
    /// Whether the run went on from the push before it (`EvalOptions::carry`) rather than from
    /// `θ_online(0)`.
    pub continued: bool,
    /// The `θ_online` that fits the whole push best, once [`Evaluation::find_best_fits`] ran.
    pub best_fit: Option<BestFit>,
}

impl TrajectoryRun {
    /// The "Online" run of a trained model on one recording (the `index`-th online recording):
    /// online learning from the model's `θ_online(0)` for the recording's object, at the model's
    /// horizon, holding θ over frames labelled bad tracking; with the COM found against the truth
    /// when the setting knows it. `pushlab eval`, the suite and the Python package's `model.online`
    /// all run this, so their numbers agree to the bit.
    pub fn learn(
        model: &CombinedModel,
        used: &UsedRecording,
        index: usize,
        config: &OnlineConfig,
    ) -> Result<Self, NoOutline> {
        Self::learn_from(model, used, index, config, None, None)
    }

    /// [`TrajectoryRun::learn`] going on from where an earlier push of the same object ended
    /// (`from`, see [`OnlineRun::continuing`]), or else from `θ_online(0)` with its COM moved by
    /// `start_com_shift` (see [`EvalOptions::start_com_shift`]), or else from `θ_online(0)`.
    pub fn learn_from(
        model: &CombinedModel,
        used: &UsedRecording,
        index: usize,
        config: &OnlineConfig,
        from: Option<&OnlineState>,
        start_com_shift: Option<[f64; 2]>,
    ) -> Result<Self, NoOutline> {
        let learner = model_on(model, used)?;
        let horizon = model.horizon();
        Ok(Self::learn_with(
            learner,
            used,
            index,
            horizon,
            config,
            from,
            start_com_shift,
        ))
    }

    /// The physics-only model's online run on one recording (the `index`-th online recording),
    /// `physics` being [`physics_model`] of its object, at `horizon`: the "Physics online" pass of
    /// `pushlab eval --physics`, starting as [`TrajectoryRun::learn_from`] does, with the COM found
    /// against the truth when the setting knows it. The Python package's `model.physics_online`
    /// runs this too.
    pub fn learn_physics(
        physics: PhysicsOnlyModel,
        used: &UsedRecording,
        index: usize,
        horizon: usize,
        config: &OnlineConfig,
        from: Option<&OnlineState>,
        start_com_shift: Option<[f64; 2]>,
    ) -> Self {
        let physics = Arc::new(physics);
        Self::learn_with(physics, used, index, horizon, config, from, start_com_shift)
    }

    /// Either model's online run, starting as [`start_state`] says, with the COM found against the
    /// truth when the setting knows it.
    fn learn_with(
        learner: SharedOnlineModel,
        used: &UsedRecording,
        index: usize,
        horizon: usize,
        config: &OnlineConfig,
        from: Option<&OnlineState>,
        start_com_shift: Option<[f64; 2]>,
    ) -> Self {
        let start = start_state(learner.as_ref(), config, from, start_com_shift);
        let run = online_run(learner, used, horizon, config, start.as_ref());
        Self {
            recording: index,
            com_truth: (used.recording.setting.com_offset)
                .and_then(|truth| ComTruth::of_run(&run, truth)),
            run,
            continued: from.is_some(),
            best_fit: None,
        }
    }

    /// NMSE of the online losses over the frames learned from: a trajectory's "Online" figure.
    pub fn online_nmse(&self) -> Nmse {
        Nmse::of_frames(self.online())
    }

    /// NMSE of the fixed model over the same frames: a trajectory's "Fixed" figure.
    pub fn fixed_nmse(&self) -> Nmse {
        Nmse::of_frames(self.fixed())
    }

    /// The frames learned from, in order: every sample's but those on frames labelled bad tracking.
    pub fn frames(&self) -> impl Iterator<Item = usize> + '_ {
        self.run.learned_steps().map(|(frame, _, _)| frame)
    }

    /// The fixed model's losses at the frames learned from.
    pub fn fixed(&self) -> impl Iterator<Item = FrameLoss> + '_ {
        self.frames().map(|frame| self.run.fixed()[frame])
    }

    /// The online losses at the frames learned from.
    pub fn online(&self) -> impl Iterator<Item = FrameLoss> + '_ {
        self.run.learned_steps().map(|(_, loss, _)| loss)
    }

    /// Samples learned from.
    pub fn steps(&self) -> usize {
        self.run.learned_steps().count()
    }

    /// `θ_online(0)` of this recording.
    pub fn theta0(&self) -> OnlineParams {
        self.run.theta0()
    }

    /// `θ_online` after the last online step.
    pub fn theta_end(&self) -> OnlineParams {
        self.run.theta_at(self.run.frontier())
    }

    /// Its posterior given every frame learned from (see `learn::uncertainty`).
    pub fn posterior_end(&self) -> &Posterior {
        self.run.posterior()
    }
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

/// Where a run starts: from `from` (a push carried on), else believing the COM `shift` from
/// `θ_online(0)`'s, else (`None`) from `θ_online(0)`.
pub fn start_state(
    learner: &dyn OnlineModel,
    config: &OnlineConfig,
    from: Option<&OnlineState>,
    shift: Option<[f64; 2]>,
) -> Option<OnlineState> {
    match (from, shift) {
        (Some(from), _) => Some(*from),
        (None, Some(shift)) => Some(OnlineState::start_with_com_shift(
            learner,
            config.optimizer,
            shift,
        )),
        (None, None) => None,
    }
}

/// Where the online recording `index` starts when pushes are carried: the end of the run just before
/// it, when that run is of the recording just before it and both push the same object. A recording
/// left out (no outline) breaks the chain.
fn carried_from(
    carry: bool,
    online: &[UsedRecording],
    index: usize,
    previous: Option<&TrajectoryRun>,
) -> Option<OnlineState> {
    let previous = previous.filter(|_| carry)?;
    (index > 0
        && previous.recording == index - 1
        && online[index].same_object_as(&online[index - 1]))
    .then(|| previous.run.end_state())
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
