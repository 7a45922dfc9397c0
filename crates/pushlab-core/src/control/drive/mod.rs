//! The controller driving a robot through its Foxglove WebSocket server: the pusher's and the
//! object's poses come from the live session (`live::session`, the one `pushlab live` and the app
//! run), are learned as they arrive by live input's grid and learner ([`super::PoseControl`]), and
//! each control step's target goes through the [`commander`] (the poses' freshness, the plan's,
//! and the safety [`gate`]) before the session sends it by client publish. What `pushlab control
//! ws://…` runs. The app plans on its UI thread with the run it shows and its live worker runs the
//! same commander on the targets it is handed.
//!
//! The loop ends on the goal reached and held, the user's interrupt, the time limit, stale poses or
//! a lost link, each after the gate's one hold. Pause and disarm stop the sending and leave the
//! loop learning and planning, so that arming again goes on from where it is.

pub mod commander;
pub mod gate;

pub use commander::{Commander, CommanderConfig, Gated, UserAction, WORKSPACE_MARGIN_M};
pub use gate::{Command, Halt, Limits, STALE_AFTER, SafetyGate, Workspace};

#[cfg(not(target_arch = "wasm32"))]
mod robot;
#[cfg(not(target_arch = "wasm32"))]
pub use robot::{Drive, DriveConfig, DriveEnd, DriveError, DriveEvent};
