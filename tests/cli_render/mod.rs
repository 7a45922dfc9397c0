//! `pushlab render` against independent readers of what it wrote: the GIF decoded by the `image`
//! crate, the MP4 by ffmpeg. The video has the frames asked for at the frame rate asked; in frame
//! k the pusher's disc is drawn where the recording puts the pusher at that frame's time (its
//! centroid within 2 px), and the learned COM marker where `pushlab eval --per-frame` puts θ at
//! that frame. A render stopped midway or refused leaves no file.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::cli_common;
use crate::skip;
mod theme;

use std::path::{Path, PathBuf};

use cli_common::{pushlab, temp_dir};
use eframe::egui::Theme;
use image::AnimationDecoder;
use nalgebra::Point2;
use pushlab::app::initial_state;
use pushlab::app::render::{RenderOptions, SceneFrames, render};
use pushlab::app::state::Persisted;

const SET: &str = "sample-data/box1-paper-ur-front";
const SIZE: [usize; 2] = [320, 200];

fn recording() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(SET)
        .join("online_000.csv")
}

/// The state the render starts from: the recording, the bundled model, only the COM layer.
fn state() -> pushlab::app::state::AppState {
    state_of(&recording())
}

/// The state a render of `push` starts from: the bundled model, only the COM layer.
fn state_of(push: &Path) -> pushlab::app::state::AppState {
    let defaults = Persisted::default();
    let persisted = Persisted {
        layers: defaults.layers.only("com").unwrap(),
        ..defaults
    };
    initial_state(std::slice::from_ref(&push.to_path_buf()), persisted)
}

/// `pushlab eval --per-frame` with the bundled model and `args` (the pushes, its options), its
/// report written in `dir`.
fn eval_report(dir: &Path, args: &[&str]) -> serde_json::Value {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let json = dir.join("eval.json");
    let model = root.join("assets/default-model.json");
    let mut all = vec!["eval", "--per-frame", "--model", model.to_str().unwrap()];
    all.extend(args);
    all.extend(["--json", json.to_str().unwrap()]);
    let run = pushlab(&all);
    assert_eq!(run.code, 0, "{}", run.stderr);
    serde_json::from_slice(&std::fs::read(json).unwrap()).unwrap()
}

/// θ's COM offset in a report's trajectory frame.
fn com_of(frame: &serde_json::Value) -> [f64; 2] {
    let c = &frame["theta"]["com_offset"];
    [c[0].as_f64().unwrap(), c[1].as_f64().unwrap()]
}

/// Every frame of the GIF at `path`, decoded by the `image` crate.
fn gif_frames(path: &Path) -> Vec<image::Frame> {
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    let decoder = image::codecs::gif::GifDecoder::new(file).unwrap();
    decoder.into_frames().collect::<Result<_, _>>().unwrap()
}

/// A frame's pixels as RGB bytes, row by row.
fn rgb_of(frame: &image::Frame) -> Vec<u8> {
    (frame.buffer().pixels())
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect()
}

/// The centroid of the pixels `wanted` picks, pixels from the top left, and how many.
fn centroid(rgb: &[u8], width: usize, wanted: impl Fn([u8; 3]) -> bool) -> ([f32; 2], usize) {
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0);
    for (i, p) in rgb.chunks_exact(3).enumerate() {
        if wanted([p[0], p[1], p[2]]) {
            sx += (i % width) as f32 + 0.5;
            sy += (i / width) as f32 + 0.5;
            n += 1;
        }
    }
    ([sx / n.max(1) as f32, sy / n.max(1) as f32], n)
}

/// The pusher's disc: its yellow ring and its darker yellow fill.
fn yellow([r, g, b]: [u8; 3]) -> bool {
    r > 60 && g > 55 && f32::from(b) < 0.6 * f32::from(g) && r.abs_diff(g) < 45
}

/// The estimated COM's orange dot.
fn orange([r, g, b]: [u8; 3]) -> bool {
    r > 215 && (110..190).contains(&g) && b < 90
}

