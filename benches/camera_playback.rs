//! Does playing at 1× show every frame of a 30 Hz camera? A measurement, not a criterion bench: the
//! app plays a 10 s push whose camera is 300 JPEG frames of 1280×720 (a native image sequence on
//! disk), in real time — each 60 Hz step of the window waits for the wall clock, so the decoder
//! thread has exactly the time it would have in the window — and counts the camera frames the panel
//! had decoded and drew at the step that showed them. A frame whose turn passed before it was
//! decoded is dropped. Each step runs the app's logic and every panel's layout and tessellation as
//! `egui_kittest` does, without the GPU upload.
//!
//! Run: `cargo bench -p pushlab --bench camera_playback` (prints the counts and the slowest step).
//! Under `cargo test` it plays 1 s of a 320×240 camera and checks only that frames were shown
//! (timing is measured here, never asserted in a test).

use std::path::Path;
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use pushlab::app::state::playback::timeline::TimelineCommand;
use pushlab::app::state::{Command, Persisted};
use pushlab::app::{PushlabApp, initial_state};

const CAMERA_HZ: f64 = 30.0;

/// A push of `seconds` at 100 Hz and a `width`×`height` JPEG camera at 30 Hz, written as a native
/// set with an image sequence; each image is noise over a moving disc, so it does not compress
/// away (about 30 % of raw, like a camera's).
fn write_set(dir: &Path, seconds: f64, (width, height): (u32, u32)) {
    let _ = std::fs::remove_dir_all(dir);
    let images = dir.join("push_000.images");
    std::fs::create_dir_all(&images).expect("bench dir");
    let mut csv = String::from("time,robot_x,robot_y,object_x,object_y,object_theta\n");
    let rows = (seconds * 100.0) as usize + 1;
    for i in 0..rows {
        let t = i as f64 / 100.0;
        let x = 0.02 * t;
        csv.push_str(&format!("{t},{},0,{},0,0\n", x - 0.35, x));
    }
    std::fs::write(dir.join("push_000.csv"), csv).expect("csv");
    std::fs::write(
        dir.join("setting.json"),
        r#"{"name": "camera-bench", "object": {"shape": "box", "width": 0.3, "length": 0.4},
            "pusher_radius": 0.175, "trajectories": [{"file": "push_000.csv"}]}"#,
    )
    .expect("setting");
    let mut frames = String::from("time,file\n");
    let mut seed = 0x9E37_79B9_7F4A_7C15_u64;
    let count = (seconds * CAMERA_HZ) as usize;
    for k in 0..count {
        let t = k as f64 / CAMERA_HZ;
        let cx = width as f64 * (0.2 + 0.6 * t / seconds);
        let image = image::RgbImage::from_fn(width, height, |x, y| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let noise = (seed & 0x3F) as u8;
            let d = (x as f64 - cx).hypot(y as f64 - height as f64 / 2.0);
            let base = if d < height as f64 / 6.0 { 190 } else { 40 };
            image::Rgb([base + noise, base + noise / 2, base])
        });
        let file = format!("{k:04}.jpg");
        image.save(images.join(&file)).expect("jpeg");
        frames.push_str(&format!("{t},{file}\n"));
    }
    std::fs::write(images.join("frames.csv"), frames).expect("frames.csv");
}

/// What playing showed.
struct Played {
    shown: usize,
    passed: usize,
    slowest_step: Duration,
    steps: usize,
}

/// Plays `seconds` of the set at 1× in real time, 60 steps a second.
fn play(dir: &Path, seconds: f64) -> Played {
    let state = initial_state(&[dir.to_path_buf()], Persisted::default());
    assert!(
        state.session().problems.is_empty(),
        "{:?}",
        state.session().problems
    );
    assert_eq!(state.cameras().streams().len(), 1, "the camera is read");
    let mut harness = Harness::builder()
        .with_size([1400.0, 900.0])
        .with_step_dt(1.0 / 60.0)
        .build_ui_state(
            |ui, app: &mut PushlabApp| app.frame(ui),
            PushlabApp::new(state),
        );
    harness.step();
    (harness.state().state.cameras()).wait_for_shown(0.0, Duration::from_secs(10));
    harness
        .state_mut()
        .state
        .apply(Command::Timeline(TimelineCommand::TogglePlay));
    let start = Instant::now();
    // Camera frames that were decoded and drawn at a step that showed them.
    let mut shown = std::collections::BTreeSet::new();
    shown.insert(0);
    let (mut slowest_step, mut steps) = (Duration::ZERO, 0);
    while harness.state().state.timeline().playing {
        steps += 1;
        // The window would draw this step at this wall-clock time.
        let due = Duration::from_secs_f64(steps as f64 / 60.0);
        if let Some(wait) = due.checked_sub(start.elapsed()) {
            std::thread::sleep(wait);
        }
        let began = Instant::now();
        harness.step();
        slowest_step = slowest_step.max(began.elapsed());
        let state = &harness.state().state;
        let frames = state.cameras().shown(state.timeline().frame_time());
        if let Some(frame) = frames.first()
            && let Some(index) = frame.frame
            && matches!(frame.decoded, Some(Ok(_)))
        {
            shown.insert(index);
        }
        if start.elapsed().as_secs_f64() > seconds + 5.0 {
            break;
        }
    }
    // Every frame of the camera had its turn, the first before playing started.
    let passed = (seconds * CAMERA_HZ) as usize;
    Played {
        shown: shown.len(),
        passed,
        slowest_step,
        steps,
    }
}

fn main() {
    let measuring = std::env::args().any(|a| a == "--bench");
    let (seconds, size) = if measuring {
        (10.0, (1280, 720))
    } else {
        (1.0, (320, 240))
    };
    let dir = std::env::temp_dir().join(format!("pushlab-camera-playback-{}", std::process::id()));
    write_set(&dir, seconds, size);
    let played = play(&dir, seconds);
    let _ = std::fs::remove_dir_all(&dir);
    println!(
        "camera_playback_30hz_{}x{}: {} of {} camera frames shown at their turn while playing {seconds} s \
         at 1x ({} steps, slowest step {:.1} ms)",
        size.0,
        size.1,
        played.shown,
        played.passed,
        played.steps,
        played.slowest_step.as_secs_f64() * 1e3
    );
    assert!(played.shown > 1, "playing showed the camera's frames");
}
