//! A test that cannot run here says so, and is counted.
//!
//! Some tests need what a fresh clone does not hold: the real recordings beside the repository
//! (`../shared/mit-push/`), or a program (ffmpeg, poppler). Such a test returns early, and `cargo
//! test` counts it as passed and hides what it printed. So a skip goes through [`skip`], which also
//! writes the test's name and the reason to the file that `PUSHLAB_SKIPPED` names: `scripts/test`
//! sets it, and ends by saying how many tests ran and how many were skipped, and why.
//!
//! Shared by both crates' tests: `tests/main.rs` declares it, `crates/pushlab-core/tests/main.rs`
//! and the app's unit tests (`src/lib.rs`) include this file by path.

#![allow(dead_code)] // each test binary uses its own part

use std::io::Write as _;
use std::path::{Path, PathBuf};

/// Says that the calling test did not run, and why: `why` completes "needs …" ("ffmpeg on the
/// PATH"), so that the summary can group the skips by what was missing.
pub fn skip(why: &str) {
    let thread = std::thread::current();
    // libtest runs each test on a thread named after it.
    let test = thread.name().unwrap_or("a test");
    eprintln!("skipped {test}: needs {why}");
    if let Some(log) = std::env::var_os("PUSHLAB_SKIPPED")
        && let Ok(mut file) = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(log)
    {
        // One short write with O_APPEND: lines of tests running side by side do not interleave.
        let _ = file.write_all(format!("{test}\t{why}\n").as_bytes());
    }
}

/// The folder `name` of the data kept beside the repository (`../shared/NAME`, not committed: the
/// real MIT Push files), or `None` after saying the test is skipped. `repository` is the
/// repository's root.
pub fn shared(repository: &Path, name: &str) -> Option<PathBuf> {
    let dir = repository.join("..").join("shared").join(name);
    if dir.is_dir() {
        Some(dir)
    } else {
        skip(&format!(
            "../shared/{name} (real recordings beside the repository)"
        ));
        None
    }
}
