//! The desktop app: play back pushes, watch and steer online learning frame by frame.
//!
//! Layout like rerun's viewer: `state/` is plain Rust (time, selection, learning), `panels/` draws it,
//! one module per panel. Each frame, `App::logic` advances time and learning, `App::ui` draws every
//! panel, collecting [`state::Command`]s that are applied after the last panel.

pub mod camera_mode;
pub mod colors;
pub mod dialogs;
pub mod export;
pub mod format;
pub mod frame_rate;
pub mod hook;
pub mod keys;
pub mod layout;
pub mod link;
pub mod panels;
pub mod platform;
pub mod projector;
#[cfg(not(target_arch = "wasm32"))]
pub mod render;
pub mod state;
pub mod view;
mod workbench;

use std::path::PathBuf;

use eframe::egui;

use self::dialogs::{DialogRequest, DialogResult};
use self::state::models::Models;
use self::state::sources::bag_import::BagCommand;
use self::state::{AppState, Command, FileCommand, Persisted};
pub use self::view::{SideTab, View};
use crate::app::state::SessionCommand;

/// Most seconds playback moves in one frame. Playback keeps real time down to 4 frames per second
/// (a software renderer on a busy machine), yet a window that was hidden for minutes does not jump
/// far when it is drawn again.
pub const MAX_FRAME_STEP_S: f64 = 0.25;

/// Key under which eframe persists [`Persisted`].
pub(crate) const STORAGE_KEY: &str = "pushlab";
/// Key under which eframe persists the window's [`layout::Layout`].
pub(crate) const LAYOUT_KEY: &str = "pushlab-layout";

/// The app: its state and its view.
pub struct PushlabApp {
    pub state: AppState,
    pub view: View,
}

impl PushlabApp {
    /// An app with the given state.
    pub fn new(state: AppState) -> Self {
        Self {
            state,
            view: View::default(),
        }
    }

    /// One frame as the window runs it: time advances by the frame's `dt` (at most
    /// [`MAX_FRAME_STEP_S`], like
    /// `logic`), then everything is drawn. The UI tests and the frame-time benchmark drive this.
    pub fn frame(&mut self, ui: &mut egui::Ui) {
        let dt = ui.input(|i| i.stable_dt) as f64;
        self.state.advance(dt.min(MAX_FRAME_STEP_S));
        self.show(ui);
    }

    /// Draws every panel and applies the commands they produced. This is the whole UI; tests drive it
    /// through `egui_kittest` exactly as the window does.
    pub fn show(&mut self, ui: &mut egui::Ui) {
        let mut commands = Vec::new();
        let mut view_changes = Vec::new();
        keys::handle(ui.ctx(), &self.state, &mut view_changes, &mut commands);
        for change in view_changes {
            self.view.apply_key(change);
        }
        dropped_files(ui.ctx(), &mut commands);

        projector::apply(ui.ctx(), self.view.projector, self.view.light);
        if !self.view.hide_menu {
            panels::menu::top_bar(ui, &self.state, &mut self.view, &mut commands);
        }
        if self.view.presentation {
            panels::presentation::ui(ui, &self.state, &mut self.view, &mut commands);
        } else {
            workbench::ui(ui, &self.state, &mut self.view, &mut commands);
        }
        panels::shortcuts::window(ui.ctx(), &self.state, &mut self.view.show_shortcuts);
        panels::landscape::window(ui.ctx(), &self.state, &mut commands);
        panels::bag_dialog::window(ui.ctx(), &self.state, &mut self.view.dialogs, &mut commands);
        panels::dataset_dialog::window(ui.ctx(), &self.state, &mut commands);
        panels::live::window(ui.ctx(), &self.state, &mut commands);
        panels::sandbox::window(ui.ctx(), &self.state, &mut self.view.dialogs, &mut commands);

        for command in commands {
            self.state.apply(command);
        }
        self.handle_dialog_results(ui.ctx());
        self.handle_screenshots();
    }

