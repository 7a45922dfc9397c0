//! How late a live robot's frames are learned and drawn, and what a long session costs (issue #48):
//! a robot in this process — the Foxglove SDK's WebSocket server — logs a pusher (JSON) and an
//! object (CDR PoseStamped) at `--rate` Hz and, with `--camera`, a 30 Hz `CompressedImage` of
//! 150 kB (bytes standing in for a 720p JPEG; a live session records images, it does not decode
//! them). Both stamped on a fixed schedule, so that grid frame `j` is made when the poses of
//! message `j + 1` arrive (a frame is final once both streams passed it): every latency below is
//! from the wall time of that `log` call.
//!
//! - `learned` — `pushlab live --setting`'s path: the core `LiveSession` (recording every message to
//!   an MCAP file) and `LiveLearner` on one thread, the frame learned.
//! - `drawn` — the app's: File → Connect's worker, the inbox, and the UI thread at 60 frames a
//!   second learning the frames that came and laying out every panel (`egui_kittest`, as the
//!   `app_frame` bench; without the GPU upload).
//!
//! It prints p50, p99 and the worst, the messages sent and recorded, the process's CPU time per
//! second and its resident memory at the start and the end.
//!
//! Run with `cargo bench -p pushlab --bench live_latency -- [--rate HZ] [--seconds S] [--camera]
//! [--only learned|drawn]`.

#![allow(clippy::unwrap_used, clippy::expect_used)]

#[path = "../tests/live_robot/mod.rs"]
mod live_robot;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use foxglove::PartialMetadata;
use pushlab::app::state::sources::live::{LiveChoice, LiveCommand};
use pushlab::app::state::{Command, Persisted};
use pushlab::app::{PushlabApp, initial_state};
use pushlab_core::learn::OnlineConfig;
use pushlab_core::live::{LiveLearner, LiveSession, SessionEvent};
use pushlab_core::model_file::ModelFile;
use pushlab_core::recording::bag::{SettingSource, encode_compressed_image, encode_pose_stamped};

fn unix_ns() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap()
        .as_nanos() as u64
}

/// The wall time of each pose pair's `log` call, by message index.
type Logged = Arc<Mutex<Vec<u64>>>;

struct Robot {
    url: String,
    /// The first message's stamp, Unix ns.
    t0: u64,
    stop: Arc<AtomicBool>,
    logged: Logged,
    thread: std::thread::JoinHandle<u64>,
}

/// A robot logging at `rate_hz` (and a camera at 30 Hz) once a client subscribed, until stopped;
/// the thread returns the messages it logged.
fn robot(rate_hz: f64, camera: bool) -> Robot {
    let (context, server, pusher, object) = live_robot::start_robot(0, false);
    let url = format!("ws://127.0.0.1:{}", server.port());
    let camera = camera.then(|| live_robot::camera_channel(&context));
    let stop = Arc::new(AtomicBool::new(false));
    let logged: Logged = Arc::default();
    let (flag, times) = (Arc::clone(&stop), Arc::clone(&logged));
    let t0 = unix_ns() + 2_000_000_000;
    let thread = std::thread::spawn(move || {
        let _context = context;
        let subscribed = || pusher.has_sinks() && object.has_sinks();
        while !flag.load(Ordering::Relaxed) && !subscribed() {
            std::thread::sleep(Duration::from_millis(5));
        }
        let image: Vec<u8> = (0..150_000u32)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 24) as u8)
            .collect();
        let dt = 1.0 / rate_hz;
        let started = Instant::now();
        let (mut k, mut sent, mut next_image) = (0u64, 0u64, 0.0);
        while !flag.load(Ordering::Relaxed) {
            let due = Duration::from_secs_f64(k as f64 * dt);
            if let Some(wait) = due.checked_sub(started.elapsed()) {
                std::thread::sleep(wait);
            }
            let stamp = t0 + (k as f64 * dt * 1e9).round() as u64;
            let at = PartialMetadata::with_log_time(stamp);
            times.lock().unwrap().push(unix_ns());
            let s = k as f64 * dt;
            let json = format!(
                r#"{{"header":{{"stamp":{{"sec":{},"nanosec":{}}}}},"pose":{{"position":{{"x":{},"y":0.0,"z":0}},"orientation":{{"x":0,"y":0,"z":0,"w":1}}}}}}"#,
                stamp / 1_000_000_000,
                stamp % 1_000_000_000,
                -0.16 + 0.02 * s,
            );
            pusher.log_with_meta(json.as_bytes(), at);
            object.log_with_meta(
                &encode_pose_stamped(stamp, "table", 0.02 * s, 0.0, 0.001 * s),
                at,
            );
            sent += 2;
            if let Some(camera) = &camera
                && s >= next_image
            {
                next_image += 1.0 / 30.0;
                camera.log_with_meta(
                    &encode_compressed_image(stamp, "camera", "jpeg", &image),
                    at,
                );
                sent += 1;
            }
            k += 1;
        }
        let _ = server.stop();
        sent
    });
    Robot {
        url,
        t0,
        stop,
        logged,
        thread,
    }
}

