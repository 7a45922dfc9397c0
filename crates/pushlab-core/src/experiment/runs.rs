//! The runs an experiment is made of, below its tables: a trained model bound to a recording's
//! object, the physics-only model of it, the fixed pass, and each online recording's online run
//! ([`TrajectoryRun`]) — where it starts and what it goes on from. `evaluate` puts them together
//! into the paper's rows; the app, the CLI and the Python package run these same functions.

use std::sync::Arc;

use super::best_fit::BestFit;
use super::com_truth::ComTruth;
use super::data::UsedRecording;
use crate::geometry::OutlineError;
use crate::learn::{Nmse, OnlineConfig, OnlineRun, OnlineState, Posterior};
use crate::model::{
    CombinedModel, FrameLoss, Loss, LossScale, NoOutline, OnlineModel, OnlineParams,
    PhysicsOnlyModel, Sample, SharedOnlineModel, samples_from_trajectory,
};
use crate::recording::Recording;

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
pub(super) fn carried_from(
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
