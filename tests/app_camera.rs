//! The camera panel, driven as a user drives the window: a sample push with a 30 Hz camera beside it
//! (a native image sequence, `online_000.images/`), whose every image shows a white disc where the
//! pusher was when it was taken. Scrubbing must show the image taken at or before the frame's time,
//! with its offset; a corrupt image shows an error and the next one plays; a hidden camera stays
//! hidden after a restart.

use crate::common;

use std::path::Path;
use std::time::Duration;

use common::{copy_of_sample_set, harness};
use egui_kittest::kittest::Queryable;
use pushlab::app::state::SessionCommand;
use pushlab::app::state::playback::cameras::CameraCommand;
use pushlab::app::state::playback::timeline::TimelineCommand;
use pushlab::app::state::{AppState, Command};
use pushlab::app::{PushlabApp, initial_state};

/// The camera's clock: image `k` is taken at `FIRST_S + k / RATE_HZ` on the recording's clock,
/// off the poses' 10 Hz grid.
const FIRST_S: f64 = 0.013;
const RATE_HZ: f64 = 30.0;
const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;
const CORRUPT: usize = 62;

/// Where a point of the table (metres) is in an image: 100 pixels a metre, the table's origin at
/// the centre, y up.
fn pixel_of(x: f64, y: f64) -> (f64, f64) {
    (80.0 + 100.0 * x, 60.0 - 100.0 * y)
}

/// The pusher's position at `t`, interpolated between the CSV's rows.
fn pusher_at(rows: &[[f64; 3]], t: f64) -> (f64, f64) {
    let after = rows.partition_point(|r| r[0] <= t).clamp(1, rows.len() - 1);
    let (a, b) = (rows[after - 1], rows[after]);
    let s = ((t - a[0]) / (b[0] - a[0])).clamp(0.0, 1.0);
    (a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2]))
}

