//! Opening a Push-T dataset in the app, as a user does: a replay buffer whose features pushlab
//! cannot guess is dropped on the window; the form lists its features, the user picks the pusher
//! and the T's pose, a wrong column is refused before opening, Open opens one push per episode and
//! the choice is remembered beside the dataset; "Not now" lists it with a Choose features… button
//! that brings the form back. On copies of the core's gym-pusht fixture.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::path::{Path, PathBuf};

use common::{drop_on_window, harness, run_until, scratch_dir};
use egui_kittest::kittest::Queryable;
use pushlab::app::state::recordings::session::RecordingId;
use pushlab::app::state::sources::dataset_import::DatasetCommand;
use pushlab::app::state::{Command, Persisted, SessionCommand};
use pushlab::app::{PushlabApp, initial_state};
use pushlab_core::recording::dataset::{Columns, ObjectSource, choice};

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

/// A copy of the fixture replay buffer with its `state` array renamed `obs` (no images), so that
/// Push-T's pre-selection finds nothing and the user must choose.
fn unguessable_replay(test: &str) -> PathBuf {
    let fixture = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("crates/pushlab-core/tests/pusht/replay.zarr");
    let replay = scratch_dir(test).join("pushes.zarr");
    copy_dir(&fixture, &replay);
    std::fs::rename(replay.join("data/state"), replay.join("data/obs")).unwrap();
    std::fs::remove_dir_all(replay.join("data/img")).unwrap();
    replay
}

fn app_with_dropped(dataset: &Path) -> egui_kittest::Harness<'static, PushlabApp> {
    let state = initial_state(&[], Persisted::default());
    let mut harness = harness(PushlabApp::new(state), 0.05);
    harness.run_steps(1);
    drop_on_window(&mut harness, dataset);
    run_until(&mut harness, "the dataset's form", |app| {
        app.state.datasets().form().is_some()
    });
    harness
}

fn send(harness: &mut egui_kittest::Harness<'_, PushlabApp>, command: DatasetCommand) {
    harness.state_mut().state.apply(Command::Dataset(command));
    harness.run_steps(2);
}

#[test]
fn an_unguessable_dataset_asks_for_its_features_then_opens_and_is_remembered() {
    let replay = unguessable_replay("dataset-choose");
    let mut harness = app_with_dropped(&replay);
    harness.get_by_label("pushes.zarr (zarr replay buffer)");
    harness.get_by_label_contains("8 episode(s), 192 frames at 10 Hz");
    // Nothing pre-selected: Open says what is missing.
    harness.get_by_label("choose the pusher's and the object's features");
    // The pusher: obs from column 0, picked in the combo box as a user does.
    harness.get_by_label("Pusher (agent x, y)");
    // The first of the form's two empty combo boxes (pusher, then the T's pose).
    harness.get_all_by_value("choose…").next().unwrap().click();
    harness.run_steps(2);
    harness.get_by_label("obs (5)").click();
    harness.run_steps(2);
    let form = harness.state().state.datasets().form().unwrap();
    assert_eq!(form.pusher, Some(Columns::new("obs", 0)));
    // A feature too narrow for what it is asked to be is refused before opening, saying why.
    send(
        &mut harness,
        DatasetCommand::SetObject(ObjectSource::Keypoints("obs".into())),
    );
    harness.get_by_label(
        "the T's 8 keypoints: `obs` has 5 value(s) per frame, 16 are needed from column 0",
    );
    send(
        &mut harness,
        DatasetCommand::SetObject(ObjectSource::Pose(Columns::new("obs", 2))),
    );
    harness.get_by_label("Open").click();
    harness.run_steps(1);
    run_until(&mut harness, "the dataset to open", |app| {
        app.state.datasets().form().is_none() && app.state.session().loading().is_none()
    });
    harness.run_steps(2);
    let app = harness.state();
    let set = (app.state.session().sets.iter())
        .find(|s| s.dir == replay)
        .unwrap_or_else(|| panic!("not opened: {:?}", app.state.session().problems));
    assert_eq!(set.recordings.len(), 8);
    // The episode shown is the dataset's first.
    assert_eq!(app.state.recording().unwrap().trajectory.len(), 24);
    let remembered = choice::remembered(&replay)
        .unwrap()
        .expect("remembered beside the dataset");
    assert_eq!(
        remembered.object,
        ObjectSource::Pose(Columns::new("obs", 2))
    );
    harness.get_by_label_contains("its features are remembered in");
    // The user's dataset is only read: the choice is kept beside it, not inside.
    let file = choice::choice_path(&replay);
    assert_eq!(file.parent(), replay.parent());
    assert!(file.is_file());
}

