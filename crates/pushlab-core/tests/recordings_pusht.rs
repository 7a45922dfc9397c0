//! Push-T datasets written by the real gym-pusht environment (`tests/pusht/make_fixtures.py`):
//! the imported poses against the environment's own state (`truth.json`, float64 from pymunk).

use crate::pusht_common;

use std::path::PathBuf;

use pushlab_core::recording::dataset::{self, DatasetChoice, ObjectSource};
use pushlab_core::recording::{DatasetError, NoProgress, load_paths};
use pusht_common::{copy_dir, fixtures, truth, worst_errors};

#[test]
fn a_replay_buffer_imports_to_the_environments_state_within_0_1_mm() {
    let zarr = fixtures().join("replay.zarr");
    let report = load_paths(std::slice::from_ref(&zarr));
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let set = &report.sets[0];
    let (pusher, object, yaw) = worst_errors(set, 0.001);
    assert!(
        pusher < 1e-4 && object < 1e-4 && yaw < 1e-5,
        "{pusher} {object} {yaw}"
    );
    // The setting: the T at 1 mm/px, its 15 mm pusher, gym-pusht's COM (0, 30/7) px off the centroid.
    let setting = &set.setting;
    assert!((setting.pusher_radius - 0.015).abs() < 1e-12);
    let com = setting.com_offset.expect("known");
    assert!(com[0] == 0.0 && (com[1] - 0.030 / 7.0).abs() < 1e-12);
    assert_eq!(setting.sample_rate_hz, Some(10.0));
    assert_eq!(set.recordings[2].name, "episode_002");
    // Every episode moved the T: the pushes touched it.
    for recording in &set.recordings {
        let frames = &recording.trajectory.frames;
        let moved = frames[frames.len() - 1].object.position - frames[0].object.position;
        assert!(moved.norm() > 0.02, "{}: {moved}", recording.name);
    }
}

#[test]
fn a_scale_and_a_range_of_episodes_are_applied() {
    let zarr = fixtures().join("replay.zarr");
    let table = dataset::read_table(&zarr, &NoProgress).expect("reads");
    assert_eq!(table.episodes.len(), 8);
    assert_eq!(table.feature_list(), "action (2), keypoint (16), state (5)");
    assert_eq!(
        table.cameras,
        vec![("img".to_owned(), "images 96×96×3".to_owned())]
    );
    let mut choice = dataset::choice::suggest(&table).expect("Push-T's layout");
    assert_eq!(
        choice.object,
        ObjectSource::Pose(dataset::Columns::new("state", 2))
    );
    choice.metres_per_px = 0.002;
    let set = dataset::to_set(&zarr, &table, &choice, Some(6..20)).expect("imports");
    assert_eq!(set.recordings.len(), 2);
    assert!((set.setting.pusher_radius - 0.030).abs() < 1e-12);
    let first = &set.recordings[0].trajectory.frames[0];
    let agent = &truth()["episodes"][6]["agent"][0];
    let x = agent[0].as_f64().expect("x") * 0.002;
    assert!((first.robot.x - x).abs() < 2e-4, "{} {x}", first.robot.x);
    let error = dataset::to_set(&zarr, &table, &choice, Some(8..9)).expect_err("past the end");
    assert!(
        error
            .to_string()
            .ends_with("no episodes in 8..9; the dataset has 8 (0..8)"),
        "{error}"
    );
}

