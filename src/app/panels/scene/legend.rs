//! The legend, which doubles as the layer toggles: each entry is a checkbox in its layer's colour.
//! Folded by default; open, it takes a strip at the scene's left that the camera leaves free (see
//! `camera`), so it never covers the object. Toggles send [`Command::SetLayers`].

use eframe::egui::{self, Color32, Rect, Vec2};

use crate::app::colors;
use crate::app::state::Command;
use crate::app::state::layers::Layers;

/// Width of the open legend, points; the camera's viewport starts right of it.
pub const WIDTH: f32 = 236.0;

/// The open legend's layer toggles and the motion gain, drawn in `area` (the scene's left strip).
pub fn ui(ui: &mut egui::Ui, area: Rect, layers: &Layers, commands: &mut Vec<Command>) {
    let mut edited = layers.clone();
    let mut child = ui.new_child(egui::UiBuilder::new().max_rect(area.shrink(6.0)));
    egui::Frame::popup(child.style())
        .fill(Color32::from_black_alpha(200))
        .show(&mut child, |ui| {
            ui.set_width(WIDTH - 30.0);
            ui.spacing_mut().item_spacing.y = 1.0;
            for (on, label, color) in entries(&mut edited) {
                ui.checkbox(on, egui::RichText::new(label).color(color).small());
            }
            ui.checkbox(
                &mut edited.grid,
                egui::RichText::new("Grid (metres)").small(),
            );
            ui.add(
                egui::Slider::new(&mut edited.motion_gain, 1.0..=50.0)
                    .logarithmic(true)
                    .text(egui::RichText::new("Motion ×").small()),
            )
            .on_hover_text("Target poses are drawn with their motion from now multiplied by this");
        });
    if edited != *layers {
        commands.push(Command::SetLayers(edited));
    }
}

/// The toggles with their labels and colours, in the order the legend lists them.
fn entries(layers: &mut Layers) -> [(&mut bool, &'static str, Color32); 12] {
    [
        (&mut layers.true_now, "True footprint now", colors::TRUE),
        (
            &mut layers.true_target,
            "True footprint at target (dashed)",
            colors::TRUE,
        ),
        (
            &mut layers.predicted_online,
            "Predicted: online θ",
            colors::ONLINE,
        ),
        (
            &mut layers.predicted_fixed,
            "Predicted: fixed θ(0)",
            colors::FIXED,
        ),
        (
            &mut layers.predicted_pure_nn,
            "Predicted: pure NN",
            colors::PURE_NN,
        ),
        (
            &mut layers.predicted_physics,
            "Predicted: physics only",
            colors::PHYSICS,
        ),
        (
            &mut layers.com_estimated,
            "Estimated COM (drag me)",
            colors::ONLINE,
        ),
        (&mut layers.com_true, "True COM ×", colors::TRUE),
        (
            &mut layers.com_label,
            "Labelled COM, diamond (drag me)",
            colors::COM_LABEL,
        ),
        (&mut layers.contact, "Contact c and u_c", colors::CONTACT),
        (&mut layers.robot_path, "Robot path", colors::ROBOT),
        (&mut layers.trails, "Trails", colors::ROBOT),
    ]
}

/// The strip of `scene` the open legend takes.
pub fn area(scene: Rect) -> Rect {
    Rect::from_min_size(
        scene.min,
        Vec2::new(WIDTH.min(scene.width()), scene.height()),
    )
}
