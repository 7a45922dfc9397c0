use std::path::PathBuf;
use std::time::{Duration, Instant};

use pushlab_core::geometry::Pose2;
use pushlab_core::model::OnlineParams;
use pushlab_core::recording::{Setting, write_set};
use pushlab_core::trajectory::{Frame, Trajectory};

use crate::app::state::learning::ahead::LEARN_AHEAD_FRAMES;
use crate::app::state::models::Models;
use crate::app::state::playback::timeline::TimelineCommand;
use crate::app::state::{AppState, Command, OnlineCommand, Persisted};

/// Frames of the long push: three times what the UI thread learns in one go.
const FRAMES: usize = 3 * LEARN_AHEAD_FRAMES;

/// A one-push set of `FRAMES` frames at 250 Hz: a box pushed round a wide circle, the pusher behind
/// its face.
fn long_set(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pushlab-ahead-{name}-{}", std::process::id()));
    let frames = (0..FRAMES)
        .map(|i| {
            let t = i as f64 / 250.0;
            let angle = 0.02 * t;
            let object = Pose2::new(
                angle.sin(),
                1.0 - angle.cos(),
                angle + 0.05 * (0.7 * t).sin(),
            );
            Frame {
                time: t,
                robot: object.point_in_world(nalgebra::Point2::new(-0.2, 0.01)),
                object,
            }
        })
        .collect();
    let setting: Setting = serde_json::from_value(serde_json::json!({
        "name": "long",
        "object": {"shape": "box", "width": 0.3, "length": 0.4},
        "pusher_radius": 0.005,
        "trajectories": [{"file": "push_000.csv"}],
    }))
    .expect("a valid setting");
    let _ = std::fs::remove_dir_all(&dir);
    write_set(&dir, &setting, &[Trajectory::new(frames)]).expect("write the long set");
    dir
}

fn state_on(dir: &std::path::Path) -> AppState {
    let mut state = AppState::new(Persisted::default(), Models::default());
    state.open_blocking(&[dir.to_path_buf()]);
    assert!(state.recording().is_some(), "{:?}", state.session.problems);
    state.settings.learn_while_playing = true;
    state
}

fn seek(state: &mut AppState, frame: usize) {
    state.apply(Command::Timeline(TimelineCommand::SeekTo(frame)));
}

/// Polls as the UI thread does until the copy learning ahead is back.
fn until_learned(state: &mut AppState) {
    waited_for(|| {
        if state.learning_ahead().is_none() {
            return Some(());
        }
        state.advance(0.0);
        None
    });
}

