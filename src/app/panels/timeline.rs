//! The timeline bar: play/pause, step ±1/±10, jump to start/end, loop, speed, and the scrub slider.

use eframe::egui;

use crate::app::state::timeline::{MAX_SPEED, MIN_SPEED, TimelineCommand};
use crate::app::state::{AppState, Command};

/// Draws the timeline bar at the bottom of the window.
pub fn bottom_bar(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let timeline = &state.timeline;
    let mut send = |c: TimelineCommand| commands.push(Command::Timeline(c));
    egui::Panel::bottom("timeline").show(ui, |ui| {
        ui.add_space(4.0);
        ui.horizontal(|ui| {
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
            });
        });
        // The scrub slider takes the whole width.
        let mut frame = timeline.frame();
        ui.spacing_mut().slider_width = (ui.available_width() - 70.0).max(100.0);
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
}
