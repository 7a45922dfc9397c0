//! Opening a ROS 2 bag like any recording: with the choice of topics and setting remembered beside
//! it (`bag::choice`), through the one loader the app and the CLI use. The bags are copies of the
//! fixtures of `recordings_bags.rs` (written by the Python `rosbags` and `mcap` libraries) in a
//! temporary folder: the fixtures themselves are never written beside.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};

use pushlab_core::recording::bag::{self, BagChoice, ImportOptions, SettingSource, choice};
use pushlab_core::recording::{
    BagError, BagProblem, LoadError, SourceChoice, load_paths, load_paths_choosing,
};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/bags")
        .join(name)
}

/// A fresh folder holding a copy of the fixture bag `name` (a file or a rosbag2 folder) and a
/// `setting.json`; returns (folder, bag).
fn bag_copy(test: &str, name: &str) -> (PathBuf, PathBuf) {
    let dir =
        std::env::temp_dir().join(format!("pushlab-bag-choice-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let from = fixture(name);
    let to = dir.join(name);
    if from.is_dir() {
        std::fs::create_dir_all(&to).unwrap();
        for entry in std::fs::read_dir(&from).unwrap() {
            let entry = entry.unwrap();
            std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
        }
    } else {
        std::fs::copy(&from, &to).unwrap();
    }
    std::fs::write(
        dir.join("setting.json"),
        r#"{"name": "bag-box", "object": {"shape": "box", "width": 0.1, "length": 0.12},
            "pusher_radius": 0.005, "material": "wood on MDF"}"#,
    )
    .unwrap();
    (dir, to)
}

fn choice_of(dir: &Path, pusher: &str, object: &str, options: ImportOptions) -> BagChoice {
    BagChoice {
        pusher: pusher.parse().unwrap(),
        object: object.parse().unwrap(),
        setting: SettingSource::File(dir.join("setting.json")),
        options,
        cameras: Vec::new(),
    }
}

#[test]
fn a_bag_with_a_remembered_choice_opens_like_a_recording() {
    let (dir, bag) = bag_copy("remembered", "zstd.mcap");
    let choice = choice_of(
        &dir,
        "/pusher/pose",
        "/object/pose",
        ImportOptions::default(),
    );
    bag::choice::remember(&bag, &choice).unwrap();
    // Opened by the file, and by its folder (the loader finds the bag and its choice there).
    for path in [bag.clone(), dir.clone()] {
        let report = load_paths(std::slice::from_ref(&path));
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        assert_eq!(report.sets.len(), 1);
        let set = &report.sets[0];
        assert_eq!(set.setting.name, "bag-box");
        assert_eq!(set.setting.material.as_deref(), Some("wood on MDF"));
        assert_eq!(set.recordings.len(), 1);
        let recording = &set.recordings[0];
        assert_eq!(recording.name, "zstd");
        assert_eq!(recording.source, bag);
        // The same frames `pushlab import` writes.
        let direct = bag::import(
            &bag,
            &choice.pusher,
            &choice.object,
            ImportOptions::default(),
        )
        .unwrap();
        assert_eq!(*recording.trajectory, direct.pushes[0].trajectory);
        let entry = recording.entry.as_ref().unwrap();
        assert_eq!(entry.extra["bag_object"], "/object/pose");
        assert_eq!(entry.extra["start_unix_s"], 1_700_000_000.0);
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn split_pushes_of_one_bag_are_told_apart() {
    let (dir, bag) = bag_copy("split", "gap.mcap");
    let options = ImportOptions {
        rate_hz: None,
        split_gap_s: Some(0.5),
    };
    let choice = choice_of(&dir, "/pusher/pose", "/object/pose", options);
    let report = load_paths_choosing(
        std::slice::from_ref(&bag),
        &[(bag.clone(), SourceChoice::Bag(Box::new(choice)))],
    );
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let names: Vec<_> = report.sets[0]
        .recordings
        .iter()
        .map(|r| (r.name.clone(), r.source.display().to_string()))
        .collect();
    let source = |n: &str| format!("{}#{n}", bag.display());
    assert_eq!(
        names,
        vec![
            ("gap_001".to_owned(), source("001")),
            ("gap_002".to_owned(), source("002"))
        ]
    );
    // Loading with a choice only reads: nothing is remembered until the caller says so.
    assert!(!choice::choice_path(&bag).exists());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_given_choice_wins_over_the_remembered_one() {
    let (dir, bag) = bag_copy("given", "tf");
    let wrong = choice_of(&dir, "/tf:box", "/tf:nothing", ImportOptions::default());
    bag::choice::remember(&bag, &wrong).unwrap();
    let right = choice_of(&dir, "/tf:pusher_tip", "/tf:box", ImportOptions::default());
    let report = load_paths_choosing(
        std::slice::from_ref(&bag),
        &[(bag.clone(), SourceChoice::Bag(Box::new(right)))],
    );
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.sets[0].recordings[0].name, "tf");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_remembered_choice_that_no_longer_fits_says_where_it_is_remembered() {
    let (dir, bag) = bag_copy("stale", "tf");
    let stale = choice_of(
        &dir,
        "/tf:pusher_tip",
        "/tf:crate",
        ImportOptions::default(),
    );
    let remembered_at = bag::choice::remember(&bag, &stale).unwrap();
    let report = load_paths(std::slice::from_ref(&bag));
    assert!(report.sets.is_empty());
    let LoadError::Bag(BagError::Problem { path, problem }) = &report.errors[0] else {
        panic!("{:?}", report.errors)
    };
    assert_eq!(path, &bag);
    assert!(matches!(problem, BagProblem::ChoiceFailed { .. }));
    let message = report.errors[0].to_string();
    assert!(
        message.contains(&format!("remembered in {}", remembered_at.display())),
        "{message}"
    );
    assert!(
        message.contains(
            "no transform with child frame `crate`; child frames seen: base_link, pusher_tip, box"
        ),
        "{message}"
    );
    // A setting file that went missing is named too.
    std::fs::remove_file(dir.join("setting.json")).unwrap();
    let message = load_paths(std::slice::from_ref(&bag)).errors[0].to_string();
    assert!(message.contains("setting.json: cannot read"), "{message}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_bag_without_a_choice_lists_its_topics_and_tf_child_frames() {
    let (dir, bag) = bag_copy("none", "tf");
    let report = load_paths(std::slice::from_ref(&bag));
    let LoadError::Bag(BagError::Problem {
        problem: BagProblem::NeedsImport { listing },
        ..
    }) = &report.errors[0]
    else {
        panic!("{:?}", report.errors)
    };
    let topics = &listing.topics;
    let tf = topics.iter().find(|t| t.topic == "/tf").unwrap();
    assert_eq!(tf.child_frames, ["base_link", "pusher_tip", "box"]);
    // What the app pre-selects for it.
    assert_eq!(
        choice::suggest(topics),
        (
            Some("/tf:pusher_tip".parse().unwrap()),
            Some("/tf:box".parse().unwrap())
        )
    );
    let message = report.errors[0].to_string();
    assert!(
        message.contains("open it in the app to choose"),
        "{message}"
    );
    assert!(message.contains("pushlab import BAG"), "{message}");
    // The setting beside it is offered.
    assert_eq!(choice::settings_beside(&bag), [dir.join("setting.json")]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_frame_behind_tf_static_is_offered_and_opens() {
    let (dir, bag) = bag_copy("tree", "tf_tree");
    let topics = bag::topics(&bag).unwrap().topics;
    let offered = choice::candidates(&topics);
    let tip: bag::TopicSpec = "/tf:tip".parse().unwrap();
    assert!(offered.contains(&tip), "{offered:?}");
    assert!(
        offered.iter().all(|s| s.topic != bag::TF_STATIC),
        "{offered:?}"
    );
    let choice = choice_of(&dir, "/tf:tip", "/tf:object", ImportOptions::default());
    let report = load_paths_choosing(
        std::slice::from_ref(&bag),
        &[(bag.clone(), SourceChoice::Bag(Box::new(choice)))],
    );
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.sets[0].recordings[0].name, "tf_tree");
    std::fs::remove_dir_all(dir).unwrap();
}

/// Cancels once any bytes were reported, counting them.
#[derive(Default)]
struct CancelAfterFirst(std::sync::atomic::AtomicU64);

impl pushlab_core::recording::Progress for CancelAfterFirst {
    fn advance(&self, bytes: u64) {
        self.0
            .fetch_add(bytes, std::sync::atomic::Ordering::Relaxed);
    }

    fn is_cancelled(&self) -> bool {
        self.0.load(std::sync::atomic::Ordering::Relaxed) > 0
    }
}

#[test]
fn opening_a_bag_reports_its_bytes_and_stops_when_cancelled() {
    use pushlab_core::recording::{LoadError, LoadProgress, load_paths_with};
    let (dir, bag) = bag_copy("progress", "zstd.mcap");
    let choice = choice_of(
        &dir,
        "/pusher/pose",
        "/object/pose",
        ImportOptions::default(),
    );
    bag::choice::remember(&bag, &choice).unwrap();
    let size = std::fs::metadata(&bag).unwrap().len();

    let progress = LoadProgress::default();
    let report = load_paths_with(std::slice::from_ref(&bag), &[], &progress);
    assert_eq!(report.recording_count(), 1, "{:?}", report.errors);
    let done = progress.snapshot();
    assert_eq!((done.files_done, done.files_total), (1, 1));
    assert_eq!((done.bytes_done, done.bytes_total), (size, size));

    let cancelling = CancelAfterFirst::default();
    let cancelled = bag::open_with(&bag, &choice, &cancelling).unwrap_err();
    assert!(
        matches!(
            cancelled,
            BagError::Problem {
                problem: BagProblem::Cancelled,
                ..
            }
        ),
        "{cancelled}"
    );
    assert!(
        cancelled.to_string().ends_with("opening cancelled"),
        "{cancelled}"
    );
    // The loader says a bag's cancel as it says any file's.
    let said = cancelled.to_string();
    let loaded = LoadError::from(cancelled);
    assert!(matches!(loaded, LoadError::Cancelled { .. }), "{loaded}");
    assert_eq!(loaded.to_string(), said);

    let stopped = LoadProgress::default();
    stopped.cancel();
    let report = load_paths_with(std::slice::from_ref(&bag), &[], &stopped);
    assert_eq!(report.recording_count(), 0);
    assert!(
        matches!(report.errors[..], [LoadError::Cancelled { .. }]),
        "{:?}",
        report.errors
    );
    let _ = std::fs::remove_dir_all(&dir);
}
