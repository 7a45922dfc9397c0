//! The scene's own view state: the camera and how it moves, the legend's fold, the drag in progress.
//! Kept apart from the drawing (`mod.rs`) and the pointer handling (`interaction`), which both
//! read and change it.

use eframe::egui::{self, Rect};

use nalgebra::Point2;

use super::camera::{Camera, Projection};
use super::goal_handles::GoalGrab;
use super::legend;
use super::sandbox::Grab;
use crate::app::camera_mode::CameraMode;
use crate::app::state::recordings::session::RecordingId;

/// What a drag that started in the scene moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Drag {
    /// The estimated COM: steers `θ_online` at the frame shown.
    Com,
    /// The COM label of the recording's metadata (one undo step per drag).
    ComLabel,
    /// The view.
    Pan,
    /// A sandbox's pusher, its guess, or an arrow drawn from its outline.
    Sandbox(Grab),
    /// A robot's Drive goal: its ghost or its knob.
    DriveGoal(GoalGrab),
}

/// The scene's view state: the camera and how it moves, the legend, the drag in progress.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneView {
    pub camera: Camera,
    pub mode: CameraMode,
    /// Whether the legend (the layer toggles) is unfolded.
    pub legend_open: bool,
    /// What the pointer is dragging.
    pub drag: Option<Drag>,
    /// Where an arrow being drawn on a sandbox's object ends now, world metres.
    pub arrow_to: Option<Point2<f64>>,
    /// The recording the camera was last framed for; a new selection is framed afresh.
    pub(super) framed: Option<RecordingId>,
    /// Where the scene was drawn last frame, screen points (for PNG export and tests).
    pub(super) rect: Rect,
}

impl Default for SceneView {
    fn default() -> Self {
        Self {
            camera: Camera::default(),
            mode: CameraMode::default(),
            legend_open: false,
            drag: None,
            arrow_to: None,
            framed: None,
            rect: Rect::NOTHING,
        }
    }
}

impl SceneView {
    /// Where the scene was drawn last frame, screen points.
    pub fn rect(&self) -> Rect {
        self.rect
    }

    /// The part of the scene the camera uses: all of it, or right of the open legend.
    pub fn viewport(&self) -> Rect {
        if self.legend_open {
            Rect::from_min_max(
                egui::pos2(legend::area(self.rect).right(), self.rect.top()),
                self.rect.max,
            )
        } else {
            self.rect
        }
    }

    /// How world points were mapped to the screen last frame.
    pub fn projection(&self) -> Projection {
        self.camera.on(self.viewport())
    }
}
