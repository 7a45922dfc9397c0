//! The Labels tab: which label to paint, in/out points, the labels at this frame, every segment and
//! event of the recording (jump to it, delete it), the metadata form, undo/redo, save, revert and
//! export. Every change is a [`LabelAction`], so undo covers it.

use eframe::egui;
use pushlab_core::labels::{
    self, LabelDocument, LabelKind, LabelSchema, MetaField, RecordingLabels, RecordingMeta,
    SaveState, Split,
};
use pushlab_core::recording::PushSide;

use super::label_bands::color;
use crate::app::dialogs::{DialogRequest, Dialogs};
use crate::app::format;
use crate::app::state::labels::labeling::{LabelAction, LabelTarget};
use crate::app::state::playback::timeline::TimelineCommand;
use crate::app::state::{AppState, Command};

/// Draws the Labels tab.
pub fn ui(ui: &mut egui::Ui, state: &AppState, dialogs: &mut Dialogs, commands: &mut Vec<Command>) {
    let Some(target) = state.label_target() else {
        ui.weak("Select a recording to label it.");
        return;
    };
    let mut act = |a: LabelAction| commands.push(Command::Label(a));
    ui.label(format!("Labels of {}", target.recording));
    ui.small(target.document.display().to_string());
    if let Some(reason) = state.labels().read_only_reason(&target) {
        ui.colored_label(
            egui::Color32::from_rgb(230, 90, 80),
            format!("Read-only, the labels file is left untouched: {reason}"),
        );
        return;
    }
    let Some(document) = state.labels().document(&target.document) else {
        return;
    };
    save_state(ui, document, &mut act);
    conflict(ui, document, &mut act);
    undo_redo(ui, document, &mut act);
    ui.separator();

    let schema = document.schema();
    let empty = RecordingLabels::default();
    let labels = document.recording(&target.recording).unwrap_or(&empty);
    palette(ui, schema, state.labels().active.as_deref(), &mut act);
    in_point(ui, state, &mut act);
    labels_here(ui, labels, state.frame());
    ui.separator();
    segment_list(ui, &target, schema, labels, commands);
    super::label_schema::ui(ui, schema, commands);
    ui.separator();
    metadata_form(ui, state, &target, &labels.meta, commands);
    ui.separator();
    revert_or_clear(ui, &target, commands);
    loss_table(ui, state);
    ui.separator();
    export(ui, dialogs);
    ui.small("Press ? for every keyboard shortcut.");
}

/// Whether the labels file is saved (or why saving failed), and Save now.
fn save_state(ui: &mut egui::Ui, document: &LabelDocument, act: &mut impl FnMut(LabelAction)) {
    ui.horizontal(|ui| {
        let saved = match document.save_state() {
            SaveState::Saved => "saved".to_owned(),
            SaveState::Unsaved => "unsaved edits".to_owned(),
            SaveState::Failed(message) => format!("NOT saved: {message}"),
        };
        ui.label(saved);
        if ui
            .add_enabled(document.is_dirty(), egui::Button::new("Save now"))
            .on_hover_text("Ctrl+S; edits also save by themselves half a second after the last one")
            .clicked()
        {
            act(LabelAction::SaveAll);
        }
    });
}

/// When another program changed the labels file since it was read: overwrite it or reload it.
fn conflict(ui: &mut egui::Ui, document: &LabelDocument, act: &mut impl FnMut(LabelAction)) {
    if !document.has_conflict() {
        return;
    }
    ui.colored_label(
        egui::Color32::from_rgb(230, 90, 80),
        "Another program changed this labels file since pushlab read it.",
    );
    ui.horizontal(|ui| {
        if ui
            .button("Overwrite it with these labels")
            .on_hover_text("the other program's changes to the file are lost")
            .clicked()
        {
            act(LabelAction::Overwrite);
        }
        if ui
            .button("Reload it")
            .on_hover_text("your unsaved edits here are dropped")
            .clicked()
        {
            act(LabelAction::Reload);
        }
    });
}

