//! What differs between the desktop and a browser tab, in one place: how work runs off the UI
//! thread, the clock, and where the bundled files are. Files themselves go through the core's
//! `pushlab_core::files`, which reads the disk on the desktop and the page's in-memory tree in a tab.
//!
//! Why one seam: a page has no threads (`std::thread::spawn` panics on `wasm32-unknown-unknown`) and
//! no `std::time::Instant`; the panels and the state must not care. On the desktop [`spawn`] and
//! [`spawn_in_slices`] start a thread; in a page they queue the work, and [`run_queued`] runs it
//! between two frames, after the frame that showed its progress bar was drawn: work in one piece
//! whole, work written in slices (`pushlab_core::slices`: training) for a slice of each frame, so
//! that the page keeps drawing and its Cancel can be pressed. The jobs' channels, cancel flags and
//! progress are the same on both.

#[cfg(any(target_arch = "wasm32", test))]
mod queue;

use std::future::Future;
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

/// Runs work written in slices off the UI thread: to its end on a thread of its own on the
/// desktop, a slice of each frame in a page. `make` builds the work where it runs (the work
/// itself need not be `Send`: it holds its progress callback across its pauses).
pub fn spawn_in_slices<F>(make: impl FnOnce() -> F + Send + 'static)
where
    F: Future<Output = ()> + 'static,
{
    backend::spawn_in_slices(make);
}

/// Runs the work queued in a page, oldest first, one item per call so that a frame is drawn
/// between two: work in one piece to its end, work in slices for about as long as the page spent
/// on everything else since the last slice (16–100 ms: `queue::slice_budget`), then back at the
/// end of the queue; returns whether one ran. Nothing is ever queued on the desktop.
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

    pub fn spawn_in_slices<F: std::future::Future<Output = ()>>(
        make: impl FnOnce() -> F + Send + 'static,
    ) {
        std::thread::spawn(move || pushlab_core::slices::finish(make()));
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
    use std::cell::{Cell, RefCell};

    use crate::app::platform::Instant;
    use crate::app::platform::queue::{WorkQueue, run_slice, slice_budget};

    thread_local! {
        static QUEUE: RefCell<WorkQueue> = RefCell::new(WorkQueue::default());
        /// When the last slice ended: the time since is what the page spent elsewhere.
        static LAST_SLICE_END: Cell<Option<Instant>> = const { Cell::new(None) };
    }

    pub fn spawn(work: Box<dyn FnOnce() + Send>) {
        QUEUE.with(|queue| queue.borrow_mut().push(Box::pin(async move { work() })));
    }

    pub fn spawn_in_slices<F: std::future::Future<Output = ()> + 'static>(
        make: impl FnOnce() -> F + Send + 'static,
    ) {
        QUEUE.with(|queue| queue.borrow_mut().push(Box::pin(make())));
    }

    pub fn run_queued() -> bool {
        // Taken out while it runs: the work may queue more.
        let Some(work) = QUEUE.with(|queue| queue.borrow_mut().pop()) else {
            return false;
        };
        let start = Instant::now();
        let budget = slice_budget(LAST_SLICE_END.get().map(|end| start - end));
        if let Some(unfinished) = run_slice(work, start, budget) {
            QUEUE.with(|queue| queue.borrow_mut().push(unfinished));
        }
        // An idle page's time is not the page's drawing: the next work starts afresh.
        LAST_SLICE_END.set(has_queued().then(Instant::now));
        true
    }

    pub fn has_queued() -> bool {
        QUEUE.with(|queue| !queue.borrow().is_empty())
    }
}

/// Makes large blocks the app frees go back to the system, on Linux with glibc; called once, before
/// the window opens.
///
/// glibc serves a request of 128 kB or more from its own mapping, returned on free, but raises that
/// threshold to the size of each such block freed, up to 32 MB. A recording's work makes many
/// vectors of a few MB, one slot per frame (loading, the proposals, the fixed runs), on worker
/// threads; once the threshold has risen they come from the workers' arenas, and an arena keeps
/// what is freed. The million-frame push (`pushlab simulate --pushes 1 --rate 250 --duration 4000`)
/// played in 460 MB, 124 MB of it freed memory held by one worker's arena. A fixed threshold of
/// 4 MB keeps the rise from happening: blocks that large are mapped and unmapped whole (292–328 MB,
/// the same push; `docs/src/performance.md`). Smaller blocks, the per-frame work, are untouched.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[allow(unsafe_code)]
pub fn return_large_blocks_when_freed() {
    const THRESHOLD: libc::c_int = 4 << 20;
    // SAFETY: `mallopt` only sets an allocator parameter; glibc takes its own lock for it.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, THRESHOLD);
    }
}

/// Other allocators return large blocks without being asked.
#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
pub fn return_large_blocks_when_freed() {}
