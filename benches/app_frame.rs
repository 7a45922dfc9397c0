//! What the app costs per frame while playing, and how long opening takes, from short pushes to a
//! 67-minute recording:
//!
//! - `frame_playing_1k5`, `frame_playing_100k`, `frame_playing_1m`: one full egui frame of the app,
//!   as `egui_kittest` runs it headlessly — `logic` (time and online learning) plus every panel's
//!   layout and tessellation, without the GPU upload — while playing at 1.0× (one 60 Hz frame of a
//!   250 Hz recording learns four frames) with learning on, on pushes of 1,500, 100,000 and
//!   1,000,001 frames. Target: ≤ 16 ms.
//! - `frame_playing_5k_recordings`: the same on the 1,500-frame push with 5,000 more recordings
//!   open (the browser lists 5,324). Target: ≤ 16 ms, and no more than a few rows' worth above
//!   `frame_playing_1k5`: a frame builds the rows in view, not every open recording's.
//! - `open_1m`: opening a 1,000,001-frame CSV (250 Hz, 55 MB) from disk as `pushlab open` does —
//!   the default model, the file, the online run with its fixed pass — and drawing the first frame.
//!   Target: ≤ 2 s.
//! - `select_1m`: selecting that recording after another — its online run with the fixed pass,
//!   the path's overview, the plots' series — all on the UI thread. Target: ≤ 0.5 s.
//! - `open_sample_data`: everything `cargo run` does before its first frame on the bundled sample
//!   data (model, 324 recordings, 9 labels files, the first run). Target: under 1 s.
//!
//! Run with `cargo bench -p pushlab --bench app_frame`.

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use criterion::{Criterion, criterion_group, criterion_main};
use egui_kittest::Harness;
use pushlab::app::state::playback::timeline::TimelineCommand;
use pushlab::app::state::recordings::session::RecordingId;
use pushlab::app::state::{AppState, Command, Persisted};
use pushlab::app::state::{OnlineCommand, SessionCommand};
use pushlab::app::{PushlabApp, initial_state, sample_data_dir};
use pushlab_core::geometry::Pose2;
use pushlab_core::recording::{Recording, RecordingSet, Setting, write_set};
use pushlab_core::trajectory::{Frame, Trajectory};

/// A push of `frames` frames at `rate_hz`: the object slides round a 1 m circle at 2 cm/s, turning
/// with it and wobbling, the pusher 8 cm behind its centre.
fn long_push(frames: usize, rate_hz: f64) -> Trajectory {
    Trajectory::new(
        (0..frames)
            .map(|i| {
                let t = i as f64 / rate_hz;
                let angle = 0.02 * t;
                let wobble = 0.05 * (0.7 * t).sin();
                let object = Pose2::new(angle.sin(), 1.0 - angle.cos(), angle + wobble);
                let robot = object.point_in_world(nalgebra::Point2::new(-0.2, 0.01));
                Frame {
                    time: t,
                    robot,
                    object,
                }
            })
            .collect(),
    )
}

/// The app on the sample data with `trajectory` added as a recording of the first sample setting
/// (and `more` recordings of the same frames beside it), selected, playing at 1.0× with learning on.
fn playing(trajectory: Trajectory, more: usize) -> Harness<'static, PushlabApp> {
    let mut app = PushlabApp::new(initial_state(&[], Persisted::default()));
    let setting = Arc::clone(
        &app.state
            .recording()
            .expect("the sample data opens")
            .setting,
    );
    let trajectory = Arc::new(trajectory);
    let recording = |name: String| Recording {
        source: PathBuf::from(format!("bench/{name}.csv")),
        name,
        setting: Arc::clone(&setting),
        entry: None,
        trajectory: Arc::clone(&trajectory),
        warnings: Vec::new(),
        notes: Vec::new(),
        cameras: Vec::new(),
    };
    let recordings = std::iter::once(recording("long-push".to_owned()))
        .chain((0..more).map(|i| recording(format!("push-{i:04}"))))
        .collect();
    let id = app.state.add_set(RecordingSet {
        dir: PathBuf::from("bench"),
        setting: Arc::clone(&setting),
        recordings,
    });
    app.state
        .apply(Command::Session(SessionCommand::Select(id)));
    app.state
        .apply(Command::Online(OnlineCommand::SetLearnWhilePlaying(true)));
    app.state
        .apply(Command::Timeline(TimelineCommand::TogglePlay));
    Harness::builder()
        .with_size([1400.0, 900.0])
        .with_step_dt(1.0 / 60.0)
        .build_ui_state(|ui, app: &mut PushlabApp| app.frame(ui), app)
}

