//! One online-learning run along the selected trajectory, with a checkpoint of `θ_online` per frame.
//!
//! The learning itself is `OnlineModel::online_step` from pushlab-core, a pure function of (sample, θ,
//! config); this module only decides *which* frames are learned from and remembers θ at every frame,
//! so that scrubbing back restores the exact `θ_online(t)` and playing on re-learns deterministically.
//!
//! Invariant: `checkpoints[k]` is θ in effect at frame k for `k <= frontier`, and `steps[k]` is what
//! happened between frame k and k+1 (`None`: θ was held, nothing learned — a frame jumped over, or one
//! whose sample touches a frame labelled "skip in training", such as bad tracking). Steering θ at frame f (a
//! slider, "Learn this frame", reset) drops everything after f: the future is re-learned from there.

use std::sync::Arc;

use pushlab_core::labels::pipeline::sample_is_skipped;
use pushlab_core::learn::{OnlineConfig, OnlineModel, OnlineStep};
use pushlab_core::model::{OnlineParams, Sample, samples_from_trajectory};
use pushlab_core::trajectory::Trajectory;

/// The model a run learns with, shared with the UI thread's other users.
pub type SharedModel = Arc<dyn OnlineModel + Send + Sync>;

/// Online learning along one trajectory.
pub struct OnlineRun {
    model: SharedModel,
    samples: Vec<Sample>,
    /// The "fixed" run: every sample predicted with `θ_online(0)`, never updated.
    fixed: Vec<OnlineStep>,
    checkpoints: Vec<OnlineParams>,
    steps: Vec<Option<OnlineStep>>,
    /// Frames between a sample's start and its target.
    horizon: usize,
    /// The update rule for steps learned from now on (steps, learning rate).
    pub config: OnlineConfig,
}

impl OnlineRun {
    /// A run at frame 0 with θ = `θ_online(0)` of the model; the fixed run is computed up front.
    pub fn new(
        model: SharedModel,
        trajectory: &Trajectory,
        horizon: usize,
        config: OnlineConfig,
    ) -> Self {
        let samples = samples_from_trajectory(trajectory, horizon);
        let theta0 = model.theta0();
        let fixed = samples
            .iter()
            .map(|s| model.online_step(s, &theta0, &OnlineConfig::fixed()))
            .collect();
        Self {
            model,
            samples,
            fixed,
            checkpoints: vec![theta0],
            steps: Vec::new(),
            horizon: horizon.max(1),
            config,
        }
    }

    /// The model learned with.
    pub fn model(&self) -> &SharedModel {
        &self.model
    }

    /// `θ_online(0)`.
    pub fn theta0(&self) -> OnlineParams {
        self.model.theta0()
    }

    /// The samples, sample i predicting from frame i.
    pub fn samples(&self) -> &[Sample] {
        &self.samples
    }

    /// The sample that predicts from `frame`, if the frame is not within the horizon of the end.
    pub fn sample(&self, frame: usize) -> Option<&Sample> {
        self.samples.get(frame)
    }

    /// The last frame θ is known at.
    pub fn frontier(&self) -> usize {
        self.steps.len()
    }

    /// θ in effect at `frame`: its checkpoint, or the last known θ beyond the frontier.
    pub fn theta_at(&self, frame: usize) -> OnlineParams {
        self.checkpoints[frame.min(self.frontier())]
    }

    /// The online step learned at each frame so far (`None` where θ was held).
    pub fn steps(&self) -> &[Option<OnlineStep>] {
        &self.steps
    }

    /// The fixed model's step at every sample.
    pub fn fixed(&self) -> &[OnlineStep] {
        &self.fixed
    }

    /// θ as learned so far, one value per frame `0..=frontier`.
    pub fn checkpoints(&self) -> &[OnlineParams] {
        &self.checkpoints
    }

    /// Predicts, scores and differentiates at `frame` with θ at that frame, without learning: what the
    /// scene and the inspector show.
    pub fn evaluate(&self, frame: usize) -> Option<OnlineStep> {
        let sample = self.sample(frame)?;
        Some(
            self.model
                .online_step(sample, &self.theta_at(frame), &OnlineConfig::fixed()),
        )
    }

