//! The controller pushing a growing push to a goal, whoever moves the pusher: the sandbox's
//! simulated object (`sandbox_goal`) or a robot through the live session (`live_drive`). Both plan
//! on the UI thread, a step per new frame of the push, with the run the app learns the push with
//! (the core's `plan_step`), so the plan drawn and the θ shown are the ones it acts on; and both
//! hold θ over the frames where the pusher is away from the object (`control::is_away`, flagged
//! by `grow`), kept here.

use pushlab_core::control::goal::DEFAULT_HOLD_STEPS;
use pushlab_core::control::{Phase, Plan, PlanWith, Planner};

/// The controller pushing to a goal.
pub struct Driving {
    pub(in crate::app::state) planner: Planner,
    pub(in crate::app::state) plan_with: PlanWith,
    /// Frames of the growing push planned from so far (a plan per new frame).
    pub(in crate::app::state) frames_seen: usize,
    /// Frames pushed so far (one per control step in the sandbox), and the control steps the
    /// object has stayed within tolerance with the pusher holding.
    pub(in crate::app::state) steps: usize,
    pub(in crate::app::state) held: usize,
    /// Per frame of the driven push (its run's generation first), whether the pusher was away
    /// from the object: kept as the frames arrive, so that each learning batch tests only the new
    /// frames.
    pub(in crate::app::state) away: (u64, Vec<bool>),
    /// The frames a second `steps` counts.
    rate_hz: f64,
}

impl Driving {
    /// A controller about to push with `planner`, its steps counted at `rate_hz`, on the run of
    /// `generation`.
    pub fn new(planner: Planner, plan_with: PlanWith, rate_hz: f64, generation: u64) -> Self {
        Self {
            planner,
            plan_with,
            frames_seen: 0,
            steps: 0,
            held: 0,
            away: (generation, Vec::new()),
            rate_hz,
        }
    }

    /// The last step's plan: the arc drawn ahead of the object, the pusher's way.
    pub fn plan(&self) -> &Plan {
        self.planner.plan()
    }

    pub fn plan_with(&self) -> PlanWith {
        self.plan_with
    }

    /// Where the object should go.
    pub fn goal(&self) -> &pushlab_core::control::Goal {
        self.planner.goal()
    }

    /// Whether a step was planned yet (the plan is there to draw).
    pub fn has_planned(&self) -> bool {
        self.steps > 0
    }

    /// Seconds of pushing so far.
    pub fn time_s(&self) -> f64 {
        self.steps as f64 / self.rate_hz
    }

    /// Counts a step planned on the push's first `frames` frames, whose plan was in `phase`:
    /// whether the goal is now reached and held (held still for [`DEFAULT_HOLD_STEPS`] steps).
    pub(in crate::app::state) fn count(&mut self, frames: usize, phase: Option<Phase>) -> bool {
        self.steps += frames.saturating_sub(self.frames_seen).max(1);
        self.frames_seen = frames;
        self.held = if phase == Some(Phase::Holding) {
            self.held + 1
        } else {
            0
        };
        self.held >= DEFAULT_HOLD_STEPS
    }
}
