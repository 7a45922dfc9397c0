//! One online-learning run along a recording (Algorithm 1), frame by frame, that can rewind to any
//! frame and replay identically: the one implementation behind `pushlab eval`, `pushlab suite` and the
//! app.
//!
//! Each step is [`learn_step`], a pure function of (sample, state, rule); the run only decides *which*
//! frames are learned from and remembers what it needs to go back:
//!
//! - `θ_online` at every frame exactly (`checkpoints[k]` is θ in effect at frame `k` for
//!   `k <= frontier`), so that scrubbing back restores `θ_online(t)` bit for bit;
//! - what happened between frame `k` and `k + 1` (`learned[k]`: the online loss, or `None` where θ
//!   was held — a frame jumped over, or one whose sample touches a frame labelled "skip in training",
//!   such as bad tracking);
//! - the fixed model's loss at every sample, and the posterior's spread at every frame.
//!
//! That is 80 bytes a frame. The posterior itself ([`Posterior`], a few hundred bytes) is kept at the
//! frontier and every [`KEYFRAME`] frames; going back to a frame replays at most that many frames'
//! linearisations from the keyframe before it. Samples are made from the shared trajectory when
//! needed. Steering θ at frame `f` (a slider, "Learn this frame", a new rule, reset) drops everything
//! after `f`: the future is learned again from there, and [`OnlineRun::take_cut`] tells a view that
//! keeps derived series (plots) from which frame to redraw.

mod beside;

use std::sync::Arc;

use super::config::OnlineConfig;
use super::step::{OnlineState, com_misfit_m, learn_step_on};
use super::uncertainty::{Posterior, Spread};
use super::weighting::ModelWeight;
use crate::model::{
    FrameLoss, OnlineParams, OnlineStep, Sample, SharedOnlineModel, sample_at, sample_count,
    sample_is_skipped,
};
use crate::parallel;
use crate::trajectory::{Frame, Trajectory};

/// Frames between kept posteriors: the most a rewind replays.
pub const KEYFRAME: usize = 64;

/// The fewest samples of the fixed run a thread scores (about 1 ms of predictions): a recording of
/// fewer than twice this is scored on one core.
const FIXED_PER_WORKER: usize = 8192;

/// Mean losses over the frames learned so far, online and fixed on the same frames.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeanLosses {
    /// Frames learned from.
    pub frames: usize,
    pub online_pos: f64,
    pub online_rot: f64,
    pub fixed_pos: f64,
    pub fixed_rot: f64,
}

/// Online learning along one trajectory (see the module documentation).
#[derive(Clone)]
pub struct OnlineRun {
    model: SharedOnlineModel,
    trajectory: Arc<Trajectory>,
    /// Frames between a sample's start and its target.
    horizon: usize,
    /// The update rule for the steps learned from now on.
    config: OnlineConfig,
    /// The "fixed" run: every sample predicted with `θ_online(0)`, never updated.
    fixed: Vec<FrameLoss>,
    checkpoints: Vec<OnlineParams>,
    learned: Vec<Option<FrameLoss>>,
    /// The posterior's spread at each checkpoint.
    spreads: Vec<Spread>,
    /// The posterior at frames `0, KEYFRAME, 2·KEYFRAME, …` up to the frontier (before steering at
    /// that frame is applied).
    keyframes: Vec<Posterior>,
    /// The posterior at the frontier.
    posterior: Posterior,
    /// Where the run starts and [`OnlineRun::reset`] returns: `θ_online(0)` and the prior, or what an
    /// earlier push of the same object ended with ([`OnlineRun::continuing`]).
    start: OnlineState,
    /// Sums over the learned frames, for [`OnlineRun::mean_losses`].
    totals: MeanLosses,
    /// The earliest frame whose results were dropped since [`OnlineRun::take_cut`] was last called.
    cut: Option<usize>,
    /// The physics-only model learning beside this run and the weight between them, when asked
    /// for ([`OnlineRun::with_physics_beside`]).
    beside: Option<Box<Beside>>,
}

/// What is kept beside a run: the physics-only model's own run and the weight between the two
/// (see `beside`).
#[derive(Clone)]
struct Beside {
    physics: OnlineRun,
    weight: ModelWeight,
}

