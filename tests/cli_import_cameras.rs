//! `pushlab import --camera` and `pushlab validate` on the camera bags of
//! crates/pushlab-core/tests/bags (written by Python's `rosbags` and Pillow): each camera written
//! beside the push as an image sequence, JPEG frames byte for byte as the bag holds them, raw frames
//! as PNG with the same pixels; the listing of camera topics; the refusals.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::cli_common;

use std::path::{Path, PathBuf};

use cli_common::{pushlab, temp_dir};
use pushlab_core::recording::NoProgress;
use pushlab_core::recording::bag::{self, ImportOptions};
use pushlab_core::recording::camera::decode;
use pushlab_core::recording::native::images::read_cameras;

const JPEG: &str = "/camera/image/compressed";
const RGB8: &str = "/camera/image_raw";

fn bag(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("crates/pushlab-core/tests/bags")
        .join(name)
}

fn setting(dir: &Path) -> String {
    let path = dir.join("box.json");
    std::fs::write(
        &path,
        r#"{"name": "bag-box", "object": {"shape": "box", "width": 0.1, "length": 0.12},
            "pusher_radius": 0.005, "trajectories": []}"#,
    )
    .unwrap();
    path.display().to_string()
}

fn import(bag: &Path, dir: &Path, cameras: &[&str]) -> cli_common::Run {
    let out = dir.join("set").display().to_string();
    let (bag, setting) = (bag.display().to_string(), setting(dir));
    let mut args = vec![
        "import",
        &bag,
        "--pusher",
        "/pusher/pose",
        "--object",
        "/object/pose",
        "--setting",
        &setting,
        "--out",
        &out,
    ];
    for camera in cameras {
        args.extend(["--camera", camera]);
    }
    pushlab(&args)
}

#[test]
fn each_camera_is_written_beside_the_push_as_the_bag_holds_it() {
    let dir = temp_dir("pushlab-import-cameras", "written");
    let run = import(&bag("camera"), &dir, &[JPEG, RGB8]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let csv = dir.join("set/camera.csv");
    let images = dir.join("set/camera.images");
    // Two cameras: one folder each, named by the topic.
    let rows = |camera: &str| {
        let text = std::fs::read_to_string(images.join(camera).join("frames.csv")).unwrap();
        text.lines().skip(1).count()
    };
    assert_eq!(rows("camera_image_compressed"), 30);
    assert_eq!(rows("camera_image_raw"), 12);

    // The set's cameras, read back, against the bag's own frames.
    let written = read_cameras(&csv).expect("the set's cameras read");
    let from_bag = bag::import_with_cameras(
        &bag("camera"),
        &"/pusher/pose".parse().unwrap(),
        &"/object/pose".parse().unwrap(),
        &[JPEG.to_owned(), RGB8.to_owned()],
        ImportOptions::default(),
        &NoProgress,
    )
    .unwrap();
    let push = &from_bag.pushes[0];
    for (folder, topic) in [
        ("camera_image_compressed", JPEG),
        ("camera_image_raw", RGB8),
    ] {
        let set = written.iter().find(|c| c.name == folder).expect(folder);
        let original = push.cameras.iter().find(|c| c.name == topic).expect(topic);
        assert_eq!(set.len(), original.len(), "{folder}");
        for (a, b) in set.times().iter().zip(original.times()) {
            assert!((a - b).abs() < 1e-9, "{folder}: {a} vs {b}");
        }
        let (mut from_set, mut from_bag) = (set.reader(), original.reader());
        for k in [0, 5, original.len() - 1] {
            let (stored, message) = (from_set.read(k).unwrap(), from_bag.read(k).unwrap());
            if topic == JPEG {
                assert_eq!(
                    stored.bytes, message.bytes,
                    "frame {k}: copied byte for byte"
                );
            } else {
                assert!(
                    stored.bytes.starts_with(b"\x89PNG"),
                    "raw frames are written as PNG"
                );
            }
            let (a, b) = (decode(&stored).unwrap(), decode(&message).unwrap());
            assert_eq!(a.pixels, b.pixels, "{folder} frame {k}: same pixels");
        }
    }
}

#[test]
fn validate_lists_camera_topics_with_encoding_size_and_count() {
    let path = bag("camera").display().to_string();
    let run = pushlab(&["validate", &path]);
    for line in [
        "/camera/image/compressed sensor_msgs/msg/CompressedImage, 30 messages, 25.0 Hz, camera: jpeg 160×120",
        "/camera/image_raw sensor_msgs/msg/Image, 12 messages, 10.0 Hz, camera: rgb8 160×120",
        "/depth/image_mono16 sensor_msgs/msg/Image, 12 messages, 10.0 Hz, camera: mono16 160×120",
        "5 topic(s), 2 readable as a pusher or object pose, 3 camera(s)",
    ] {
        assert!(run.stdout.contains(line), "{line}\n{}", run.stdout);
    }
}

#[test]
fn bad_camera_frames_are_left_out_and_counted_and_bad_topics_refused() {
    let dir = temp_dir("pushlab-import-cameras", "bad");
    let run = import(&bag("camera_bad"), &dir, &[JPEG, RGB8, "/camera/yuv"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let warnings = format!("{}{}", run.stdout, run.stderr);
    assert!(
        warnings.contains("camera /camera/image_raw: 1 frame(s) could not be read and were left out; the first: frame 3 (0.700 s): rgb8 pixels"),
        "{warnings}"
    );
    assert!(
        warnings.contains("camera /camera/yuv: 3 frame(s) could not be read and were left out; the first: frame 0 (0.100 s): its encoding `yuv422` is not one pushlab reads"),
        "{warnings}"
    );

    let dir = temp_dir("pushlab-import-cameras", "refused");
    let run = import(&bag("camera"), &dir, &["/nope"]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("no topic `/nope` in the bag; its topics: /camera/image/compressed (sensor_msgs/msg/CompressedImage, 30 messages)"), "{}", run.stderr);
    let run = import(&bag("camera"), &dir, &["/object/pose"]);
    assert_eq!(run.code, 1);
    assert!(
        run.stderr.contains("topic `/object/pose` carries geometry_msgs/msg/PoseStamped (encoding cdr), not camera frames"),
        "{}",
        run.stderr
    );
    assert!(!dir.join("set").exists(), "nothing written when refused");
}
