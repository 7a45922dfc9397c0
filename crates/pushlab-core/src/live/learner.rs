//! Online learning as a live session's frames arrive: the poses put on the grid ([`LiveGrid`]) and
//! each final frame learned from by the core [`OnlineRun`], the run `pushlab eval`, the app and
//! Python follow on a file. The model is set on the object by the rule an evaluation uses
//! ([`crate::experiment::model_on`] through the setting's geometry) and the run starts at
//! `θ_online(0)`, so a live session and the replay of its recording (imported at the same rate)
//! give the same θ, spread and losses to the bit.
//!
//! From each new frame it also predicts where the object will be a horizon later
//! ([`crate::inspect::ahead`]: the pusher assumed to keep its velocity, since its future is not known
//! yet) and, when that frame arrives, scores the prediction: what is drawn in front of the object
//! and how far ahead the model can be trusted right now.

use std::collections::VecDeque;
use std::sync::Arc;

use super::grid::{LiveGrid, Refused, Stream};
use crate::experiment::geometry_of;
use crate::geometry::Pose2;
use crate::inspect::ahead;
use crate::learn::{OnlineConfig, OnlineRun};
use crate::model::{CombinedModel, NoOutline};
use crate::recording::Setting;
use crate::recording::bag::PlanarPose;
use crate::trajectory::Trajectory;

/// Poses refused so far, per stream (see [`Refused`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RefusedCounts {
    pub out_of_order: [usize; 2],
    pub bad_value: [usize; 2],
}

/// Where the object is predicted to be a horizon ahead of the newest frame, and how such predictions
/// did once their frame arrived.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AheadScore {
    /// Predictions whose frame has arrived.
    pub predictions: usize,
    /// Mean distance of the predicted object centre from where it was, metres.
    pub mean_position_m: f64,
    /// Mean absolute yaw error, radians.
    pub mean_yaw_rad: f64,
    /// The same for the object's own motion over the last horizon repeated (no model): what the
    /// model's prediction must beat to be worth drawing.
    pub baseline_position_m: f64,
    pub baseline_yaw_rad: f64,
}

/// A live session's online learning (see the module documentation).
#[derive(Debug)]
pub struct LiveLearner {
    grid: LiveGrid,
    run: OnlineRun,
    refused: RefusedCounts,
    /// Predictions ahead whose frame has not arrived: `(frame, the model's pose, the baseline's)`,
    /// oldest first (at most a horizon of them).
    pending: VecDeque<(usize, Pose2, Pose2)>,
    /// Sums over the predictions scored: count, then distance and |yaw error| of the model's and of
    /// the baseline's.
    scored: (usize, [f64; 4]),
    /// Per frame, whether θ is held over it (empty while none is).
    held: Vec<bool>,
}

impl LiveLearner {
    /// Learning with `model` on the object and pusher of `setting`, on a grid at `rate_hz`, by the
    /// rule `config`; refused as an evaluation refuses it (a contact-frame model needs the object's
    /// outline).
    pub fn new(
        model: &CombinedModel,
        setting: &Setting,
        config: OnlineConfig,
        rate_hz: f64,
    ) -> Result<Self, NoOutline> {
        let geometry = geometry_of(setting);
        let learner = model.on_object(geometry.as_ref().ok())?;
        Ok(Self::with_learner(
            learner,
            model.horizon(),
            config,
            rate_hz,
        ))
    }

    /// Learning with `learner` (a model already set on the object: the physics-only model, for
    /// one) at `horizon`, on a grid at `rate_hz`.
    pub fn with_learner(
        learner: crate::model::SharedOnlineModel,
        horizon: usize,
        config: OnlineConfig,
        rate_hz: f64,
    ) -> Self {
        let run = OnlineRun::new(
            learner,
            Arc::new(Trajectory::new(Vec::new())),
            horizon,
            config,
        );
        Self::with_run(run, rate_hz)
    }

    /// Learning in `run` (on a push not begun: a controller's, with physics alone beside it for
    /// the weighted prediction), on a grid at `rate_hz`.
    pub fn with_run(run: OnlineRun, rate_hz: f64) -> Self {
        Self {
            grid: LiveGrid::new(rate_hz),
            run,
            refused: RefusedCounts::default(),
            pending: VecDeque::new(),
            scored: (0, [0.0; 4]),
            held: Vec::new(),
        }
    }

