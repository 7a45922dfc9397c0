//! One online-learning run along the selected trajectory, with a checkpoint of `θ_online` per frame.
//!
//! The learning itself is `OnlineModel::online_step` from pushlab-core, a pure function of (sample, θ,
//! config); this module only decides *which* frames are learned from and remembers θ at every frame,
//! so that scrubbing back restores the exact `θ_online(t)` and playing on re-learns deterministically.
//!
//! Invariant: `checkpoints[k]` is θ in effect at frame k for `k <= frontier`, and `learned[k]` is what
//! happened between frame k and k+1 (`None`: θ was held, nothing learned — a frame jumped over, or one
//! whose sample touches a frame labelled "skip in training", such as bad tracking). Steering θ at frame f (a
//! slider, "Learn this frame", reset) drops everything after f: the future is re-learned from there.
//!
//! Per frame the run keeps only what a long recording can afford (about 56 bytes: θ exactly, the
//! online and fixed losses and the posterior's spread as `f32` for plots, tables and the ellipse).
//! The posterior itself (`learn::uncertainty`) is kept at the frontier and every [`KEYFRAME`] frames;
//! cutting back to a frame replays at most that many frames' linearisations from a keyframe. Samples are made from the shared trajectory
//! when needed, and full predictions are computed again for the frame shown: a million-frame run
//! holds tens of megabytes, not the gigabytes that a stored sample and `OnlineStep` per frame took.

use std::sync::Arc;

use pushlab_core::labels::pipeline::sample_is_skipped;
use pushlab_core::learn::uncertainty::{com_block, ellipse_95, std_of};
use pushlab_core::learn::{
    Loss, OnlineConfig, OnlineModel, OnlineState, OnlineStep, Posterior, learn_step,
};
use pushlab_core::model::{OnlineParams, Sample, sample_at, sample_count};
use pushlab_core::trajectory::Trajectory;

use super::run_plots::RunPlots;

/// The model a run learns with, shared with the UI thread's other users.
pub type SharedModel = Arc<dyn OnlineModel + Send + Sync>;

/// The losses of one prediction as a run keeps them for every frame: the positional loss
/// `(ℓ_pos,x + ℓ_pos,y) / 2` and `ℓ_rot`, in `f32` (for plots and tables; exports recompute them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameLoss {
    pub pos: f32,
    pub rot: f32,
}

impl From<&Loss> for FrameLoss {
    fn from(loss: &Loss) -> Self {
        Self {
            pos: loss.pos() as f32,
            rot: loss.rot as f32,
        }
    }
}

/// Frames between kept posteriors.
pub const KEYFRAME: usize = 64;

/// How sure the run is of `θ_online` at a frame, as drawn: the COM offset's covariance (m², object
/// frame: xx, xy, yy) and the standard deviation of `h` (m), in `f32`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spread {
    pub com_cov: [f32; 3],
    pub h_std: f32,
}

impl Spread {
    fn of(posterior: &Posterior) -> Self {
        // One covariance for both (each takes an inverse and the correlation factor).
        let covariance = posterior.covariance();
        let c = com_block(&covariance);
        Self {
            com_cov: [c[0][0] as f32, c[0][1] as f32, c[1][1] as f32],
            h_std: std_of(&covariance)[2] as f32,
        }
    }

    /// Standard deviations of `[com_x, com_y, h]`, metres.
    pub fn std(&self) -> [f64; 3] {
        let [xx, _, yy] = self.com_cov.map(f64::from);
        [
            xx.max(0.0).sqrt(),
            yy.max(0.0).sqrt(),
            f64::from(self.h_std),
        ]
    }

    /// The COM's 95 % ellipse: half-axes (metres, major first) and the major axis's angle in the
    /// object frame.
    pub fn ellipse_95(&self) -> ([f64; 2], f64) {
        let [xx, xy, yy] = self.com_cov.map(f64::from);
        ellipse_95([[xx, xy], [xy, yy]])
    }
}

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

/// Online learning along one trajectory.
pub struct OnlineRun {
    model: SharedModel,
    trajectory: Arc<Trajectory>,
    /// Frames between a sample's start and its target.
    horizon: usize,
    /// The "fixed" run: every sample predicted with `θ_online(0)`, never updated.
    fixed: Vec<FrameLoss>,
    checkpoints: Vec<OnlineParams>,
    learned: Vec<Option<FrameLoss>>,
    /// The posterior's spread at each checkpoint.
    spreads: Vec<Spread>,
    /// The posterior at frames `0, KEYFRAME, 2·KEYFRAME, …` up to the frontier (before `θ` steering
    /// at that frame is applied), and at the frontier itself.
    keyframes: Vec<Posterior>,
    posterior: Posterior,
    /// Sums over the learned frames, for [`OnlineRun::mean_losses`].
    totals: MeanLosses,
    /// Moving averages and min/max envelopes of the series above, for the plots.
    plots: RunPlots,
    /// The update rule for steps learned from now on (steps, learning rate).
    pub config: OnlineConfig,
}