/// Undo and Redo of the labels file's edits, each naming the edit on hover.
fn undo_redo(ui: &mut egui::Ui, document: &LabelDocument, act: &mut impl FnMut(LabelAction)) {
    ui.horizontal(|ui| {
        let undo = document.undo_description();
        if ui
            .add_enabled(undo.is_some(), egui::Button::new("Undo"))
            .on_hover_text(undo.map_or("nothing to undo".to_owned(), |d| format!("{d} (Ctrl+Z)")))
            .clicked()
        {
            act(LabelAction::Undo);
        }
        let redo = document.redo_description();
        if ui
            .add_enabled(redo.is_some(), egui::Button::new("Redo"))
            .on_hover_text(redo.map_or("nothing to redo".to_owned(), |d| {
                format!("{d} (Ctrl+Shift+Z)")
            }))
            .clicked()
        {
            act(LabelAction::Redo);
        }
    });
}

/// The in point for in/out painting: where it is, set or clear it, and paint from it to here.
fn in_point(ui: &mut egui::Ui, state: &AppState, act: &mut impl FnMut(LabelAction)) {
    ui.horizontal(|ui| {
        match state.labels().in_point {
            Some(f) => ui.label(format!("In point: frame {f}")),
            None => ui.label("In point: not set"),
        };
        if ui.button("Set in").on_hover_text("I").clicked() {
            act(LabelAction::SetInPoint);
        }
        if state.labels().in_point.is_some() && ui.button("Clear in").clicked() {
            act(LabelAction::ClearInPoint);
        }
        if ui
            .add_enabled(
                state.labels().in_point.is_some() && state.labels().active.is_some(),
                egui::Button::new("Paint in to here"),
            )
            .on_hover_text("O: paints the chosen label from the in point to this frame")
            .clicked()
        {
            act(LabelAction::PaintFromInPoint);
        }
    });
}

/// The labels at the frame shown: its segments, then its events.
fn labels_here(ui: &mut egui::Ui, labels: &RecordingLabels, frame: usize) {
    let here: Vec<String> = labels
        .segments_at(frame)
        .map(|s| s.label.clone())
        .chain(
            labels
                .events
                .iter()
                .filter(|e| e.frame == frame)
                .map(|e| e.label.clone()),
        )
        .collect();
    ui.label(if here.is_empty() {
        format!("Frame {frame}: no labels")
    } else {
        format!("Frame {frame}: {}", here.join(", "))
    });
}

/// Revert the recording's labels to how the file had them, or clear them (both undoable).
fn revert_or_clear(ui: &mut egui::Ui, target: &LabelTarget, commands: &mut Vec<Command>) {
    ui.horizontal(|ui| {
        let recording = target.recording.clone();
        if ui
            .button("Revert recording")
            .on_hover_text("Back to how its labels were when the file was opened (undoable)")
            .clicked()
        {
            commands.push(Command::Label(LabelAction::Edit(
                labels::Command::RevertRecording {
                    recording: recording.clone(),
                },
            )));
        }
        if ui
            .button("Clear recording")
            .on_hover_text("Removes every label and field of this recording (undoable)")
            .clicked()
        {
            commands.push(Command::Label(LabelAction::Edit(
                labels::Command::ClearRecording { recording },
            )));
        }
    });
}

/// Export every label as CSV or as JSON.
fn export(ui: &mut egui::Ui, dialogs: &mut Dialogs) {
    ui.horizontal(|ui| {
        if ui.button("Export labels as CSV…").clicked() {
            dialogs.open(DialogRequest::ExportLabelsCsv);
        }
        if ui.button("as JSON…").clicked() {
            dialogs.open(DialogRequest::ExportLabelsJson);
        }
    });
}

/// The labels of the schema: click a range label to choose it for in/out painting.
fn palette(
    ui: &mut egui::Ui,
    schema: &LabelSchema,
    active: Option<&str>,
    act: &mut impl FnMut(LabelAction),
) {
    ui.label("Labels (hold the key to paint while stepping or playing):");
    egui::Grid::new("label-palette")
        .num_columns(3)
        .show(ui, |ui| {
            for label in &schema.labels {
                let (rect, _) =
                    ui.allocate_exact_size(egui::vec2(12.0, 12.0), egui::Sense::hover());
                ui.painter().rect_filled(rect, 2.0, color(label.colour));
                let name = match label.kind {
                    LabelKind::Range => label.name.clone(),
                    LabelKind::Event => format!("{} (event)", label.name),
                };
                if label.kind == LabelKind::Range {
                    if ui
                        .selectable_label(active == Some(label.name.as_str()), name)
                        .on_hover_text("use for in/out painting")
                        .clicked()
                    {
                        act(LabelAction::SetActive(label.name.clone()));
                    }
                } else {
                    // Inset by a button's padding, so that its name lines up with the range
                    // labels' names, which sit inside selectable buttons.
                    ui.horizontal(|ui| {
                        ui.add_space(ui.spacing().button_padding.x);
                        ui.label(name);
                    });
                }
                ui.monospace(label.hotkey.as_deref().unwrap_or(""));
                ui.end_row();
            }
        });
}

