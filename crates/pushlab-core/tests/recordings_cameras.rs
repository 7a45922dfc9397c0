//! Cameras of ROS 2 bags, on fixtures written by Python's `rosbags` and Pillow
//! (`tests/bags/make_camera_fixtures.py`) whose every image shows a white disc where the pusher was
//! at the image's stamp: the frame shown at a time decodes to the image taken at that time, for a
//! JPEG, an rgb8 and a mono16 camera; a corrupt JPEG, a truncated raw image and an unknown encoding
//! are errors of their own frames, naming what is wrong, and the other frames still read.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::PathBuf;
use std::sync::Arc;

use pushlab_core::recording::NoProgress;
use pushlab_core::recording::bag::{self, BagImport, ImportOptions, TopicSpec};
use pushlab_core::recording::camera::{CameraStream, RgbaImage, decode};

const JPEG: &str = "/camera/image/compressed";
const RGB8: &str = "/camera/image_raw";
const MONO16: &str = "/depth/image_mono16";

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/bags")
        .join(name)
}

fn spec(text: &str) -> TopicSpec {
    text.parse().expect("a topic")
}

/// push.csv's pusher positions: (time, x, y).
fn pusher_rows() -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(fixture("push.csv")).expect("push.csv");
    (text.lines().skip(1))
        .map(|line| {
            let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

/// Where the script drew the pusher at `t`: push.csv interpolated, then its metres-to-pixels map.
fn drawn_at(rows: &[[f64; 3]], t: f64) -> (f64, f64) {
    let after = rows.partition_point(|r| r[0] <= t).clamp(1, rows.len() - 1);
    let (a, b) = (rows[after - 1], rows[after]);
    let s = (t - a[0]) / (b[0] - a[0]);
    let (x, y) = (a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2]));
    (80.0 + 1000.0 * (x + 0.05), 60.0 - 1000.0 * y)
}

/// The centroid of the image's bright pixels (red channel over half).
fn disc_centre(image: &RgbaImage) -> (f64, f64) {
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
    for y in 0..image.height {
        for x in 0..image.width {
            if image.pixel(x, y).unwrap()[0] > 128 {
                sx += x as f64 + 0.5;
                sy += y as f64 + 0.5;
                n += 1.0;
            }
        }
    }
    assert!(n > 50.0, "a disc in the image");
    (sx / n, sy / n)
}

fn import(name: &str, cameras: &[&str]) -> BagImport {
    let cameras: Vec<String> = cameras.iter().map(|c| (*c).to_owned()).collect();
    bag::import_with_cameras(
        &fixture(name),
        &spec("/pusher/pose"),
        &spec("/object/pose"),
        &cameras,
        ImportOptions::default(),
        &NoProgress,
    )
    .expect("the fixture imports")
}

fn stream<'a>(import: &'a BagImport, name: &str) -> &'a Arc<CameraStream> {
    (import.pushes[0].cameras.iter())
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("{name} is a camera of the push"))
}

#[test]
fn the_image_shown_at_a_time_was_taken_at_that_time() {
    let import = import("camera", &[JPEG, RGB8, MONO16]);
    assert_eq!(import.pushes.len(), 1);
    let push = &import.pushes[0];
    assert_eq!(push.cameras.len(), 3);
    let rows = pusher_rows();
    // The push's clock starts at its first frame, the bag's first pose (stamp 0 in push.csv).
    assert_eq!(push.trajectory.frames[0].time, 0.0);
    for (name, first, rate, count) in [
        (JPEG, 0.013, 25.0, 30),
        (RGB8, 0.007, 10.0, 12),
        (MONO16, 0.007, 10.0, 12),
    ] {
        let camera = stream(&import, name);
        assert_eq!(camera.len(), count, "{name}");
        let mut reader = camera.reader();
        for t in [0.05_f64, 0.2, 0.37, 0.61, 0.9, 1.19] {
            let k = ((t - first) * rate + 1e-9).floor() as usize;
            let frame = camera.frame_at(t).expect("a frame before t");
            assert_eq!(frame, k, "{name} at {t}");
            let taken = first + k as f64 / rate;
            assert!(
                (camera.times()[frame] - taken).abs() < 1e-6,
                "{name}: the header stamp is its time"
            );
            let image = decode(&reader.read(frame).expect("readable")).expect("decodes");
            assert_eq!((image.width, image.height), (160, 120));
            let found = disc_centre(&image);
            let drawn = drawn_at(&rows, taken);
            let miss = (found.0 - drawn.0).hypot(found.1 - drawn.1);
            assert!(
                miss < 0.6,
                "{name} at {t}: disc at {found:?}, drawn at {drawn:?}"
            );
            // One camera frame earlier the pusher was visibly elsewhere, so an off-by-one frame
            // would fail the check above.
            let before = drawn_at(&rows, taken - 1.0 / rate);
            if frame > 0 {
                assert!(
                    (before.0 - drawn.0).hypot(before.1 - drawn.1) > 1.5,
                    "{name}: motion"
                );
            }
        }
        assert_eq!(
            camera.frame_at(first - 0.001),
            None,
            "nothing before the first image"
        );
    }
}

