//! What the pointer does in the scene: drag the orange COM marker to steer `θ_online`, drag the
//! magenta diamond to move the recording's COM label, drag anywhere else to pan (which frees the
//! camera), wheel or pinch to zoom about the pointer, double-click to fit the whole push.

use eframe::egui::{self, Pos2};
use pushlab_core::geometry::Pose2;
use pushlab_core::labels::MetaField;
use pushlab_core::model::OnlineParams;

use super::camera::Projection;
use super::drive_goal;
use super::goal_handles::GoalHandles;
use super::sandbox::{self, Grips};
use super::view::{Drag, SceneView};
use crate::app::camera_mode::CameraMode;
use crate::app::state::OnlineCommand;
use crate::app::state::labels::labeling::{LabelAction, LabelTarget};
use crate::app::state::{AppState, Command};

/// Pick radius of the COM markers, points.
pub const PICK_RADIUS: f32 = 10.0;

/// Where the two draggable markers are on the screen this frame, if drawn.
#[derive(Clone, Copy, Debug, Default)]
pub struct Markers {
    pub com: Option<Pos2>,
    pub com_label: Option<Pos2>,
}

impl Markers {
    /// The marker within reach of `pointer`, the nearer of the two when both are.
    fn picked(&self, pointer: Pos2) -> Option<Drag> {
        let reach = |marker: Option<Pos2>| {
            marker
                .map(|m| pointer.distance(m))
                .filter(|&d| d < PICK_RADIUS)
        };
        match (reach(self.com), reach(self.com_label)) {
            (Some(a), Some(b)) if b < a => Some(Drag::ComLabel),
            (Some(_), _) => Some(Drag::Com),
            (None, Some(_)) => Some(Drag::ComLabel),
            (None, None) => None,
        }
    }

    /// Whether `pointer` is over one of the markers (or dragging it), for its highlight.
    pub fn hot(&self, which: Drag, pointer: Option<Pos2>, view: &SceneView) -> bool {
        view.drag == Some(which) || pointer.is_some_and(|p| self.picked(p) == Some(which))
    }
}

/// Handles this frame's pointer input on the scene; `projection` is the camera the markers were
/// placed with, `pose` the object's pose at the frame shown.
#[allow(clippy::too_many_arguments)] // each is one thing the interaction reads or changes
pub fn handle(
    ui: &egui::Ui,
    response: &egui::Response,
    state: &AppState,
    view: &mut SceneView,
    projection: &Projection,
    pose: &Pose2,
    (markers, grips, drive_goal): (&Markers, Option<&Grips>, Option<&GoalHandles>),
    commands: &mut Vec<Command>,
) {
    // Pick by where the button went down: egui reports the drag only after the pointer has moved a
    // few points, and a quick drag is past the marker by then. A sandbox's handles come first.
    if response.drag_started()
        && let Some(pointer) = ui
            .input(|i| i.pointer.press_origin())
            .or(response.interact_pointer_pos())
    {
        let grabbed = (grips
            .and_then(|g| g.grab(pointer, projection))
            .map(Drag::Sandbox))
        .or_else(|| {
            drive_goal
                .and_then(|h| h.grab(pointer))
                .map(Drag::DriveGoal)
        });
        view.drag = Some(
            grabbed
                .or_else(|| markers.picked(pointer))
                .unwrap_or(Drag::Pan),
        );
        if view.drag == Some(Drag::ComLabel) {
            commands.push(Command::Label(LabelAction::BeginGroup(
                "move the COM label".to_owned(),
            )));
        }
    }
    if response.dragged() {
        let com_under_pointer = || {
            response
                .interact_pointer_pos()
                .map(|p| pose.point_in_object(projection.to_world(p)))
        };
        match view.drag {
            Some(Drag::ComLabel) => {
                if let (Some(com), Some(target)) = (com_under_pointer(), state.label_target()) {
                    commands.push(move_com_label(&target, [com.x, com.y]));
                }
            }
            Some(Drag::Com) => {
                if let (Some(com), Some(theta)) = (com_under_pointer(), state.theta()) {
                    commands.push(Command::Online(OnlineCommand::SetTheta(OnlineParams {
                        com_offset: [com.x, com.y],
                        ..theta
                    })));
                }
            }
            Some(Drag::Sandbox(grab)) => {
                if let Some(pointer) = response.interact_pointer_pos() {
                    let world = projection.to_world(pointer);
                    view.arrow_to = Some(world);
                    commands.extend(sandbox::dragged(grab, world, pose));
                }
            }
            Some(Drag::DriveGoal(grab)) => {
                if let Some(pointer) = response.interact_pointer_pos() {
                    commands.extend(drive_goal::dragged(grab, projection.to_world(pointer)));
                }
            }
            Some(Drag::Pan) | None => {
                view.camera.pan(response.drag_delta());
                view.mode = CameraMode::Free;
            }
        }
    }
    if response.drag_stopped() {
        if view.drag == Some(Drag::ComLabel) {
            commands.push(Command::Label(LabelAction::EndGroup));
        }
        if let (Some(Drag::Sandbox(grab)), Some(grips)) = (view.drag, grips) {
            let world = response
                .interact_pointer_pos()
                .map(|p| projection.to_world(p))
                .or(view.arrow_to);
            if let Some(world) = world {
                commands.extend(sandbox::released(state, grab, world, grips));
            }
        }
        view.drag = None;
        view.arrow_to = None;
    }
    if response.hovered() {
        let (scroll, zoom) = ui.input(|i| (i.smooth_scroll_delta.y, i.zoom_delta()));
        let factor = zoom * (scroll / 400.0).exp();
        if (factor - 1.0).abs() > 1e-4
            && let Some(pointer) = response.hover_pos()
        {
            view.camera.zoom_about(projection.viewport, pointer, factor);
            // Following keeps the zoom; a fitted view zoomed into is the user's own.
            if view.mode == CameraMode::FitAll {
                view.mode = CameraMode::Free;
            }
        }
    }
    if response.double_clicked() {
        view.mode = CameraMode::FitAll;
    }
}

fn move_com_label(target: &LabelTarget, com_in_object: [f64; 2]) -> Command {
    Command::Label(LabelAction::Edit(pushlab_core::labels::Command::SetMeta {
        recording: target.recording.clone(),
        field: MetaField::ComOffset(Some(com_in_object)),
    }))
}
