//! The window that opens a ROS 2 bag: the bag's topics, which stream is the pusher and which the
//! object (pre-selected when their names make it obvious), the object from a `setting.json` or
//! entered as a box, and how to import. Open tries the choice; it is remembered beside the bag only
//! once the bag opened (`state::sources::bag_import`).

use eframe::egui::{self, RichText};
use pushlab_core::recording::bag::{ImportOptions, TopicSpec, choice};

use crate::app::dialogs::{DialogRequest, Dialogs};
use crate::app::state::sources::bag_import::{BagCommand, BagForm, EnteredBox, ObjectSource};
use crate::app::state::{AppState, Command};

/// Draws the form of the first bag waiting for a choice, or says whose topics are being read.
pub fn window(
    ctx: &egui::Context,
    state: &AppState,
    dialogs: &mut Dialogs,
    commands: &mut Vec<Command>,
) {
    let chooser = &state.bags();
    if let Some(bag) = chooser.listing()
        && chooser.form().is_none()
    {
        egui::Window::new("Open ROS 2 bag")
            .collapsible(false)
            .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
            .show(ctx, |ui| {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.label(format!("reading the topics of {}…", bag.display()));
                });
            });
    }
    let Some(form) = chooser.form() else {
        return;
    };
    let mut send = |c| commands.push(Command::Bag(c));
    egui::Window::new("Open ROS 2 bag")
        .collapsible(false)
        .resizable(true)
        .default_width(560.0)
        .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
        .show(ctx, |ui| {
            let name = form
                .bag
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
            let kind = if form.bag.is_dir() {
                "rosbag2 folder"
            } else {
                "MCAP file"
            };
            ui.heading(format!("{name} ({kind})"))
                .on_hover_text(form.bag.display().to_string());
            if let Some(error) = &form.error {
                ui.colored_label(ui.visuals().error_fg_color, error);
            }
            for cut in &form.cut_short {
                ui.colored_label(ui.visuals().warn_fg_color, cut);
            }
            topics_table(ui, form);
            ui.separator();
            streams(ui, form, &mut send);
            ui.separator();
            object(ui, form, dialogs, &mut send);
            ui.separator();
            cameras(ui, form, &mut send);
            options(ui, form.options, &mut send);
            ui.separator();
            buttons(ui, state, form, &mut send);
        });
}

/// One checkbox per camera topic: which are shown beside the push (none, one or several).
fn cameras(ui: &mut egui::Ui, form: &BagForm, send: &mut impl FnMut(BagCommand)) {
    let cameras: Vec<_> = form.topics.iter().filter(|t| t.is_camera()).collect();
    if cameras.is_empty() {
        return;
    }
    ui.label("Cameras to show beside the push:");
    for topic in cameras {
        let mut shown = form.cameras.contains(&topic.topic);
        let what = topic.camera.as_ref().map_or_else(String::new, |c| {
            let size = c
                .size
                .map_or_else(String::new, |(w, h)| format!(", {w}×{h}"));
            format!(" ({}{size}, {} frames)", c.encoding, topic.count)
        });
        if ui
            .checkbox(&mut shown, format!("{}{what}", topic.topic))
            .changed()
        {
            send(BagCommand::SetCamera {
                topic: topic.topic.clone(),
                shown,
            });
        }
    }
    ui.separator();
}