/// Every segment and event of the recording, each with Go and Delete.
fn segment_list(
    ui: &mut egui::Ui,
    target: &LabelTarget,
    schema: &LabelSchema,
    labels: &RecordingLabels,
    commands: &mut Vec<Command>,
) {
    ui.label(format!(
        "{}, {}",
        format::count(labels.segments.len(), "segment", "segments"),
        format::count(labels.events.len(), "event", "events")
    ));
    egui::ScrollArea::vertical()
        .id_salt("segment-list")
        .max_height(160.0)
        .show(ui, |ui| {
            for segment in &labels.segments {
                ui.horizontal(|ui| {
                    swatch(ui, schema, &segment.label);
                    ui.label(if segment.last_frame() == segment.start {
                        format!("{}: frame {}", segment.label, segment.start)
                    } else {
                        format!(
                            "{}: frames {}–{}",
                            segment.label,
                            segment.start,
                            segment.last_frame()
                        )
                    });
                    if ui.small_button("Go").clicked() {
                        commands.push(Command::Timeline(TimelineCommand::SeekTo(segment.start)));
                    }
                    if ui.small_button("Delete").clicked() {
                        commands.push(Command::Label(LabelAction::Edit(labels::Command::Erase {
                            recording: target.recording.clone(),
                            label: Some(segment.label.clone()),
                            frames: segment.frames(),
                        })));
                    }
                });
            }
            for event in &labels.events {
                ui.horizontal(|ui| {
                    swatch(ui, schema, &event.label);
                    ui.label(format!("{}: frame {}", event.label, event.frame));
                    if ui.small_button("Go").clicked() {
                        commands.push(Command::Timeline(TimelineCommand::SeekTo(event.frame)));
                    }
                    if ui.small_button("Delete").clicked() {
                        commands.push(Command::Label(LabelAction::Edit(
                            labels::Command::RemoveEvent {
                                recording: target.recording.clone(),
                                label: event.label.clone(),
                                frame: event.frame,
                            },
                        )));
                    }
                });
            }
        });
}

fn swatch(ui: &mut egui::Ui, schema: &LabelSchema, label: &str) {
    let colour = schema
        .get(label)
        .map_or(egui::Color32::GRAY, |l| color(l.colour));
    let (rect, _) = ui.allocate_exact_size(egui::vec2(10.0, 10.0), egui::Sense::hover());
    ui.painter().rect_filled(rect, 2.0, colour);
}

