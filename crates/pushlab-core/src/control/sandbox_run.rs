//! The controller pushing the sandbox's mystery object to a goal, headless: each control step
//! reads the newest tracked frame, plans with the model as the run has learned it so far, moves the
//! pusher's target, and lets the sandbox make the frame; the frame is learned by the core's online
//! run, the one every recording is learned with. What `pushlab control --sandbox`, the experiments
//! and the tests run; the app drives the same planner from its own sandbox feed.

use nalgebra::Point2;

use super::goal::{DEFAULT_HOLD_STEPS, Goal, GoalError};
use super::planner::{Phase, Planner, PlannerConfig};
use super::{PlanWith, plan_step, planning_theta};
use crate::geometry::Pose2;
use crate::learn::{OnlineConfig, OnlineRun};
use crate::model::{CombinedModel, OnlineParams};
use crate::sandbox::mystery::RATE_HZ;
use crate::sandbox::{Mystery, Sandbox, SandboxEvent};
use crate::sim::TrackingNoise;
use crate::trajectory::Frame;

/// The longest a run may take before it is called failed, seconds.
pub const DEFAULT_TIME_LIMIT_S: f64 = 120.0;

/// Why a control run cannot start.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ControlError {
    #[error("the model cannot be set on the mystery object: {0}")]
    Model(String),
    #[error("the mystery object's outline: {0}")]
    Outline(String),
}

/// One control step, as `--json` prints it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ControlStep {
    pub step: usize,
    pub time_s: f64,
    /// The object's tracked pose the step planned from.
    pub object: Pose2,
    pub pusher: [f64; 2],
    /// The pusher's target sent this step.
    pub target: [f64; 2],
    pub phase: &'static str,
    /// θ the step planned with.
    pub theta: OnlineParams,
    pub position_error_m: f64,
    pub yaw_error_rad: f64,
    /// Model predictions the planner made.
    pub predictions: usize,
}

/// What a control step decided, before it is carried out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decision {
    pub object: Pose2,
    pub pusher: Point2<f64>,
    pub theta: OnlineParams,
    pub target: Point2<f64>,
    pub phase: Phase,
    pub predictions: usize,
}

impl Decision {
    /// A control step's decision: [`plan_step`] from `object` and `pusher` with what `run` has
    /// learned, and the θ it planned with ([`planning_theta`]). Where nothing can be planned the
    /// pusher holds (not reached: [`super::run_for`] gives the weighted prediction its physics
    /// run).
    pub fn plan(
        planner: &mut Planner,
        run: &OnlineRun,
        (plan_with, truth): (PlanWith, &OnlineParams),
        object: Pose2,
        pusher: Point2<f64>,
    ) -> Self {
        let theta = planning_theta(run, plan_with, truth);
        let planned = plan_step(planner, run, plan_with, truth, (&object, pusher));
        let (target, phase, predictions) = planned.map_or((pusher, Phase::Holding, 0), |plan| {
            (
                plan.target,
                plan.phase.unwrap_or(Phase::Holding),
                plan.predictions,
            )
        });
        Self {
            object,
            pusher,
            theta,
            target,
            phase,
            predictions,
        }
    }
}

/// A controller's count of its steps and of those it has held the goal in a row: what numbers a
/// [`ControlStep`] and says when the goal is reached and held. One for the sandbox's controller
/// and for the one on poses from outside.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Progress {
    steps: usize,
    held: usize,
}

impl Progress {
    /// The step `d` decided at `time_s`, counted, with its error from `goal`.
    pub(super) fn record(&mut self, d: &Decision, time_s: f64, goal: &Goal) -> ControlStep {
        self.held = match d.phase {
            Phase::Holding => self.held + 1,
            _ => 0,
        };
        let error = goal.error(&d.object);
        let step = ControlStep {
            step: self.steps,
            time_s,
            object: d.object,
            pusher: [d.pusher.x, d.pusher.y],
            target: [d.target.x, d.target.y],
            phase: d.phase.name(),
            theta: d.theta,
            position_error_m: error.position_m,
            yaw_error_rad: error.yaw_rad,
            predictions: d.predictions,
        };
        self.steps += 1;
        step
    }

    pub(super) fn steps(&self) -> usize {
        self.steps
    }

