//! Opening recordings: on this thread (command line, tests) or merged from the loading thread, the
//! recent paths the File menu lists, and what the status line says after a load. Opening touches
//! the session, the labels, the bags' forms, the model per folder and the fit, so it is the whole
//! state's; nothing here is imported by the state itself.

use std::path::PathBuf;

use crate::app::state::AppState;

/// How many recent paths the File menu remembers.
pub const MAX_RECENT: usize = 10;

/// What the status line says when a background load finished.
fn load_message(new_recordings: usize, new_problems: usize) -> String {
    let opened = match new_recordings {
        0 => "no new recordings opened".to_owned(),
        1 => "opened 1 recording".to_owned(),
        n => format!("opened {n} recordings"),
    };
    match new_problems {
        0 => opened,
        1 => format!("{opened}; 1 file could not be read (see the browser)"),
        n => format!("{opened}; {n} files could not be read (see the browser)"),
    }
}

impl AppState {
    /// Opens paths on this thread (command line, tests) and selects the first new recording.
    pub fn open_blocking(&mut self, paths: &[PathBuf]) {
        self.remember(paths);
        self.labels.unreadable.clear();
        let selected = self.session.open_blocking(paths);
        self.labels.sync(self.session.recordings().map(|(_, r)| r));
        if selected {
            self.start_run();
        }
        self.after_opening();
        let effects = self.bags.poll(&mut self.session);
        self.apply_effects(effects);
        let effects = self.datasets.poll(&mut self.session);
        self.apply_effects(effects);
        self.proposals.wait();
        self.refresh_frame_cache();
    }

    /// Merges what the loading threads finished: the recordings (the first new one shown), the
    /// labels files beside them, the bags waiting for a choice, and a status line saying what
    /// opened.
    pub(in crate::app::state) fn poll_opening(&mut self) {
        let was_loading = self.session.loading().is_some();
        let (recordings, problems) = (self.session.recording_count(), self.session.problems.len());
        let selected = self.session.poll_loading();
        if was_loading && self.session.loading().is_none() {
            self.labels.sync(self.session.recordings().map(|(_, r)| r));
            self.status = Some(load_message(
                self.session.recording_count().saturating_sub(recordings),
                self.session.problems.len() - problems,
            ));
            self.after_opening();
        }
        let effects = self.bags.poll(&mut self.session);
        self.apply_effects(effects);
        let effects = self.datasets.poll(&mut self.session);
        self.apply_effects(effects);
        if selected {
            self.start_run();
        }
    }

    /// After recordings were opened: the model remembered for their folders comes back, and the
    /// status line says when the model in use does not fit them.
    fn after_opening(&mut self) {
        self.remember_parameters();
        self.reopen_folder_model();
        self.refresh_fit();
        if let Some(mismatch) = &self.fit {
            let message = format!("warning: {}", mismatch.message);
            self.status = Some(match self.status.take() {
                Some(before) => format!("{before} — {message}"),
                None => message,
            });
        }
    }

    /// Puts opened paths first in the recent list.
    pub(in crate::app::state) fn remember(&mut self, paths: &[PathBuf]) {
        for path in paths.iter().rev() {
            let path = std::path::absolute(path).unwrap_or_else(|_| path.clone());
            self.settings.recent.retain(|p| *p != path);
            self.settings.recent.insert(0, path);
        }
        self.settings.recent.truncate(MAX_RECENT);
    }
}
