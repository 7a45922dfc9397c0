//! The controller driving a robot through its Foxglove WebSocket server: the pusher's and the
//! object's poses come from the live session (`live::session`, the one `pushlab live` and the app
//! run), are learned as they arrive by live input's grid and learner ([`super::PoseControl`]), and
//! each control step's target goes through the safety gate ([`gate`]) before the session sends it
//! by client publish. What `pushlab control ws://…` runs; the app can run the same loop on a
//! worker, with its buttons as [`UserAction`]s.
//!
//! The loop ends on the goal reached and held, the user's interrupt, the time limit, stale poses or
//! a lost link, each after the gate's one hold. Pause and disarm stop the sending and leave the
//! loop learning and planning, so that arming again goes on from where it is.

pub mod gate;

pub use gate::{Command, Halt, Limits, STALE_AFTER, SafetyGate, Workspace};

#[cfg(not(target_arch = "wasm32"))]
mod robot;
#[cfg(not(target_arch = "wasm32"))]
pub use robot::{Drive, DriveConfig, DriveEnd, DriveError, DriveEvent, UserAction};