/// The bag's topics: name, type, messages, rate, and whether pushlab reads it.
fn topics_table(ui: &mut egui::Ui, form: &BagForm) {
    egui::ScrollArea::vertical()
        .max_height(160.0)
        .id_salt("bag topics")
        .show(ui, |ui| {
            egui::Grid::new("bag topics grid")
                .striped(true)
                .num_columns(4)
                .show(ui, |ui| {
                    for head in ["Topic", "Type", "Messages", "Rate"] {
                        ui.strong(head);
                    }
                    ui.end_row();
                    for topic in &form.topics {
                        let text = RichText::new(&topic.topic);
                        if topic.pose_type().is_some() {
                            ui.label(text);
                        } else {
                            ui.label(text.weak())
                                .on_hover_text("not a pose type pushlab reads");
                        }
                        ui.label(RichText::new(&topic.type_name).small());
                        ui.label(topic.count.to_string());
                        ui.label(format!("{:.1} Hz", topic.rate_hz()));
                        ui.end_row();
                        if !topic.child_frames.is_empty() {
                            ui.label("");
                            ui.weak(format!("child frames: {}", topic.child_frames.join(", ")));
                            ui.end_row();
                        }
                    }
                });
        });
}

/// The pusher's and the object's streams, from the ones the bag offers.
fn streams(ui: &mut egui::Ui, form: &BagForm, send: &mut impl FnMut(BagCommand)) {
    if form.streams.is_empty() {
        ui.colored_label(
            ui.visuals().error_fg_color,
            "no topic of this bag is a pose pushlab reads (PoseStamped, TFMessage, Odometry, \
             Pose2D in CDR)",
        );
        return;
    }
    egui::Grid::new("bag streams")
        .num_columns(2)
        .show(ui, |ui| {
            for (label, chosen, command) in [
                (
                    "Pusher",
                    &form.pusher,
                    BagCommand::SetPusher as fn(TopicSpec) -> BagCommand,
                ),
                ("Object", &form.object, BagCommand::SetObject),
            ] {
                let name = ui.label(label);
                let shown = chosen
                    .as_ref()
                    .map_or_else(|| "choose…".to_owned(), ToString::to_string);
                egui::ComboBox::from_id_salt(label)
                    .selected_text(shown)
                    .width(300.0)
                    .show_ui(ui, |ui| {
                        for spec in &form.streams {
                            let selected = chosen.as_ref() == Some(spec);
                            if ui.selectable_label(selected, spec.to_string()).clicked() {
                                send(command(spec.clone()));
                            }
                        }
                    })
                    .response
                    .labelled_by(name.id);
                ui.end_row();
            }
        });
}

/// The object: a `setting.json` (found beside the bag, or chosen) or a box entered by hand.
fn object(
    ui: &mut egui::Ui,
    form: &BagForm,
    dialogs: &mut Dialogs,
    send: &mut impl FnMut(BagCommand),
) {
    ui.horizontal(|ui| {
        ui.strong("What the object is");
        let from_file = matches!(form.object_source, ObjectSource::File { .. });
        if ui.radio(from_file, "from a setting.json").clicked() && !from_file {
            match form.settings_found.first() {
                Some(path) => send(BagCommand::UseSettingFile(path.clone())),
                None => dialogs.open(DialogRequest::BagSetting),
            }
        }
        if ui.radio(!from_file, "a box entered here").clicked() && from_file {
            send(BagCommand::EnterObject);
        }
    });
    match &form.object_source {
        ObjectSource::File { path, checked } => {
            ui.horizontal(|ui| {
                ui.label(path.display().to_string());
                for found in form.settings_found.iter().filter(|f| *f != path) {
                    if ui
                        .small_button(format!("use {}", found.display()))
                        .clicked()
                    {
                        send(BagCommand::UseSettingFile(found.clone()));
                    }
                }
                if ui.small_button("Choose file…").clicked() {
                    dialogs.open(DialogRequest::BagSetting);
                }
            });
            match checked {
                Ok(name) => ui.label(format!("setting \"{name}\"")),
                Err(why) => ui.colored_label(ui.visuals().error_fg_color, why),
            };
        }
        ObjectSource::Entered(entered) => entered_box(ui, entered, send),
    }
}