impl OnlineRun {
    /// A run at frame 0 with θ = `θ_online(0)` of the model; the fixed run is computed up front.
    pub fn new(
        model: SharedModel,
        trajectory: Arc<Trajectory>,
        horizon: usize,
        config: OnlineConfig,
    ) -> Self {
        let horizon = horizon.max(1);
        let theta0 = model.theta0();
        let fixed: Vec<FrameLoss> = (0..sample_count(&trajectory, horizon))
            .filter_map(|k| sample_at(&trajectory, k, horizon))
            .map(|s| FrameLoss::from(&model.online_step(&s, &theta0, &OnlineConfig::fixed()).loss))
            .collect();
        let checkpoints = vec![theta0];
        let posterior = OnlineState::start(model.as_ref()).posterior;
        let spreads = vec![Spread::of(&posterior)];
        let plots = RunPlots::new(&fixed, &checkpoints, &spreads);
        Self {
            model,
            trajectory,
            horizon,
            fixed,
            checkpoints,
            learned: Vec::new(),
            spreads,
            keyframes: vec![posterior],
            posterior,
            totals: MeanLosses::default(),
            plots,
            config,
        }
    }

    /// The model learned with.
    pub fn model(&self) -> &SharedModel {
        &self.model
    }

    /// The trajectory learned along.
    pub fn trajectory(&self) -> &Trajectory {
        &self.trajectory
    }

    /// `θ_online(0)`.
    pub fn theta0(&self) -> OnlineParams {
        self.model.theta0()
    }

