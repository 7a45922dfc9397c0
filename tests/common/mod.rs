//! What the app's test files share: a harness that runs the app frame by frame as the window does,
//! and the sample-data sets (read in place, or copied when a test writes labels).

#![allow(dead_code)] // each test file uses its own part

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use pushlab::app::PushlabApp;

/// The app in a 1400×900 window, each step `step_dt` seconds long.
pub fn harness(app: PushlabApp, step_dt: f32) -> Harness<'static, PushlabApp> {
    Harness::builder()
        .with_size([1400.0, 900.0])
        .with_step_dt(step_dt)
        .build_ui_state(|ui, app: &mut PushlabApp| app.frame(ui), app)
}

/// Runs frames until `done` holds (background loading or training), with a generous wall-clock
/// limit for the threads behind them.
pub fn run_until(
    harness: &mut Harness<'_, PushlabApp>,
    what: &str,
    done: impl Fn(&PushlabApp) -> bool,
) {
    let deadline = Instant::now() + Duration::from_secs(120);
    while !done(harness.state()) {
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        harness.run_steps(1);
        std::thread::sleep(Duration::from_millis(10));
    }
    harness.run_steps(2);
}

/// A set of the bundled sample data, or `None` (with a message) where it is missing.
pub fn sample_set(name: &str) -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample-data")
        .join(name);
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("skipped: {} is missing", dir.display());
        None
    }
}

/// An empty folder of the system's temporary directory for one test.
pub fn scratch_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pushlab-test-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// A private copy of a sample set, so that a test that writes labels never touches the repository.
pub fn copy_of_sample_set(name: &str, test: &str) -> Option<PathBuf> {
    let source = sample_set(name)?;
    let dir = scratch_dir(test);
    for entry in std::fs::read_dir(&source).expect("sample set") {
        let entry = entry.expect("dir entry");
        std::fs::copy(entry.path(), dir.join(entry.file_name())).expect("copy");
    }
    Some(dir)
}