    /// Learns from every frame in `from..to` in order (playing forward with learning on), holding θ
    /// over samples that start or end on a frame flagged in `skip_frames` (one flag per frame; frames
    /// past its end are not skipped), as `pushlab train` and `eval` leave them out. A frame already
    /// done the way the flags say (learned, or held where flagged) is kept, since doing it again
    /// gives the same θ bit for bit; one done the other way (labelled bad tracking after it was
    /// learned, or the label erased since) is done again, and everything after it is re-learned.
    pub fn learn_through(&mut self, from: usize, to: usize, skip_frames: &[bool]) {
        let to = to.min(self.samples.len());
        for k in from..to {
            let skipped = self.is_skipped(k, skip_frames);
            if k < self.frontier() && self.steps[k].is_some() != skipped {
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

    /// Whether the sample at `frame` touches a frame flagged in `skip_frames`.
    pub fn is_skipped(&self, frame: usize, skip_frames: &[bool]) -> bool {
        sample_is_skipped(skip_frames, frame, self.horizon)
    }

    /// Sets θ at `frame` (a user's steering), forgetting everything learned after it.
    pub fn set_theta_at(&mut self, frame: usize, theta: OnlineParams) {
        self.truncate_to(frame);
        self.checkpoints[frame] = theta.clamped();
    }

    /// One online update from the sample at `frame` ("Learn this frame"): θ at the frame becomes the
    /// updated θ, so the prediction shown at this frame improves and the future is re-learned from it.
    /// Returns the step, or `None` at the last frames, which have no sample.
    pub fn learn_this_frame(&mut self, frame: usize) -> Option<OnlineStep> {
        let sample = *self.sample(frame)?;
        self.truncate_to(frame);
        let step = self
            .model
            .online_step(&sample, &self.checkpoints[frame], &self.config);
        self.checkpoints[frame] = step.theta_after;
        Some(step)
    }

    /// Back to `θ_online(0)` at frame 0, forgetting all learning.
    pub fn reset(&mut self) {
        self.checkpoints.truncate(1);
        self.checkpoints[0] = self.model.theta0();
        self.steps.clear();
    }

    /// Makes `frame` the frontier: drops what came after it, or holds θ constant up to it.
    fn truncate_to(&mut self, frame: usize) {
        if frame <= self.frontier() {
            self.steps.truncate(frame);
            self.checkpoints.truncate(frame + 1);
        } else {
            let held = self.checkpoints[self.frontier()];
            while self.frontier() < frame {
                self.steps.push(None);
                self.checkpoints.push(held);
            }
        }
    }

    fn learn_at(&mut self, frame: usize) {
        let Some(sample) = self.samples.get(frame).copied() else {
            return;
        };
        self.truncate_to(frame);
        let step = self
            .model
            .online_step(&sample, &self.checkpoints[frame], &self.config);
        self.steps.push(Some(step));
        self.checkpoints.push(step.theta_after);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pushlab_core::geometry::{Outline, Pose2};
    use pushlab_core::learn::LossScale;
    use pushlab_core::model::PhysicsOnlyModel;
    use pushlab_core::trajectory::Frame;

    /// A 10 cm box pushed along +x at its face, turning slowly (as an off-centre COM would make it):
    /// enough signal for learning to move θ.
    fn push() -> Trajectory {
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
        Trajectory::new(frames)
    }

    fn run() -> OnlineRun {
        let outline = Outline::rectangle(0.1, 0.1).expect("valid box");
        let trajectory = push();
        let mut scale = LossScale::from_samples(&samples_from_trajectory(&trajectory, 1));
        // This synthetic push barely moves sideways; keep the σ of a real push's millimetres.
        scale.sigma_pos = scale.sigma_pos.map(|s| s.max(1e-3));
        scale.sigma_rot = scale.sigma_rot.max(1e-3);
        let model = PhysicsOnlyModel::new(outline, 0.01, 0.002, scale);
        OnlineRun::new(Arc::new(model), &trajectory, 1, OnlineConfig::default())
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
            let step = run.steps()[k].expect("every frame was learned");
            assert_eq!(step.theta_before, run.theta_at(k));
            assert_eq!(step.theta_after, run.theta_at(k + 1));
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
        assert!(run.steps()[20..60].iter().all(Option::is_none));
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
            assert_eq!(run.steps()[k].is_none(), skipped, "frame {k}");
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
            assert!(run.steps()[k].is_none(), "frame {k} still learned");
        }
        assert!(
            run.steps()[35].is_some(),
            "the frames after are learned again"
        );
        // And erasing the flags learns them again.
        skip.fill(false);
        run.learn_through(0, 40, &skip);
        assert!(run.steps()[..40].iter().all(Option::is_some));
    }
}
