//! The top bar: the File menu (open, recent, export, models) and the status line.

use eframe::egui;

use crate::app::View;
use crate::app::dialogs::DialogRequest;
use crate::app::state::{AppState, Command};

/// Draws the menu bar and the status line.
pub fn top_bar(ui: &mut egui::Ui, state: &AppState, view: &mut View, commands: &mut Vec<Command>) {
    egui::Panel::top("menu").show(ui, |ui| {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
                if ui.button("Open files…").clicked() {
                    view.dialogs.open(DialogRequest::OpenFiles);
                }
                if ui.button("Open folder…").clicked() {
                    view.dialogs.open(DialogRequest::OpenFolder);
                }
                ui.menu_button("Open recent", |ui| {
                    if state.recent.is_empty() {
                        ui.label("nothing yet");
                    }
                    for path in &state.recent {
                        if ui.button(path.display().to_string()).clicked() {
                            commands.push(Command::Open(vec![path.clone()]));
                        }
                    }
                });
                ui.separator();
                if ui.button("Load model…").clicked() {
                    view.dialogs.open(DialogRequest::LoadModel);
                }
                if ui
                    .add_enabled(
                        state.models.combined.is_some(),
                        egui::Button::new("Save model…"),
                    )
                    .clicked()
                {
                    view.dialogs.open(DialogRequest::SaveModel);
                }
                ui.separator();
                if ui.button("Export scene as PNG…").clicked() {
                    view.dialogs.open(DialogRequest::SaveScene);
                }
                if ui.button("Export plots as PNG…").clicked() {
                    view.dialogs.open(DialogRequest::SavePlots);
                }
                if ui
                    .add_enabled(
                        state.run.is_some(),
                        egui::Button::new("Export losses as CSV…"),
                    )
                    .clicked()
                {
                    view.dialogs.open(DialogRequest::SaveLossCsv);
                }
            });
            ui.separator();
            let model = match &state.models.source {
                Some(source) => format!("Model: {} ({source})", state.models.learner_name()),
                None => format!("Model: {}", state.models.learner_name()),
            };
            ui.label(model);
            if let Some(paths) = state.session.loading() {
                ui.separator();
                ui.spinner();
                ui.label(format!("loading {} path(s)…", paths.len()));
            }
            if let Some(status) = &state.status {
                ui.separator();
                ui.label(status);
            }
        });
    });
}
