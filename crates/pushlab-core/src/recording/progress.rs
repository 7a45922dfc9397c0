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
    /// What a progress bar says: `1.20 GB of 4.00 GB`, with the file when there are several.
    pub fn describe(&self) -> String {
        let bytes = format!("{} of {}", size(self.bytes_done), size(self.bytes_total));
        if self.files_total > 1 {
            let file = (self.files_done + 1).min(self.files_total);
            format!("{bytes}, file {file} of {}", self.files_total)
        } else {
            bytes
        }
    }

    /// How long the rest should take at the rate so far, once enough is done to tell (2 % of the
    /// bytes and half a second).
    pub fn remaining(&self, elapsed: std::time::Duration) -> Option<std::time::Duration> {
        let done = self.fraction();
        ((0.02..1.0).contains(&done) && elapsed.as_secs_f64() >= 0.5)
            .then(|| elapsed.mul_f64((1.0 - done) / done))
    }

    /// The sum of two loads' progress.
    pub fn plus(self, other: Self) -> Self {
        Self {
            bytes_done: self.bytes_done + other.bytes_done,
            bytes_total: self.bytes_total + other.bytes_total,
            files_done: self.files_done + other.files_done,
            files_total: self.files_total + other.files_total,
        }
    }

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

/// A size in bytes as people read it (decimal units, three significant digits).
fn size(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["kB", "MB", "GB", "TB"];
    if bytes < 1000 {
        return format!("{bytes} B");
    }
    let mut value = bytes as f64;
    let mut unit = "B";
    for u in UNITS {
        if value < 1000.0 {
            break;
        }
        value /= 1000.0;
        unit = u;
    }
    let digits = if value < 10.0 {
        2
    } else if value < 100.0 {
        1
    } else {
        0
    };
    format!("{value:.digits$} {unit}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn progress_reads_as_sizes_and_files() {
        let one = ProgressSnapshot {
            bytes_done: 1_234_000_000,
            bytes_total: 4_000_000_000,
            files_done: 0,
            files_total: 1,
        };
        assert_eq!(one.describe(), "1.23 GB of 4.00 GB");
        let two = one.plus(ProgressSnapshot {
            bytes_done: 500,
            bytes_total: 56_700,
            files_done: 1,
            files_total: 2,
        });
        assert_eq!(two.describe(), "1.23 GB of 4.00 GB, file 2 of 3");
        assert_eq!(size(999), "999 B");
        let quarter = ProgressSnapshot {
            bytes_done: 250,
            bytes_total: 1000,
            files_done: 0,
            files_total: 1,
        };
        let elapsed = std::time::Duration::from_secs(2);
        assert_eq!(
            quarter.remaining(elapsed),
            Some(std::time::Duration::from_secs(6))
        );
        assert_eq!(
            quarter.remaining(std::time::Duration::from_millis(100)),
            None,
            "too soon"
        );
        assert_eq!(size(56_700), "56.7 kB");
        assert_eq!(size(123_456_789), "123 MB");
    }
}