    fn handle_dialog_results(&mut self, ctx: &egui::Context) {
        while let Some(result) = self.view.dialogs.poll() {
            self.apply_dialog_result(ctx, result);
        }
    }

    /// Does what a dialog's answer asks for: open the files, save the scene, export the labels….
    /// Public so that tests can answer a dialog the way a user would.
    pub fn apply_dialog_result(&mut self, ctx: &egui::Context, result: DialogResult) {
        match result {
            DialogResult::Open(paths) => self
                .state
                .apply(Command::Session(SessionCommand::Open(paths))),
            DialogResult::BagSetting(path) => self
                .state
                .apply(Command::Bag(BagCommand::UseSettingFile(path))),
            DialogResult::SaveScene(path) => {
                self.request_screenshot(ctx, self.view.scene.rect(), path)
            }
            DialogResult::SavePlots(path) => {
                self.request_screenshot(ctx, self.view.plots_rect, path)
            }
            DialogResult::SavePlotsSvg(path) => self
                .state
                .apply(Command::File(FileCommand::ExportPlots(path))),
            #[cfg(not(target_arch = "wasm32"))]
            DialogResult::SaveVideo(path) => {
                // The push as on screen — at the speed it plays, with the plots when they are
                // shown — at 1280 × 720 and 30 frames a second.
                let options = render::RenderOptions {
                    speed: self.state.persisted().speed,
                    theme: self::colors::theme_of(ctx),
                    with_plots: self.view.layout.is_shown(layout::Pane::Plots),
                    ..render::RenderOptions::default()
                };
                match render::work_for(&self.state, path.clone(), options) {
                    Ok(work) => self.state.start_video_export(path, work),
                    Err(why) => self.state.apply(Command::Report(why)),
                }
            }
            #[cfg(target_arch = "wasm32")]
            DialogResult::SaveVideo(_) => {}
            DialogResult::SaveLossCsv(path) => self
                .state
                .apply(Command::File(FileCommand::SaveLosses(path))),
            DialogResult::LoadModel(path) => self
                .state
                .apply(Command::File(FileCommand::LoadModel(path))),
            DialogResult::ExportLabels(path, format) => {
                (self.state).apply(Command::File(FileCommand::ExportLabels(path, format)))
            }
            DialogResult::Unavailable(message) => self.state.apply(Command::Report(message)),
            DialogResult::SaveModel(path) => self
                .state
                .apply(Command::File(FileCommand::SaveModel(path))),
            DialogResult::SaveSandbox(dir) => self
                .state
                .apply(Command::File(FileCommand::SaveSandbox(dir))),
        }
    }

    /// Asks the renderer for a screenshot; the region is cropped and saved when it arrives.
    fn request_screenshot(&mut self, ctx: &egui::Context, rect: egui::Rect, path: PathBuf) {
        let ppp = ctx.pixels_per_point();
        let sender = self.view.screenshot_status.0.clone();
        let repaint = ctx.clone();
        let callback = egui::ScreenshotCallback::new(move |image| {
            let message = match export::save_region_png(&image, rect, ppp, &path) {
                Ok(()) => format!("saved {}", path.display()),
                Err(e) => format!("could not save {}: {e:#}", path.display()),
            };
            // The receiver is gone only when the app closed.
            let _ = sender.send(message);
            repaint.request_repaint();
        });
        ctx.send_viewport_cmd(egui::ViewportCommand::Screenshot(callback));
    }

    fn handle_screenshots(&mut self) {
        while let Ok(message) = self.view.screenshot_status.1.try_recv() {
            self.state.apply(Command::Report(message));
        }
    }
}

impl eframe::App for PushlabApp {
    fn logic(&mut self, ctx: &egui::Context, _frame: &mut eframe::Frame) {
        let dt = ctx.input(|i| i.stable_dt) as f64;
        if self.state.advance(dt.min(MAX_FRAME_STEP_S)) || self.view.dialogs.is_open() {
            ctx.request_repaint();
        }
        if platform::run_queued() || platform::has_queued() {
            ctx.request_repaint();
        }
        self.state.autosave_labels(ctx.input(|i| i.time));
        if self.state.labels().any_unsaved() {
            // Wake up to autosave even when nothing else moves.
            ctx.request_repaint_after(std::time::Duration::from_millis(250));
        }
    }