    /// Whether the goal is reached and held.
    pub(super) fn is_done(&self) -> bool {
        self.held >= DEFAULT_HOLD_STEPS
    }
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ControlOutcome {
    pub reached: bool,
    /// Seconds from the first step to the goal held (or to the time limit).
    pub time_s: f64,
    /// Metres the pusher moved.
    pub pusher_path_m: f64,
    /// The object's true pose's error at the end.
    pub final_position_error_m: f64,
    pub final_yaw_error_rad: f64,
    pub steps: usize,
    /// θ the run had learned at the end.
    pub theta_end: OnlineParams,
}

/// The sandbox, its online run and the planner (see the module documentation).
pub struct SandboxControl {
    sandbox: Sandbox,
    run: OnlineRun,
    planner: Planner,
    plan_with: PlanWith,
    truth: OnlineParams,
    progress: Progress,
    pusher_path_m: f64,
    last_pusher: Point2<f64>,
    /// The newest frame planned from (before the first push: the object at rest, untracked).
    newest: Option<Frame>,
    /// Per frame, whether the pusher was away from the object (see [`super::is_away`]): the run
    /// holds θ over samples that start or end there.
    away: Vec<bool>,
}

impl SandboxControl {
    /// The controller on `mystery`, planning with `model` as `plan_with` says, learning by
    /// `config`, to `goal`; `noise` on the poses it is given.
    pub fn new(
        mystery: Mystery,
        noise: Option<TrackingNoise>,
        model: &CombinedModel,
        plan_with: PlanWith,
        config: OnlineConfig,
        goal: Goal,
        planner: PlannerConfig,
    ) -> Result<Self, ControlError> {
        let setting = mystery.public_setting();
        let outline = setting
            .object
            .outline()
            .map_err(|e| ControlError::Outline(e.to_string()))?;
        let horizon = model.horizon();
        let run = super::run_for(model, &setting, plan_with, config)?;
        let planner = Planner::paced(
            &outline,
            setting.pusher_radius,
            goal,
            super::Pacing::sandbox(),
            horizon,
            planner,
        );
        let truth = OnlineParams {
            com_offset: mystery.hidden.com_offset,
            h: mystery.h,
        };
        let sandbox = Sandbox::new(mystery, noise);
        let last_pusher = sandbox.pusher();
        Ok(Self {
            sandbox,
            run,
            planner,
            plan_with,
            truth,
            progress: Progress::default(),
            pusher_path_m: 0.0,
            last_pusher,
            newest: None,
            away: Vec::new(),
        })
    }

    pub fn sandbox(&self) -> &Sandbox {
        &self.sandbox
    }

    pub fn run(&self) -> &OnlineRun {
        &self.run
    }

    pub fn planner(&self) -> &Planner {
        &self.planner
    }

    /// Whether the goal is reached and held.
    pub fn is_done(&self) -> bool {
        self.progress.is_done()
    }

    /// One control step: plan from the newest frame ([`SandboxControl::decide`]), then move the
    /// pusher's target, make the frame and learn it ([`SandboxControl::carry_out`]).
    pub fn step(&mut self) -> ControlStep {
        let decision = self.decide();
        self.carry_out(decision)
    }

    /// The planning half of a step (what a control step's cost is measured on).
    pub fn decide(&mut self) -> Decision {
        let (object, pusher) = match &self.newest {
            Some(f) => (f.object, f.robot),
            None => (self.sandbox.object_pose(), self.sandbox.pusher()),
        };
        Decision::plan(
            &mut self.planner,
            &self.run,
            (self.plan_with, &self.truth),
            object,
            pusher,
        )
    }

    /// The acting half of a step: the pusher's target held, the frame made and learned.
    pub fn carry_out(&mut self, d: Decision) -> ControlStep {
        let mut events = self.sandbox.hold(d.target);
        events.extend(self.sandbox.advance(1.0 / RATE_HZ));
        self.take(events);
        let now = self.sandbox.pusher();
        self.pusher_path_m += (now - self.last_pusher).norm();
        self.last_pusher = now;
        let time_s = self.progress.steps() as f64 / RATE_HZ;
        self.progress.record(&d, time_s, self.planner.goal())
    }

    /// Steps until the goal is held or `time_limit_s` has passed; each step handed to `each`.
    pub fn run_to_goal(
        &mut self,
        time_limit_s: f64,
        mut each: impl FnMut(&ControlStep),
    ) -> ControlOutcome {
        let limit = (time_limit_s * RATE_HZ).ceil() as usize;
        while !self.is_done() && self.progress.steps() < limit {
            let step = self.step();
            each(&step);
        }
        self.outcome()
    }

    /// How the run stands: reached or not, its time, path and the true pose's error.
    pub fn outcome(&self) -> ControlOutcome {
        let GoalError {
            position_m,
            yaw_rad,
        } = self.planner.goal().error(&self.sandbox.object_pose());
        ControlOutcome {
            reached: self.is_done(),
            time_s: self.progress.steps() as f64 / RATE_HZ,
            pusher_path_m: self.pusher_path_m,
            final_position_error_m: position_m,
            final_yaw_error_rad: yaw_rad,
            steps: self.progress.steps(),
            theta_end: self.run.theta_at(self.run.frontier()),
        }
    }

    /// The sandbox's frames onto the run, learned.
    fn take(&mut self, events: Vec<SandboxEvent>) {
        for event in events {
            let frames = match event {
                SandboxEvent::PushStarted { first, .. } => vec![first],
                SandboxEvent::Frames { frames, .. } => frames,
                SandboxEvent::PushEnded { .. } => continue,
            };
            self.newest = frames.last().copied().or(self.newest);
            let sites = self.planner.sites();
            self.away
                .extend(frames.iter().map(|f| super::is_away(sites, f)));
            self.run.extend(frames);
        }
        let from = self.run.frontier();
        self.run
            .learn_through(from, self.run.sample_count(), &self.away);
    }
}
