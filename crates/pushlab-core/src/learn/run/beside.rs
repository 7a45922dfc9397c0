//! The physics-only model learning its own θ beside a run, and the weight between the two
//! (`learn::ModelWeight`): kept frame by frame with the run, rewound with it, so that the weight
//! at a frame is the one `pushlab eval --physics` reports for that push, wherever the run went
//! since (the app scrubbing back, steering, a new rule).
//!
//! The physics-only run learns exactly the frames the run learns (θ held where it holds θ) from
//! its own start; steering θ is the run's alone, and drops the weights after the frame steered.

use super::{Beside, OnlineRun};
use crate::learn::weighting::ModelWeight;
use crate::learn::{OnlineConfig, OnlineState};
use crate::trajectory::Trajectory;

impl OnlineRun {
    /// Takes into `weight` the frames this run (the combined model's) and `physics` (the
    /// physics-only run on the same recording, with the same frames learned) learned from that it
    /// has not taken in yet, each predicted with the θ each run had at that frame: the weighted run
    /// of `pushlab eval --physics`, the app's and Python's.
    pub fn weigh_against(&self, physics: &OnlineRun, weight: &mut ModelWeight) {
        let next = weight.frames().last().map_or(0, |f| f.frame + 1);
        let scale = self.model.loss_scale();
        let learned = self.learned.len().min(physics.learned.len());
        for frame in next..learned {
            if self.learned[frame].is_none() || physics.learned[frame].is_none() {
                continue;
            }
            let Some(sample) = self.sample(frame) else {
                continue;
            };
            let c = self.model.predict(&sample.input, &self.theta_at(frame));
            let p = physics
                .model
                .predict(&sample.input, &physics.theta_at(frame));
            let frames = &self.trajectory.frames;
            let when = crate::learn::FrameTime {
                time: frames[frame].time,
                previous: frame.checked_sub(1).map(|b| frames[b].time),
            };
            weight.take(frame, when, &c.motion, &p.motion, &sample.target, &scale);
        }
    }

    /// This run with the physics-only run `physics` (on the same trajectory, at the same horizon,
    /// at its start) learning beside it and `weight` between them; what this run learned so far is
    /// learned by `physics` too.
    pub fn with_physics_beside(mut self, mut physics: OnlineRun, weight: ModelWeight) -> Self {
        physics.trajectory = std::sync::Arc::clone(&self.trajectory);
        let mut beside = Beside { physics, weight };
        for (frame, learned) in self.learned.iter().enumerate() {
            match learned {
                Some(_) => beside.physics.learn_at(frame),
                None => beside.physics.truncate_to(frame + 1),
            }
        }
        self.weigh_against(&beside.physics, &mut beside.weight);
        self.beside = Some(Box::new(beside));
        self
    }

    /// The physics-only run learning beside this one, if any.
    pub fn physics_beside(&self) -> Option<&OnlineRun> {
        self.beside.as_ref().map(|b| &b.physics)
    }

    /// The weight between this run's model and the physics-only one, if it runs beside.
    pub fn model_weight(&self) -> Option<&ModelWeight> {
        self.beside.as_ref().map(|b| &b.weight)
    }

    /// Where the physics-only run beside this one ended, and its weight: what the next push of
    /// the same object goes on from.
    pub fn beside_end(&self) -> Option<(OnlineState, ModelWeight)> {
        let beside = self.beside.as_ref()?;
        Some((
            beside.physics.end_state(),
            ModelWeight::continuing(&beside.weight),
        ))
    }

    /// Where the physics-only run beside this one started, and the weight as it started: what the
    /// same push run again from its start begins with beside it.
    pub fn beside_start(&self) -> Option<(OnlineState, ModelWeight)> {
        let beside = self.beside.as_ref()?;
        Some((*beside.physics.start_state(), beside.weight.restarted()))
    }

    /// After the run learned `frame`: the physics-only run learns it too, and the weight takes it in.
    pub(super) fn beside_learned(&mut self, frame: usize) {
        let Some(mut beside) = self.beside.take() else {
            return;
        };
        beside.physics.learn_at(frame);
        self.weigh_against(&beside.physics, &mut beside.weight);
        self.beside = Some(beside);
    }

    /// After the run was cut back or held up to `frame`.
    pub(super) fn beside_truncated(&mut self, frame: usize) {
        if let Some(beside) = self.beside.as_mut() {
            beside.physics.truncate_to(frame);
            beside.weight.rewind_to(frame);
        }
    }

    /// After the run's rule changed at `frame`.
    pub(super) fn beside_config(&mut self, frame: usize, config: OnlineConfig) {
        if let Some(beside) = self.beside.as_mut() {
            beside.physics.set_config_at(frame, config);
            beside.weight.rewind_to(frame);
        }
    }

    /// After "Learn this frame" at `frame`: the physics-only run takes one update there too.
    pub(super) fn beside_learned_this_frame(&mut self, frame: usize) {
        if let Some(beside) = self.beside.as_mut() {
            beside.physics.learn_this_frame(frame);
            beside.weight.rewind_to(frame);
        }
    }

    /// After a reset to the run's start.
    pub(super) fn beside_reset(&mut self) {
        if let Some(beside) = self.beside.as_mut() {
            beside.physics.reset();
            beside.weight.rewind_to(0);
        }
    }

    /// Lets go of the trajectory's share before it grows, so it grows in place.
    pub(super) fn beside_release(&mut self) {
        if let Some(beside) = self.beside.as_mut() {
            beside.physics.trajectory = std::sync::Arc::new(Trajectory::new(Vec::new()));
        }
    }

    /// After the trajectory grew (a live push): the physics-only run shares it and scores the
    /// samples it completes. (Through `extend` it would copy the trajectory it shares, a whole
    /// push's frames for every batch.)
    pub(super) fn beside_extended(&mut self) {
        if let Some(beside) = self.beside.as_mut() {
            beside.physics.trajectory = std::sync::Arc::clone(&self.trajectory);
            beside.physics.score_new_samples();
        }
    }
}

#[cfg(test)]
mod tests;