fn distance(a: [f32; 2], b: [f32; 2]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

/// θ's COM offset at every frame, as `pushlab eval --per-frame` learns it with the bundled model.
fn eval_com(dir: &Path) -> Vec<[f64; 2]> {
    let set = Path::new(env!("CARGO_MANIFEST_DIR")).join(SET);
    let report = eval_report(
        dir,
        &[
            "--offline",
            set.to_str().unwrap(),
            "--online",
            recording().to_str().unwrap(),
        ],
    );
    (report["trajectories"][0]["frames"]
        .as_array()
        .unwrap()
        .iter())
    .map(com_of)
    .collect()
}

#[test]
fn a_gif_shows_the_pusher_where_it_was_and_the_com_where_eval_learned_it() {
    let dir = temp_dir("render", "gif");
    let out = dir.join("push.gif");
    let run = pushlab(&[
        "render",
        recording().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--size",
        "320x200",
        "--fps",
        "20",
        "--frames",
        "10..30",
        "--layers",
        "com",
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains("wrote "), "{}", run.stdout);

    // 20 frames of a 10 Hz push at 20 frames a second: 2 s, 39 frames (times 1.0 … 2.9 s).
    let frames = gif_frames(&out);
    assert_eq!(frames.len(), 39);
    let (numer, denom) = frames[0].delay().numer_denom_ms();
    assert_eq!(
        f64::from(numer) / f64::from(denom),
        50.0,
        "20 frames a second"
    );

    // Where the app's scene puts the table's points in this frame size (it fits the whole push).
    let mut scene = SceneFrames::new(state(), SIZE, false, Theme::Dark);
    scene.show(10);
    scene.draw();
    let trajectory = scene.state().recording().unwrap().trajectory.clone();
    let com = eval_com(&dir);
    for (i, frame) in frames.iter().enumerate() {
        let k = 10 + i / 2;
        let rgb = rgb_of(frame);
        let (pusher, n) = centroid(&rgb, SIZE[0], yellow);
        let want = scene.pixel_of(trajectory.frames[k].robot);
        assert!(n > 20, "frame {i}: the pusher's disc is drawn");
        assert!(
            distance(pusher, want) <= 2.0,
            "frame {i} (recording frame {k}): the pusher at {pusher:?}, the recording at {want:?}"
        );
        let object = trajectory.frames[k].object;
        let want = scene.pixel_of(object.point_in_world(Point2::from(com[k])));
        let (marker, n) = centroid(&rgb, SIZE[0], orange);
        assert!(n > 10, "frame {i}: the COM marker is drawn");
        assert!(
            distance(marker, want) <= 2.0,
            "frame {i} (recording frame {k}): the COM marker at {marker:?}, eval's θ at {want:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_mp4_and_a_webm_hold_the_frames_asked_for() {
    if pushlab_core::recording::camera::find_ffmpeg().is_err() {
        skip::skip("ffmpeg on the PATH (apt install ffmpeg)");
        return;
    }
    let dir = temp_dir("render", "mp4");
    for name in ["push.mp4", "push.webm"] {
        let out = dir.join(name);
        let run = pushlab(&[
            "render",
            recording().to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--size",
            "320x200",
            "--fps",
            "10",
            "--frames",
            "0..25",
            "--layers",
            "com",
        ]);
        assert_eq!(run.code, 0, "{}", run.stderr);
        // ffmpeg decodes every frame as raw RGB: 25 frames of 320 × 200.
        let decoded = std::process::Command::new("ffmpeg")
            .args(["-loglevel", "error", "-i"])
            .arg(&out)
            .args(["-f", "rawvideo", "-pix_fmt", "rgb24", "-"])
            .output()
            .unwrap();
        assert!(decoded.status.success());
        let frame_bytes = SIZE[0] * SIZE[1] * 3;
        assert_eq!(decoded.stdout.len(), 25 * frame_bytes, "{name}: 25 frames");
        // The pusher's disc in the last frame is where the recording puts it (lossy, yet within
        // 2 px).
        let mut scene = SceneFrames::new(state(), SIZE, false, Theme::Dark);
        scene.show(24);
        scene.draw();
        let robot = scene.state().recording().unwrap().trajectory.frames[24].robot;
        let last = &decoded.stdout[24 * frame_bytes..];
        let (pusher, _) = centroid(last, SIZE[0], yellow);
        let want = scene.pixel_of(robot);
        assert!(
            distance(pusher, want) <= 2.0,
            "{name}: {pusher:?} against {want:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn with_plots_the_losses_are_drawn_below_the_scene() {
    let dir = temp_dir("render", "plots");
    let out = dir.join("plots.gif");
    let run = pushlab(&[
        "render",
        recording().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--size",
        "640x400",
        "--fps",
        "10",
        "--frames",
        "0..30",
        "--layers",
        "com",
        "--with-plots",
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let frames = gif_frames(&out);
    let last = frames.last().unwrap().buffer();
    // The fixed loss's blue: only in the plots (the scene draws no fixed footprint with only the
    // COM layer on), which take the bottom 42 % of the frame.
    let blue_rows: Vec<u32> = (last.enumerate_pixels())
        .filter(|(_, _, p)| p[2] > 200 && p[0] < 140 && p[1] > 120)
        .map(|(_, y, _)| y)
        .collect();
    assert!(blue_rows.len() > 20, "the fixed loss is drawn");
    assert!(
        blue_rows.iter().all(|&y| y as f32 > 0.55 * 400.0),
        "below the scene: rows {:?}",
        blue_rows.iter().min()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The COM marker's centroid in the first frame of a GIF rendered at `SIZE` with only the COM
/// layer on.
fn first_com_marker(gif: &Path) -> [f32; 2] {
    let (at, n) = centroid(&rgb_of(&gif_frames(gif)[0]), SIZE[0], orange);
    assert!(n > 10, "the COM marker is drawn");
    at
}

#[test]
fn carrying_theta_the_render_starts_where_eval_carry_theta_does() {
    let dir = temp_dir("render", "carry");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let set = root.join(SET);
    let push = set.join("online_001.csv");
    let render_to = |out: &Path, carry: bool| {
        let mut args = vec![
            "render",
            push.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--size",
            "320x200",
            "--frames",
            "0..2",
            "--layers",
            "com",
        ];
        if carry {
            args.push("--carry-theta");
        }
        let run = pushlab(&args);
        assert_eq!(run.code, 0, "{}", run.stderr);
        run
    };
    let carried = dir.join("carried.gif");
    let run = render_to(&carried, true);
    // The set's 27 offline pushes and online_000 come before it in its folder.
    assert!(
        run.stderr
            .contains("went on from the θ learned along 28 push(es) before it"),
        "{}",
        run.stderr
    );
    let fresh = dir.join("fresh.gif");
    render_to(&fresh, false);

    let set_s = set.to_str().unwrap();
    let report = eval_report(
        &dir,
        &["--carry-theta", "--offline", set_s, "--online", set_s],
    );
    let this = (report["trajectories"].as_array().unwrap().iter())
        .find(|t| t["source"].as_str().unwrap().ends_with("online_001.csv"))
        .unwrap();
    assert_eq!(this["continued"], serde_json::Value::Bool(true));
    let com = com_of(&this["frames"][0]);

    // Where the scene of this push puts the table's points (the camera fits the whole push).
    let mut scene = SceneFrames::new(state_of(&push), SIZE, false, Theme::Dark);
    scene.show(0);
    scene.draw();
    let object = scene.state().recording().unwrap().trajectory.frames[0].object;
    let want = scene.pixel_of(object.point_in_world(Point2::from(com)));
    let marker = first_com_marker(&carried);
    assert!(
        distance(marker, want) <= 2.0,
        "carried: the COM marker at {marker:?}, eval --carry-theta's θ at {want:?}"
    );
    let marker = first_com_marker(&fresh);
    assert!(
        distance(marker, want) > 5.0,
        "without --carry-theta it starts elsewhere: {marker:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_shifted_start_is_where_eval_start_com_shift_starts() {
    let dir = temp_dir("render", "shift");
    let out = dir.join("shifted.gif");
    let run = pushlab(&[
        "render",
        recording().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--size",
        "320x200",
        "--frames",
        "0..2",
        "--layers",
        "com",
        "--start-com-shift",
        "0.04,-0.03",
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let report = eval_report(
        &dir,
        &[
            "--start-com-shift",
            "0.04,-0.03",
            "--online",
            recording().to_str().unwrap(),
        ],
    );
    let com = com_of(&report["trajectories"][0]["frames"][0]);
    let mut scene = SceneFrames::new(state(), SIZE, false, Theme::Dark);
    scene.show(0);
    scene.draw();
    let object = scene.state().recording().unwrap().trajectory.frames[0].object;
    let want = scene.pixel_of(object.point_in_world(Point2::from(com)));
    let unshifted = scene
        .pixel_of(object.point_in_world(Point2::from(scene.state().theta().unwrap().com_offset)));
    let marker = first_com_marker(&out);
    assert!(
        distance(marker, want) <= 2.0 && distance(want, unshifted) > 5.0,
        "the COM marker at {marker:?}, eval's shifted θ at {want:?}, unshifted at {unshifted:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A push longer than the app learns on the UI thread in one jump (10,000 frames): the render
/// starting past that point waits for the app's worker, so its first frame shows θ learned up to
/// there — where `eval --per-frame` has it — not θ_online(0).
#[test]
fn a_render_starting_far_into_a_long_push_shows_theta_learned_up_to_there() {
    let dir = temp_dir("render", "long");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    std::fs::copy(
        root.join(SET).join("setting.json"),
        dir.join("setting.json"),
    )
    .unwrap();
    let mut csv = String::from("time,robot_x,robot_y,object_x,object_y,object_theta\n");
    for k in 0..10_200 {
        let t = k as f64 / 10.0;
        let (x, yaw) = (0.05 * (t / 5.0).sin(), 0.1 * (t / 7.0).sin());
        csv.push_str(&format!(
            "{t},{},-0.25,{},0.1,{}\n",
            x,
            x + 0.01 * t.cos(),
            1.6 + yaw
        ));
    }
    let push = dir.join("long_000.csv");
    std::fs::write(&push, csv).unwrap();
    let out = dir.join("far.gif");
    let run = pushlab(&[
        "render",
        push.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--size",
        "320x200",
        "--fps",
        "10",
        "--frames",
        "10100..10102",
        "--layers",
        "com",
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let report = eval_report(&dir, &["--online", push.to_str().unwrap()]);
    let com = com_of(&report["trajectories"][0]["frames"][10_100]);
    let mut scene = SceneFrames::new(state_of(&push), SIZE, false, Theme::Dark);
    scene.draw();
    let start = scene.state().theta().unwrap().com_offset;
    let object = scene.state().recording().unwrap().trajectory.frames[10_100].object;
    let want = scene.pixel_of(object.point_in_world(Point2::from(com)));
    let unlearned = scene.pixel_of(object.point_in_world(Point2::from(start)));
    let marker = first_com_marker(&out);
    assert!(
        distance(marker, want) <= 2.0 && distance(want, unlearned) > 5.0,
        "the COM marker at {marker:?}, eval's θ at frame 10100 at {want:?}, θ_online(0)'s at {unlearned:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_render_stopped_or_refused_leaves_no_file() {
    let dir = temp_dir("render", "stopped");
    let out = dir.join("push.gif");
    let options = RenderOptions {
        size: SIZE,
        ..RenderOptions::default()
    };
    let error = render(state(), &out, &options, &mut |done, _| done < 5).unwrap_err();
    assert_eq!(error.to_string(), "stopped: nothing written");
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "nothing left in the folder"
    );
    // MP4 without ffmpeg: said, naming the program, and nothing written.
    let mp4 = dir.join("push.mp4");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_pushlab"))
        .args(["render", recording().to_str().unwrap(), "--out"])
        .arg(&mp4)
        .env("PUSHLAB_FFMPEG", dir.join("no-ffmpeg-here"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("ffmpeg") && stderr.contains("no-ffmpeg-here"),
        "{stderr}"
    );
    // A folder that does not exist is said before any frame is drawn.
    let nowhere = dir.join("no-such-folder").join("push.gif");
    let started = std::time::Instant::now();
    let error = render(state(), &nowhere, &options, &mut |_, _| true).unwrap_err();
    assert!(
        error.to_string().ends_with("no-such-folder does not exist"),
        "{error}"
    );
    assert!(started.elapsed().as_secs() < 30, "said at once");
    // An extension that says no format, and a layer that does not exist.
    let run = pushlab(&["render", recording().to_str().unwrap(), "--out", "push.avi"]);
    assert!(run.stderr.contains(".gif, .mp4 or .webm"), "{}", run.stderr);
    let run = pushlab(&[
        "render",
        recording().to_str().unwrap(),
        "--out",
        "push.gif",
        "--layers",
        "com,pusher",
    ]);
    assert!(
        run.stderr
            .contains("--layers: no layer `pusher`: the layers are"),
        "{}",
        run.stderr
    );
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    assert!(!Path::new("push.gif").exists() && !Path::new("push.avi").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
