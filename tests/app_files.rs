//! Files that go wrong under the app: a recording too large for memory, and a folder that vanishes
//! while it is open. Each gets a message naming the file; nothing panics and the window keeps
//! working on what is open.

use crate::common;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use pushlab::app::state::SessionCommand;
use pushlab::app::state::{Command, Persisted};
use pushlab::app::{PushlabApp, initial_state};

/// Opens `dir` as File → Open does (in the background) and waits for the load.
fn open_in_background(harness: &mut Harness<'_, PushlabApp>, dir: &std::path::Path) {
    harness
        .state_mut()
        .state
        .apply(Command::Session(SessionCommand::Open(vec![
            dir.to_path_buf(),
        ])));
    common::run_until(harness, "the load", |app| {
        app.state.session().loading().is_none()
    });
}

fn shows(harness: &Harness<'_, PushlabApp>, text: &str) -> bool {
    harness.query_all_by_label_contains(text).next().is_some()
}

#[test]
fn a_recording_larger_than_memory_is_refused_by_name_and_what_is_open_stays() {
    let sample = common::sample_dir("box1-paper-center-front");
    let mut harness = common::harness(
        PushlabApp::new(initial_state(&[sample], Persisted::default())),
        0.05,
    );
    harness.run_steps(2);
    let open_before = harness.state().state.session().recording_count();

    // A set whose one push is a terabyte (a sparse file: no disk is used).
    let dir = common::scratch_dir("too-large");
    std::fs::write(
        dir.join("setting.json"),
        r#"{"name": "huge", "object": {"shape": "box", "width": 0.1, "length": 0.1},
            "pusher_radius": 0.005, "trajectories": [{"file": "push_000.csv"}]}"#,
    )
    .expect("setting.json");
    std::fs::File::create(dir.join("push_000.csv"))
        .and_then(|f| f.set_len(1 << 40))
        .expect("a sparse file");
    open_in_background(&mut harness, &dir);

    let state = &harness.state().state;
    assert_eq!(
        state.session().recording_count(),
        open_before,
        "what was open stays"
    );
    let problem = state
        .session()
        .problems
        .iter()
        .find(|p| p.path.ends_with("push_000.csv"))
        .expect("the huge file is reported");
    assert!(
        problem
            .message
            .contains("too large to open: the file is 1099.5 GB"),
        "{}",
        problem.message
    );
    assert!(shows(&harness, "too large to open"), "the browser lists it");
    // Still usable.
    harness.get_by_label("+1").click();
    harness.run_steps(1);
    assert_eq!(harness.state().state.frame(), 1);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_folder_that_vanishes_while_open_keeps_playing_and_opening_it_again_says_it_is_gone() {
    let dir = common::copy_of_sample_set("box1-paper-center-front", "vanish");
    let mut harness = common::harness(
        PushlabApp::new(initial_state(
            std::slice::from_ref(&dir),
            Persisted::default(),
        )),
        0.05,
    );
    harness.run_steps(2);
    let recordings = harness.state().state.session().recording_count();
    assert_eq!(recordings, 36);
    // Paint a label (unsaved), then the folder goes away: a dataset on a drive that was unmounted.
    harness.key_down(egui::Key::Num1);
    harness.run_steps(1);
    harness.key_press(egui::Key::ArrowRight);
    harness.run_steps(1);
    harness.key_up(egui::Key::Num1);
    harness.run_steps(1);
    std::fs::remove_dir_all(&dir).expect("remove the folder");

    // What is in memory plays and learns on.
    harness.get_by_label("Play").click();
    harness.run_steps(20);
    assert!(harness.state().state.frame() > 5);
    assert!(
        harness
            .state()
            .state
            .run()
            .as_ref()
            .expect("a run")
            .frontier()
            > 5
    );

    // Saving the labels says where it could not write; nothing is lost from memory.
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::S);
    harness.run_steps(1);
    let status = common::status(&harness);
    assert!(status.starts_with("labels not saved"), "{status}");
    assert!(status.contains("vanish"), "names the file: {status}");

    // Opening it again reports the folder by name and keeps what is open.
    open_in_background(&mut harness, &dir);
    let state = &harness.state().state;
    assert_eq!(state.session().recording_count(), recordings);
    let problem = state.session().problems.last().expect("a problem");
    assert_eq!(problem.path, dir);
    assert!(
        problem.message.contains("cannot read"),
        "{}",
        problem.message
    );
    assert!(state.recording().is_some(), "the recording shown stays");
}