    /// Takes one pose of `stream` (see [`LiveGrid::push`]); a refused pose is counted and its reason
    /// returned, for saying once.
    pub fn take(
        &mut self,
        stream: Stream,
        pose: &PlanarPose,
        log_time_ns: u64,
    ) -> Result<(), Refused> {
        let result = self.grid.push(stream, pose, log_time_ns);
        let slot = usize::from(stream == Stream::Object);
        match &result {
            Ok(()) => {}
            Err(Refused::OutOfOrder) => self.refused.out_of_order[slot] += 1,
            Err(Refused::BadValue(_)) => self.refused.bad_value[slot] += 1,
        }
        result
    }

    /// Puts the frames that became final on the run and learns from every sample they complete;
    /// returns how many frames arrived.
    pub fn learn(&mut self) -> usize {
        self.learn_holding(|_| false)
    }

    /// [`LiveLearner::learn`], holding θ over samples that start or end on a frame `held` flags
    /// (a controller's frames with the pusher away from the object), as the run holds it over
    /// frames labelled bad.
    pub fn learn_holding(&mut self, held: impl Fn(&crate::trajectory::Frame) -> bool) -> usize {
        let frames = self.grid.take_frames();
        let arrived = frames.len();
        if arrived > 0 {
            let first = self.run.trajectory().len();
            if !self.held.is_empty() || frames.iter().any(&held) {
                self.held.resize(first, false);
                self.held.extend(frames.iter().map(&held));
            }
            self.run.extend(frames);
            let from = self.run.frontier();
            self.run
                .learn_through(from, self.run.sample_count(), &self.held);
            self.predict_ahead(first);
        }
        arrived
    }

    /// Scores the predictions whose frame is among those from `first` on, and predicts ahead from
    /// each of them with θ as learned now.
    fn predict_ahead(&mut self, first: usize) {
        let theta = self.run.theta_at(self.run.frontier());
        let horizon = self.run.horizon();
        let frames = &self.run.trajectory().frames;
        for k in first..frames.len() {
            while let Some(&(frame, predicted, baseline)) = self.pending.front() {
                if frame > k {
                    break;
                }
                self.pending.pop_front();
                if frame == k {
                    let (offset, yaw) = frames[k].object.motion_to(&predicted);
                    let (base_offset, base_yaw) = frames[k].object.motion_to(&baseline);
                    self.scored.0 += 1;
                    let sums = &mut self.scored.1;
                    sums[0] += offset.norm();
                    sums[1] += yaw.abs();
                    sums[2] += base_offset.norm();
                    sums[3] += base_yaw.abs();
                }
            }
            if let Some((frame, pose)) =
                ahead(self.run.model().as_ref(), &frames[..=k], horizon, &theta)
            {
                // The object's last motion over a horizon, repeated.
                let (before, now) = (frames[k - horizon].object, frames[k].object);
                let (moved, turned) = before.motion_to(&now);
                self.pending
                    .push_back((frame, pose, now.moved_by(moved, turned)));
            }
        }
    }

    /// The newest prediction ahead: the frame it is for (a horizon after the newest frame) and the
    /// object's pose then, if the pusher keeps its velocity; `None` before a horizon of frames.
    pub fn ahead(&self) -> Option<(usize, Pose2)> {
        self.pending.back().map(|&(frame, pose, _)| (frame, pose))
    }

    /// How the predictions ahead did, once their frame arrived.
    pub fn ahead_score(&self) -> AheadScore {
        let (n, sums) = self.scored;
        let [position, yaw, base_position, base_yaw] =
            sums.map(|sum| if n > 0 { sum / n as f64 } else { 0.0 });
        AheadScore {
            predictions: n,
            mean_position_m: position,
            mean_yaw_rad: yaw,
            baseline_position_m: base_position,
            baseline_yaw_rad: base_yaw,
        }
    }

    /// The run so far: θ, its spread and the losses at every frame learned.
    pub fn run(&self) -> &OnlineRun {
        &self.run
    }

    /// The grid the frames are made on.
    pub fn grid(&self) -> &LiveGrid {
        &self.grid
    }

    /// Poses refused so far.
    pub fn refused(&self) -> RefusedCounts {
        self.refused
    }
}
