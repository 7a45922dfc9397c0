//! Drive, in File → Connect to a live robot…: the controller pushing the robot's object to a goal
//! through the robot's Foxglove server, as `pushlab control ws://…` does, with the app's buttons.
//!
//! The plan is made on the UI thread (`live_drive_steps`), a step per new frame of the live push, with the run
//! the app learns that push with (`driving`, the core's `plan_step`): the plan drawn, θ shown and
//! the target sent are one. The target goes to the live worker through its inbox, stamped; the
//! worker runs the core's `Commander` on it (the safety gate, the poses' freshness, the plan's),
//! since only the worker sees each pose as it arrives and holds the socket. So every rule of the
//! CLI's drive holds here too, and one more: a window that stops planning (frozen, or showing
//! another push) lets the plan go stale, and the worker holds the pusher.

use nalgebra::Point2;
use pushlab_core::control::drive::{Command, CommanderConfig, Halt, Workspace};
use pushlab_core::control::{Goal, Pacing, PlanWith, Planner, PlannerConfig};
use pushlab_core::geometry::Pose2;
use pushlab_core::model::OnlineParams;
use pushlab_core::recording::Setting;
use serde::{Deserialize, Serialize};

use crate::app::platform::Instant;
use crate::app::state::sources::driving::Driving;

/// What the Connect form asks of a drive; remembered with the rest of the server's choice.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct DriveChoice {
    /// Drive the robot in this session (armed only by the Arm button).
    pub on: bool,
    /// Where the pusher's target is published.
    pub command: String,
    /// The target's `header.frame_id`: the pose streams' frame.
    pub frame: String,
    /// The object's goal: centre `x, y` (metres) and yaw (radians), in the pose streams' frame.
    pub goal: [f64; 3],
    /// The pusher's top speed, m/s, and control steps a second: no target further than a step.
    pub speed: f64,
    pub control_hz: f64,
    pub plan_with: PlanWith,
}

impl Default for DriveChoice {
    /// `pushlab control`'s defaults.
    fn default() -> Self {
        Self {
            on: false,
            command: "/pusher_target".to_owned(),
            frame: String::new(),
            goal: [0.0; 3],
            speed: 0.04,
            control_hz: 10.0,
            plan_with: PlanWith::Online,
        }
    }
}

/// What the drive's buttons ask.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DriveCommand {
    /// Send the controller's targets from the next control step on.
    Arm,
    /// Hold the pusher where it is and stop sending; planning goes on (Arm goes on from there).
    Pause,
    /// As Pause, and forget the arming.
    Disarm,
    /// A new goal (`x, y, yaw`, the pose streams' frame), dragged in the scene: kept only where
    /// the object fits the workspace; an armed drive pauses, to go on toward it at Arm.
    SetGoal([f64; 3]),
}

/// What the UI asks of the worker's commander.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WorkerAsk {
    Arm,
    Halt(Halt),
}

/// The UI's half of the inbox: the newest target planned and when, and the asks in order.
#[derive(Debug, Default)]
pub struct ToWorker {
    pub target: Option<(Point2<f64>, Instant)>,
    pub asks: Vec<WorkerAsk>,
}

/// What the worker says of the drive: the UI copies it every frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DriveStatus {
    pub armed: bool,
    /// Why the gate stopped sending, since it was last armed.
    pub halted: Option<Halt>,
    /// Targets sent so far (holds included), and the last.
    pub sent: u64,
    pub last: Option<Command>,
    /// The workspace the targets are kept in, once the first poses gave it.
    pub workspace: Option<Workspace>,
    /// Why this server cannot be driven (it does not offer client publish): the session watches.
    pub refused: Option<String>,
}

/// What the worker needs to drive: where to send, and the commander's bounds.
#[derive(Clone, Debug)]
pub struct DriveSetup {
    pub command: String,
    pub frame: String,
    pub commander: CommanderConfig,
}

/// The drive of a running session: the controller planning on the UI thread.
pub struct LiveDrive {
    pub(in crate::app::state) driving: Driving,
    /// The true θ where the setting gives it (planning with the truth needs it).
    pub(in crate::app::state) truth: Option<OnlineParams>,
    /// The goal reached and held: planning stopped until armed again.
    pub(in crate::app::state) reached: bool,
    /// The drive's time when it was first armed: its time to the goal is counted from there,
    /// not from Connect.
    pub(in crate::app::state) armed_at_s: Option<f64>,
    /// How far the object reaches from its centre: a goal moved must keep it in the workspace.
    pub(in crate::app::state) object_reach: f64,
}

impl std::fmt::Debug for LiveDrive {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LiveDrive")
            .field("plan_with", &self.driving.plan_with)
            .field("steps", &self.driving.steps)
            .field("reached", &self.reached)
            .finish_non_exhaustive()
    }
}

impl LiveDrive {
    pub fn driving(&self) -> &Driving {
        &self.driving
    }

    pub fn reached(&self) -> bool {
        self.reached
    }
}

/// The controller and the worker's setup for `choice` on the object of `setting`, the grid at
/// `grid_hz`, or why it cannot drive.
pub(in crate::app::state) fn prepare(
    choice: &DriveChoice,
    setting: &Setting,
    model: Option<&pushlab_core::model::CombinedModel>,
    grid_hz: f64,
    generation: u64,
) -> Result<(LiveDrive, DriveSetup), String> {
    if choice.command.trim().is_empty() {
        return Err("driving needs the command topic the pusher's target is sent on".to_owned());
    }
    for (name, value) in [("speed", choice.speed), ("control rate", choice.control_hz)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(format!("the drive's {name} {value} is not positive"));
        }
    }
    let [x, y, yaw] = choice.goal;
    if !(x.is_finite() && y.is_finite() && yaw.is_finite()) {
        return Err("the drive's goal is not a number".to_owned());
    }
    let model = model.ok_or("driving needs a trained model to plan with")?;
    let truth = pushlab_core::control::truth_of(setting);
    if choice.plan_with == PlanWith::Truth && truth.is_none() {
        return Err(
            "planning with the true θ needs the setting's com_offset and h: choose another"
                .to_owned(),
        );
    }
    let outline = (setting.object.outline()).map_err(|e| format!("the object's outline: {e}"))?;
    let pacing = Pacing {
        pusher_speed: choice.speed,
        control_hz: choice.control_hz,
        grid_hz,
    };
    let goal = Pose2::new(x, y, yaw);
    let planner = Planner::paced(
        &outline,
        setting.pusher_radius,
        Goal::at(goal),
        pacing,
        model.horizon(),
        PlannerConfig::default(),
    );
    let setup = DriveSetup {
        command: choice.command.trim().to_owned(),
        frame: choice.frame.clone(),
        commander: CommanderConfig {
            pacing,
            workspace: None,
            goal: goal.position,
            object_reach: CommanderConfig::reach_of(&outline),
            arm: false,
        },
    };
    let drive = LiveDrive {
        driving: Driving::new(planner, choice.plan_with, grid_hz, generation),
        truth,
        reached: false,
        armed_at_s: None,
        object_reach: CommanderConfig::reach_of(&outline),
    };
    Ok((drive, setup))
}