impl std::fmt::Debug for OnlineRun {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OnlineRun")
            .field("frames", &self.trajectory.len())
            .field("horizon", &self.horizon)
            .field("config", &self.config)
            .field("frontier", &self.frontier())
            .field("theta", &self.theta_at(self.frontier()))
            .finish_non_exhaustive()
    }
}

impl OnlineRun {
    /// A run at frame 0 with θ = `θ_online(0)` of the model and its prior; the fixed run is computed
    /// up front.
    pub fn new(
        model: SharedOnlineModel,
        trajectory: Arc<Trajectory>,
        horizon: usize,
        config: OnlineConfig,
    ) -> Self {
        let start = OnlineState::start(model.as_ref(), config.optimizer);
        Self::starting_at(model, trajectory, horizon, config, start)
    }

    /// A run that goes on from where a run on an earlier push of the same object ended
    /// ([`OnlineRun::end_state`]): its θ (kept physical on this object) and its posterior, with
    /// every frame it took in. A push on one face leaves the COM's depth along that face's normal
    /// barely seen; the next push, on another face, sees it. The fixed run still predicts with
    /// `θ_online(0)`, so "Online" against "Fixed" measures everything learned so far.
    pub fn continuing(
        model: SharedOnlineModel,
        trajectory: Arc<Trajectory>,
        horizon: usize,
        config: OnlineConfig,
        from: &OnlineState,
    ) -> Self {
        let theta = model.keep_physical(from.theta);
        let misfit = com_misfit_m(model.as_ref(), config.optimizer);
        let start = OnlineState::at(theta, from.posterior.with_com_misfit(misfit));
        Self::starting_at(model, trajectory, horizon, config, start)
    }

    fn starting_at(
        model: SharedOnlineModel,
        trajectory: Arc<Trajectory>,
        horizon: usize,
        config: OnlineConfig,
        start: OnlineState,
    ) -> Self {
        let horizon = horizon.max(1);
        let theta0 = model.theta0();
        // Every sample is scored on its own: a long recording's are shared between the cores.
        let fixed =
            parallel::ordered_map(sample_count(&trajectory, horizon), FIXED_PER_WORKER, |k| {
                sample_at(&trajectory, k, horizon)
                    .map(|s| FrameLoss::of(&model.loss_at(&s, &theta0)))
            })
            .into_iter()
            .flatten()
            .collect();
        Self {
            checkpoints: vec![start.theta],
            spreads: vec![Spread::of(&start.posterior)],
            keyframes: vec![start.posterior],
            posterior: start.posterior,
            start,
            model,
            trajectory,
            horizon,
            config,
            fixed,
            learned: Vec::new(),
            totals: MeanLosses::default(),
            cut: None,
            beside: None,
        }
    }

    /// Frames that arrived after the run started (a live session): appended to the trajectory, the
    /// fixed run scored on the samples they complete. Learning goes on from the frontier as before
    /// ([`OnlineRun::learn_through`]); nothing learned is touched, so a run grown frame by frame and
    /// one made on the whole trajectory at once hold the same bits. The trajectory is copied only if
    /// someone else holds it.
    pub fn extend(&mut self, frames: impl IntoIterator<Item = Frame>) {
        self.beside_release();
        Arc::make_mut(&mut self.trajectory).frames.extend(frames);
        self.score_new_samples();
        self.beside_extended();
    }

    /// Scores the fixed run on the samples the trajectory completed since it was last scored.
    fn score_new_samples(&mut self) {
        let theta0 = self.model.theta0();
        for k in self.fixed.len()..sample_count(&self.trajectory, self.horizon) {
            if let Some(sample) = sample_at(&self.trajectory, k, self.horizon) {
                self.fixed
                    .push(FrameLoss::of(&self.model.loss_at(&sample, &theta0)));
            }
        }
    }

    /// The model learned with.
    pub fn model(&self) -> &SharedOnlineModel {
        &self.model
    }

    /// The trajectory learned along.
    pub fn trajectory(&self) -> &Trajectory {
        &self.trajectory
    }

    /// The same, shared: what a recording growing with the run (a live push) holds.
    pub fn shared_trajectory(&self) -> &Arc<Trajectory> {
        &self.trajectory
    }

