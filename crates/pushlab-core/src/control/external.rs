//! The controller on poses from outside: a physics engine pushlab did not write, or a robot's
//! tracker. Each control step takes the pusher's and the object's poses as they are now, puts them
//! on live input's grid and learns the frames that became final by the live learner (the core
//! `OnlineRun`, as `pushlab live` learns), then plans from the poses just taken with the θ the
//! run has; the pusher's target is for whoever moves the pusher. `pushlab control --pipe` runs it
//! over standard input and output, which is how the MuJoCo measurement drives it.

use nalgebra::Point2;

use super::goal::Goal;
use super::planner::{Planner, PlannerConfig};
use super::sandbox_run::{ControlError, ControlStep, Decision, Progress};
use super::{Pacing, PlanWith, is_away};
use crate::geometry::Pose2;
use crate::learn::OnlineConfig;
use crate::live::LiveLearner;
use crate::live::grid::Stream;
use crate::model::{CombinedModel, OnlineParams};
use crate::recording::Setting;
use crate::recording::bag::PlanarPose;

/// The controller fed poses from outside (see the module documentation).
pub struct PoseControl {
    learner: LiveLearner,
    planner: Planner,
    plan_with: PlanWith,
    truth: Option<OnlineParams>,
    progress: Progress,
}

impl PoseControl {
    /// The controller for the object and pusher of `setting` (whose COM offset and `h`, when it
    /// has them, are the truth `PlanWith::Truth` plans with), paced by `pacing`: the learner's
    /// grid at its `grid_hz`, a target no further than a step of the pusher.
    pub fn new(
        model: &CombinedModel,
        setting: &Setting,
        plan_with: PlanWith,
        config: OnlineConfig,
        goal: Goal,
        planner: PlannerConfig,
        pacing: Pacing,
    ) -> Result<Self, ControlError> {
        let outline =
            (setting.object.outline()).map_err(|e| ControlError::Outline(e.to_string()))?;
        let truth = super::truth_of(setting);
        if plan_with == PlanWith::Truth && truth.is_none() {
            return Err(ControlError::Model(
                "planning with the true θ needs the setting's com_offset and h".into(),
            ));
        }
        let learner = LiveLearner::with_run(
            super::run_for(model, setting, plan_with, config)?,
            pacing.grid_hz,
        );
        let planner = Planner::paced(
            &outline,
            setting.pusher_radius,
            goal,
            pacing,
            model.horizon(),
            planner,
        );
        Ok(Self {
            learner,
            planner,
            plan_with,
            truth,
            progress: Progress::default(),
        })
    }

    /// Whether the goal is reached and held.
    pub fn is_done(&self) -> bool {
        self.progress.is_done()
    }

    pub fn learner(&self) -> &LiveLearner {
        &self.learner
    }

    pub fn planner(&self) -> &Planner {
        &self.planner
    }

    /// One control step on the poses at `time_s`, taken and planned from at once (a caller that
    /// gets both poses each step: `--pipe`).
    pub fn step(&mut self, time_s: f64, pusher: Point2<f64>, object: Pose2) -> ControlStep {
        let stamp_ns = (time_s.max(0.0) * 1e9).round() as u64;
        let pose = |x, y, yaw| PlanarPose {
            stamp_ns,
            x,
            y,
            yaw,
        };
        self.take(Stream::Pusher, &pose(pusher.x, pusher.y, 0.0), stamp_ns);
        let object_pose = pose(object.position.x, object.position.y, object.yaw);
        self.take(Stream::Object, &object_pose, stamp_ns);
        self.plan(time_s, pusher, object)
    }

    /// A pose as it arrives, at the log time it has (a robot's streams, each at its own rate):
    /// put on the grid, learned from once its frame is final. A pose refused (out of order, not
    /// finite) is counted by the learner and planned past.
    pub fn take(&mut self, stream: Stream, pose: &PlanarPose, log_time_ns: u64) {
        let _ = self.learner.take(stream, pose, log_time_ns);
    }

    /// Plans a control step from the poses as they are at `time_s` (seconds since the control
    /// began), with the θ the run has after learning the frames that became final.
    pub fn plan(&mut self, time_s: f64, pusher: Point2<f64>, object: Pose2) -> ControlStep {
        let sites = self.planner.sites();
        self.learner.learn_holding(|f| is_away(sites, f));
        let run = self.learner.run();
        let truth = self.truth.unwrap_or(run.theta0());
        let decision = Decision::plan(
            &mut self.planner,
            run,
            (self.plan_with, &truth),
            object,
            pusher,
        );
        self.progress.record(&decision, time_s, self.planner.goal())
    }
}
