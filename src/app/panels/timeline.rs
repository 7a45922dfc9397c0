//! The timeline bar: play/pause, step ±1/±10, jump to start/end, loop, speed, and the scrub slider.

use eframe::egui;

use crate::app::state::playback::timeline::{MAX_SPEED, MIN_SPEED, TimelineCommand};
use pushlab_core::labels::SaveState;

use crate::app::state::{AppState, Command};

/// Draws the timeline bar at the bottom of the window.
pub fn bottom_bar(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let timeline = &state.timeline();
    let mut timeline_commands = Vec::new();
    let mut send = |c: TimelineCommand| timeline_commands.push(Command::Timeline(c));
    egui::Panel::bottom("timeline").show(ui, |ui| {
        ui.add_space(4.0);
        ui.horizontal(|ui| {
            super::live::strip(ui, state, commands);
            super::live_drive::strip(ui, state, commands);
            ui.add_enabled_ui(!timeline.is_empty(), |ui| {
                if ui
                    .button("Start")
                    .on_hover_text("Jump to start (Home)")
                    .clicked()
                {
                    send(TimelineCommand::JumpStart);
                }
                if ui
                    .button("-10")
                    .on_hover_text("Back 10 frames (Shift+←)")
                    .clicked()
                {
                    send(TimelineCommand::Step(-10));
                }
                if ui.button("-1").on_hover_text("Back 1 frame (←)").clicked() {
                    send(TimelineCommand::Step(-1));
                }
                let play = if timeline.playing { "Pause" } else { "Play" };
                if ui
                    .add(egui::Button::new(play).min_size(egui::vec2(60.0, 0.0)))
                    .on_hover_text("Play or pause (Space)")
                    .clicked()
                {
                    send(TimelineCommand::TogglePlay);
                }
                if ui.button("+1").on_hover_text("Step 1 frame (→)").clicked() {
                    send(TimelineCommand::Step(1));
                }
                if ui
                    .button("+10")
                    .on_hover_text("Step 10 frames (Shift+→)")
                    .clicked()
                {
                    send(TimelineCommand::Step(10));
                }
                if ui
                    .button("End")
                    .on_hover_text("Jump to end (End)")
                    .clicked()
                {
                    send(TimelineCommand::JumpEnd);
                }
                let mut looping = timeline.looping;
                if ui.checkbox(&mut looping, "Loop").changed() {
                    send(TimelineCommand::SetLoop(looping));
                }
                let mut speed = timeline.speed;
                let response = ui.add(
                    egui::Slider::new(&mut speed, MIN_SPEED..=MAX_SPEED)
                        .logarithmic(true)
                        .text("Speed")
                        .suffix("×")
                        .fixed_decimals(1),
                );
                if response.changed() {
                    send(TimelineCommand::SetSpeed(speed));
                }
                ui.separator();
                ui.monospace(format!(
                    "frame {:>5} / {:<5} {:>7.2} s",
                    timeline.frame(),
                    timeline.last_frame(),
                    timeline.elapsed()
                ));
                ui.separator();
                saved_indicator(ui, state);
                super::proposal_band::menu(ui, state, commands);
            });
        });
        // The label bands, the proposals band, the gaps band and the scrub slider take the whole width.
        let width = (ui.available_width() - 70.0).max(100.0);
        super::label_bands::ui(ui, state, width, commands);
        super::proposal_band::ui(ui, state, width, commands);
        super::gap_band::ui(ui, state, width, commands);
        let mut frame = timeline.frame();
        ui.spacing_mut().slider_width = width;
        let response = ui.add_enabled(
            !timeline.is_empty(),
            egui::Slider::new(&mut frame, 0..=timeline.last_frame())
                .text("Frame")
                .show_value(false),
        );
        if response.changed() {
            send(TimelineCommand::SeekTo(frame));
        }
        ui.add_space(2.0);
    });
    commands.extend(timeline_commands);
}

/// Whether the selected recording's labels are on disk: "labels saved", "unsaved", the reason a
/// save failed, or why the labels are read-only.
fn saved_indicator(ui: &mut egui::Ui, state: &AppState) {
    let Some(target) = state.label_target() else {
        return;
    };
    let file = target.document.display().to_string();
    if let Some(reason) = state.labels().read_only_reason(&target) {
        ui.colored_label(egui::Color32::from_rgb(230, 90, 80), "labels read-only")
            .on_hover_text(reason);
        return;
    }
    match state.labels().save_state(&target) {
        Some(SaveState::Saved) => {
            ui.colored_label(egui::Color32::from_rgb(120, 200, 120), "labels saved")
                .on_hover_text(format!("{file} holds every edit"));
        }
        Some(SaveState::Unsaved) => {
            ui.colored_label(egui::Color32::from_rgb(240, 200, 80), "labels unsaved…")
                .on_hover_text(format!("saving to {file} in a moment (Ctrl+S saves now)"));
        }
        Some(SaveState::Failed(message)) => {
            ui.colored_label(egui::Color32::from_rgb(230, 90, 80), "labels NOT saved")
                .on_hover_text(message);
        }
        None => {}
    }
}
