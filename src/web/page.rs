//! The app as the page runs it: the desktop's [`PushlabApp`] with what only a page does around each
//! frame — the hook's commands in, its `state()` out, files dropped on the page put among the page's
//! files and opened, files the app saved handed to the browser as downloads.

use std::path::Path;

use eframe::egui;
use pushlab_core::files::memory::TREE;

use crate::app::PushlabApp;
use crate::app::link::{Link, Steps};
use crate::app::state::Command;

use super::address::{self, AddressBar};
use crate::app::dialogs::browser;
use crate::app::platform::APP_FOLDER;

pub struct Page {
    app: PushlabApp,
    /// The link the page was opened with, while it is being applied.
    link: Option<Steps>,
    address_bar: AddressBar,
    drawn: u64,
}

impl Page {
    pub fn new(mut app: PushlabApp, context: &egui::Context) -> Self {
        browser::keep_context(context);
        app.view.page_address = address::page_address();
        let link = match Link::parse(&address::opened_query()) {
            Ok(link) => {
                app.view.follow_link_part(&link.view());
                Some(link.steps())
            }
            Err(why) => {
                app.state.apply(Command::Report(why));
                None
            }
        };
        Self {
            app,
            link,
            address_bar: AddressBar::default(),
            drawn: 0,
        }
    }

    /// Applies the next stage of the link the page was opened with, once the app is ready for it.
    fn follow_link(&mut self, context: &egui::Context) {
        let Some(steps) = self.link.as_mut() else {
            return;
        };
        match steps.next(&self.app.state) {
            Some(Ok(commands)) => {
                for command in commands {
                    self.app.state.apply(command);
                }
                context.request_repaint();
            }
            Some(Err(why)) => {
                self.app.state.apply(Command::Report(why));
                self.link = None;
            }
            None => self.link = None,
        }
    }

    fn hook_commands(&mut self) {
        for command in super::hook::take_commands() {
            match crate::app::hook::translate(&command, &self.app.state) {
                Ok(translated) => {
                    for command in translated.commands {
                        self.app.state.apply(command);
                    }
                    if let Some(url) = translated.fetch {
                        browser::open_urls(vec![url]);
                    }
                }
                Err(why) => self.app.state.apply(Command::Report(why)),
            }
        }
    }

    /// Files dropped on the page (a name, and bytes the browser reads asynchronously) are written
    /// into a folder of their own and opened: the folder when they hold a set's `setting.json`,
    /// else each file.
    fn dropped_files(&mut self, context: &egui::Context) {
        let dropped = context.input(|i| i.raw.dropped_files.clone());
        if dropped.is_empty() {
            return;
        }
        browser::read_dropped(dropped);
    }
}

/// Key of the browser's storage under which the page keeps the user's own files.
const KEPT_FILES: &str = "pushlab-files";

/// Whether a file of the page's is the user's work that must outlive the tab: labels (and labels
/// rescued beside or in the app's folder).
fn is_kept(path: &Path) -> bool {
    path.file_name()
        .map(|n| n.to_string_lossy())
        .is_some_and(|n| n.starts_with("pushlab-labels") && n.ends_with(".json"))
        || path.starts_with(APP_FOLDER)
            && path.extension().is_some_and(|e| e == "json")
            && !path.starts_with(format!("{APP_FOLDER}/models"))
}

/// Writes the user's files (labels) into the browser's storage, as text by path.
fn keep_files(storage: &mut dyn eframe::Storage) {
    let kept: std::collections::BTreeMap<String, String> = TREE
        .files()
        .into_iter()
        .filter(|(p, _)| is_kept(p))
        .filter_map(|(p, _)| {
            let text = String::from_utf8(TREE.read(&p).ok()?).ok()?;
            Some((p.display().to_string(), text))
        })
        .collect();
    if let Ok(json) = serde_json::to_string(&kept) {
        storage.set_string(KEPT_FILES, json);
    }
}

/// Puts the files kept by [`keep_files`] back among the page's files, before anything opens.
pub fn restore_kept_files(storage: &dyn eframe::Storage) {
    let Some(json) = storage.get_string(KEPT_FILES) else {
        return;
    };
    let kept: std::collections::BTreeMap<String, String> =
        serde_json::from_str(&json).unwrap_or_default();
    for (path, text) in kept {
        TREE.write(Path::new(&path), text.into_bytes());
    }
}

impl eframe::App for Page {
    fn logic(&mut self, context: &egui::Context, frame: &mut eframe::Frame) {
        self.follow_link(context);
        self.hook_commands();
        self.dropped_files(context);
        for result in browser::take_opened() {
            self.app.apply_dialog_result(context, result);
        }
        self.app.logic(context, frame);
    }

    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        self.app.ui(ui, frame);
        if self.link.is_none() {
            let link = Link::of(&self.app.state, &self.app.view.link_part());
            (self.address_bar).follow(&link, self.app.state.timeline().playing);
        }
        self.drawn += 1;
        let mut shown = crate::app::hook::shown(&self.app.state);
        shown.frames_drawn = Some(self.drawn);
        shown.frame_cpu_ms = frame.info().cpu_usage.map(|s| s * 1e3);
        shown.busy |=
            self.link.is_some() || crate::app::platform::has_queued() || browser::under_way();
        super::hook::set_shown(shown);
        browser::download_saved();
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        self.app.save(storage);
        keep_files(storage);
    }
}
