//! "Edit labels", inside the Labels tab: the labels file's schema. Recolour a label, give it another
//! hotkey, remove it, or add a new one, without touching the JSON. Every change is an undoable edit of
//! the labels document, like painting.

use eframe::egui;
use pushlab_core::labels::{self, LabelDef, LabelSchema, Rgb};

use crate::app::keys::is_app_key;
use crate::app::state::Command;
use crate::app::state::labels::labeling::LabelAction;

/// Colours offered to new labels in turn (matplotlib's tab10, which the default schema starts with).
const NEW_COLOURS: [Rgb; 6] = [
    Rgb::new(0x8c, 0x56, 0x4b),
    Rgb::new(0xe3, 0x77, 0xc2),
    Rgb::new(0x7f, 0x7f, 0x7f),
    Rgb::new(0xbc, 0xbd, 0x22),
    Rgb::new(0x17, 0xbe, 0xcf),
    Rgb::new(0x94, 0x67, 0xbd),
];

/// What the "Add label" row is being filled with (egui temp memory: view state, not labels).
#[derive(Clone, Default)]
struct Draft {
    name: String,
    event: bool,
    group: String,
}

/// Draws the schema editor.
pub fn ui(ui: &mut egui::Ui, schema: &LabelSchema, commands: &mut Vec<Command>) {
    let mut edit = |command: labels::Command| {
        commands.push(Command::Label(LabelAction::Edit(command)));
    };
    egui::CollapsingHeader::new("Edit labels")
        .id_salt("edit-labels")
        .show(ui, |ui| {
            egui::Grid::new("schema-editor")
                .num_columns(4)
                .show(ui, |ui| {
                    for label in &schema.labels {
                        let [r, g, b] = label.colour.0;
                        let mut rgb = [r, g, b];
                        if egui::color_picker::color_edit_button_srgb(ui, &mut rgb).changed() {
                            edit(labels::Command::SetLabelAppearance {
                                name: label.name.clone(),
                                colour: Rgb(rgb),
                                hotkey: label.hotkey.clone(),
                            });
                        }
                        let name = ui.label(&label.name);
                        let mut key = label.hotkey.clone().unwrap_or_default();
                        let response = ui
                            .add(
                                egui::TextEdit::singleline(&mut key)
                                    .desired_width(48.0)
                                    .hint_text("key"),
                            )
                            .labelled_by(name.id)
                            .on_hover_text("its hotkey, an egui key name: 1, A, F2 …");
                        if response.changed()
                            && let Some(hotkey) = hotkey_from(&key)
                        {
                            edit(labels::Command::SetLabelAppearance {
                                name: label.name.clone(),
                                colour: label.colour,
                                hotkey,
                            });
                        }
                        ui.horizontal(|ui| {
                            let remove = ui.small_button("Remove").on_hover_text(
                                "only while nothing carries it; right-click to remove it with \
                                 every segment and event that does",
                            );
                            remove.context_menu(|ui| {
                                if ui.button("Remove with all its uses").clicked() {
                                    edit(labels::Command::RemoveLabel {
                                        name: label.name.clone(),
                                        with_uses: true,
                                    });
                                }
                            });
                            if remove.clicked() {
                                edit(labels::Command::RemoveLabel {
                                    name: label.name.clone(),
                                    with_uses: false,
                                });
                            }
                            if label
                                .hotkey
                                .as_deref()
                                .and_then(egui::Key::from_name)
                                .is_some_and(is_app_key)
                            {
                                ui.weak("key taken by the app");
                            }
                        });
                        ui.end_row();
                    }
                });
            add_row(ui, schema, &mut edit);
        });
}

/// The row that adds a label: name, range or event, optional exclusive group.
fn add_row(ui: &mut egui::Ui, schema: &LabelSchema, edit: &mut impl FnMut(labels::Command)) {
    let id = egui::Id::unique("pushlab-new-label-draft");
    let mut draft: Draft = ui.data_mut(|d| d.get_temp(id)).unwrap_or_default();
    ui.horizontal(|ui| {
        let label = ui.label("New label");
        ui.add(egui::TextEdit::singleline(&mut draft.name).desired_width(110.0))
            .labelled_by(label.id);
        ui.checkbox(&mut draft.event, "event");
    });
    ui.horizontal(|ui| {
        let label = ui.label("Exclusive group");
        ui.add_enabled(
            !draft.event,
            egui::TextEdit::singleline(&mut draft.group)
                .desired_width(110.0)
                .hint_text("none"),
        )
        .labelled_by(label.id);
        let name = draft.name.trim().to_owned();
        if ui
            .add_enabled(
                !name.is_empty() && schema.get(&name).is_none(),
                egui::Button::new("Add label"),
            )
            .clicked()
        {
            edit(labels::Command::AddLabel(new_label(schema, &draft)));
            draft = Draft::default();
        }
    });
    ui.data_mut(|d| d.insert_temp(id, draft));
}

/// A label as the draft describes it, with the next unused colour and the first free digit key.
fn new_label(schema: &LabelSchema, draft: &Draft) -> LabelDef {
    let name = draft.name.trim();
    let colour = NEW_COLOURS[schema.labels.len() % NEW_COLOURS.len()];
    let mut label = if draft.event {
        LabelDef::event(name, colour)
    } else {
        LabelDef::range(name, colour)
    };
    let taken = |key: &str| {
        schema.labels.iter().any(|l| {
            l.hotkey
                .as_deref()
                .is_some_and(|k| k.eq_ignore_ascii_case(key))
        })
    };
    label.hotkey = ["8", "9", "0"]
        .into_iter()
        .find(|k| !taken(k))
        .map(str::to_owned);
    let group = draft.group.trim();
    if !draft.event && !group.is_empty() {
        label.group = Some(group.to_owned());
    }
    label
}

/// The hotkey typed into a label's key field: `Some(None)` for an empty field (no hotkey),
/// `Some(Some(key))` for a key egui knows, `None` while the text is not (yet) a key.
fn hotkey_from(text: &str) -> Option<Option<String>> {
    let text = text.trim();
    if text.is_empty() {
        Some(None)
    } else {
        egui::Key::from_name(text).map(|_| Some(text.to_owned()))
    }
}

#[cfg(test)]
mod tests {
    use pushlab_core::labels::LabelKind;

    use super::*;

    #[test]
    fn a_new_label_gets_a_free_key_and_its_group() {
        let schema = LabelSchema::default();
        let draft = Draft {
            name: " wobble ".into(),
            event: false,
            group: "contact mode".into(),
        };
        let label = new_label(&schema, &draft);
        assert_eq!(label.name, "wobble");
        assert_eq!(label.hotkey.as_deref(), Some("8"));
        assert_eq!(label.group.as_deref(), Some("contact mode"));
        assert_eq!(label.kind, LabelKind::Range);
        let event = new_label(
            &schema,
            &Draft {
                name: "slip start".into(),
                event: true,
                group: "ignored".into(),
            },
        );
        assert_eq!(event.kind, LabelKind::Event);
        assert_eq!(event.group, None, "events have no group");
    }

    #[test]
    fn only_real_key_names_become_hotkeys() {
        assert_eq!(hotkey_from("8"), Some(Some("8".to_owned())));
        assert_eq!(hotkey_from(" F2 "), Some(Some("F2".to_owned())));
        assert_eq!(hotkey_from(""), Some(None));
        assert_eq!(hotkey_from("Shift+"), None);
    }
}
