//! Online learning as a live session's frames arrive: the poses put on the grid ([`LiveGrid`]) and
//! each final frame learned from by the core [`OnlineRun`], the run `pushlab eval`, the app and
//! Python follow on a file. The model is set on the object by the rule an evaluation uses
//! ([`crate::experiment::model_on`] through the setting's geometry) and the run starts at
//! `θ_online(0)`, so a live session and the replay of its recording (imported at the same rate)
//! give the same θ, spread and losses to the bit.

use std::sync::Arc;

use super::grid::{LiveGrid, Refused, Stream};
use crate::experiment::geometry_of;
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

/// A live session's online learning (see the module documentation).
#[derive(Debug)]
pub struct LiveLearner {
    grid: LiveGrid,
    run: OnlineRun,
    refused: RefusedCounts,
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
        let run = OnlineRun::new(
            learner,
            Arc::new(Trajectory::new(Vec::new())),
            model.horizon(),
            config,
        );
        Ok(Self {
            grid: LiveGrid::new(rate_hz),
            run,
            refused: RefusedCounts::default(),
        })
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
        let frames = self.grid.take_frames();
        let arrived = frames.len();
        if arrived > 0 {
            self.run.extend(frames);
            let from = self.run.frontier();
            self.run.learn_through(from, self.run.sample_count(), &[]);
        }
        arrived
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
