//! The bag form's rules: the core's pre-selection shown, a choice remembered only once the bag
//! opened with it, a failing choice back in its form with the error, Skip and Choose topics…, and a
//! remembered bag opening without asking. On copies of the core's bag fixtures.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use super::*;
use crate::app::state::SessionCommand;
use crate::app::state::models::Models;
use crate::app::state::{AppState, Command, Persisted};

/// A fresh folder with a copy of the `/tf` fixture bag (a rosbag2 folder) and, when asked, a
/// `setting.json` beside it; returns (folder, bag).
fn tf_bag(test: &str, with_setting: bool) -> (PathBuf, PathBuf) {
    copied_bag("tf", test, with_setting)
}

/// A fresh folder with a copy of the fixture bag `fixture` (a rosbag2 folder) and, when asked, a
/// `setting.json` beside it; returns (folder, bag).
fn copied_bag(fixture: &str, test: &str, with_setting: bool) -> (PathBuf, PathBuf) {
    let from = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("crates/pushlab-core/tests/bags")
        .join(fixture);
    let dir = std::env::temp_dir().join(format!("pushlab-bag-form-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let bag = dir.join(fixture);
    std::fs::create_dir_all(&bag).unwrap();
    for entry in std::fs::read_dir(&from).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), bag.join(entry.file_name())).unwrap();
    }
    if with_setting {
        std::fs::write(
            dir.join("setting.json"),
            r#"{"name": "bag-box", "object": {"shape": "box", "width": 0.1, "length": 0.12},
                "pusher_radius": 0.005}"#,
        )
        .unwrap();
    }
    (dir, bag)
}

fn state_on(path: &Path) -> AppState {
    let mut state = AppState::new(Persisted::default(), Models::default());
    state.open_blocking(&[path.to_path_buf()]);
    state
}