#[test]
fn a_dataset_not_chosen_now_comes_back_with_choose_features() {
    let replay = unguessable_replay("dataset-skip");
    let mut harness = app_with_dropped(&replay);
    harness.get_by_label("Not now").click();
    harness.run_steps(2);
    assert!(harness.state().state.datasets().form().is_none());
    harness.get_by_label_contains("not opened: its pusher and object features were not chosen");
    harness.get_by_label("Choose features…").click();
    run_until(&mut harness, "the form again", |app| {
        app.state.datasets().form().is_some()
    });
    harness.get_by_label("pushes.zarr (zarr replay buffer)");
    assert!(harness.query_by_label("Choose features…").is_none());
}

#[test]
fn an_opened_dataset_can_be_chosen_again_and_its_set_is_replaced() {
    // The fixture in Push-T's own layout opens at once, at 1 mm per pixel.
    let fixture = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("crates/pushlab-core/tests/pusht/replay.zarr");
    let replay = scratch_dir("dataset-again").join("pusht.zarr");
    copy_dir(&fixture, &replay);
    let state = initial_state(&[], Persisted::default());
    let mut harness = harness(PushlabApp::new(state), 0.05);
    harness.run_steps(1);
    drop_on_window(&mut harness, &replay);
    run_until(&mut harness, "the dataset to open", |app| {
        app.state.session().sets.iter().any(|s| s.dir == replay)
    });
    assert!(harness.state().state.datasets().form().is_none(), "no form");
    // Its first episode shown (the sample data was).
    let set = (harness.state().state.session().sets.iter())
        .position(|s| s.dir == replay)
        .unwrap();
    let first = RecordingId { set, recording: 0 };
    let select = Command::Session(SessionCommand::Select(first));
    harness.state_mut().state.apply(select);
    harness.run_steps(2);
    let before = harness
        .state()
        .state
        .recording()
        .unwrap()
        .trajectory
        .clone();
    // File → Choose the dataset's features again… shows its form, Push-T's layout pre-selected.
    harness.get_by_label("File").click();
    harness.run_steps(2);
    harness
        .get_by_label("Choose the dataset's features again…")
        .click();
    run_until(&mut harness, "the form", |app| {
        app.state.datasets().form().is_some()
    });
    let form = harness.state().state.datasets().form().unwrap();
    assert_eq!(form.pusher, Some(Columns::new("state", 0)));
    assert_eq!(
        form.object,
        Some(ObjectSource::Pose(Columns::new("state", 2)))
    );
    // Twice the scale: the set opened again replaces the first, every length doubled.
    send(&mut harness, DatasetCommand::SetScale(0.002));
    harness.get_by_label("Open").click();
    harness.run_steps(1);
    run_until(&mut harness, "the dataset to open again", |app| {
        app.state.datasets().form().is_none() && app.state.session().loading().is_none()
    });
    harness.run_steps(2);
    let app = harness.state();
    let sets: Vec<_> = (app.state.session().sets.iter())
        .filter(|s| s.dir == replay)
        .collect();
    assert_eq!(sets.len(), 1, "replaced, not added");
    assert_eq!(sets[0].recordings.len(), 8);
    let after = &sets[0].recordings[0].trajectory;
    let (a, b) = (&before.frames[5], &after.frames[5]);
    assert!(
        (b.object.position - 2.0 * a.object.position).norm() < 1e-9
            && (b.robot - 2.0 * a.robot.coords).coords.norm() < 1e-9,
        "{a:?} then {b:?}"
    );
    let remembered = choice::remembered(&replay).unwrap().expect("remembered");
    assert_eq!(remembered.metres_per_px, 0.002);
}