/// Writes `online_000.images/`: one PNG per image with a disc of radius 5 at the pusher, frame
/// `CORRUPT` a file that is not a PNG. Returns the number of images.
fn write_camera(set: &Path) -> (usize, Vec<[f64; 3]>) {
    let csv = std::fs::read_to_string(set.join("online_000.csv")).expect("csv");
    let rows: Vec<[f64; 3]> = (csv.lines().skip(1))
        .map(|line| {
            let v: Vec<f64> = line
                .split(',')
                .map(|x| x.parse().expect("number"))
                .collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    let dir = set.join("online_000.images");
    std::fs::create_dir_all(&dir).expect("images dir");
    let last = rows.last().expect("rows")[0];
    let count = ((last - FIRST_S) * RATE_HZ) as usize + 1;
    let mut index = String::from("time,file\n");
    for k in 0..count {
        let t = FIRST_S + k as f64 / RATE_HZ;
        let file = format!("{k:04}.png");
        index.push_str(&format!("{t},{file}\n"));
        if k == CORRUPT {
            std::fs::write(dir.join(&file), b"\x89PNG\r\n\x1a\nnot a png at all").expect("write");
            continue;
        }
        let (px, py) = pusher_at(&rows, t);
        let (cx, cy) = pixel_of(px, py);
        let image = image::RgbImage::from_fn(WIDTH, HEIGHT, |x, y| {
            let d = (x as f64 + 0.5 - cx).hypot(y as f64 + 0.5 - cy);
            if d <= 5.0 {
                image::Rgb([255, 255, 255])
            } else {
                image::Rgb([20, 20, 30])
            }
        });
        image.save(dir.join(&file)).expect("png");
    }
    std::fs::write(dir.join("frames.csv"), index).expect("frames.csv");
    (count, rows)
}

/// The centroid of the image's bright pixels.
fn disc_centre(image: &pushlab_core::recording::camera::RgbaImage) -> (f64, f64) {
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
    for y in 0..image.height {
        for x in 0..image.width {
            if image.pixel(x, y).is_some_and(|p| p[0] > 128) {
                sx += x as f64 + 0.5;
                sy += y as f64 + 0.5;
                n += 1.0;
            }
        }
    }
    assert!(n > 0.0, "no disc in the image");
    (sx / n, sy / n)
}

fn select_online_000(state: &mut AppState) {
    let id = (state.session().recordings())
        .find(|(_, r)| r.name == "online_000")
        .map(|(id, _)| id)
        .expect("online_000 is open");
    state.apply(Command::Session(SessionCommand::Select(id)));
}

/// Seeks to `frame` and draws until its camera image is decoded and shown.
fn scrub_to(harness: &mut egui_kittest::Harness<'_, PushlabApp>, frame: usize) {
    let state = &mut harness.state_mut().state;
    state.apply(Command::Timeline(TimelineCommand::SeekTo(frame)));
    let time = state.timeline().frame_time();
    harness.run_steps(1);
    (harness.state().state.cameras()).wait_for_shown(time, Duration::from_secs(30));
    harness.run_steps(2);
}

#[test]
fn scrubbing_shows_the_image_taken_at_the_frame_with_its_offset() {
    let set = copy_of_sample_set("box1-paper-center-front", "app-camera");
    let (count, rows) = write_camera(&set);
    let mut state = initial_state(std::slice::from_ref(&set), Default::default());
    select_online_000(&mut state);
    assert_eq!(
        state.cameras().streams().len(),
        1,
        "{:?}",
        state.session().problems
    );
    let mut harness = harness(PushlabApp::new(state), 0.05);

    for frame in [37, 5, 80, 37] {
        scrub_to(&mut harness, frame);
        let state = &harness.state().state;
        let time = state.timeline().frame_time();
        // The image at or before the frame's time, counted independently of the app.
        let k = ((time - FIRST_S) * RATE_HZ + 1e-9).floor() as usize;
        let taken = FIRST_S + k as f64 / RATE_HZ;
        let offset_ms = ((taken - time) * 1e3).round();
        let caption = format!("frame {} of {count} · {offset_ms:+.0} ms", k + 1);
        harness.get_by_label_contains(&caption);
        // What the panel shows was taken at that time: the disc is where the pusher was then.
        let shown = state.cameras().shown(time);
        let image = shown[0]
            .decoded
            .clone()
            .expect("decoded")
            .expect("readable");
        let (px, py) = pusher_at(&rows, taken);
        let expected = pixel_of(px, py);
        let found = disc_centre(&image);
        let miss = (found.0 - expected.0).hypot(found.1 - expected.1);
        assert!(
            miss < 0.75,
            "frame {frame}: disc at {found:?}, pusher at {expected:?}"
        );
        // Where the pusher was one camera frame earlier is measurably elsewhere, or the check
        // above could not tell a frame off by one.
        let (qx, qy) = pusher_at(&rows, taken - 1.0 / RATE_HZ);
        let earlier = pixel_of(qx, qy);
        if (earlier.0 - expected.0).hypot(earlier.1 - expected.1) > 2.0 {
            assert!((found.0 - earlier.0).hypot(found.1 - earlier.1) > 1.0);
        }
    }
}

#[test]
fn a_corrupt_image_is_named_in_the_panel_and_the_next_one_plays() {
    let set = copy_of_sample_set("box1-paper-center-front", "app-camera-corrupt");
    write_camera(&set);
    let mut state = initial_state(std::slice::from_ref(&set), Default::default());
    select_online_000(&mut state);
    let mut harness = harness(PushlabApp::new(state), 0.05);
    // Frame 21 (2.1 s) shows image 62 (2.080 s), the corrupt one; frame 22 (2.2 s) image 65.
    scrub_to(&mut harness, 21);
    harness.get_by_label_contains("frame 63 of");
    harness.get_by_label_contains("frame cannot be shown: not a readable png image");
    scrub_to(&mut harness, 22);
    harness.get_by_label_contains("frame 66 of");
    let state = &harness.state().state;
    let image = state.cameras().shown(state.timeline().frame_time())[0]
        .decoded
        .clone();
    assert!(
        matches!(image, Some(Ok(_))),
        "the next image plays: {image:?}"
    );
    assert!(
        harness
            .query_by_label_contains("frame cannot be shown")
            .is_none(),
        "the error went with its frame"
    );
}

#[test]
fn a_hidden_camera_stays_hidden_after_a_restart() {
    let set = copy_of_sample_set("box1-paper-center-front", "app-camera-hidden");
    write_camera(&set);
    let mut state = initial_state(std::slice::from_ref(&set), Default::default());
    select_online_000(&mut state);
    let name = state.cameras().streams()[0].name.clone();
    assert!(state.cameras().any_shown());
    state.apply(Command::Camera(CameraCommand::Show {
        name: name.clone(),
        shown: false,
    }));
    let mut window = harness(PushlabApp::new(state), 0.05);
    scrub_to(&mut window, 10);
    assert!(window.query_by_label_contains("frame 30 of").is_none());
    let persisted = window.state().state.persisted();
    assert!(persisted.hidden_cameras.contains(&name));

    let mut state = initial_state(std::slice::from_ref(&set), persisted);
    select_online_000(&mut state);
    assert!(!state.cameras().any_shown(), "still hidden after a restart");
    state.apply(Command::Camera(CameraCommand::Show { name, shown: true }));
    let mut harness = harness(PushlabApp::new(state), 0.05);
    scrub_to(&mut harness, 10);
    harness.get_by_label_contains("frame 30 of");
}
