//! What is under the pointer in the scene, said in a tooltip: every footprint and marker drawn
//! there — the object now, each target pose and prediction (with the exaggeration its motion is
//! drawn with), the pusher, the COM markers. A newcomer sees an orange box well ahead of the
//! object and can ask what it is without opening the legend.

use eframe::egui;
use nalgebra::Point2;

use super::camera::Projection;
use super::content::{Content, Target};
use crate::app::colors;
use crate::app::state::AppState;

/// How near the pointer must be to a point marker to name it, points.
const MARKER_REACH: f32 = 10.0;

/// Shows, at the pointer, what of the scene lies under it (nothing when nothing does).
pub(super) fn say_what_is_under(
    response: &egui::Response,
    state: &AppState,
    projection: &Projection,
    content: &Content<'_>,
) {
    let Some(pointer) = response.hover_pos() else {
        return;
    };
    let lines = under(state, projection, content, pointer);
    if lines.is_empty() {
        return;
    }
    response.clone().on_hover_ui_at_pointer(|ui| {
        for line in &lines {
            ui.label(line);
        }
    });
}

/// The sentences for what lies under `pointer`, top first.
fn under(
    state: &AppState,
    projection: &Projection,
    content: &Content<'_>,
    pointer: egui::Pos2,
) -> Vec<String> {
    let layers = &state.settings().layers;
    let world = projection.to_world(pointer);
    let near = |at: Point2<f64>| projection.to_screen(at).distance(pointer) < MARKER_REACH;
    let mut lines = Vec::new();
    let com_at = |com: [f64; 2]| content.pose.point_in_world(Point2::from(com));
    if layers.com_true
        && let Some(com) = state.recording().and_then(|r| r.setting.com_offset)
        && near(com_at(com))
    {
        lines.push("the true COM (the recording's setting)".to_owned());
    }
    if !state.estimate_hidden()
        && let Some(theta) = state.theta()
        && near(com_at(theta.com_offset))
    {
        lines.push("the COM online learning estimates now (drag it to set θ)".to_owned());
    }
    if (world - content.robot).norm() <= content.pusher_radius {
        lines.push("the pusher".to_owned());
    }
    if let Some(outline) = content.outline {
        let gain = if content.gain == 1.0 {
            String::new()
        } else {
            format!(", its motion from now drawn ×{:.0}", content.gain)
        };
        for Target { pose, what, .. } in content.targets(state, &colors::DARK).into_iter().rev() {
            if outline.contains(pose.point_in_object(world)) {
                lines.push(format!("{what}{gain}"));
            }
        }
        if layers.true_now && outline.contains(content.pose.point_in_object(world)) {
            lines.push("the object, where it is measured now".to_owned());
        }
    }
    lines
}