    fn on_exit(&mut self) {
        // Closing the window must not lose labels that autosave had not written yet.
        for line in self.state.save_labels_on_exit() {
            eprintln!("pushlab: {line}");
        }
    }

    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        // Frame intervals count only while the window animates; idle gaps are the user's pauses.
        let animating = self.state.timeline().playing;
        let interval = ui.input(|i| i.unstable_dt);
        self.view
            .frame_rate
            .record(animating.then_some(interval), frame.info().cpu_usage);
        self.show(ui);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, STORAGE_KEY, &self.state.persisted());
        eframe::set_value(storage, LAYOUT_KEY, &self.view.layout);
    }
}

/// Files and folders dropped on the window are opened like the Open dialog's.
fn dropped_files(ctx: &egui::Context, commands: &mut Vec<Command>) {
    let paths: Vec<PathBuf> = ctx.input(|i| {
        i.raw
            .dropped_files
            .iter()
            .map(|f| f.path().to_path_buf())
            // A page's drops carry a bare file name and their bytes: the page reads them.
            .filter(|p| p.is_absolute())
            .collect()
    });
    if !paths.is_empty() {
        commands.push(Command::Session(SessionCommand::Open(paths)));
    }
}

/// The bundled sample data: `sample-data/` next to the working directory, else in the source tree
/// the binary was built from.
pub fn sample_data_dir() -> PathBuf {
    platform::bundled_root().join("sample-data")
}

/// The suite of the paper's experiments on the sample data, whose experiments are the Demos menu's
/// presets: `experiments/sample-data.json` beside the sample data.
pub fn demo_suite_path() -> PathBuf {
    platform::bundled_root()
        .join("experiments")
        .join("sample-data.json")
}

/// The app state opened on `paths`, or on the bundled sample data when `paths` is empty, with the
/// bundled default model when there is one. Used by the binary and by the UI tests.
pub fn initial_state(paths: &[PathBuf], persisted: Persisted) -> AppState {
    let mut state = AppState::new(persisted, Models::default());
    state.load_demos(&demo_suite_path());
    if let Some(path) = export::default_model_path()
        && let Err(e) = state.load_model(&path)
    {
        state.apply(Command::Report(format!("{e:#}")));
    }
    let paths = if paths.is_empty() {
        vec![sample_data_dir()]
    } else {
        paths.to_vec()
    };
    state.open_blocking(&paths);
    state
}

/// Opens the app window; returns when it is closed.
#[cfg(not(target_arch = "wasm32"))]
pub fn run(paths: Vec<PathBuf>) -> anyhow::Result<()> {
    platform::return_large_blocks_when_freed();
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("pushlab")
            .with_inner_size([1400.0, 900.0])
            .with_min_inner_size([900.0, 600.0])
            .with_drag_and_drop(true),
        ..Default::default()
    };
    eframe::run_native(
        "pushlab",
        options,
        Box::new(move |cc| {
            let persisted: Persisted = cc
                .storage
                .and_then(|s| eframe::get_value(s, STORAGE_KEY))
                .unwrap_or_default();
            let mut state = initial_state(&paths, persisted);
            state.keep_files_in(eframe::storage_dir("pushlab"));
            let mut app = PushlabApp::new(state);
            if let Some(layout) = cc.storage.and_then(|s| eframe::get_value(s, LAYOUT_KEY)) {
                app.view.layout = layout;
            }
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| anyhow::anyhow!("could not open the window: {e}"))
}

/// A request to open a native dialog (used by the menu).
pub fn open_dialog(view: &mut View, request: DialogRequest) {
    view.dialogs.open(request);
}
