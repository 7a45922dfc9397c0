//! The window that opens a Push-T dataset (a zarr replay buffer or a LeRobot folder): its features,
//! which is the pusher and how the T is read (pre-selected for Push-T's own layouts), and the scale.
//! Open tries the choice; it is remembered beside the dataset only once the dataset opened
//! (`state::sources::dataset_import`).

use eframe::egui;
use pushlab_core::recording::dataset::{Columns, ObjectSource};

use crate::app::state::sources::dataset_import::{DatasetCommand, DatasetForm};
use crate::app::state::{AppState, Command};

/// Draws the form of the first dataset waiting for a choice, or says which dataset is being read.
pub fn window(ctx: &egui::Context, state: &AppState, commands: &mut Vec<Command>) {
    let chooser = state.datasets();
    if let Some(dataset) = chooser.listing()
        && chooser.form().is_none()
    {
        egui::Window::new("Open dataset")
            .collapsible(false)
            .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
            .show(ctx, |ui| {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.label(format!("reading the features of {}…", dataset.display()));
                });
            });
    }
    let Some(form) = chooser.form() else {
        return;
    };
    let mut send = |c| commands.push(Command::Dataset(c));
    egui::Window::new("Open dataset")
        .collapsible(false)
        .resizable(true)
        .default_width(480.0)
        .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
        .show(ctx, |ui| {
            let name = (form.dataset.file_name())
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
            let s = &form.summary;
            ui.heading(format!("{name} ({})", s.format))
                .on_hover_text(form.dataset.display().to_string());
            ui.label(format!(
                "{} episode(s), {} frames at {} Hz; each episode opens as one push of the Push-T T",
                s.episodes, s.frames, s.fps
            ));
            if let Some(error) = &form.error {
                ui.colored_label(ui.visuals().error_fg_color, error);
            }
            ui.separator();
            egui::Grid::new("dataset_choice")
                .num_columns(2)
                .show(ui, |ui| {
                    ui.label("Pusher (agent x, y)");
                    pusher(ui, form, &mut send);
                    ui.end_row();
                    ui.label("Object (the T)");
                    object(ui, form, &mut send);
                    ui.end_row();
                    ui.label("Scale");
                    scale(ui, form, &mut send);
                    ui.end_row();
                });
            ui.separator();
            buttons(ui, form, &mut send);
        });
}

/// Features with at least `needed` values per frame, as combo-box entries.
fn features_with(form: &DatasetForm, needed: usize) -> impl Iterator<Item = (&str, usize)> {
    (form.summary.features.iter())
        .filter(move |(_, w)| *w >= needed)
        .map(|(n, w)| (n.as_str(), *w))
}

/// A feature and the column its values start at.
fn columns(
    ui: &mut egui::Ui,
    id: &str,
    form: &DatasetForm,
    current: Option<&Columns>,
    needed: usize,
) -> Option<Columns> {
    let mut chosen = None;
    let shown = current.map_or_else(|| "choose…".to_owned(), |c| c.feature.clone());
    egui::ComboBox::from_id_salt(id)
        .selected_text(shown)
        .show_ui(ui, |ui| {
            for (name, width) in features_with(form, needed) {
                let selected = current.is_some_and(|c| c.feature == name);
                if ui
                    .selectable_label(selected, format!("{name} ({width})"))
                    .clicked()
                {
                    chosen = Some(Columns::new(name, 0));
                }
            }
        });
    if let Some(current) = current {
        let width = form.width(&current.feature).unwrap_or(needed);
        let mut first = current.first;
        let last = width.saturating_sub(needed);
        if ui
            .add(
                egui::DragValue::new(&mut first)
                    .range(0..=last)
                    .prefix("from column "),
            )
            .changed()
        {
            chosen = Some(Columns::new(current.feature.clone(), first));
        }
    }
    chosen
}

fn pusher(ui: &mut egui::Ui, form: &DatasetForm, send: &mut impl FnMut(DatasetCommand)) {
    ui.horizontal(|ui| {
        if let Some(c) = columns(ui, "dataset_pusher", form, form.pusher.as_ref(), 2) {
            send(DatasetCommand::SetPusher(c));
        }
    });
}

fn object(ui: &mut egui::Ui, form: &DatasetForm, send: &mut impl FnMut(DatasetCommand)) {
    ui.vertical(|ui| {
        let pose = match &form.object {
            Some(ObjectSource::Pose(c)) => Some(c),
            _ => None,
        };
        ui.horizontal(|ui| {
            if ui
                .radio(pose.is_some(), "pose: x, y, angle of the T's origin")
                .clicked()
                && pose.is_none()
                && let Some((name, width)) = features_with(form, 3).next()
            {
                let first = if width >= 5 { 2 } else { 0 };
                send(DatasetCommand::SetObject(ObjectSource::Pose(Columns::new(
                    name, first,
                ))));
            }
            if let Some(c) = columns(ui, "dataset_object_pose", form, pose, 3) {
                send(DatasetCommand::SetObject(ObjectSource::Pose(c)));
            }
        });
        let keypoints = match &form.object {
            Some(ObjectSource::Keypoints(f)) => Some(f),
            _ => None,
        };
        ui.horizontal(|ui| {
            let sixteen: Vec<_> = (form.summary.features.iter())
                .filter(|(_, w)| *w == 16)
                .map(|(n, _)| n.clone())
                .collect();
            let radio = ui.add_enabled(
                !sixteen.is_empty(),
                egui::RadioButton::new(keypoints.is_some(), "keypoints: the T's 8 corners"),
            );
            let radio = radio.on_disabled_hover_text("no feature has 16 values per frame");
            if radio.clicked()
                && keypoints.is_none()
                && let Some(name) = sixteen.first()
            {
                send(DatasetCommand::SetObject(ObjectSource::Keypoints(
                    name.clone(),
                )));
            }
            if let Some(current) = keypoints {
                egui::ComboBox::from_id_salt("dataset_object_keypoints")
                    .selected_text(current.as_str())
                    .show_ui(ui, |ui| {
                        for name in &sixteen {
                            if ui.selectable_label(name == current, name).clicked() {
                                send(DatasetCommand::SetObject(ObjectSource::Keypoints(
                                    name.clone(),
                                )));
                            }
                        }
                    });
            }
        });
    });
}

fn scale(ui: &mut egui::Ui, form: &DatasetForm, send: &mut impl FnMut(DatasetCommand)) {
    let mut mm_per_px = form.metres_per_px * 1e3;
    let response = ui
        .add(
            egui::DragValue::new(&mut mm_per_px)
                .range(0.001..=100.0)
                .speed(0.01)
                .suffix(" mm per px"),
        )
        .on_hover_text("1 mm per px gives a 120 mm T and a 15 mm pusher");
    if response.changed() {
        send(DatasetCommand::SetScale(mm_per_px * 1e-3));
    }
}

fn buttons(ui: &mut egui::Ui, form: &DatasetForm, send: &mut impl FnMut(DatasetCommand)) {
    ui.horizontal(|ui| {
        let ready = form.choice();
        let open = ui.add_enabled(ready.is_ok(), egui::Button::new("Open"));
        let open = match &ready {
            Ok(_) => open.on_hover_text("open every episode; the choice is remembered beside it"),
            Err(why) => open.on_disabled_hover_text(why),
        };
        if open.clicked() {
            send(DatasetCommand::Open);
        }
        if ui
            .button("Not now")
            .on_hover_text("leave it unopened; the browser's problems list offers it again")
            .clicked()
        {
            send(DatasetCommand::Skip);
        }
        if let Err(why) = &ready {
            ui.label(why);
        }
    });
}