/// p50, p99 and the worst of latencies in milliseconds.
fn summary(mut ms: Vec<f64>) -> String {
    if ms.is_empty() {
        return "no frames".to_owned();
    }
    ms.sort_by(f64::total_cmp);
    let at = |q: f64| ms[((ms.len() - 1) as f64 * q).round() as usize];
    format!(
        "p50 {:.2} ms, p99 {:.2} ms, worst {:.2} ms over {} frames",
        at(0.5),
        at(0.99),
        ms[ms.len() - 1],
        ms.len()
    )
}

/// The process's CPU time (user + system), seconds, and resident memory, MB.
fn usage() -> (f64, f64) {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map_or(vec![], |(_, rest)| rest.split_whitespace().collect());
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    let cpu = (ticks(11) + ticks(12)) / 100.0;
    let statm = std::fs::read_to_string("/proc/self/statm").unwrap_or_default();
    let pages: f64 = (statm.split_whitespace().nth(1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(0.0);
    (cpu, pages * 4096.0 / 1e6)
}

fn setting_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("sample-data/box1-paper-ur-front/setting.json")
}

/// When the message that made grid frame `j` final was logged: the first whose stamp is after the
/// frame's time `t_s` (seconds since the first stamp), computed as the grid computes it.
fn released(logged: &[u64], rate_hz: f64, t_s: f64) -> Option<u64> {
    let stamp_s = |k: usize| (k as f64 / rate_hz * 1e9).round() * 1e-9;
    let mut k = (t_s * rate_hz).floor().max(0.0) as usize;
    while stamp_s(k) <= t_s {
        k += 1;
    }
    logged.get(k).copied()
}

/// `pushlab live --setting`'s path on this thread: each frame's latency to learned.
fn learned(rate_hz: f64, seconds: f64, camera: bool, record: &Path) -> (Vec<f64>, u64) {
    let robot = robot(rate_hz, camera);
    let model =
        ModelFile::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/default-model.json"))
            .unwrap();
    let setting = SettingSource::File(setting_path()).resolve().unwrap();
    let mut learner =
        LiveLearner::new(&model.combined, &setting, OnlineConfig::default(), rate_hz).unwrap();
    let never = || false;
    let mut session =
        LiveSession::open(&robot.url, "/pusher", "/object", Some(record), &never).unwrap();
    let started = Instant::now();
    let (mut ms, mut received) = (Vec::new(), Vec::new());
    while started.elapsed().as_secs_f64() < seconds {
        if let Some(SessionEvent::Pose {
            stream,
            pose,
            log_time_ns,
        }) = session.next(&never).unwrap()
        {
            // The message's index from its stamp (the robot's fixed schedule).
            let k = ((log_time_ns - robot.t0) as f64 * 1e-9 * rate_hz).round() as usize;
            received.extend(
                robot
                    .logged
                    .lock()
                    .unwrap()
                    .get(k)
                    .map(|&sent| unix_ns().saturating_sub(sent) as f64 * 1e-6),
            );
            let _ = learner.take(stream, &pose, log_time_ns);
            let before = learner.run().trajectory().len();
            learner.learn();
            let now = unix_ns();
            let logged = robot.logged.lock().unwrap();
            for frame in &learner.run().trajectory().frames[before..] {
                ms.extend(
                    released(&logged, rate_hz, frame.time)
                        .map(|sent| now.saturating_sub(sent) as f64 * 1e-6),
                );
            }
        }
    }
    robot.stop.store(true, Ordering::Relaxed);
    let sent = robot.thread.join().unwrap();
    let recorded = session.finish().unwrap().map_or(0, |r| r.messages);
    assert!(recorded <= sent);
    println!("  messages: {sent} sent, {recorded} recorded (the rest were in flight at the end)");
    println!(
        "  received (log call to the pose read): {}",
        summary(received)
    );
    (ms, recorded)
}

/// The app's path: each frame's latency to the UI frame that learned it and to that frame laid out.
fn drawn(rate_hz: f64, seconds: f64, camera: bool, record: &Path) -> (Vec<f64>, Vec<f64>) {
    let robot = robot(rate_hz, camera);
    let mut state = initial_state(&[], Persisted::default());
    state.apply(Command::Live(LiveCommand::OpenForm));
    state.apply(Command::Live(LiveCommand::Edit(LiveChoice {
        url: robot.url.clone(),
        pusher: "/pusher".to_owned(),
        object: "/object".to_owned(),
        setting: setting_path(),
        record: record.to_path_buf(),
        rate_hz: Some(rate_hz),
        ..LiveChoice::default()
    })));
    state.apply(Command::Live(LiveCommand::Connect));
    let timings: Arc<Mutex<(Vec<f64>, Vec<f64>)>> = Arc::default();
    let frames_seen = Arc::new(Mutex::new(0usize));
    let mut harness = {
        let (timings, seen) = (Arc::clone(&timings), Arc::clone(&frames_seen));
        let logged = Arc::clone(&robot.logged);
        egui_kittest::Harness::builder()
            .with_size([1400.0, 900.0])
            .with_step_dt(1.0 / 60.0)
            .build_ui_state(
                move |ui, app: &mut PushlabApp| {
                    app.state.advance(1.0 / 60.0);
                    let learned_at = unix_ns();
                    app.show(ui);
                    let drawn_at = unix_ns();
                    let Some(recording) = app.state.recording() else {
                        return;
                    };
                    let frames = &recording.trajectory.frames;
                    let mut seen = seen.lock().unwrap();
                    let logged = logged.lock().unwrap();
                    let mut t = timings.lock().unwrap();
                    for frame in frames.get(*seen..).unwrap_or_default() {
                        if let Some(sent) = released(&logged, rate_hz, frame.time) {
                            t.0.push(learned_at.saturating_sub(sent) as f64 * 1e-6);
                            t.1.push(drawn_at.saturating_sub(sent) as f64 * 1e-6);
                        }
                    }
                    *seen = frames.len();
                },
                PushlabApp::new(state),
            )
    };
    let started = Instant::now();
    let frame = Duration::from_secs_f64(1.0 / 60.0);
    let mut next = Instant::now();
    // Over a long session, the cost and the memory once a minute: they should stay flat.
    let (mut minute, mut cpu_then) = (1u64, usage().0);
    while started.elapsed().as_secs_f64() < seconds {
        if started.elapsed() >= Duration::from_secs(60 * minute) {
            let (cpu, rss) = usage();
            println!(
                "  {minute:>3} min: {} frames, {:.1} % of a core over the minute, resident {rss:.0} MB",
                harness
                    .state()
                    .state
                    .live()
                    .running()
                    .map_or(0, |r| r.frames),
                (cpu - cpu_then) / 60.0 * 100.0
            );
            (minute, cpu_then) = (minute + 1, cpu);
        }
        harness.step();
        next += frame;
        if let Some(wait) = next.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
    }
    harness
        .state_mut()
        .state
        .apply(Command::Live(LiveCommand::Disconnect));
    robot.stop.store(true, Ordering::Relaxed);
    let sent = robot.thread.join().unwrap();
    while harness.state().state.live().is_live() {
        harness.step();
    }
    println!(
        "  messages: {sent} sent; {}",
        harness.state().state.status().unwrap_or("")
    );
    let t = timings.lock().unwrap();
    (t.0.clone(), t.1.clone())
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let value =
        |name: &str| (args.iter().position(|a| a == name)).and_then(|i| args.get(i + 1).cloned());
    let rate: f64 = value("--rate").map_or(100.0, |v| v.parse().unwrap());
    // `cargo test --all-targets` runs this without `--bench`: a one-second check that both paths
    // learn and draw frames, not a measurement.
    let measuring = args.iter().any(|a| a == "--bench");
    let seconds: f64 =
        value("--seconds").map_or(if measuring { 10.0 } else { 1.0 }, |v| v.parse().unwrap());
    let camera = args.iter().any(|a| a == "--camera");
    let only = value("--only");
    let dir = std::env::temp_dir().join(format!("pushlab-live-latency-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    println!(
        "live latency: {rate} Hz poses{}, {seconds} s",
        if camera {
            " + a 30 Hz 150 kB camera"
        } else {
            ""
        }
    );
    if only.as_deref() != Some("drawn") {
        let (cpu0, rss0) = usage();
        let (ms, _) = learned(rate, seconds, camera, &dir.join("learned.mcap"));
        assert!(!ms.is_empty(), "frames were learned");
        let (cpu1, rss1) = usage();
        println!("  learned: {}", summary(ms));
        println!(
            "  process: {:.1} % of a core, resident {rss0:.0} → {rss1:.0} MB",
            (cpu1 - cpu0) / seconds * 100.0
        );
    }
    if only.as_deref() != Some("learned") {
        let (cpu0, rss0) = usage();
        let (learned, drawn) = drawn(rate, seconds, camera, &dir.join("drawn.mcap"));
        assert!(!drawn.is_empty(), "frames were drawn");
        let (cpu1, rss1) = usage();
        println!("  app, learned on the UI thread: {}", summary(learned));
        println!("  app, drawn: {}", summary(drawn));
        println!(
            "  process: {:.1} % of a core, resident {rss0:.0} → {rss1:.0} MB",
            (cpu1 - cpu0) / seconds * 100.0
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
