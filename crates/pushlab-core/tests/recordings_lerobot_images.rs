//! A LeRobot dataset that keeps its pictures inside its parquet files, as `lerobot/pusht_image`
//! does (the `observation.image` feature of dtype `image`, a PNG in each row): each episode has it
//! as a camera, and frame k of that camera is, pixel for pixel, the render the replay buffer's
//! `data/img` holds for the same episode and frame (`tests/pusht/make_fixtures.py` wrote both from
//! one gym-pusht run; PNG is lossless), in v2.1's file per episode and v3.0's shared file. A cell that is not a picture is that frame's error, naming
//! the file and the row; the other frames play on.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::pusht_common;

use std::path::Path;

use pushlab_core::recording::camera::{CameraStream, decode};
use pushlab_core::recording::{NoProgress, RecordingSet, dataset};
use pusht_common::{copy_dir, fixtures};

fn open(path: &Path) -> RecordingSet {
    dataset::open_with(path, None, None, &NoProgress).expect("opens")
}

/// Frame `index` of `camera` as RGBA bytes.
fn pixels(camera: &CameraStream, index: usize) -> Vec<u8> {
    let image = camera.reader().read(index).expect("reads");
    decode(&image).expect("decodes").pixels.clone()
}

#[test]
fn pictures_in_the_parquet_files_are_each_episodes_camera_frame_for_frame() {
    // v2.1: a file per episode; v3.0: both episodes in one file, the second from row 24.
    for layout in ["lerobot-v2.1-images", "lerobot-v3.0-images"] {
        pictures_are_the_renders(layout);
    }
}

fn pictures_are_the_renders(layout: &str) {
    let set = open(&fixtures().join(layout));
    let replay = open(&fixtures().join("replay.zarr"));
    assert_eq!(
        set.recordings.len(),
        2,
        "{layout}: the fixture's two episodes"
    );
    let table = dataset::read_table(&fixtures().join(layout), &NoProgress).unwrap();
    assert_eq!(
        table.cameras,
        [(
            "observation.image".to_owned(),
            "images 96×96×3 in parquet".to_owned()
        )]
    );
    for (episode, recording) in set.recordings.iter().enumerate() {
        assert_eq!(recording.cameras.len(), 1, "episode {episode}: one camera");
        let camera = &recording.cameras[0];
        assert_eq!(camera.name, "observation.image");
        let renders = &replay.recordings[episode].cameras[0];
        assert_eq!(camera.len(), renders.len());
        let times = camera.times().iter().zip(renders.times());
        assert!(times.clone().all(|(a, b)| (a - b).abs() < 1e-6));
        // Read backwards too: a reader that keeps one row group must find any frame.
        let order: Vec<usize> = (0..camera.len()).chain((0..camera.len()).rev()).collect();
        let mut reader = camera.reader();
        for k in order {
            let image = reader.read(k).expect("reads");
            let shown = decode(&image).expect("decodes");
            assert_eq!((shown.width, shown.height), (96, 96));
            assert!(
                shown.pixels == pixels(renders, k),
                "{layout} episode {episode} frame {k}: not the render"
            );
        }
        // Neighbouring renders differ (the pusher moves), so a frame off by one would fail above.
        assert_ne!(pixels(camera, 0), pixels(camera, camera.len() - 1));
        let past = camera
            .reader()
            .read(camera.len())
            .expect_err("past the end");
        assert!(past.to_string().contains("past the episode's"), "{past}");
    }
}

#[test]
fn a_cell_that_is_not_a_picture_is_that_frames_error_naming_the_file() {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("pushlab-lerobot-images-broken");
    let _ = std::fs::remove_dir_all(&out);
    let dir = out.join("lerobot-v2.1-images");
    copy_dir(&fixtures().join("lerobot-v2.1-images"), &dir);
    // Every PNG signature in episode 0's file overwritten (snappy keeps the first few as literals and
    // copies the rest from them): the bytes are there, not a picture.
    let file = dir.join("data/chunk-000/episode_000000.parquet");
    let mut bytes = std::fs::read(&file).unwrap();
    let signature = b"\x89PNG\r\n\x1a\n";
    let mut spoiled = 0;
    for at in 0..bytes.len().saturating_sub(signature.len()) {
        if &bytes[at..at + signature.len()] == signature {
            bytes[at + 1] = b'X';
            spoiled += 1;
        }
    }
    assert!(spoiled > 0);
    std::fs::write(&file, &bytes).unwrap();
    let set = open(&dir);
    let mut reader = set.recordings[0].cameras[0].reader();
    for k in 0..24 {
        let error = reader.read(k).expect_err("not a picture").to_string();
        assert!(
            error.contains(&format!(
                "episode_000000.parquet: row {k}'s `observation.image` holds"
            )) && error.contains("neither PNG nor JPEG"),
            "{error}"
        );
    }
    // The other episode's file is untouched: its frames play.
    set.recordings[1].cameras[0]
        .reader()
        .read(3)
        .expect("reads");
    let _ = std::fs::remove_dir_all(&out);
}