/// A copy of the fixture buffer in a fresh folder, for breaking.
fn copy_of_buffer(name: &str) -> PathBuf {
    let out = std::env::temp_dir().join(format!("pushlab-pusht-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    copy_dir(&fixtures().join("replay.zarr"), &out.join("replay.zarr"));
    out.join("replay.zarr")
}

#[test]
fn broken_buffers_are_errors_naming_the_file_and_the_problem() {
    let zarr = copy_of_buffer("broken");
    let chunk = zarr.join("data/state/1.0");
    let mut bytes = std::fs::read(&chunk).expect("chunk");
    bytes.truncate(40);
    std::fs::write(&chunk, bytes).expect("write");
    let message = dataset::read_table(&zarr, &NoProgress)
        .expect_err("cut")
        .to_string();
    assert!(message.contains("data/state/1.0: blosc:"), "{message}");

    // A chunk file removed is refused by name, never read as the fill value (zeros: the pusher and
    // the object at the origin for 64 frames).
    std::fs::remove_file(&chunk).expect("remove");
    let message = dataset::read_table(&zarr, &NoProgress)
        .expect_err("missing")
        .to_string();
    assert!(
        message.contains("data/state/1.0: chunk file missing: rows 64..128 of the array"),
        "{message}"
    );

    let meta = zarr.join("data/action/.zarray");
    let text = std::fs::read_to_string(&meta).expect("meta");
    std::fs::write(&meta, text.replace("<f4", "<c8")).expect("write");
    std::fs::copy(fixtures().join("replay.zarr/data/state/1.0"), &chunk).expect("restore");
    let error = dataset::read_table(&zarr, &NoProgress).expect_err("dtype");
    assert!(matches!(error, DatasetError::Problem { .. }));
    let message = error.to_string();
    assert!(
        message.contains("data/action/.zarray: field `dtype`: \"<c8\""),
        "{message}"
    );

    std::fs::write(&meta, text).expect("restore");
    let table = dataset::read_table(&zarr, &NoProgress).expect("restored");
    let choice = DatasetChoice {
        pusher: "action:1".parse().expect("columns"),
        object: "keypoints:state".parse().expect("source"),
        metres_per_px: 0.001,
    };
    let message = dataset::to_set(&zarr, &table, &choice, None)
        .expect_err("narrow")
        .to_string();
    assert!(
        message.ends_with(
            "feature `action` has 2 value(s) per frame, expected 2 (x, y) from column 1"
        ),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(zarr.parent().expect("parent"));
}

#[test]
fn a_replay_buffers_images_are_each_episodes_camera_read_when_shown() {
    use pushlab_core::recording::camera::{ImageFormat, decode};
    let zarr = fixtures().join("replay.zarr");
    let set = dataset::open_with(&zarr, None, None, &NoProgress).expect("opens");
    // The whole image array read the other way, value by value, as the numeric features are.
    let array = dataset::zarr::ZarrArray::open(&zarr.join("data/img")).expect("img");
    let all = array.read_f64(&NoProgress).expect("every value");
    let frame_len = 96 * 96 * 3;
    let mut first_row = 0;
    for recording in &set.recordings {
        assert_eq!(recording.cameras.len(), 1, "{}", recording.name);
        let camera = &recording.cameras[0];
        assert_eq!(camera.name, "img");
        assert_eq!(camera.len(), recording.trajectory.len());
        assert_eq!(camera.times()[1], 0.1);
        let mut reader = camera.reader();
        // The last frame (in the episode's last chunk) and the first (another chunk for most).
        for index in [camera.len() - 1, 0] {
            let image = reader.read(index).expect("a frame");
            assert!(matches!(
                image.format,
                ImageFormat::Raw {
                    width: 96,
                    height: 96,
                    ..
                }
            ));
            let row = first_row + index;
            let expected: Vec<u8> = (all[row * frame_len..(row + 1) * frame_len].iter())
                .map(|&v| v as u8)
                .collect();
            assert!(image.bytes == expected, "{} frame {index}", recording.name);
            // gym-pusht's render: a light arena with the grey T and the blue agent on it.
            let rgba = decode(&image).expect("decodes");
            let distinct: std::collections::HashSet<_> = rgba.pixels.chunks(4).collect();
            assert!(distinct.len() > 3, "a blank frame");
        }
        first_row += camera.len();
    }
    assert_eq!(first_row, 192);
}

#[test]
fn an_image_array_split_within_a_frame_is_an_error_naming_its_zarray() {
    let zarr = copy_of_buffer("split-images");
    let meta = zarr.join("data/img/.zarray");
    let text = std::fs::read_to_string(&meta).expect("meta");
    let split = text.replacen("96,", "48,", 1);
    assert_ne!(split, text);
    std::fs::write(&meta, split).expect("write");
    let message = dataset::open_with(&zarr, None, None, &NoProgress)
        .expect_err("split")
        .to_string();
    assert!(
        message.contains("data/img/.zarray: field `shape`:")
            && message
                .contains("split a frame; pushlab reads image arrays chunked along time only"),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(zarr.parent().expect("parent"));
}
