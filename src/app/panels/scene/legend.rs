//! The legend, which doubles as the layer toggles: each entry is a checkbox in its layer's colour.
//! Folded by default; open, it takes a strip at the scene's left that the camera leaves free (see
//! `camera`), so it never covers the object. Toggles send [`Command::SetLayers`].

use eframe::egui::{self, Color32, Rect, Vec2};

use crate::app::colors::{self, Palette};
use crate::app::state::playback::layers::Layers;
use crate::app::state::playback::predictions::PredictionLayer;
use crate::app::state::{AppState, Command};

/// Width of the open legend, points; the camera's viewport starts right of it.
pub const WIDTH: f32 = 236.0;

/// The open legend's layer toggles and the motion gain, drawn in `area` (the scene's left strip).
/// A prediction layer that draws nothing, or draws a model trained on other data, says so.
pub fn ui(ui: &mut egui::Ui, area: Rect, state: &AppState, commands: &mut Vec<Command>) {
    let layers = &state.settings().layers;
    let mut edited = layers.clone();
    let mut child = ui.new_child(egui::UiBuilder::new().max_rect(area.shrink(6.0)));
    egui::Frame::popup(child.style())
        .fill(colors::of(ui.ctx()).legend_fill)
        .show(&mut child, |ui| {
            // A scene shorter than the legend scrolls it rather than cutting its last rows off.
            egui::ScrollArea::vertical()
                .max_height(area.height() - 24.0)
                .show(ui, |ui| toggles(ui, state, &mut edited));
        });
    if edited != *layers {
        commands.push(Command::SetLayers(edited));
    }
}

/// The legend's rows: a toggle per layer, the grid's, and the motion gain.
fn toggles(ui: &mut egui::Ui, state: &AppState, edited: &mut Layers) {
    ui.set_width(WIDTH - 30.0);
    ui.spacing_mut().item_spacing.y = 1.0;
    for (on, label, color, layer) in entries(edited, colors::of(ui.ctx())) {
        ui.checkbox(on, egui::RichText::new(label).color(color).small());
        if let Some(note) = layer.and_then(|l| state.layer_note(l)) {
            ui.indent(label, |ui| {
                ui.label(egui::RichText::new(note).small().weak());
            });
        }
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
}

/// A toggle: the layer's switch, label and colour, and the prediction it draws, if any.
type Entry<'a> = (&'a mut bool, &'static str, Color32, Option<PredictionLayer>);

/// The toggles in the order the legend lists them.
fn entries<'a>(layers: &'a mut Layers, palette: &Palette) -> [Entry<'a>; 17] {
    use PredictionLayer::{Fixed, Online, Physics, PureNn};
    [
        (
            &mut layers.true_now,
            "True footprint now",
            palette.truth,
            None,
        ),
        (
            &mut layers.true_target,
            "True footprint at target (dashed)",
            palette.truth,
            None,
        ),
        (
            &mut layers.predicted_online,
            "Predicted: online θ",
            palette.online,
            Some(Online),
        ),
        (
            &mut layers.predicted_fixed,
            "Predicted: fixed θ(0)",
            palette.fixed,
            Some(Fixed),
        ),
        (
            &mut layers.predicted_pure_nn,
            "Predicted: pure NN",
            palette.pure_nn,
            Some(PureNn),
        ),
        (
            &mut layers.predicted_physics,
            "Predicted: physics only, online θ",
            palette.physics,
            Some(Physics),
        ),
        (
            &mut layers.com_estimated,
            "Estimated COM (drag me)",
            palette.online,
            None,
        ),
        (
            &mut layers.com_ellipse,
            "COM 95 % ellipse",
            palette.online,
            None,
        ),
        (
            &mut layers.what_if,
            "What if: k steps ahead (ghosts)",
            palette.online,
            None,
        ),
        (
            &mut layers.controller,
            "What would the controller do here (to where the push ends)",
            palette.suggestion,
            None,
        ),
        (&mut layers.com_true, "True COM ×", palette.truth, None),
        (
            &mut layers.com_best,
            "Best θ's COM, ring (Steer: Find the best θ)",
            palette.online,
            None,
        ),
        (
            &mut layers.com_label,
            "Labelled COM, diamond (drag me)",
            palette.com_label,
            None,
        ),
        (
            &mut layers.contact,
            "Contact c and u_c",
            palette.contact,
            None,
        ),
        (
            &mut layers.next_pushes,
            "Next pushes, arrows (Steer: Suggest)",
            palette.suggestion,
            None,
        ),
        (&mut layers.robot_path, "Robot path", palette.robot, None),
        (&mut layers.trails, "Trails", palette.robot, None),
    ]
}

/// The strip of `scene` the open legend takes.
pub fn area(scene: Rect) -> Rect {
    Rect::from_min_size(
        scene.min,
        Vec2::new(WIDTH.min(scene.width()), scene.height()),
    )
}
