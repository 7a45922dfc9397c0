//! How far a load has come, told to whoever shows it (the app's progress bar, the CLI's), and a way
//! for them to stop it.
//!
//! Loading plans first — which files the paths hold and how many bytes — so that the bar shows bytes
//! of a known total from the start; readers then report bytes as they pass them (a bag chunk by
//! chunk, other files whole) and look at the cancel flag between files and between chunks, so that
//! cancelling a multi-GB bag stops within one chunk.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};

/// Where a reader reports the bytes it passed, and learns whether to stop.
pub trait Progress: Sync {
    /// `bytes` more of the planned total were passed.
    fn advance(&self, bytes: u64);
    /// Whether whoever waits asked to stop.
    fn is_cancelled(&self) -> bool;
}

/// For callers that show nothing and never cancel.
pub struct NoProgress;

impl Progress for NoProgress {
    fn advance(&self, _: u64) {}

    fn is_cancelled(&self) -> bool {
        false
    }
}

/// A load's progress, shared between the loading thread and the one showing it.
#[derive(Debug, Default)]
pub struct LoadProgress {
    bytes_total: AtomicU64,
    bytes_done: AtomicU64,
    files_total: AtomicUsize,
    files_done: AtomicUsize,
    cancelled: AtomicBool,
}

/// A moment of a load's progress.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ProgressSnapshot {
    pub bytes_done: u64,
    pub bytes_total: u64,
    pub files_done: usize,
    pub files_total: usize,
}

impl ProgressSnapshot {
    /// The fraction done, 0 … 1 (0 before anything is planned).
    pub fn fraction(&self) -> f64 {
        if self.bytes_total == 0 {
            0.0
        } else {
            (self.bytes_done as f64 / self.bytes_total as f64).clamp(0.0, 1.0)
        }
    }
}

impl LoadProgress {
    /// Asks the load to stop at its next file or chunk.
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    /// Where the load is now.
    pub fn snapshot(&self) -> ProgressSnapshot {
        ProgressSnapshot {
            bytes_done: self.bytes_done.load(Ordering::Relaxed),
            bytes_total: self.bytes_total.load(Ordering::Relaxed),
            files_done: self.files_done.load(Ordering::Relaxed),
            files_total: self.files_total.load(Ordering::Relaxed),
        }
    }

    /// Sets the planned total (done by `load_paths_with`; a caller reading files itself sets it).
    pub fn plan(&self, files: usize, bytes: u64) {
        self.files_total.store(files, Ordering::Relaxed);
        self.bytes_total.store(bytes, Ordering::Relaxed);
    }

    /// One planned file done; its bytes not yet reported are counted now.
    pub(crate) fn file_done(&self, bytes_reported: u64, bytes: u64) {
        self.advance(bytes.saturating_sub(bytes_reported));
        self.files_done.fetch_add(1, Ordering::Relaxed);
    }
}

impl Progress for LoadProgress {
    fn advance(&self, bytes: u64) {
        self.bytes_done.fetch_add(bytes, Ordering::Relaxed);
    }

    fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }
}