/// Object, material, COM label, pushing side, split and notes of the recording.
fn metadata_form(
    ui: &mut egui::Ui,
    state: &AppState,
    target: &LabelTarget,
    meta: &RecordingMeta,
    commands: &mut Vec<Command>,
) {
    // Edits are collected and sent after the form, in the order made.
    let mut edits: Vec<LabelAction> = Vec::new();
    let rec = target.recording.as_str();
    let mut seal = false;
    ui.label("What this recording is:");
    egui::Grid::new("label-meta").num_columns(2).show(ui, |ui| {
        let label = ui.label("Object");
        let mut object = meta.object.clone();
        let response = ui.text_edit_singleline(&mut object).labelled_by(label.id);
        if response.changed() {
            edits.push(set_meta(rec, MetaField::Object(object)));
        }
        seal |= response.lost_focus();
        ui.end_row();

        let label = ui.label("Material");
        let mut material = meta.material.clone();
        let response = ui.text_edit_singleline(&mut material).labelled_by(label.id);
        if response.changed() {
            edits.push(set_meta(rec, MetaField::Material(material)));
        }
        seal |= response.lost_focus();
        ui.end_row();

        ui.label("COM label");
        ui.horizontal(|ui| match meta.com_offset {
            Some([x, y]) => {
                let mut mm = [x * 1e3, y * 1e3];
                let mut changed = false;
                for (value, axis) in mm.iter_mut().zip(["x", "y"]) {
                    let response = ui.add(
                        egui::DragValue::new(value)
                            .speed(0.5)
                            .prefix(format!("{axis} "))
                            .suffix(" mm")
                            .max_decimals(1),
                    );
                    // A drag of the value is one undo step, like dragging the diamond.
                    if response.drag_started() {
                        edits.push(LabelAction::BeginGroup("set the COM label".to_owned()));
                    }
                    changed |= response.changed();
                    if response.drag_stopped() {
                        edits.push(LabelAction::EndGroup);
                    }
                }
                if changed {
                    edits.push(set_meta(
                        rec,
                        MetaField::ComOffset(Some([mm[0] * 1e-3, mm[1] * 1e-3])),
                    ));
                }
                if ui.small_button("Clear").clicked() {
                    edits.push(set_meta(rec, MetaField::ComOffset(None)));
                }
            }
            None => {
                if ui
                    .button("Place at estimated COM")
                    .on_hover_text("then drag the diamond in the scene")
                    .clicked()
                {
                    let at = state.theta().map_or([0.0, 0.0], |t| t.com_offset);
                    edits.push(set_meta(rec, MetaField::ComOffset(Some(at))));
                }
            }
        });
        ui.end_row();

        let label = ui.label("Pushing side");
        if let Some(side) = choose(ui, label.id, meta.push_side, &PushSide::ALL, PushSide::name) {
            edits.push(set_meta(rec, MetaField::PushSide(side)));
        }
        ui.end_row();

        let label = ui.label("Split");
        if let Some(split) = choose(ui, label.id, meta.split, &Split::ALL, Split::name) {
            edits.push(set_meta(rec, MetaField::Split(split)));
        }
        ui.end_row();

        let label = ui.label("Notes");
        let mut notes = meta.notes.clone();
        let response = ui
            .add(egui::TextEdit::multiline(&mut notes).desired_rows(2))
            .labelled_by(label.id);
        if response.changed() {
            edits.push(set_meta(rec, MetaField::Notes(notes)));
        }
        seal |= response.lost_focus();
        ui.end_row();
    });
    if seal {
        edits.push(LabelAction::Seal);
    }
    commands.extend(edits.into_iter().map(Command::Label));
}

/// The edit that sets one metadata field of `recording`.
fn set_meta(recording: &str, field: MetaField) -> LabelAction {
    LabelAction::Edit(labels::Command::SetMeta {
        recording: recording.to_owned(),
        field,
    })
}

/// Mean losses by label over the frames learned so far: where the model does badly, and whether
/// online learning helps there.
fn loss_table(ui: &mut egui::Ui, state: &AppState) {
    let rows = state.loss_by_label();
    let Some(all) = rows.first().filter(|r| r.frames > 0) else {
        ui.weak("Loss by label: play or step with learning on to fill this in.");
        return;
    };
    ui.label(format!(
        "Mean loss by label over the {} learned so far (online / fixed):",
        format::count(all.frames, "frame", "frames")
    ));
    egui::Grid::new("loss-by-label")
        .num_columns(4)
        .striped(true)
        .show(ui, |ui| {
            ui.strong("label");
            ui.strong("frames");
            ui.strong("position");
            ui.strong("rotation");
            ui.end_row();
            for row in &rows {
                ui.label(&row.label);
                ui.label(row.frames.to_string());
                ui.label(format!("{:.3} / {:.3}", row.online_pos, row.fixed_pos));
                ui.label(format!("{:.3} / {:.3}", row.online_rot, row.fixed_rot));
                ui.end_row();
            }
        });
}

/// A drop-down of `options` plus "—" for none, named by the label `label`; returns the new choice
/// when the user changed it.
fn choose<T: Copy + PartialEq>(
    ui: &mut egui::Ui,
    label: egui::Id,
    current: Option<T>,
    options: &[T],
    name: fn(T) -> &'static str,
) -> Option<Option<T>> {
    let mut chosen = current;
    egui::ComboBox::from_id_salt(label)
        .selected_text(chosen.map_or("—", name))
        .show_ui(ui, |ui| {
            ui.selectable_value(&mut chosen, None, "—");
            for &option in options {
                ui.selectable_value(&mut chosen, Some(option), name(option));
            }
        })
        .response
        .labelled_by(label);
    (chosen != current).then_some(chosen)
}
