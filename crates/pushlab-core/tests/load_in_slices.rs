//! Loading as a browser tab does it: polled a slice at a time (`pushlab_core::slices`), a file or
//! set a slice, so that the page's progress bar moves and its Cancel is seen between two files.

use std::path::{Path, PathBuf};

use pushlab_core::recording::{LoadError, LoadProgress, load_paths, load_paths_in_slices};
use pushlab_core::slices;

fn sample_sets() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../sample-data");
    [
        "box1-paper-center-front",
        "box1-paper-ur-front",
        "box1-paper-center-left",
    ]
    .iter()
    .map(|name| root.join(name))
    .collect()
}

#[test]
fn a_load_in_slices_pauses_after_each_set_and_opens_what_a_load_in_one_piece_opens() {
    let sets = sample_sets();
    let whole = load_paths(&sets);
    let progress = LoadProgress::default();
    let mut work = Box::pin(load_paths_in_slices(&sets, &[], &progress));
    let mut done_after_each_slice = Vec::new();
    let report = loop {
        if let Some(report) = slices::poll_once(work.as_mut()) {
            break report;
        }
        done_after_each_slice.push(progress.snapshot().files_done);
    };
    drop(work);
    assert_eq!(done_after_each_slice, [1, 2, 3]);
    let names = |r: &pushlab_core::recording::LoadReport| -> Vec<String> {
        (r.sets.iter())
            .flat_map(|s| s.recordings.iter().map(|r| r.name.clone()))
            .collect()
    };
    assert!(names(&whole).len() > 30, "{}", names(&whole).len());
    assert_eq!(names(&report), names(&whole));

    // Cancelled between the first set and the second: the rest is said cancelled, not read.
    let progress = LoadProgress::default();
    let mut work = Box::pin(load_paths_in_slices(&sets, &[], &progress));
    assert!(slices::poll_once(work.as_mut()).is_none());
    progress.cancel();
    let report = slices::poll_once(work.as_mut()).expect("ends at the next set");
    assert!(
        matches!(report.errors[..], [LoadError::Cancelled { .. }]),
        "{:?}",
        report.errors
    );
}
