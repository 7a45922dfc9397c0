//! The top bar: the File menu (open, recent, export, models), the Edit menu (label undo/redo, save),
//! Help, and the status line.

use eframe::egui;

use super::sandbox;
use crate::app::dialogs::DialogRequest;
use crate::app::layout::Pane;
use crate::app::state::SessionCommand;
use crate::app::state::demos::demo::DemoCommand;
use crate::app::state::labels::labeling::LabelAction;
use crate::app::state::learning::landscape::LandscapeCommand;
use crate::app::state::playback::cameras::CameraCommand;
use crate::app::state::sources::bag_import::BagCommand;
use crate::app::state::sources::dataset_import::DatasetCommand;
use crate::app::state::sources::live::LiveCommand;
use crate::app::state::{AppState, ChooseAgain, Command, FileCommand};
use crate::app::view::View;

/// The File menu's way back to the form of the bag or dataset shown: its topics or features
/// chosen again replace the set.
fn choose_again(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let (label, hover, command) = match state.source_to_choose_again() {
        Some(ChooseAgain::Dataset(dataset)) => (
            "Choose the dataset's features again…",
            format!(
                "which features of {} are the pusher and the T, and the scale",
                dataset.display()
            ),
            Command::Dataset(DatasetCommand::Choose(dataset)),
        ),
        Some(ChooseAgain::Bag(bag)) => (
            "Choose the bag's topics again…",
            format!(
                "which topics of {} are the pusher and the object, and the object",
                bag.display()
            ),
            Command::Bag(BagCommand::ChooseAgain(bag)),
        ),
        None => return,
    };
    if ui.button(label).on_hover_text(hover).clicked() {
        commands.push(command);
    }
}

/// Draws the menu bar and the status line.
pub fn top_bar(ui: &mut egui::Ui, state: &AppState, view: &mut View, commands: &mut Vec<Command>) {
    egui::Panel::top("menu").show(ui, |ui| {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| file_menu(ui, state, view, commands));
            ui.menu_button("Edit", |ui| edit_menu(ui, state, commands));
            ui.menu_button("View", |ui| view_menu(ui, state, view, commands));
            ui.menu_button("Demos", |ui| demos_menu(ui, state, view, commands));
            ui.menu_button("Help", |ui| help_menu(ui, state, view, commands));
            ui.separator();
            status_line(ui, state, view, commands);
        });
    });
}