/// Benchmarks frames of the harness while playing; starts over (forgetting what was learned) before
/// the end, so that every frame learns.
fn bench_playing(c: &mut Criterion, name: &str, trajectory: Trajectory, more: usize) {
    let frames = trajectory.len();
    let mut harness = playing(trajectory, more);
    c.bench_function(name, |b| {
        b.iter(|| {
            let state: &mut AppState = &mut harness.state_mut().state;
            if state.frame() + 10 >= frames || !state.timeline().playing {
                state.apply(Command::Online(OnlineCommand::ResetTheta));
                state.apply(Command::Timeline(TimelineCommand::JumpStart));
                if !state.timeline().playing {
                    state.apply(Command::Timeline(TimelineCommand::TogglePlay));
                }
            }
            harness.step();
        })
    });
    let run = harness.state().state.run().expect("a run");
    assert!(run.frontier() > 0, "the benchmark did not learn");
}

fn frame_playing(c: &mut Criterion) {
    bench_playing(c, "frame_playing_1k5", long_push(1500, 100.0), 0);
    bench_playing(c, "frame_playing_100k", long_push(100_000, 250.0), 0);
    bench_playing(c, "frame_playing_1m", long_push(1_000_001, 250.0), 0);
    bench_playing(
        c,
        "frame_playing_5k_recordings",
        long_push(1500, 100.0),
        5000,
    );
}

/// Writes a one-push native set of `trajectory` with the object and pusher of the sample data.
fn write_long_set(dir: &Path, trajectory: Trajectory) {
    let setting: Setting = serde_json::from_value(serde_json::json!({
        "name": "long",
        "object": {"shape": "box", "width": 0.3, "length": 0.4},
        "pusher_radius": 0.175,
        "trajectories": [{"file": "push_000.csv"}],
    }))
    .expect("a valid setting");
    let _ = std::fs::remove_dir_all(dir);
    write_set(dir, &setting, &[trajectory]).expect("write the long set");
}

fn open_1m(c: &mut Criterion) {
    let dir = std::env::temp_dir().join(format!("pushlab-bench-open-1m-{}", std::process::id()));
    write_long_set(&dir, long_push(1_000_001, 250.0));
    c.bench_function("open_1m", |b| {
        b.iter(|| {
            let state = initial_state(std::slice::from_ref(&dir), Persisted::default());
            assert!(
                state.session().problems.is_empty(),
                "{:?}",
                state.session().problems
            );
            assert_eq!(state.run().expect("a run").sample_count(), 999_991);
            let mut harness = Harness::builder()
                .with_size([1400.0, 900.0])
                .build_ui_state(
                    |ui, app: &mut PushlabApp| app.frame(ui),
                    PushlabApp::new(state),
                );
            harness.step();
            black_box(harness.state().state.frame())
        })
    });
    let _ = std::fs::remove_dir_all(&dir);
}

fn select_1m(c: &mut Criterion) {
    let dir = std::env::temp_dir().join(format!("pushlab-bench-select-1m-{}", std::process::id()));
    write_long_set(&dir, long_push(1_000_001, 250.0));
    let paths = [
        dir.clone(),
        sample_data_dir().join("box1-paper-center-front"),
    ];
    let mut state = initial_state(&paths, Persisted::default());
    let (long, short) = (
        RecordingId {
            set: 0,
            recording: 0,
        },
        RecordingId {
            set: 1,
            recording: 0,
        },
    );
    c.bench_function("select_1m", |b| {
        b.iter(|| {
            state.apply(Command::Session(SessionCommand::Select(short)));
            state.apply(Command::Session(SessionCommand::Select(long)));
            black_box(state.run().expect("a run").sample_count())
        })
    });
    let _ = std::fs::remove_dir_all(&dir);
}

/// What `cargo run` does before the first frame: load the default model, the sample data's 324
/// recordings and 9 labels files, and start the online run on the first recording.
fn open_sample_data(c: &mut Criterion) {
    let dir = sample_data_dir();
    c.bench_function("open_sample_data", |b| {
        b.iter(|| {
            let state = initial_state(std::slice::from_ref(&dir), Persisted::default());
            assert!(state.session().problems.is_empty());
            assert!(state.run().is_some());
            black_box(state.session().recording_count())
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = frame_playing, open_1m, select_1m, open_sample_data
}
criterion_main!(benches);
