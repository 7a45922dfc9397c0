//! A robot's Drive goal in the scene: its ghost moved and turned as the sandbox's is
//! (`goal_handles`), each drag sent as the drive's `SetGoal` (the state decides whether it may
//! move there, and pauses an armed drive).

use eframe::egui;
use nalgebra::Point2;
use pushlab_core::geometry::Outline;

use super::camera::Projection;
use super::goal_handles::{GoalGrab, GoalHandles};
use super::view::{Drag, SceneView};
use crate::app::state::sources::live::{DriveCommand, LiveCommand};
use crate::app::state::{AppState, Command};

/// The handles of the goal of the drive of the live push shown, for an object of `outline`.
pub fn handles(
    state: &AppState,
    projection: &Projection,
    outline: &Outline,
) -> Option<GoalHandles> {
    let drive = state.live_drive_shown()?;
    Some(GoalHandles::of(
        outline,
        drive.driving().goal().pose,
        projection,
    ))
}

/// The command a drag of `grab` to `pointer` (world) sends.
pub fn dragged(grab: GoalGrab, pointer: Point2<f64>) -> Option<Command> {
    let goal = grab.dragged_to(pointer)?;
    Some(Command::Live(LiveCommand::Drive(DriveCommand::SetGoal(
        goal,
    ))))
}

/// The goal's ghost and its handles, the one under the pointer or dragged bolder.
pub fn draw(
    painter: &egui::Painter,
    state: &AppState,
    projection: &Projection,
    outline: &Outline,
    view: &SceneView,
    response: &egui::Response,
) {
    let Some(handles) = handles(state, projection, outline) else {
        return;
    };
    let hot = match view.drag {
        Some(Drag::DriveGoal(grab)) => Some(grab),
        _ => response.hover_pos().and_then(|p| handles.grab(p)),
    };
    handles.draw(painter, projection, outline, "goal", hot);
}
