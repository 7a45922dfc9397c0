//! What the app's test files share: a harness that runs the app frame by frame as the window does,
//! and the sample-data sets (read in place, or copied when a test writes labels).
//!
//! `sample-data/` is committed, so a missing set can only mean a broken checkout: the test fails
//! with the path, it never skips. (Skipping is right only for data outside the repository, such as
//! `../shared/mit-push/`.)

#![allow(dead_code)] // each test file uses its own part

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use pushlab::app::state::playback::timeline::TimelineCommand;
use pushlab::app::state::{Command, Persisted};
use pushlab::app::{PushlabApp, initial_state};

/// The app in a 1400×900 window, each step `step_dt` seconds long.
pub fn harness(app: PushlabApp, step_dt: f32) -> Harness<'static, PushlabApp> {
    Harness::builder()
        .with_size([1400.0, 900.0])
        .with_step_dt(step_dt)
        .build_ui_state(|ui, app: &mut PushlabApp| app.frame(ui), app)
}

/// The app on one bundled sample set with the default settings — learning while playing on, so that
/// stepping learns — in a window whose steps are 0.05 s.
pub fn app_on_sample(set: &str) -> Harness<'static, PushlabApp> {
    let persisted = Persisted::default();
    assert!(persisted.learn_while_playing);
    let state = initial_state(&[sample_dir(set)], persisted);
    assert!(state.run().is_some(), "{:?}", state.session().problems);
    harness(PushlabApp::new(state), 0.05)
}

/// The status line's text ("" when it says nothing).
pub fn status(harness: &Harness<'_, PushlabApp>) -> String {
    harness
        .state()
        .state
        .status()
        .unwrap_or_default()
        .to_owned()
}

/// Steps `frames` frames forward one at a time (learning each, as playing does), then draws.
pub fn step_frames(harness: &mut Harness<'_, PushlabApp>, frames: usize) {
    for _ in 0..frames {
        harness
            .state_mut()
            .state
            .apply(Command::Timeline(TimelineCommand::Step(1)));
    }
    harness.run_steps(2);
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

/// A set of the bundled sample data; panics (fails the test) when it is missing.
pub fn sample_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample-data")
        .join(name);
    assert!(
        dir.is_dir(),
        "{} is missing: sample-data/ is part of the repository, so the checkout is broken",
        dir.display()
    );
    dir
}

/// An empty folder for one test under cargo's `target/tmp`: emptied when the test starts, so runs
/// leave one folder per test there rather than one per run in the system's temporary directory.
pub fn scratch_dir(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("pushlab-test-{test}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// A private copy of a sample set, so that a test that writes labels never touches the repository.
pub fn copy_of_sample_set(name: &str, test: &str) -> PathBuf {
    let source = sample_dir(name);
    let dir = scratch_dir(test);
    for entry in std::fs::read_dir(&source).expect("sample set") {
        let entry = entry.expect("dir entry");
        std::fs::copy(entry.path(), dir.join(entry.file_name())).expect("copy");
    }
    dir
}

/// Makes a folder unwritable for this process until dropped: `chmod 555`, and where that does not
/// stop writes (tests running as root) also the immutable attribute, `chattr +i`.
pub struct Unwritable(PathBuf);

impl Unwritable {
    /// `None` where neither stops this process from writing into `dir`.
    pub fn make(dir: &Path) -> Option<Self> {
        use std::os::unix::fs::PermissionsExt as _;
        let writable = || {
            let probe = dir.join(".probe");
            let ok = std::fs::write(&probe, b"").is_ok();
            let _ = std::fs::remove_file(&probe);
            ok
        };
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o555)).ok()?;
        let guard = Self(dir.to_path_buf());
        if writable() {
            let _ = std::process::Command::new("chattr")
                .arg("+i")
                .arg(dir)
                .status();
        }
        (!writable()).then_some(guard)
    }
}

impl Drop for Unwritable {
    fn drop(&mut self) {
        use std::os::unix::fs::PermissionsExt as _;
        let _ = std::process::Command::new("chattr")
            .arg("-i")
            .arg(&self.0)
            .status();
        let _ = std::fs::set_permissions(&self.0, std::fs::Permissions::from_mode(0o755));
    }
}

/// Every file of a folder and its bytes.
pub fn contents(dir: &Path) -> Vec<(std::ffi::OsString, Vec<u8>)> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .expect("folder")
        .map(|e| {
            let e = e.expect("entry");
            (e.file_name(), std::fs::read(e.path()).expect("file"))
        })
        .collect();
    files.sort();
    files
}

/// A path dropped on the window, as the windowing integration hands it to egui.
#[derive(Debug)]
struct Dropped(PathBuf);

impl eframe::egui::DroppedFile for Dropped {
    fn path(&self) -> &Path {
        &self.0
    }

    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

/// Drops `path` on the app's window, as a user dragging a file or folder onto it.
pub fn drop_on_window(harness: &mut Harness<'_, PushlabApp>, path: &Path) {
    harness
        .input_mut()
        .dropped_files
        .push(std::sync::Arc::new(Dropped(path.to_path_buf())));
}