/// Runs the state until background loading and topic listing are done.
fn settle(state: &mut AppState) {
    let deadline = Instant::now() + Duration::from_secs(30);
    while state.advance(0.0) && Instant::now() < deadline {
        if state.session.loading().is_none() && state.bags.listing().is_none() {
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    state.advance(0.0);
}

#[test]
fn a_bag_without_a_choice_asks_with_the_cores_preselection() {
    let (dir, bag) = tf_bag("asks", true);
    let state = state_on(&bag);
    assert!(state.recording().is_none());
    assert!(
        state.session.problems.is_empty(),
        "{:?}",
        state.session.problems
    );
    let form = state.bags.form().expect("a form for the bag");
    assert_eq!(form.bag, bag);
    assert_eq!(form.pusher, Some("/tf:pusher_tip".parse().unwrap()));
    assert_eq!(form.object, Some("/tf:box".parse().unwrap()));
    assert_eq!(
        form.object_source,
        ObjectSource::File {
            path: dir.join("setting.json"),
            checked: Ok("bag-box".to_owned())
        }
    );
    assert_eq!(form.streams.len(), 3, "base_link, pusher_tip and box");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn the_form_offers_the_cameras_and_the_bag_opens_with_those_ticked() {
    let (dir, bag) = copied_bag("camera", "cameras", true);
    let mut state = state_on(&bag);
    let form = state.bags.form().expect("a form for the bag");
    // Every camera topic here says camera or image in its name: all are ticked.
    assert_eq!(
        form.cameras,
        [
            "/camera/image/compressed",
            "/camera/image_raw",
            "/depth/image_mono16"
        ]
    );
    state.apply(Command::Bag(BagCommand::SetCamera {
        topic: "/depth/image_mono16".to_owned(),
        shown: false,
    }));
    state.apply(Command::Bag(BagCommand::Open));
    settle(&mut state);
    let names: Vec<_> = (state.cameras().streams().iter())
        .map(|s| s.name.clone())
        .collect();
    assert_eq!(names, ["/camera/image/compressed", "/camera/image_raw"]);
    let remembered = choice::remembered(&bag).unwrap().expect("remembered");
    assert_eq!(remembered.cameras, names);
    // Opened again, the remembered cameras come with it.
    let again = state_on(&bag);
    assert_eq!(again.cameras().streams().len(), 2);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn open_remembers_the_choice_only_once_the_bag_opened() {
    let (dir, bag) = tf_bag("open", true);
    let mut state = state_on(&bag);
    state.apply(Command::Bag(BagCommand::Open));
    assert!(state.bags.form().is_none());
    assert_eq!(state.bags.opening().count(), 1);
    settle(&mut state);
    let recording = state.recording().expect("the bag opened");
    assert_eq!(recording.name, "tf");
    assert_eq!(recording.setting.name, "bag-box");
    let remembered = choice::remembered(&bag).unwrap().expect("remembered");
    assert_eq!(remembered.object, "/tf:box".parse().unwrap());
    assert_eq!(
        remembered.setting,
        SettingSource::File(dir.join("setting.json"))
    );
    let status = state.status.clone().unwrap();
    assert!(status.contains("its topics are remembered in"), "{status}");
    // Labels go beside the bag, keyed by its name, like a CSV's.
    let target = state.label_target().unwrap();
    assert_eq!(target.document, dir.join("pushlab-labels.json"));
    assert_eq!(target.recording, "tf");
    // Another session opens it without asking.
    let again = state_on(&bag);
    assert!(again.bags.form().is_none());
    assert_eq!(again.recording().unwrap().name, "tf");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_choice_that_fails_comes_back_with_its_error_and_is_not_remembered() {
    let (dir, bag) = tf_bag("fails", true);
    let mut state = state_on(&bag);
    // Split at every pause of 1 ms: each piece is too short, so nothing is left to open.
    state.apply(Command::Bag(BagCommand::SetOptions(ImportOptions {
        rate_hz: None,
        split_gap_s: Some(0.001),
    })));
    state.apply(Command::Bag(BagCommand::Open));
    settle(&mut state);
    assert!(state.recording().is_none());
    let form = state.bags.form().expect("the form is back");
    let error = form.error.clone().unwrap();
    assert!(error.contains(&bag.display().to_string()), "{error}");
    assert_eq!(
        form.options.split_gap_s,
        Some(0.001),
        "the form keeps its choice"
    );
    assert!(
        state.session.problems.is_empty(),
        "the error is in the form, not listed twice"
    );
    assert!(!choice::choice_path(&bag).exists());
    // Without the split it opens.
    state.apply(Command::Bag(BagCommand::SetOptions(
        ImportOptions::default(),
    )));
    state.apply(Command::Bag(BagCommand::Open));
    settle(&mut state);
    assert!(state.recording().is_some());
    assert!(choice::choice_path(&bag).exists());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn an_incomplete_form_says_what_is_missing_and_does_not_open() {
    let (dir, bag) = tf_bag("incomplete", false);
    let mut state = state_on(&bag);
    let form = state.bags.form().unwrap();
    // No setting beside the bag: a box to enter, named after the bag, with no size yet.
    let ObjectSource::Entered(entered) = &form.object_source else {
        panic!("{:?}", form.object_source)
    };
    assert_eq!(entered.name, "tf");
    let why = form.choice().unwrap_err();
    assert_eq!(
        why,
        "the object: a box needs a positive finite width and length, got 0 x 0 m"
    );
    state.apply(Command::Bag(BagCommand::SetObject(
        "/tf:pusher_tip".parse().unwrap(),
    )));
    let why = state.bags.form().unwrap().choice().unwrap_err();
    assert_eq!(why, "the pusher and the object are both /tf:pusher_tip");
    state.apply(Command::Bag(BagCommand::Open));
    assert!(state.session.loading().is_none());
    assert_eq!(
        state.bags.form().unwrap().error.as_deref(),
        Some(why.as_str())
    );
    // Entered by hand: a box of 90 × 60 mm.
    state.apply(Command::Bag(BagCommand::SetObject(
        "/tf:box".parse().unwrap(),
    )));
    state.apply(Command::Bag(BagCommand::SetEntered(EnteredBox {
        name: "bench box".to_owned(),
        width_mm: 90.0,
        length_mm: 60.0,
        pusher_radius_mm: 4.0,
        material: "acrylic".to_owned(),
    })));
    state.apply(Command::Bag(BagCommand::Open));
    settle(&mut state);
    let recording = state.recording().expect("opened");
    assert_eq!(recording.setting.pusher_radius, 0.004);
    assert_eq!(recording.setting.material.as_deref(), Some("acrylic"));
    let remembered = choice::remembered(&bag).unwrap().unwrap();
    let SettingSource::Entered(setting) = remembered.setting else {
        panic!("{:?}", remembered.setting)
    };
    assert_eq!(setting.name, "bench box");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_skipped_bag_is_listed_and_its_form_comes_back_on_request() {
    let (dir, bag) = tf_bag("skip", true);
    let mut state = state_on(&bag);
    state.apply(Command::Bag(BagCommand::SetPusher(
        "/tf:base_link".parse().unwrap(),
    )));
    state.apply(Command::Bag(BagCommand::Skip));
    assert!(state.bags.form().is_none());
    let problem = &state.session.problems[0];
    assert!(problem.bag_to_choose);
    assert!(
        problem
            .message
            .ends_with("not opened: its pusher and object topics were not chosen"),
        "{}",
        problem.message
    );
    state.apply(Command::Bag(BagCommand::ChooseAgain(bag.clone())));
    assert_eq!(state.bags.listing(), Some(bag.as_path()));
    settle(&mut state);
    let form = state.bags.form().expect("the form is back");
    // Nothing was remembered, so it starts from the pre-selection again.
    assert_eq!(form.pusher, Some("/tf:pusher_tip".parse().unwrap()));
    assert!(state.session.problems.is_empty());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn cancelling_the_load_brings_the_form_back_and_remembers_nothing() {
    let (dir, bag) = tf_bag("cancel", true);
    let mut state = state_on(&bag);
    state.apply(Command::Bag(BagCommand::Open));
    assert!(state.session.loading().is_some());
    // Before any frame merges the worker's result.
    state.apply(Command::Session(SessionCommand::CancelLoading));
    assert!(state.session.loading().is_none());
    assert_eq!(state.status.as_deref(), Some("opening cancelled"));
    settle(&mut state);
    assert!(state.recording().is_none());
    let form = state.bags.form().expect("the form is back");
    assert_eq!(form.error.as_deref(), Some("opening was cancelled"));
    assert!(!choice::choice_path(&bag).exists());
    std::fs::remove_dir_all(dir).unwrap();
}