#[test]
fn a_raw_image_decodes_to_its_pixels() {
    let import = import("camera", &[RGB8, MONO16]);
    let rgb = decode(&stream(&import, RGB8).reader().read(4).unwrap()).unwrap();
    // The script writes gray g as (g, g / 2, g): channel order is kept.
    let (u, v) = disc_centre(&rgb);
    assert_eq!(rgb.pixel(u as u32, v as u32), Some([255, 127, 255, 255]));
    assert_eq!(rgb.pixel(0, 0), Some([24, 12, 24, 255]));
    // mono16 (depth, IR) is shown from its darkest value (1000) to its brightest (60000).
    let mono = decode(&stream(&import, MONO16).reader().read(4).unwrap()).unwrap();
    let (u, v) = disc_centre(&mono);
    assert_eq!(mono.pixel(u as u32, v as u32), Some([255, 255, 255, 255]));
    assert_eq!(mono.pixel(0, 0), Some([0, 0, 0, 255]));
}

#[test]
fn a_bad_frame_is_an_error_of_its_own_and_the_others_read() {
    let import = import("camera_bad", &[JPEG, RGB8, "/camera/yuv"]);
    let jpeg = stream(&import, JPEG);
    let mut reader = jpeg.reader();
    for k in [0, 1, 3, 4] {
        decode(&reader.read(k).unwrap()).unwrap_or_else(|e| panic!("frame {k}: {e}"));
    }
    let corrupt = decode(&reader.read(2).unwrap()).unwrap_err().to_string();
    assert!(
        corrupt.starts_with("not a readable jpeg image"),
        "{corrupt}"
    );

    let rgb = stream(&import, RGB8);
    let mut reader = rgb.reader();
    let truncated = (reader.read(3))
        .map_err(|e| e.to_string())
        .and_then(|image| decode(&image).map_err(|e| e.to_string()))
        .unwrap_err();
    assert!(
        truncated.contains("rgb8 pixels of 160×120 with 480 bytes a row need 57600 bytes, but the frame holds 28800"),
        "{truncated}"
    );
    assert!(
        decode(&reader.read(4).unwrap()).is_ok(),
        "the next frame reads"
    );

    let yuv = stream(&import, "/camera/yuv");
    let unknown = yuv.reader().read(0).unwrap_err().to_string();
    assert!(
        unknown.contains("`yuv422` is not one pushlab reads"),
        "{unknown}"
    );
}

/// The fuzz target's promise on stable Rust, over its seeds (`fuzz/seeds/image_message/`, written
/// by the fixture script): every prefix of each message and every message with one byte changed
/// is read, decoded and described as either kind without a panic, and a frame accepted holds the
/// pixels its size says.
#[test]
fn cut_or_changed_image_messages_are_refused_never_a_panic() {
    use pushlab_core::recording::bag::{ImageKind, decode_image_message, describe_image_message};
    let seeds = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/image_message");
    let mut seen = 0;
    let mut check = |data: &[u8]| {
        for kind in [ImageKind::Compressed, ImageKind::Raw] {
            let _ = describe_image_message(kind, data);
            if let Ok((_, encoded)) = decode_image_message(kind, data)
                && let Ok(image) = decode(&encoded)
            {
                assert_eq!(
                    image.pixels.len(),
                    4 * (image.width * image.height) as usize
                );
            }
        }
        seen += 1;
    };
    let mut state = 0x2545_F491_4F6C_DD1D_u64;
    for entry in std::fs::read_dir(&seeds).expect("the fuzz seeds") {
        let bytes = std::fs::read(entry.unwrap().path()).unwrap();
        let step = (bytes.len() / 300).max(1);
        for len in (0..bytes.len()).step_by(step) {
            check(&bytes[..len]);
        }
        for _ in 0..200 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let mut changed = bytes.clone();
            // The header and the fields before the pixels are where a change misleads a reader.
            let at = (state as usize) % changed.len().min(96);
            changed[at] = (state >> 32) as u8;
            check(&changed);
        }
    }
    assert!(seen > 1000, "the seeds were read: {seen}");
}
