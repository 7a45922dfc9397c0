//! A progress bar for loading (bytes of the total, files), on stderr, drawn from the core's
//! `LoadProgress` by a thread that polls it while the load runs on this one.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pushlab_core::recording::LoadProgress;

/// Runs `work` with a progress to report to, showing it as a bar labelled `what`; the bar is
/// removed when the work ends (it is hidden when stderr is not a terminal).
pub fn with_load_bar<T>(what: &str, work: impl FnOnce(&LoadProgress) -> T) -> T {
    let progress = Arc::new(LoadProgress::default());
    let done = Arc::new(AtomicBool::new(false));
    let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template(
            "{msg} [{bar:30}] {bytes}/{total_bytes} ({bytes_per_sec}, {eta})",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    bar.set_message(what.to_owned());
    let poller = {
        let (progress, done, bar) = (Arc::clone(&progress), Arc::clone(&done), bar.clone());
        std::thread::spawn(move || {
            while !done.load(Ordering::Relaxed) {
                let now = progress.snapshot();
                bar.set_length(now.bytes_total);
                bar.set_position(now.bytes_done);
                std::thread::sleep(Duration::from_millis(100));
            }
        })
    };
    let result = work(&progress);
    done.store(true, Ordering::Relaxed);
    // The poller only reads the progress; a panic in it cannot leave anything half done.
    let _ = poller.join();
    bar.finish_and_clear();
    result
}
