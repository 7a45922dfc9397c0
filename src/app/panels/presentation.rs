//! The presentation layout (demo mode), readable from the back of a room: the scene and the loss
//! plots large, big Play / Step / Reset buttons, and the narration line in large text. Browser, side
//! panel and timeline are hidden; the larger text is this layout's own style, so leaving it (F5 or
//! the Demos menu) restores the usual sizes.

use eframe::egui;

use crate::app::state::playback::timeline::TimelineCommand;
use crate::app::state::{AppState, Command};
use crate::app::state::{OnlineCommand, TrainingCommand};
use crate::app::view::View;

/// How much larger text and controls are than in the usual layout.
const SCALE: f32 = 1.8;

/// Draws the presentation layout below the menu bar.
pub fn ui(ui: &mut egui::Ui, state: &AppState, view: &mut View, commands: &mut Vec<Command>) {
    egui::Panel::bottom("presentation-controls").show(ui, |ui| {
        enlarge(ui, SCALE);
        ui.add_space(8.0);
        controls(ui, state, view, commands);
        ui.add_space(6.0);
        ui.add(egui::Label::new(egui::RichText::new(state.narration()).strong()).wrap());
        ui.add_space(8.0);
    });
    let height = ui.available_height();
    egui::Panel::bottom("presentation-plots")
        .exact_size((0.42 * height).max(160.0))
        .show(ui, |ui| {
            enlarge(ui, 1.3);
            view.plots_rect = ui.max_rect();
            super::plots::ui(ui, state, commands);
        });
    egui::CentralPanel::no_frame().show(ui, |ui| {
        super::camera::beside_scene(ui, state, &mut view.cameras);
        super::scene::ui(ui, state, &mut view.scene, commands);
    });
}

/// The demo's name, the big buttons, and the training progress while its model trains.
fn controls(ui: &mut egui::Ui, state: &AppState, view: &mut View, commands: &mut Vec<Command>) {
    ui.horizontal(|ui| {
        let title = match (&state.demos().active, state.recording()) {
            (Some(demo), Some(r)) => format!("{} — {}", demo.name, r.name),
            (None, Some(r)) => r.name.clone(),
            (_, None) => "no recording".to_owned(),
        };
        ui.heading(title);
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            if ui
                .button("Leave presentation")
                .on_hover_text("F5")
                .clicked()
            {
                view.presentation = false;
            }
        });
    });
    ui.horizontal(|ui| {
        let big = egui::vec2(150.0, 0.0);
        ui.add_enabled_ui(state.run().is_some(), |ui| {
            let play = if state.timeline().playing {
                "Pause"
            } else {
                "Play"
            };
            if ui.add(egui::Button::new(play).min_size(big)).clicked() {
                commands.push(Command::Timeline(TimelineCommand::TogglePlay));
            }
            if ui
                .add(egui::Button::new("Step").min_size(big))
                .on_hover_text("learn from the next frame")
                .clicked()
            {
                commands.push(Command::Timeline(TimelineCommand::Step(1)));
            }
            if ui
                .add(egui::Button::new("Reset").min_size(big))
                .on_hover_text("back to the first frame, forgetting what was learned")
                .clicked()
            {
                commands.push(Command::Timeline(TimelineCommand::JumpStart));
                commands.push(Command::Online(OnlineCommand::ResetTheta));
            }
        });
        if state.training().is_running() {
            ui.add_space(20.0);
            ui.spinner();
            ui.add(
                egui::ProgressBar::new(state.training().progress())
                    .desired_width(260.0)
                    .text(format!("training {}", state.training().phase())),
            );
            if ui.button("Cancel").clicked() {
                commands.push(Command::Training(TrainingCommand::Cancel));
            }
        }
    });
}

/// Scales this panel's text and controls (its own style: the rest of the window keeps its sizes).
fn enlarge(ui: &mut egui::Ui, factor: f32) {
    let style = ui.style_mut();
    for font in style.text_styles.values_mut() {
        font.size *= factor;
    }
    style.spacing.button_padding *= factor;
    style.spacing.interact_size *= factor;
    style.spacing.item_spacing *= factor;
}