fn entered_box(ui: &mut egui::Ui, entered: &EnteredBox, send: &mut impl FnMut(BagCommand)) {
    let mut edited = entered.clone();
    egui::Grid::new("entered box")
        .num_columns(2)
        .show(ui, |ui| {
            ui.label("Name");
            ui.text_edit_singleline(&mut edited.name);
            ui.end_row();
            for (label, value) in [
                ("Width (along x)", &mut edited.width_mm),
                ("Length (along y)", &mut edited.length_mm),
                ("Pusher radius", &mut edited.pusher_radius_mm),
            ] {
                ui.label(label);
                ui.add(
                    egui::DragValue::new(value)
                        .range(0.0..=2000.0)
                        .speed(0.5)
                        .suffix(" mm"),
                );
                ui.end_row();
            }
            ui.label("Material");
            ui.text_edit_singleline(&mut edited.material);
            ui.end_row();
        });
    if edited != *entered {
        send(BagCommand::SetEntered(edited));
    }
}

/// Splitting at pauses and the grid's rate.
fn options(ui: &mut egui::Ui, options: ImportOptions, send: &mut impl FnMut(BagCommand)) {
    let mut edited = options;
    optional_value(
        ui,
        &mut edited.split_gap_s,
        OptionalValue {
            label: "Split at pauses longer than",
            hover: "one push per piece of the bag between pauses of the pusher or object",
            when_off: "off: one push per bag",
            initial: 0.5,
            range: 0.01..=600.0,
            suffix: " s",
        },
    );
    optional_value(
        ui,
        &mut edited.rate_hz,
        OptionalValue {
            label: "Resample at",
            hover: "the rate of the common time grid of both streams",
            when_off: "off: the slower stream's rate",
            initial: 100.0,
            range: 1.0..=pushlab_core::recording::bag::MAX_RATE_HZ,
            suffix: " Hz",
        },
    );
    if edited != options {
        send(BagCommand::SetOptions(edited));
    }
}

/// How an import option that may be left to pushlab is shown.
struct OptionalValue {
    label: &'static str,
    hover: &'static str,
    /// What happens when it is off.
    when_off: &'static str,
    /// The value it takes when switched on.
    initial: f64,
    range: std::ops::RangeInclusive<f64>,
    suffix: &'static str,
}

/// A checkbox that switches an optional value on (with a drag value) or off (leaving it to pushlab).
fn optional_value(ui: &mut egui::Ui, value: &mut Option<f64>, how: OptionalValue) {
    ui.horizontal(|ui| {
        let mut on = value.is_some();
        if ui
            .checkbox(&mut on, how.label)
            .on_hover_text(how.hover)
            .changed()
        {
            *value = on.then_some(how.initial);
        }
        match value {
            Some(v) => {
                let speed = (how.range.end() - how.range.start()) / 2000.0;
                ui.add(
                    egui::DragValue::new(v)
                        .range(how.range)
                        .speed(speed.max(0.01))
                        .suffix(how.suffix),
                );
            }
            None => {
                ui.weak(how.when_off);
            }
        }
    });
}

fn buttons(ui: &mut egui::Ui, state: &AppState, form: &BagForm, send: &mut impl FnMut(BagCommand)) {
    let ready = form.choice();
    ui.horizontal(|ui| {
        let open = ui.add_enabled(ready.is_ok(), egui::Button::new("Open"));
        let open = match &ready {
            Ok(_) => open.on_hover_text(format!(
                "import the two streams and open the bag; the choice is then remembered in {}",
                choice::choice_path(&form.bag).display()
            )),
            Err(why) => open.on_disabled_hover_text(why),
        };
        if open.clicked() {
            send(BagCommand::Open);
        }
        if ui
            .button("Skip")
            .on_hover_text("do not open this bag now (it is listed under the load problems)")
            .clicked()
        {
            send(BagCommand::Skip);
        }
        if let Err(why) = &ready {
            ui.weak(why);
        }
    });
    let waiting = state.bags().waiting();
    if waiting > 0 {
        ui.weak(format!("{waiting} more bag(s) waiting"));
    }
}