/// The File menu: open (files, folder, recent, choose again, live robot), the model, exports.
fn file_menu(ui: &mut egui::Ui, state: &AppState, view: &mut View, commands: &mut Vec<Command>) {
    if ui.button("Open files…").clicked() {
        view.dialogs.open(DialogRequest::OpenFiles);
    }
    if ui.button("Open folder…").clicked() {
        view.dialogs.open(DialogRequest::OpenFolder);
    }
    ui.menu_button("Open recent", |ui| {
        if state.settings().recent.is_empty() {
            ui.label("nothing yet");
        }
        for path in &state.settings().recent {
            if ui.button(path.display().to_string()).clicked() {
                commands.push(Command::Session(SessionCommand::Open(vec![path.clone()])));
            }
        }
    });
    choose_again(ui, state, commands);
    ui.menu_button("New sandbox", |ui| sandbox::start_menu(ui, state, commands));
    if ui
        .button("Connect to a live robot…")
        .on_hover_text("a Foxglove WebSocket server: learn while the robot pushes")
        .clicked()
    {
        commands.push(Command::Live(LiveCommand::OpenForm));
    }
    ui.separator();
    if ui.button("Load model…").clicked() {
        view.dialogs.open(DialogRequest::LoadModel);
    }
    if ui
        .add_enabled(
            state.models().combined.is_some(),
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
    if cfg!(not(target_arch = "wasm32"))
        && ui
            .button("Export plots as SVG or PDF…")
            .on_hover_text(
                "a vector figure of the losses and θ, text as text (by the name: .svg or .pdf)",
            )
            .clicked()
    {
        view.dialogs.open(DialogRequest::SavePlotsSvg);
    }
    if cfg!(not(target_arch = "wasm32"))
        && ui
            .add_enabled(
                state.recording().is_some() && state.video_export().is_none(),
                egui::Button::new("Export video of this push…"),
            )
            .on_hover_text(
                "the scene as it plays, learning online: MP4 or WebM (through ffmpeg) or GIF",
            )
            .clicked()
    {
        view.dialogs.open(DialogRequest::SaveVideo);
    }
    if ui
        .add_enabled(
            state.run().is_some(),
            egui::Button::new("Export losses as CSV…"),
        )
        .clicked()
    {
        view.dialogs.open(DialogRequest::SaveLossCsv);
    }
}

/// The Edit menu: undo and redo of the labels shown, each naming the edit, and saving the labels.
fn edit_menu(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let document = state
        .label_target()
        .and_then(|t| state.labels().document(&t.document).cloned());
    let undo = document
        .as_ref()
        .and_then(|d| d.undo_description().map(str::to_owned));
    let redo = document
        .as_ref()
        .and_then(|d| d.redo_description().map(str::to_owned));
    let undo_text = undo.map_or("Undo label edit".to_owned(), |d| format!("Undo {d}"));
    if ui
        .add_enabled(
            document
                .as_ref()
                .is_some_and(|d| d.undo_description().is_some()),
            egui::Button::new(undo_text).shortcut_text("Ctrl+Z"),
        )
        .clicked()
    {
        commands.push(Command::Label(LabelAction::Undo));
    }
    let redo_text = redo.map_or("Redo label edit".to_owned(), |d| format!("Redo {d}"));
    if ui
        .add_enabled(
            document
                .as_ref()
                .is_some_and(|d| d.redo_description().is_some()),
            egui::Button::new(redo_text).shortcut_text("Ctrl+Shift+Z"),
        )
        .clicked()
    {
        commands.push(Command::Label(LabelAction::Redo));
    }
    ui.separator();
    if ui
        .add_enabled(
            state.labels().any_unsaved(),
            egui::Button::new("Save labels").shortcut_text("Ctrl+S"),
        )
        .clicked()
    {
        commands.push(Command::Label(LabelAction::SaveAll));
    }
}

/// The View menu: the loss landscape, the panes, the cameras, and the theme.
fn view_menu(ui: &mut egui::Ui, state: &AppState, view: &mut View, commands: &mut Vec<Command>) {
    let mut open = state.landscape().open;
    if ui
        .add(egui::Checkbox::new(&mut open, "Loss landscape"))
        .on_hover_text("the online loss over COM offsets and h at the frame shown (F2)")
        .changed()
    {
        commands.push(Command::Landscape(LandscapeCommand::Show(open)));
    }
    panes_menu(ui, view);
    cameras_menu(ui, state, commands);
    ui.separator();
    ui.checkbox(&mut view.light, "Light theme")
        .on_hover_text("dark strokes on white, as on paper; the colours keep their meaning");
    ui.checkbox(&mut view.projector, "Projector mode")
        .on_hover_text("high-contrast colours and larger text, for a lecture hall");
}

/// The Help menu: the keyboard shortcuts and, on the web page, a link to this view.
fn help_menu(ui: &mut egui::Ui, state: &AppState, view: &mut View, commands: &mut Vec<Command>) {
    if ui
        .add(egui::Button::new("Keyboard shortcuts").shortcut_text("?"))
        .clicked()
    {
        view.show_shortcuts = true;
    }
    if let Some(address) = &view.page_address {
        let link = crate::app::link::Link::of(state, &view.link_part());
        if ui
            .button("Copy link to this view")
            .on_hover_text("the address of this page showing this push, frame, θ and settings")
            .clicked()
        {
            ui.ctx().copy_text(format!("{address}?{}", link.to_query()));
            commands.push(Command::Report("link copied".to_owned()));
        }
    }
}

/// The model in use, then from the right: the frame rate, what is opening or written, the status.
fn status_line(ui: &mut egui::Ui, state: &AppState, view: &View, commands: &mut Vec<Command>) {
    let model = match &state.models().source {
        Some(source) => format!("Model: {} · {source}", state.models().learner_name()),
        None => format!("Model: {}", state.models().learner_name()),
    };
    ui.label(model);
    // Right to left: the frame rate keeps its place, the status line takes what is left
    // and is cut short there (hover for all of it).
    ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
        if let Some(rate) = view.frame_rate.text() {
            ui.weak(rate);
            ui.separator();
        }
        ui.with_layout(egui::Layout::left_to_right(egui::Align::Center), |ui| {
            opening(ui, state, commands);
            video_export(ui, state, commands);
            if let Some(status) = state.status() {
                ui.separator();
                ui.add(egui::Label::new(status).truncate())
                    .on_hover_text(status);
            }
        });
    });
}

