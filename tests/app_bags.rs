//! Opening a ROS 2 bag in the app, as a user does: drop it on the window, the form shows its topics
//! with the pusher and object pre-selected and the setting beside it, pick another stream from the
//! combo box, Open; the bag opens like any recording and its choice is remembered beside it. Skip
//! lists it with a Choose topics… button that brings the form back. On copies of the core's bag
//! fixtures (written by the Python `rosbags` library).

#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::path::PathBuf;

use common::{drop_on_window, harness, run_until, scratch_dir};
use egui_kittest::kittest::Queryable;
use pushlab::app::state::Persisted;
use pushlab::app::{PushlabApp, initial_state};
use pushlab_core::recording::bag::choice;

/// A scratch folder with a copy of the `/tf` fixture bag and a setting.json; returns the bag.
fn tf_bag(test: &str) -> PathBuf {
    let dir = scratch_dir(test);
    let from = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("crates/pushlab-core/tests/bags/tf");
    let bag = dir.join("tf");
    std::fs::create_dir_all(&bag).unwrap();
    for entry in std::fs::read_dir(&from).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), bag.join(entry.file_name())).unwrap();
    }
    std::fs::write(
        dir.join("setting.json"),
        r#"{"name": "bag-box", "object": {"shape": "box", "width": 0.1, "length": 0.12},
            "pusher_radius": 0.005}"#,
    )
    .unwrap();
    bag
}

/// The app with nothing open, the bag dropped on its window, run until the form shows.
fn app_with_dropped(bag: &std::path::Path) -> egui_kittest::Harness<'static, PushlabApp> {
    let state = initial_state(&[], Persisted::default());
    let mut harness = harness(PushlabApp::new(state), 0.05);
    harness.run_steps(1);
    drop_on_window(&mut harness, bag);
    run_until(&mut harness, "the bag's form", |app| {
        app.state.bags().form().is_some()
    });
    harness
}

#[test]
fn a_dropped_bag_asks_for_its_topics_then_opens_and_is_remembered() {
    let bag = tf_bag("bag-drop");
    let mut harness = app_with_dropped(&bag);
    harness.get_by_label("tf (rosbag2 folder)");
    harness.get_by_label_contains("child frames: base_link, pusher_tip, box");
    harness.get_by_label("setting \"bag-box\"");
    // Pre-selected: the pusher tip and the box. The user picks base_link as the pusher instead…
    harness.get_by_label("Pusher").click();
    harness.run_steps(2);
    harness.get_by_label("/tf:base_link").click();
    harness.run_steps(2);
    let form = harness.state().state.bags().form().unwrap();
    assert_eq!(form.pusher, Some("/tf:base_link".parse().unwrap()));
    // …and back, then opens.
    harness.get_by_label("Pusher").click();
    harness.run_steps(2);
    harness.get_by_label("/tf:pusher_tip").click();
    harness.run_steps(2);
    harness.get_by_label("Open").click();
    harness.run_steps(1);
    assert_eq!(harness.state().state.bags().opening().count(), 1);
    run_until(&mut harness, "the bag to open", |app| {
        app.state.bags().opening().count() == 0 && app.state.session().loading().is_none()
    });
    assert!(harness.query_by_label("tf (rosbag2 folder)").is_none());
    let app = harness.state();
    assert_eq!(app.state.recording().unwrap().name, "tf");
    let remembered = choice::remembered(&bag)
        .unwrap()
        .expect("remembered beside the bag");
    assert_eq!(remembered.pusher, "/tf:pusher_tip".parse().unwrap());
    // Shown, and the status line says where the choice is kept.
    harness.get_by_label_contains("its topics are remembered in");
}

#[test]
fn a_skipped_bag_comes_back_with_choose_topics() {
    let bag = tf_bag("bag-skip");
    let mut harness = app_with_dropped(&bag);
    harness.get_by_label("Skip").click();
    harness.run_steps(2);
    assert!(harness.state().state.bags().form().is_none());
    harness.get_by_label_contains("not opened: its pusher and object topics were not chosen");
    harness.get_by_label("Choose topics…").click();
    run_until(&mut harness, "the form again", |app| {
        app.state.bags().form().is_some()
    });
    harness.get_by_label("tf (rosbag2 folder)");
    assert!(harness.query_by_label("Choose topics…").is_none());
}

#[test]
fn a_bag_cut_short_opens_marked_as_loaded_with_warnings() {
    let dir = scratch_dir("bag-cut-short");
    let fixture =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("crates/pushlab-core/tests/bags/zstd.mcap");
    let bytes = std::fs::read(fixture).unwrap();
    let bag = dir.join("cut.mcap");
    std::fs::write(&bag, &bytes[..bytes.len() / 2]).unwrap();
    let entered = choice::entered_box("bag-box", 0.1, 0.12, 0.005, None).unwrap();
    let chosen = choice::BagChoice {
        pusher: "/pusher/pose".parse().unwrap(),
        object: "/object/pose".parse().unwrap(),
        setting: choice::SettingSource::Entered(entered),
        options: Default::default(),
        cameras: Vec::new(),
    };
    // Dropped before its topics are chosen, the form says it is cut short.
    let dropped = app_with_dropped(&bag);
    dropped.get_by_label_contains("the file is cut short (a recording that did not finish");
    drop(dropped);
    choice::remember(&bag, &chosen).unwrap();
    let state = initial_state(std::slice::from_ref(&bag), Persisted::default());
    let mut harness = harness(PushlabApp::new(state), 0.05);
    harness.run_steps(2);
    let recording = harness.state().state.recording().unwrap();
    assert!(
        (recording.warnings.iter()).any(|w| w.starts_with("the file is cut short")),
        "{:?}",
        recording.warnings
    );
    // Marked in the browser, where the user picks it; hovering says the warning.
    harness.get_by_label("! cut");
}