    /// Frames between a sample's start and its target.
    pub fn horizon(&self) -> usize {
        self.horizon
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

    /// The losses learned at each frame so far (`None` where θ was held).
    pub fn learned(&self) -> &[Option<FrameLoss>] {
        &self.learned
    }

    /// The fixed model's losses at every sample.
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

    /// The plots' derived series.
    pub fn plots(&self) -> &RunPlots {
        &self.plots
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

    /// Predicts, scores and differentiates at `frame` with θ at that frame, without learning: what the
    /// scene and the inspector show. At a learned frame this is the step that was learned.
    pub fn evaluate(&self, frame: usize) -> Option<OnlineStep> {
        self.evaluate_with(frame, self.theta_at(frame))
    }

    /// What the fixed model (θ = `θ_online(0)`) predicts at `frame`.
    pub fn evaluate_fixed(&self, frame: usize) -> Option<OnlineStep> {
        self.evaluate_with(frame, self.theta0())
    }

    fn evaluate_with(&self, frame: usize, theta: OnlineParams) -> Option<OnlineStep> {
        let sample = self.sample(frame)?;
        Some(
            self.model
                .online_step(&sample, &theta, &OnlineConfig::fixed()),
        )
    }

    /// Learns from every frame in `from..to` in order (playing forward with learning on), holding θ
    /// over samples that start or end on a frame flagged in `skip_frames` (one flag per frame; frames
    /// past its end are not skipped), as `pushlab train` and `eval` leave them out. A frame already
    /// done the way the flags say (learned, or held where flagged) is kept, since doing it again
    /// gives the same θ bit for bit; one done the other way (labelled bad tracking after it was
    /// learned, or the label erased since) is done again, and everything after it is re-learned.
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
        self.plots
            .extend(&self.fixed, &self.learned, &self.checkpoints, &self.spreads);
    }

    /// Whether the sample at `frame` touches a frame flagged in `skip_frames`.
    pub fn is_skipped(&self, frame: usize, skip_frames: &[bool]) -> bool {
        sample_is_skipped(skip_frames, frame, self.horizon)
    }

    /// Sets θ at `frame` (a user's steering), forgetting everything learned after it.
    pub fn set_theta_at(&mut self, frame: usize, theta: OnlineParams) {
        self.truncate_to(frame);
        self.checkpoints[frame] = theta.clamped();
        self.posterior = self.posterior.at(&self.checkpoints[frame]);
        self.spreads[frame] = Spread::of(&self.posterior);
        self.plots.cut(&self.learned, frame);
        self.plots
            .extend(&self.fixed, &self.learned, &self.checkpoints, &self.spreads);
    }

    /// One online update from the sample at `frame` ("Learn this frame"): θ at the frame becomes the
    /// updated θ, so the prediction shown at this frame improves and the future is re-learned from it.
    /// Returns the step, or `None` at the last frames, which have no sample.
    pub fn learn_this_frame(&mut self, frame: usize) -> Option<OnlineStep> {
        let sample = self.sample(frame)?;
        self.truncate_to(frame);
        let (step, next) = learn_step(
            self.model.as_ref(),
            &sample,
            &self.state(frame),
            &self.config,
        );
        self.checkpoints[frame] = next.theta;
        self.posterior = next.posterior;
        self.spreads[frame] = Spread::of(&self.posterior);
        self.plots.cut(&self.learned, frame);
        self.plots
            .extend(&self.fixed, &self.learned, &self.checkpoints, &self.spreads);
        Some(step)
    }

    /// Back to `θ_online(0)` at frame 0, forgetting all learning.
    pub fn reset(&mut self) {
        self.truncate_to(0);
        let start = OnlineState::start(self.model.as_ref());
        self.checkpoints[0] = start.theta;
        self.posterior = start.posterior;
        self.keyframes = vec![start.posterior];
        self.spreads[0] = Spread::of(&start.posterior);
        self.plots.cut(&self.learned, 0);
        self.plots
            .extend(&self.fixed, &self.learned, &self.checkpoints, &self.spreads);
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
                self.plots.cut(&self.learned, frame);
                self.posterior = self.replay_posterior(frame);
                self.keyframes.truncate(frame / KEYFRAME + 1);
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
        let (step, next) = learn_step(
            self.model.as_ref(),
            &sample,
            &self.state(frame),
            &self.config,
        );
        let loss = FrameLoss::from(&step.loss);
        self.add_to_totals(frame, loss);
        self.learned.push(Some(loss));
        self.checkpoints.push(next.theta);
        self.posterior = next.posterior;
        self.spreads.push(Spread::of(&self.posterior));
        self.keep_keyframe();
    }

    fn add_to_totals(&mut self, frame: usize, online: FrameLoss) {
        let fixed = self.fixed[frame];
        let t = &mut self.totals;
        t.frames += 1;
        t.online_pos += f64::from(online.pos);
        t.online_rot += f64::from(online.rot);
        t.fixed_pos += f64::from(fixed.pos);
        t.fixed_rot += f64::from(fixed.rot);
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
mod tests {
    use super::*;
    use pushlab_core::geometry::{Outline, Pose2};
    use pushlab_core::learn::LossScale;
    use pushlab_core::model::{PhysicsOnlyModel, samples_from_trajectory};
    use pushlab_core::trajectory::Frame;

    /// A 10 cm box pushed along +x at its face, turning slowly (as an off-centre COM would make it):
    /// enough signal for learning to move θ.
    fn push() -> Arc<Trajectory> {
        let frames = (0..200)
            .map(|i| {
                let t = i as f64 * 0.01;
                let yaw = 0.3 * t;
                let object = Pose2::new(0.05 * t, 0.0, yaw);
                let robot = object.point_in_world(nalgebra::Point2::new(-0.05 - 0.01, 0.01));
                Frame {
                    time: t,
                    robot,
                    object,
                }
            })
            .collect();
        Arc::new(Trajectory::new(frames))
    }

    fn run() -> OnlineRun {
        let outline = Outline::rectangle(0.1, 0.1).expect("valid box");
        let trajectory = push();
        let mut scale = LossScale::from_samples(&samples_from_trajectory(&trajectory, 1));
        // This synthetic push barely moves sideways; keep the σ of a real push's millimetres.
        scale.sigma_pos = scale.sigma_pos.map(|s| s.max(1e-3));
        scale.sigma_rot = scale.sigma_rot.max(1e-3);
        let model = PhysicsOnlyModel::new(outline, 0.01, 0.002, scale);
        OnlineRun::new(Arc::new(model), trajectory, 1, OnlineConfig::default())
    }

    #[test]
    fn learning_moves_theta_and_keeps_a_checkpoint_per_frame() {
        let mut run = run();
        let theta0 = run.theta0();
        run.learn_through(0, 50, &[]);
        assert_eq!(run.frontier(), 50);
        assert_eq!(run.checkpoints().len(), 51);
        assert_ne!(
            run.theta_at(50),
            theta0,
            "50 steps of learning changed nothing"
        );
        for k in 0..50 {
            let loss = run.learned()[k].expect("every frame was learned");
            // The step learned at k predicted with θ(k) and moved it to θ(k + 1).
            let step = run.evaluate(k).expect("frame has a sample");
            assert_eq!(step.theta_before, run.theta_at(k));
            assert_eq!(FrameLoss::from(&step.loss), loss);
            let relearned = run.model().online_step(
                &run.sample(k).expect("sample"),
                &run.theta_at(k),
                &run.config,
            );
            assert_eq!(relearned.theta_after, run.theta_at(k + 1));
        }
    }

    #[test]
    fn scrubbing_back_restores_the_exact_earlier_theta_and_replay_is_identical() {
        let mut run = run();
        run.learn_through(0, 80, &[]);
        let at_30 = run.theta_at(30);
        let all: Vec<_> = run.checkpoints().to_vec();
        // Re-learning the same frames from the same θ(30) gives the same θ bit for bit.
        let theta = run.theta_at(30);
        run.set_theta_at(30, theta);
        assert_eq!(run.frontier(), 30);
        assert_eq!(run.theta_at(30), at_30);
        run.learn_through(30, 80, &[]);
        assert_eq!(run.checkpoints(), &all[..]);
    }

    #[test]
    fn steering_drops_the_future_and_beyond_the_frontier_theta_is_held() {
        let mut run = run();
        run.learn_through(0, 40, &[]);
        let mut steered = run.theta_at(20);
        steered.com_offset = [0.01, -0.02];
        run.set_theta_at(20, steered);
        assert_eq!(run.frontier(), 20);
        assert_eq!(run.theta_at(20).com_offset, [0.01, -0.02]);
        assert_eq!(run.theta_at(150), run.theta_at(20));
        // Steering ahead of the frontier holds θ over the gap.
        run.set_theta_at(60, run.theta0());
        assert_eq!(run.frontier(), 60);
        assert!(run.learned()[20..60].iter().all(Option::is_none));
        assert_eq!(run.theta_at(59).com_offset, [0.01, -0.02]);
    }

    #[test]
    fn learn_this_frame_lowers_the_loss_at_that_frame() {
        let mut run = run();
        let before = run.evaluate(10).expect("frame 10 has a sample");
        let step = run.learn_this_frame(10).expect("frame 10 has a sample");
        let after = run.evaluate(10).expect("frame 10 has a sample");
        assert_eq!(step.theta_before, before.theta_before);
        assert_eq!(run.theta_at(10), step.theta_after);
        assert!(
            after.loss.total() < before.loss.total(),
            "loss {} → {}",
            before.loss.total(),
            after.loss.total()
        );
    }

    #[test]
    fn the_last_frames_have_no_sample_and_reset_forgets_everything() {
        let mut run = run();
        assert!(run.learn_this_frame(199).is_none());
        run.learn_through(0, 500, &[]);
        assert_eq!(run.frontier(), 199);
        run.reset();
        assert_eq!(run.frontier(), 0);
        assert_eq!(run.theta_at(100), run.theta0());
    }

    #[test]
    fn frames_flagged_to_skip_hold_theta_and_the_rest_learn() {
        let mut run = run();
        let mut skip = vec![false; 200];
        skip[20..25].fill(true);
        run.learn_through(0, 40, &skip);
        for k in 0..40 {
            // Horizon 1: the sample at k uses frames k and k + 1.
            let skipped = (19..25).contains(&k);
            assert_eq!(run.learned()[k].is_none(), skipped, "frame {k}");
            if skipped {
                assert_eq!(
                    run.checkpoints()[k + 1],
                    run.checkpoints()[k],
                    "θ held at {k}"
                );
            }
        }
        assert_ne!(
            run.checkpoints()[40],
            run.checkpoints()[0],
            "the other frames learned"
        );
        // Playing over the same frames again changes nothing.
        let before = run.checkpoints().to_vec();
        run.learn_through(10, 40, &skip);
        assert_eq!(run.checkpoints(), &before[..]);

        // Flagging frames that were already learned: playing over them again holds θ there.
        skip[30..33].fill(true);
        run.learn_through(0, 40, &skip);
        for k in 29..33 {
            assert!(run.learned()[k].is_none(), "frame {k} still learned");
        }
        assert!(
            run.learned()[35].is_some(),
            "the frames after are learned again"
        );
        // And erasing the flags learns them again.
        skip.fill(false);
        run.learn_through(0, 40, &skip);
        assert!(run.learned()[..40].iter().all(Option::is_some));
    }
}
