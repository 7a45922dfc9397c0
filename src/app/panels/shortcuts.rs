//! The keyboard cheat-sheet (`?` or F1): the fixed bindings from [`crate::app::keys::BINDINGS`] and
//! the label hotkeys of the selected recording's labels file, so it always shows what the keys do.

use eframe::egui;
use pushlab_core::labels::LabelSchema;

use crate::app::keys::{BINDINGS, STEER_HELP, STEER_KEYS, label_hotkey_rows};
use crate::app::state::AppState;

/// Draws the cheat-sheet window while `open`.
pub fn window(ctx: &egui::Context, state: &AppState, open: &mut bool) {
    let default_schema = LabelSchema::default();
    let schema = state
        .label_target()
        .and_then(|t| state.labels().schema_of(&t))
        .unwrap_or(&default_schema);
    egui::Window::new("Keyboard shortcuts")
        .open(open)
        .resizable(false)
        .collapsible(false)
        .show(ctx, |ui| {
            ui.weak("Keys act when no text field has the keyboard.");
            egui::Grid::new("shortcut-sheet")
                .num_columns(2)
                .striped(true)
                .show(ui, |ui| {
                    for binding in &BINDINGS {
                        ui.monospace(ctx.format_shortcut(&binding.shortcut));
                        ui.label(binding.help);
                        ui.end_row();
                    }
                    ui.monospace("?");
                    ui.label("show / hide this sheet");
                    ui.end_row();
                    // The same text as the bindings' rows (the fonts draw →, not ⏵).
                    let arrows: Vec<String> = STEER_KEYS
                        .iter()
                        .map(|(k, _)| {
                            ctx.format_shortcut(&egui::KeyboardShortcut::new(
                                egui::Modifiers::NONE,
                                *k,
                            ))
                        })
                        .collect();
                    ui.monospace(arrows.join(" "));
                    ui.label(STEER_HELP);
                    ui.end_row();
                });
            ui.separator();
            ui.strong("Label keys (from the labels file)");
            egui::Grid::new("label-key-sheet")
                .num_columns(2)
                .striped(true)
                .show(ui, |ui| {
                    for (key, label, what) in label_hotkey_rows(schema) {
                        ui.monospace(key);
                        ui.label(format!("{label}: {what}"));
                        ui.end_row();
                    }
                });
        });
}