#[test]
fn a_lerobot_dataset_dropped_on_the_window_opens_with_push_ts_layout() {
    let fixture = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("crates/pushlab-core/tests/pusht/lerobot-v3.0");
    let dataset = scratch_dir("dataset-lerobot").join("lerobot-v3.0");
    copy_dir(&fixture, &dataset);
    let state = initial_state(&[], Persisted::default());
    let mut harness = harness(PushlabApp::new(state), 0.05);
    harness.run_steps(1);
    drop_on_window(&mut harness, &dataset);
    run_until(&mut harness, "the dataset to open", |app| {
        app.state.session().sets.iter().any(|s| s.dir == dataset)
            || !app.state.session().problems.is_empty()
    });
    let app = harness.state();
    assert!(
        app.state.datasets().form().is_none(),
        "no form: Push-T's layout is guessed"
    );
    let set = (app.state.session().sets.iter())
        .find(|s| s.dir == dataset)
        .unwrap_or_else(|| panic!("not opened: {:?}", app.state.session().problems));
    assert_eq!(set.recordings.len(), 8);
    assert_eq!(set.setting.extra["dataset_format"], "LeRobot dataset v3.0");
}

#[test]
fn a_dataset_opened_after_the_sample_data_is_what_the_scene_shows() {
    let sample = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("sample-data/box1-paper-ur-front");
    let state = initial_state(std::slice::from_ref(&sample), Persisted::default());
    let mut harness = harness(PushlabApp::new(state), 0.05);
    harness.run_steps(1);
    let shown = |app: &PushlabApp| {
        let session = app.state.session();
        session.selected_set_dir().map(Path::to_path_buf)
    };
    assert_eq!(shown(harness.state()), Some(sample.clone()));
    // The user looks at another push of the sample, then opens a dataset: its first push is shown.
    harness
        .state_mut()
        .state
        .apply(Command::Session(SessionCommand::Select(RecordingId {
            set: 0,
            recording: 3,
        })));
    let fixture = scratch_dir("dataset-shown").join("replay.zarr");
    copy_dir(
        &PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("crates/pushlab-core/tests/pusht/replay.zarr"),
        &fixture,
    );
    harness
        .state_mut()
        .state
        .apply(Command::Session(SessionCommand::Open(vec![
            fixture.clone(),
        ])));
    run_until(&mut harness, "the dataset to open", |app| {
        app.state.session().sets.iter().any(|s| s.dir == fixture)
            || !app.state.session().problems.is_empty()
    });
    let app = harness.state();
    assert_eq!(
        shown(app),
        Some(fixture.clone()),
        "{:?}",
        app.state.session().problems
    );
    assert_eq!(app.state.session().selected.map(|id| id.recording), Some(0));
    // Opening the dataset shown again keeps the push shown.
    harness
        .state_mut()
        .state
        .apply(Command::Session(SessionCommand::Select(RecordingId {
            set: 1,
            recording: 2,
        })));
    harness
        .state_mut()
        .state
        .apply(Command::Session(SessionCommand::Open(vec![
            fixture.clone(),
        ])));
    run_until(&mut harness, "the dataset to open again", |app| {
        app.state.session().loading().is_none()
    });
    let selected = harness.state().state.session().selected;
    assert_eq!(
        selected,
        Some(RecordingId {
            set: 1,
            recording: 2
        })
    );
}