/// The paths being opened: how far, about how long is left, and Cancel.
fn opening(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let Some(loading) = state.session().loading() else {
        return;
    };
    ui.separator();
    ui.spinner();
    ui.label(format!("opening {} path(s)", loading.paths));
    let mut text = loading.progress.describe();
    if let Some(left) = loading.progress.remaining(loading.elapsed) {
        text.push_str(&format!(", about {:.0} s left", left.as_secs_f64().ceil()));
    }
    ui.add(
        egui::ProgressBar::new(loading.progress.fraction() as f32)
            .desired_width(260.0)
            .text(text),
    );
    if ui
        .small_button("Cancel")
        .on_hover_text("stop opening them; what they hold is not added")
        .clicked()
    {
        commands.push(Command::Session(SessionCommand::CancelLoading));
    }
}

/// The video being written: how far, and Cancel.
fn video_export(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let Some((path, done)) = state.video_export() else {
        return;
    };
    ui.separator();
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    ui.add(
        egui::ProgressBar::new(done)
            .desired_width(200.0)
            .text(format!("writing {name}: {:.0} %", 100.0 * done)),
    );
    if ui
        .small_button("Cancel")
        .on_hover_text("stop writing the video; nothing is written")
        .clicked()
    {
        commands.push(Command::File(FileCommand::CancelVideoExport));
    }
}

/// One checkbox per pane of the window (the view's own, remembered across restarts), and Reset
/// layout.
fn panes_menu(ui: &mut egui::Ui, view: &mut View) {
    ui.separator();
    for pane in Pane::ALL {
        let mut shown = view.layout.is_shown(pane);
        if ui.checkbox(&mut shown, pane.title()).changed() {
            view.layout.set_shown(pane, shown);
        }
    }
    // The controls a classroom link can hide (`hide=`), hidden and shown here too.
    let mut timeline = !view.hide_timeline;
    if ui.checkbox(&mut timeline, "Timeline").changed() {
        view.hide_timeline = !timeline;
    }
    if ui
        .add(egui::Button::new("Hide the menu bar").shortcut_text("F10"))
        .on_hover_text("for a class; F10 brings it back")
        .clicked()
    {
        view.hide_menu = true;
    }
    if ui
        .button("Reset layout")
        .on_hover_text("every pane shown, where it was at first")
        .clicked()
    {
        view.layout.reset();
    }
}

/// One checkbox per camera of the recording shown: which the camera panel shows (remembered by
/// name across recordings and restarts).
fn cameras_menu(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let streams = state.cameras().streams();
    ui.separator();
    if streams.is_empty() {
        ui.weak("No cameras in this recording");
        return;
    }
    ui.label("Cameras");
    for stream in streams {
        let mut shown = state.cameras().is_shown(&stream.name);
        let label = format!("{} ({} frames)", stream.name, stream.len());
        if ui.checkbox(&mut shown, label).changed() {
            commands.push(Command::Camera(CameraCommand::Show {
                name: stream.name.clone(),
                shown,
            }));
        }
    }
}

/// The Demos menu: the paper's experiments on the sample data (one click opens a demo in the
/// presentation layout), and the presentation layout's toggle.
fn demos_menu(ui: &mut egui::Ui, state: &AppState, view: &mut View, commands: &mut Vec<Command>) {
    ui.menu_button("Push it yourself", |ui| {
        sandbox::start_menu(ui, state, commands)
    });
    ui.separator();
    if let Err(why) = &state.demos().suite {
        ui.label(format!("no demos: {why}"));
    }
    for (index, name) in state.demos().names().into_iter().enumerate() {
        if ui
            .add_enabled(!state.training().is_running(), egui::Button::new(name))
            .on_hover_text("open its online set, train (or reuse) its offline model, and present")
            .clicked()
        {
            commands.push(Command::Demo(DemoCommand::Start(index)));
            view.presentation = true;
        }
    }
    ui.separator();
    ui.add(egui::Checkbox::new(
        &mut view.presentation,
        "Presentation layout (F5)",
    ));
}