    /// `θ_online(0)`.
    pub fn theta0(&self) -> OnlineParams {
        self.model.theta0()
    }

    /// The model's COM misfit on this object for the run's optimiser, metres: what every COM spread
    /// of the run includes (see `model::ComMisfit`); 0 for a model whose training measured none.
    pub fn com_misfit_m(&self) -> f64 {
        com_misfit_m(self.model.as_ref(), self.config.optimizer)
    }

    /// θ and the posterior the run started from (frame 0): `θ_online(0)` and the prior, or what it
    /// went on from. [`OnlineRun::continuing`] from it starts the same run again — how the app's
    /// video export renders a push that carried θ on.
    pub fn start_state(&self) -> &OnlineState {
        &self.start
    }

    /// θ and the posterior at the frontier: what [`OnlineRun::continuing`] goes on from.
    pub fn end_state(&self) -> OnlineState {
        self.state(self.frontier())
    }

    /// Frames between a sample's start and its target.
    pub fn horizon(&self) -> usize {
        self.horizon
    }

    /// The update rule of the steps learned from now on.
    pub fn config(&self) -> OnlineConfig {
        self.config
    }

    /// Number of samples: one per frame but the last `horizon`.
    pub fn sample_count(&self) -> usize {
        self.fixed.len()
    }

    /// The sample that predicts from `frame`, if the frame is not within the horizon of the end.
    pub fn sample(&self, frame: usize) -> Option<Sample> {
        sample_at(&self.trajectory, frame, self.horizon)
    }

    /// The last frame θ is known at.
    pub fn frontier(&self) -> usize {
        self.learned.len()
    }

    /// θ in effect at `frame`: its checkpoint, or the last known θ beyond the frontier.
    pub fn theta_at(&self, frame: usize) -> OnlineParams {
        self.checkpoints[frame.min(self.frontier())]
    }

    /// The online loss learned at each frame so far (`None` where θ was held).
    pub fn learned(&self) -> &[Option<FrameLoss>] {
        &self.learned
    }

    /// The fixed model's loss at every sample.
    pub fn fixed(&self) -> &[FrameLoss] {
        &self.fixed
    }

    /// θ as learned so far, one value per frame `0..=frontier`.
    pub fn checkpoints(&self) -> &[OnlineParams] {
        &self.checkpoints
    }

    /// The posterior's spread at each frame `0..=frontier`.
    pub fn spreads(&self) -> &[Spread] {
        &self.spreads
    }

    /// The posterior's spread in effect at `frame`.
    pub fn spread_at(&self, frame: usize) -> Spread {
        self.spreads[frame.min(self.frontier())]
    }

    /// The posterior of `θ_online` at the frontier, given every frame learned before it.
    pub fn posterior(&self) -> &Posterior {
        &self.posterior
    }

