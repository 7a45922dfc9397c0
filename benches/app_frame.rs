//! What the app costs per frame while playing a 1,500-frame push with online learning on (target:
//! under 16 ms), and how long opening the bundled sample data takes (target: under 1 s).
//!
//! A frame here is one full egui frame of the app as `egui_kittest` runs it headlessly: `logic`
//! (time and learning) plus every panel's layout and tessellation, without the GPU upload.
//!
//! Run with `cargo bench -p pushlab --bench app_frame`.

use std::hint::black_box;
use std::path::PathBuf;
use std::sync::Arc;

use criterion::{Criterion, criterion_group, criterion_main};
use egui_kittest::Harness;
use pushlab::app::state::session::RecordingId;
use pushlab::app::state::timeline::TimelineCommand;
use pushlab::app::state::{Command, Persisted};
use pushlab::app::{PushlabApp, initial_state, sample_data_dir};
use pushlab_core::geometry::Pose2;
use pushlab_core::recording::{Recording, RecordingSet};
use pushlab_core::trajectory::{Frame, Trajectory};

/// Frames of the long push.
const FRAMES: usize = 1500;

/// A 1,500-frame push at 100 Hz of the first sample object: pushed along +x while turning slowly.
fn long_push(like: &Recording) -> Recording {
    let frames = (0..FRAMES)
        .map(|i| {
            let t = i as f64 * 0.01;
            let object = Pose2::new(0.02 * t, 0.002 * t * t, 0.05 * t);
            let robot = object.point_in_world(nalgebra::Point2::new(-0.08, 0.005));
            Frame {
                time: t,
                robot,
                object,
            }
        })
        .collect();
    Recording {
        source: PathBuf::from("bench/long-push.csv"),
        name: "long-push".to_owned(),
        setting: like.setting.clone(),
        entry: None,
        trajectory: Trajectory::new(frames),
        warnings: Vec::new(),
    }
}

fn frame_while_playing(c: &mut Criterion) {
    let mut app = PushlabApp::new(initial_state(&[], Persisted::default()));
    let first = app
        .state
        .recording()
        .expect("the sample data opens")
        .clone();
    app.state.session.sets.push(RecordingSet {
        dir: PathBuf::from("bench"),
        setting: Arc::clone(&first.setting),
        recordings: vec![long_push(&first)],
    });
    let id = RecordingId {
        set: app.state.session.sets.len() - 1,
        recording: 0,
    };
    app.state.apply(Command::Select(id));
    app.state.learn_while_playing = true;
    app.state
        .apply(Command::Timeline(TimelineCommand::TogglePlay));

    let mut harness = Harness::builder()
        .with_size([1400.0, 900.0])
        .with_step_dt(1.0 / 60.0)
        .build_ui_state(|ui, app: &mut PushlabApp| app.frame(ui), app);
    c.bench_function("app frame, playing 1500 frames with learning", |b| {
        b.iter(|| {
            let state = &mut harness.state_mut().state;
            // Start over before the end, forgetting what was learned, so every frame learns.
            if state.frame() + 10 >= FRAMES || !state.timeline.playing {
                state.apply(Command::ResetTheta);
                state.apply(Command::Timeline(TimelineCommand::JumpStart));
                if !state.timeline.playing {
                    state.apply(Command::Timeline(TimelineCommand::TogglePlay));
                }
            }
            harness.step();
        })
    });
    let run = harness.state().state.run.as_ref().expect("a run");
    assert!(run.frontier() > 0, "the benchmark did not learn");
}

/// What `cargo run` does before the first frame: load the default model, the sample data's 324
/// recordings and 9 labels files, and start the online run on the first recording.
fn open_sample_data(c: &mut Criterion) {
    let dir = sample_data_dir();
    c.bench_function("open sample data", |b| {
        b.iter(|| {
            let state = initial_state(std::slice::from_ref(&dir), Persisted::default());
            assert!(state.session.problems.is_empty());
            assert!(state.run.is_some());
            black_box(state.session.recording_count())
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = frame_while_playing, open_sample_data
}
criterion_main!(benches);