/// What `ready` gives once it gives something, asked every 5 ms for up to two minutes.
fn waited_for<T>(mut ready: impl FnMut() -> Option<T>) -> T {
    let started = Instant::now();
    loop {
        if let Some(done) = ready() {
            return done;
        }
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "still learning"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The long set learned up to frame `to` on the UI thread alone, by seeks short enough for it:
/// what learning ahead must give.
fn learned_by_short_seeks(dir: &std::path::Path, to: usize) -> AppState {
    let mut state = state_on(dir);
    for frame in (LEARN_AHEAD_FRAMES / 2..to).step_by(LEARN_AHEAD_FRAMES / 2) {
        seek(&mut state, frame);
        assert!(state.learning_ahead().is_none());
    }
    seek(&mut state, to);
    assert!(state.learning_ahead().is_none());
    state
}

#[test]
fn a_long_seek_learns_on_a_worker_what_short_seeks_learn_on_the_ui_thread() {
    let dir = long_set("seek");
    let target = FRAMES - 100;
    let mut state = state_on(&dir);
    seek(&mut state, target);
    assert!(
        state.learning_ahead().is_some(),
        "learned in the background"
    );
    let run = state.run().expect("a run");
    assert_eq!(run.frontier(), 0, "θ is held while the copy learns");
    let status = |state: &AppState| state.status.clone().unwrap_or_default();
    assert!(status(&state).starts_with("learning up to the frame shown"));
    until_learned(&mut state);
    let said = format!("learned up to frame {target} in the background in ");
    assert!(status(&state).starts_with(&said), "{}", status(&state));

    let reference = learned_by_short_seeks(&dir, target);
    let (run, reference) = (state.run().expect("a run"), reference.run().expect("a run"));
    assert_eq!(run.frontier(), target);
    assert_eq!(run.checkpoints(), reference.checkpoints());
    assert_eq!(run.learned(), reference.learned());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn frames_passed_while_the_copy_learns_are_learned_when_it_is_back() {
    let dir = long_set("passed");
    let mut state = state_on(&dir);
    seek(&mut state, 2 * LEARN_AHEAD_FRAMES);
    state.apply(Command::Timeline(TimelineCommand::Step(5)));
    until_learned(&mut state);
    assert_eq!(
        state.run().expect("a run").frontier(),
        2 * LEARN_AHEAD_FRAMES + 5
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn steering_drops_the_copy_and_it_never_lands() {
    let dir = long_set("steer");
    let mut state = state_on(&dir);
    let frame = FRAMES - 100;
    seek(&mut state, frame);
    let steered = OnlineParams {
        com_offset: [0.01, -0.01],
        h: 0.1,
    };
    state.apply(Command::Online(OnlineCommand::SetTheta(steered)));
    assert!(state.learning_ahead().is_none());
    assert_eq!(
        state.status.as_deref(),
        Some("stopped learning ahead: θ is held from frame 0 (play or seek to learn on)")
    );
    let held = state.run().expect("a run").checkpoints().to_vec();
    assert_eq!(
        held.len(),
        frame + 1,
        "θ set at the frame shown, held before it"
    );
    // Long enough for the copy to have learned, had it not been stopped.
    std::thread::sleep(Duration::from_millis(500));
    state.advance(0.0);
    assert_eq!(state.run().expect("a run").checkpoints(), held.as_slice());

    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cancel_stops_the_copy_where_it_got_and_keeps_what_it_learned() {
    let dir = long_set("cancel");
    let mut state = state_on(&dir);
    let target = FRAMES - 100;
    seek(&mut state, target);
    assert!(state.learning_ahead().is_some());
    state.apply(Command::Online(OnlineCommand::StopLearningAhead));
    until_learned(&mut state);
    let run = state.run().expect("a run");
    let got_to = run.frontier();
    // Stopped between two blocks of frames: almost always before the end (a worker scheduled
    // through all of them before the stop was asked for would have finished).
    let said = if got_to < target {
        format!("stopped learning ahead at frame {got_to} after ")
    } else {
        format!("learned up to frame {target} in the background")
    };
    let status = state.status.clone().unwrap_or_default();
    assert!(status.starts_with(&said), "{status}");
    // What it learned is what learning up to there on the UI thread gives; nothing after it.
    let reference = learned_by_short_seeks(&dir, got_to);
    let reference = reference.run().expect("a run");
    assert_eq!(run.checkpoints(), reference.checkpoints());
    assert_eq!(run.learned(), reference.learned());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_label_handed_to_the_copy_as_it_learns_holds_theta_over_the_frames_it_had_not_passed() {
    use std::sync::Arc;

    use pushlab_core::learn;

    use crate::app::state::learning::ahead::LearningAhead;
    let dir = long_set("label");
    let state = state_on(&dir);
    let run = state.run.as_ref().expect("a run");
    let target = FRAMES - 100;
    // Bad tracking near the frame sought to, labelled just after the copy set out: the worker,
    // which reads the labels before each block of 4,096 frames, is still far from there.
    let (first, last) = (target - 50, target - 40);
    let mut labelled = vec![false; FRAMES];
    labelled[first..=last].fill(true);
    let mut ahead = LearningAhead::default();
    ahead.start(run, 0, target, Arc::from(vec![false; FRAMES]), 7);
    ahead.follow_labels(Arc::from(labelled.clone()));
    let (done, to) = ahead.progress().expect("learning");
    assert!(
        (done * to as f32) as usize + 2 * 4_096 < first - 20,
        "the worker was at {done} of {to} when the label was handed: too near it for this test"
    );
    let learned = waited_for(|| ahead.poll(7));
    // What learning with the label from the start gives, θ held over the samples touching it.
    let mut reference = learn::OnlineRun::clone(run);
    reference.learn_through(0, target, &labelled);
    assert_eq!(learned.run.checkpoints(), reference.checkpoints());
    assert_eq!(learned.run.learned(), reference.learned());
    let held = (first - 10..=last).filter(|&k| learned.run.learned()[k].is_none());
    assert!(held.count() > last - first, "every labelled frame held");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_label_painted_while_the_copy_learns_is_handed_to_it() {
    use crate::app::state::labels::labeling::tests::paint_frames;
    let dir = long_set("painted");
    let mut state = state_on(&dir);
    let target = FRAMES - 100;
    seek(&mut state, target);
    let handed = |state: &AppState| state.learning_ahead.labels_handed().expect("learning");
    assert!(!handed(&state).contains(&true));
    paint_frames(&mut state, "bad tracking", target - 50, target - 40);
    let painted = handed(&state);
    assert_eq!(&*painted, &*state.frames_to_skip());
    assert_eq!(painted.iter().filter(|&&s| s).count(), 11);
    until_learned(&mut state);
    let _ = std::fs::remove_dir_all(&dir);
}
