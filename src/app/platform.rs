//! What differs between the desktop and a browser tab, in one place: how work runs off the UI
//! thread, the clock, and where the bundled files are. Files themselves go through the core's
//! `pushlab_core::files`, which reads the disk on the desktop and the page's in-memory tree in a tab.
//!
//! Why one seam: a page has no threads (`std::thread::spawn` panics on `wasm32-unknown-unknown`) and
//! no `std::time::Instant`; the panels and the state must not care. On the desktop [`spawn`] starts
//! a thread; in a page it queues the work, and [`run_queued`] runs what is queued between two
//! frames, after the frame that showed its progress bar was drawn. The jobs' channels, cancel flags
//! and progress are the same on both.

use std::path::PathBuf;

pub use web_time::{Duration, Instant, SystemTime, UNIX_EPOCH};

/// Where the bundled sample data, demos and default model sit among a page's files (the page
/// fetches them there before the app starts).
pub const BUNDLED_ROOT: &str = "/pushlab";

/// The app's own folder among a page's files: what the desktop keeps in its data folder (models
/// trained for demos, labels rescued).
pub const APP_FOLDER: &str = "/pushlab-app";

/// Runs `work` off the UI thread: on a thread of its own on the desktop, between frames in a page.
pub fn spawn(work: impl FnOnce() + Send + 'static) {
    backend::spawn(Box::new(work));
}

/// Runs the work [`spawn`] queued in a page, oldest first, one item per call so that a frame is
/// drawn between two; returns whether one ran. Nothing is ever queued on the desktop.
pub fn run_queued() -> bool {
    backend::run_queued()
}

/// Whether work is queued and waiting for [`run_queued`] (always `false` on the desktop).
pub fn has_queued() -> bool {
    backend::has_queued()
}

/// Where the bundled sample data, demos and default model are: beside the working directory or in
/// the source tree on the desktop, under `/pushlab` among a page's files (the page fetches them
/// there before the app starts).
pub fn bundled_root() -> PathBuf {
    #[cfg(target_arch = "wasm32")]
    return PathBuf::from(BUNDLED_ROOT);
    #[cfg(not(target_arch = "wasm32"))]
    backend::bundled_root()
}

#[cfg(not(target_arch = "wasm32"))]
mod backend {
    use std::path::{Path, PathBuf};

    pub fn spawn(work: Box<dyn FnOnce() + Send>) {
        std::thread::spawn(work);
    }

    pub fn run_queued() -> bool {
        false
    }

    pub fn has_queued() -> bool {
        false
    }

    pub fn bundled_root() -> PathBuf {
        if pushlab_core::files::is_dir(Path::new("sample-data")) {
            PathBuf::new()
        } else {
            PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        }
    }
}

#[cfg(target_arch = "wasm32")]
mod backend {
    use std::cell::RefCell;
    use std::collections::VecDeque;

    thread_local! {
        static QUEUE: RefCell<VecDeque<Box<dyn FnOnce() + Send>>> = RefCell::new(VecDeque::new());
    }

    pub fn spawn(work: Box<dyn FnOnce() + Send>) {
        QUEUE.with(|queue| queue.borrow_mut().push_back(work));
    }

    pub fn run_queued() -> bool {
        // Taken out before it runs: the work may queue more.
        let next = QUEUE.with(|queue| queue.borrow_mut().pop_front());
        next.map(|work| work()).is_some()
    }

    pub fn has_queued() -> bool {
        QUEUE.with(|queue| !queue.borrow().is_empty())
    }
}