    /// The frames learned from, in order, with their online loss and θ after learning from them.
    pub fn learned_steps(&self) -> impl Iterator<Item = (usize, FrameLoss, OnlineParams)> + '_ {
        self.learned
            .iter()
            .enumerate()
            .filter_map(|(k, loss)| loss.map(|l| (k, l, self.checkpoints[k + 1])))
    }

    /// Mean online and fixed losses over the frames learned so far; `None` before any.
    pub fn mean_losses(&self) -> Option<MeanLosses> {
        let t = &self.totals;
        let n = t.frames as f64;
        (t.frames > 0).then(|| MeanLosses {
            frames: t.frames,
            online_pos: t.online_pos / n,
            online_rot: t.online_rot / n,
            fixed_pos: t.fixed_pos / n,
            fixed_rot: t.fixed_rot / n,
        })
    }

    /// Predicts, scores and differentiates at `frame` with θ at that frame, without learning: what a
    /// viewer shows. At a learned frame this is the step that was learned.
    pub fn evaluate(&self, frame: usize) -> Option<OnlineStep> {
        self.evaluate_with(frame, self.theta_at(frame))
    }

    /// What the fixed model (θ = `θ_online(0)`) predicts at `frame`.
    pub fn evaluate_fixed(&self, frame: usize) -> Option<OnlineStep> {
        self.evaluate_with(frame, self.theta0())
    }

    fn evaluate_with(&self, frame: usize, theta: OnlineParams) -> Option<OnlineStep> {
        Some(self.model.evaluate(&self.sample(frame)?, &theta))
    }

    /// Whether the sample at `frame` touches a frame flagged in `skip_frames`.
    pub fn is_skipped(&self, frame: usize, skip_frames: &[bool]) -> bool {
        sample_is_skipped(skip_frames, frame, self.horizon)
    }

    /// The earliest frame whose results (θ, losses, spread) were dropped since the last call, if any:
    /// a view that keeps series derived from the run cuts them back to it before following the run.
    pub fn take_cut(&mut self) -> Option<usize> {
        self.cut.take()
    }

    /// Learns from every frame in `from..to` in order (playing forward with learning on), holding θ
    /// over samples that start or end on a frame flagged in `skip_frames` (one flag per frame; frames
    /// past its end are not skipped), as training and evaluation leave them out. A frame already
    /// done the way the flags say (learned, or held where flagged) is kept, since doing it again
    /// gives the same θ bit for bit; one done the other way (labelled bad tracking after it was
    /// learned, or the label erased since) is done again, and everything after it is learned again.
    pub fn learn_through(&mut self, from: usize, to: usize, skip_frames: &[bool]) {
        let to = to.min(self.sample_count());
        for k in from..to {
            let skipped = self.is_skipped(k, skip_frames);
            if k < self.frontier() && self.learned[k].is_some() != skipped {
                continue;
            }
            if skipped {
                self.truncate_to(k);
                self.truncate_to(k + 1);
            } else {
                self.learn_at(k);
            }
        }
    }

    /// Learns from every sample of the recording from frame 0: what `pushlab eval` does.
    pub fn learn_all(&mut self, skip_frames: &[bool]) {
        self.learn_through(0, self.sample_count(), skip_frames);
    }

    /// Sets θ at `frame` (a user's steering, kept physical like every learned step), forgetting
    /// everything learned after it.
    pub fn set_theta_at(&mut self, frame: usize, theta: OnlineParams) {
        self.truncate_to(frame);
        self.checkpoints[frame] = self.model.keep_physical(theta);
        self.posterior = self.posterior.at(&self.checkpoints[frame]);
        self.spreads[frame] = Spread::of(&self.posterior);
        self.mark_cut(frame);
    }

    /// A new update rule from `frame` on: the steps learned after it used the old rule and are
    /// learned again. The COM misfit is the new optimiser's from `frame` on, in the kept keyframes
    /// too: going back to `frame` replays the posterior from a keyframe, and every frame learned
    /// after it, with either rule, is replayed from one.
    pub fn set_config_at(&mut self, frame: usize, config: OnlineConfig) {
        self.config = config;
        let theta = self.theta_at(frame);
        self.set_theta_at(frame, theta);
        let misfit = self.com_misfit_m();
        for keyframe in &mut self.keyframes {
            *keyframe = keyframe.with_com_misfit(misfit);
        }
        self.posterior = self.posterior.with_com_misfit(misfit);
        self.spreads[frame] = Spread::of(&self.posterior);
        self.beside_config(frame, config);
    }

    /// One online update from the sample at `frame` ("Learn this frame"): θ at the frame becomes the
    /// updated θ, so the prediction shown at this frame improves and the future is learned again from
    /// it. Returns the step, or `None` at the last frames, which have no sample.
    pub fn learn_this_frame(&mut self, frame: usize) -> Option<OnlineStep> {
        let sample = self.sample(frame)?;
        self.truncate_to(frame);
        let step = self.step_at(frame, &sample);
        self.checkpoints[frame] = step.theta_after;
        self.spreads[frame] = Spread::of(&self.posterior);
        self.mark_cut(frame);
        self.beside_learned_this_frame(frame);
        Some(step)
    }

    /// Back to the run's start at frame 0 (`θ_online(0)` and the prior, or what the push it goes on
    /// from ended with), forgetting all learning along this recording.
    pub fn reset(&mut self) {
        self.truncate_to(0);
        let start = OnlineState {
            theta: self.start.theta,
            posterior: self.start.posterior.with_com_misfit(self.com_misfit_m()),
        };
        self.checkpoints[0] = start.theta;
        self.posterior = start.posterior;
        self.keyframes = vec![start.posterior];
        self.spreads[0] = Spread::of(&start.posterior);
        self.mark_cut(0);
        self.beside_reset();
    }

    fn mark_cut(&mut self, frame: usize) {
        self.cut = Some(self.cut.map_or(frame, |c| c.min(frame)));
    }

    /// One step from [`OnlineRun::state`] at `frame` (the frontier), the run's posterior taking the
    /// frame in place rather than copied out and back (it is about 1.4 kB): the step, its `θ_after`
    /// not yet kept.
    fn step_at(&mut self, frame: usize, sample: &Sample) -> OnlineStep {
        let theta = self.checkpoints[frame].clamped();
        self.posterior.move_to(&theta);
        learn_step_on(
            self.model.as_ref(),
            sample,
            theta,
            &mut self.posterior,
            &self.config,
        )
    }

    /// What learning carries at `frame` (the frontier).
    fn state(&self, frame: usize) -> OnlineState {
        OnlineState::at(self.checkpoints[frame], self.posterior)
    }

    /// Makes `frame` the frontier: drops what came after it, or holds θ constant up to it.
    fn truncate_to(&mut self, frame: usize) {
        if frame <= self.frontier() {
            if frame < self.frontier() {
                self.learned.truncate(frame);
                self.recount_totals();
                self.posterior = self.replay_posterior(frame);
                self.keyframes.truncate(frame / KEYFRAME + 1);
                self.mark_cut(frame);
            }
            self.checkpoints.truncate(frame + 1);
            self.spreads.truncate(frame + 1);
        } else {
            let held = self.checkpoints[self.frontier()];
            let spread = self.spreads[self.frontier()];
            while self.frontier() < frame {
                self.learned.push(None);
                self.checkpoints.push(held);
                self.spreads.push(spread);
                self.keep_keyframe();
            }
        }
        self.beside_truncated(frame);
    }

    /// The posterior at `frame` (below the frontier): the keyframe before it and the learned frames
    /// between, linearised at their checkpoints as they were learned.
    fn replay_posterior(&self, frame: usize) -> Posterior {
        let key = frame / KEYFRAME;
        let mut posterior = self.keyframes[key];
        for k in key * KEYFRAME..frame {
            if self.learned[k].is_some()
                && let Some(sample) = self.sample(k)
            {
                let theta = self.checkpoints[k];
                posterior = posterior.with(&self.model.linearize(&sample, &theta), &theta);
            }
        }
        posterior.at(&self.checkpoints[frame])
    }

    /// Keeps the frontier's posterior when the frontier is a keyframe.
    fn keep_keyframe(&mut self) {
        let frontier = self.frontier();
        if frontier.is_multiple_of(KEYFRAME) && self.keyframes.len() == frontier / KEYFRAME {
            self.keyframes.push(self.posterior);
        }
    }

    fn learn_at(&mut self, frame: usize) {
        let Some(sample) = self.sample(frame) else {
            return;
        };
        self.truncate_to(frame);
        let step = self.step_at(frame, &sample);
        let loss = FrameLoss::of(&step.loss);
        self.add_to_totals(frame, loss);
        self.learned.push(Some(loss));
        self.checkpoints.push(step.theta_after);
        self.spreads.push(Spread::of(&self.posterior));
        self.keep_keyframe();
        self.beside_learned(frame);
    }

    fn add_to_totals(&mut self, frame: usize, online: FrameLoss) {
        let fixed = self.fixed[frame];
        let t = &mut self.totals;
        t.frames += 1;
        t.online_pos += online.pos;
        t.online_rot += online.rot;
        t.fixed_pos += fixed.pos;
        t.fixed_rot += fixed.rot;
    }

    /// Sums what is learned now, after the learned frames were cut back.
    fn recount_totals(&mut self) {
        self.totals = MeanLosses::default();
        for frame in 0..self.learned.len() {
            if let Some(loss) = self.learned[frame] {
                self.add_to_totals(frame, loss);
            }
        }
    }
}

#[cfg(test)]
mod tests;
