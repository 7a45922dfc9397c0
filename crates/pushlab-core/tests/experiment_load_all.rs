//! `experiment::load_all`, what a script loads with (the Python package's `pushlab.load`): every
//! recording with its folder's labels attached by the same rule as `experiment::load` (what `pushlab
//! train` and `eval` use), and every unreadable file as an error naming it rather than a skip.

use std::path::{Path, PathBuf};

use pushlab_core::experiment;
use pushlab_core::labels::{Command, LabelDocument};

/// A copy of one sample set in a fresh folder.
fn sample_set_copy(test: &str) -> PathBuf {
    let from =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../sample-data/box1-paper-center-front");
    let dir = std::env::temp_dir()
        .join(format!("pushlab-load-all-{test}-{}", std::process::id()))
        .join("set");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    for entry in std::fs::read_dir(&from).expect("sample set") {
        let path = entry.expect("entry").path();
        let name = path.file_name().expect("file name");
        std::fs::copy(&path, dir.join(name)).expect("copy");
    }
    dir
}

#[test]
fn labels_and_bad_tracking_attach_as_for_training() {
    let dir = sample_set_copy("labels");
    let mut doc = LabelDocument::open_set_folder(&dir).expect("labels file");
    let paint = |label: &str, frames| Command::Paint {
        recording: "online_002.csv".into(),
        label: label.into(),
        frames,
    };
    doc.apply(paint("bad tracking", 10..13)).expect("paint");
    doc.apply(paint("sticking", 20..50)).expect("paint");
    doc.save().expect("save");

    let all = experiment::load_all(std::slice::from_ref(&dir)).expect("loads");
    assert_eq!(all.len(), 36);
    let by_experiment = experiment::load(std::slice::from_ref(&dir), None, 1);
    assert_eq!(by_experiment.used.len(), 36);
    for (a, b) in all.iter().zip(&by_experiment.used) {
        assert_eq!(a.recording.source, b.recording.source);
        assert_eq!(a.skip, b.skip);
        assert_eq!(a.labels, b.labels);
    }
    let push = all
        .iter()
        .find(|u| u.recording.name == "online_002")
        .expect("online_002");
    let skipped: Vec<usize> = (0..push.skip.len()).filter(|&k| push.skip[k]).collect();
    assert_eq!(skipped, vec![10, 11, 12]);
    let labels = push.labels.as_ref().expect("labelled");
    let sticking = labels.mask("sticking", push.recording.trajectory.len());
    assert_eq!(sticking.len(), 101);
    assert_eq!(sticking.iter().filter(|&&s| s).count(), 30);
    assert!(sticking[20] && sticking[49] && !sticking[19] && !sticking[50]);
    assert_eq!(labels.range_labels(), vec!["bad tracking", "sticking"]);
}

#[test]
fn every_unreadable_file_is_an_error_naming_it() {
    let dir = sample_set_copy("broken");
    let csv = dir.join("online_005.csv");
    let text = std::fs::read_to_string(&csv).expect("csv");
    std::fs::write(&csv, text.replacen("\n0.1,", "\n0.1,oops", 1)).expect("write");
    std::fs::write(dir.join("pushlab-labels.json"), "{ not json").expect("write");

    let problems = experiment::load_all(std::slice::from_ref(&dir)).expect_err("refused");
    let messages: Vec<String> = problems.iter().map(|p| p.message()).collect();
    assert_eq!(messages.len(), 2, "{messages:#?}");
    assert!(
        messages[0].starts_with(&format!("{} line 3", csv.display())),
        "{messages:#?}"
    );
    assert!(messages[1].contains("pushlab-labels.json"), "{messages:#?}");
}
