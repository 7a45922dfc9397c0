//! Opening recordings: on this thread (command line, tests) or merged from the loading thread, the
//! recent paths the File menu lists, and what the status line says after a load.

use std::path::PathBuf;

use super::AppState;

/// How many recent paths the File menu remembers.
pub const MAX_RECENT: usize = 10;

/// What the status line says when a background load finished.
pub(super) fn load_message(new_recordings: usize, new_problems: usize) -> String {
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
        self.labels.sync(&self.session);
        if selected {
            self.start_run();
        }
        self.after_opening();
        if let Some(message) = self.after_bag_work() {
            self.status = Some(message);
        }
        self.proposals.wait();
    }

    /// After recordings were opened: the model remembered for their folders comes back, and the
    /// status line says when the model in use does not fit them.
    pub(super) fn after_opening(&mut self) {
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

    pub(super) fn remember(&mut self, paths: &[PathBuf]) {
        for path in paths.iter().rev() {
            let path = std::path::absolute(path).unwrap_or_else(|_| path.clone());
            self.settings.recent.retain(|p| *p != path);
            self.settings.recent.insert(0, path);
        }
        self.settings.recent.truncate(MAX_RECENT);
    }
}
