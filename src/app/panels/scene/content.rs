//! What the scene draws at the frame shown (`Content`) and the footprints of the target frame
//! (`Target`), apart from the drawing so that the hover's words and the camera read the same list.

use nalgebra::Point2;
use pushlab_core::geometry::{Outline, Pose2};
use pushlab_core::inspect::Rollout;

use super::camera::WorldBox;
use super::draw::{self, FootprintStyle};
use crate::app::colors::Palette;
use crate::app::state::AppState;
use crate::app::state::playback::predictions::FramePredictions;

/// A footprint drawn at the target frame: where, how, and what it is (said on hover).
pub(super) struct Target {
    pub(super) pose: Pose2,
    pub(super) style: FootprintStyle,
    pub(super) what: &'static str,
}

/// What is drawn at the frame shown.
pub(super) struct Content<'a> {
    pub(super) pose: Pose2,
    pub(super) robot: Point2<f64>,
    pub(super) pusher_radius: f64,
    pub(super) outline: Option<&'a Outline>,
    pub(super) predictions: Option<FramePredictions>,
    pub(super) gain: f64,
    /// The what-if rollout from this frame, when its layer is on.
    pub(super) what_if: Option<&'a Rollout>,
}

impl Content<'_> {
    /// The footprints drawn at the target frame, each with its style, for the layers switched on.
    pub(super) fn targets(&self, state: &AppState, palette: &Palette) -> Vec<Target> {
        let layers = &state.settings().layers;
        let mut targets = Vec::new();
        // At a live push's newest frame no later frame is known yet: the online model's prediction
        // a horizon ahead (the pusher keeping its velocity) is drawn instead.
        if layers.predicted_online
            && let Some((_, pose)) = state.growing_ahead()
        {
            let (moved, turned) = self.pose.motion_to(&pose);
            let pose = self.pose.moved_by(moved * self.gain, turned * self.gain);
            targets.push(Target {
                pose,
                style: FootprintStyle::predicted(palette.online),
                what: "the online model's prediction a horizon past the newest frame, the pusher \
                       keeping its velocity",
            });
        }
        let Some(p) = &self.predictions else {
            return targets;
        };
        let at = |motion| draw::exaggerated(&self.pose, motion, self.gain);
        if layers.true_target {
            targets.push(Target {
                pose: at(&p.sample.target),
                style: FootprintStyle::measured_target(palette),
                what: "the measured pose at the target frame",
            });
        }
        if layers.predicted_fixed {
            targets.push(Target {
                pose: at(&p.fixed.prediction.motion),
                style: FootprintStyle::predicted(palette.fixed),
                what: "the fixed model's prediction (θ_online(0))",
            });
        }
        if layers.predicted_physics
            && let Some(physics) = &p.physics
        {
            targets.push(Target {
                pose: at(&physics.motion),
                style: FootprintStyle::predicted(palette.physics),
                what: "physics alone's prediction (Lynch's model, no network)",
            });
        }
        if layers.predicted_pure_nn
            && let Some(pure_nn) = &p.pure_nn
        {
            targets.push(Target {
                pose: at(&pure_nn.motion),
                style: FootprintStyle::predicted(palette.pure_nn),
                what: "the pure network's prediction",
            });
        }
        if layers.predicted_online {
            targets.push(Target {
                pose: at(&p.online.prediction.motion),
                style: FootprintStyle::predicted(palette.online),
                what: "the online model's prediction (θ as learned)",
            });
        }
        targets
    }

    /// The box around the object's footprint at `pose` (or a point without an outline).
    pub(super) fn footprint_box(&self, pose: &Pose2) -> Option<WorldBox> {
        match self.outline {
            Some(outline) => {
                WorldBox::around(outline.vertices().iter().map(|v| pose.point_in_world(*v)))
            }
            None => WorldBox::around([pose.position]),
        }
    }
}
