//! The recordings browser: settings → trajectories with their metadata, split and label count, and
//! the load problems.

use std::path::Path;

use eframe::egui;
use pushlab_core::labels::LabelDocument;
use pushlab_core::labels::pipeline::labels_file_beside;

use crate::app::state::session::RecordingId;
use crate::app::state::{AppState, Command};

/// Draws the browser.
pub fn ui(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    ui.heading("Recordings");
    if state.session.sets.is_empty() {
        ui.label("Nothing open. Use File > Open, or drop files or folders here.");
    }
    egui::ScrollArea::vertical()
        .id_salt("browser")
        .max_height(ui.available_height() - problems_height(state))
        .show(ui, |ui| {
            for (set_index, set) in state.session.sets.iter().enumerate() {
                let setting = &set.setting;
                egui::CollapsingHeader::new(&setting.name)
                    .id_salt(("set", set_index))
                    .default_open(true)
                    .show(ui, |ui| {
                        setting_metadata(ui, setting);
                        // The labels file of the folder the last recording came from: a set's
                        // recordings share one, so it is looked up once per set, not per row.
                        let mut folder_labels: Option<(&Path, Option<&LabelDocument>)> = None;
                        for (index, recording) in set.recordings.iter().enumerate() {
                            let id = RecordingId {
                                set: set_index,
                                recording: index,
                            };
                            let selected = state.session.selected == Some(id);
                            let trajectory = &recording.trajectory;
                            let mut label = format!(
                                "{}  ·  {} frames, {:.1} s",
                                recording.name,
                                trajectory.len(),
                                trajectory.duration()
                            );
                            let folder = recording.source.parent().unwrap_or(Path::new("."));
                            let document = match folder_labels {
                                Some((f, document)) if f == folder => document,
                                _ => {
                                    let document = state
                                        .labels
                                        .document(&labels_file_beside(&recording.source));
                                    folder_labels = Some((folder, document));
                                    document
                                }
                            };
                            let key = recording.source.file_name().map(|n| n.to_string_lossy());
                            if let Some(labels) =
                                document.zip(key).and_then(|(d, key)| d.recording(&key))
                            {
                                if let Some(split) = labels.meta.split {
                                    label.push_str(&format!("  ·  {}", split.name()));
                                }
                                let count = labels.segments.len() + labels.events.len();
                                match count {
                                    0 => {}
                                    1 => label.push_str("  ·  1 label"),
                                    n => label.push_str(&format!("  ·  {n} labels")),
                                }
                            }
                            let response = ui.selectable_label(selected, label);
                            let response = response.on_hover_ui(|ui| {
                                ui.label(recording.source.display().to_string());
                                ui.label(format!("{:.0} Hz", trajectory.mean_rate_hz()));
                                if let Some(entry) = &recording.entry {
                                    if let Some(offset) = entry.contact_offset {
                                        ui.label(format!("contact offset {:.1} mm", offset * 1e3));
                                    }
                                    if let Some(angle) = entry.push_angle_deg {
                                        ui.label(format!("push angle {angle:.0}°"));
                                    }
                                }
                                for warning in &recording.warnings {
                                    ui.colored_label(ui.visuals().warn_fg_color, warning);
                                }
                            });
                            if response.clicked() && !selected {
                                commands.push(Command::Select(id));
                            }
                        }
                    });
            }
        });
    problems(ui, state, commands);
}

fn setting_metadata(ui: &mut egui::Ui, setting: &pushlab_core::recording::Setting) {
    use pushlab_core::recording::ObjectShape;
    let shape = match &setting.object {
        ObjectShape::Box { width, length } => {
            format!("box {:.0} × {:.0} mm", width * 1e3, length * 1e3)
        }
        ObjectShape::Polygon { vertices } => format!("polygon, {} vertices", vertices.len()),
    };
    let mut lines = vec![
        shape,
        format!("pusher r {:.1} mm", setting.pusher_radius * 1e3),
    ];
    if let Some(material) = &setting.material {
        lines.push(material.clone());
    }
    match (setting.com_offset, setting.h) {
        (Some([x, y]), Some(h)) => lines.push(format!(
            "true COM offset ({:.1}, {:.1}) mm, h {:.1} mm",
            x * 1e3,
            y * 1e3,
            h * 1e3
        )),
        (Some([x, y]), None) => lines.push(format!(
            "true COM offset ({:.1}, {:.1}) mm",
            x * 1e3,
            y * 1e3
        )),
        (None, Some(h)) => lines.push(format!("true h {:.1} mm", h * 1e3)),
        (None, None) => {}
    }
    ui.weak(lines.join(" · "));
}

fn problems_height(state: &AppState) -> f32 {
    if state.session.problems.is_empty() {
        0.0
    } else {
        160.0
    }
}

/// Load problems, each naming the file and the reason; they stay until dismissed.
fn problems(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    if state.session.problems.is_empty() {
        return;
    }
    ui.separator();
    ui.horizontal(|ui| {
        ui.colored_label(
            ui.visuals().error_fg_color,
            format!(
                "{} file(s) could not be loaded",
                state.session.problems.len()
            ),
        );
        if ui.small_button("Dismiss").clicked() {
            commands.push(Command::DismissProblems);
        }
    });
    egui::ScrollArea::vertical()
        .id_salt("problems")
        .max_height(130.0)
        .show(ui, |ui| {
            for problem in &state.session.problems {
                ui.label(egui::RichText::new(&problem.message).small())
                    .on_hover_text(problem.path.display().to_string());
            }
        });
}
