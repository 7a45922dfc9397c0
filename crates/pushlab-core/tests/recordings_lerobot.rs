//! LeRobot datasets written by the real gym-pusht environment (`tests/pusht/make_fixtures.py`), v2.1
//! and v3.0: the imported poses against the environment's own state and the replay buffer's
//! recordings; broken datasets as errors naming the file and the field; and the videos as each
//! episode's camera — they hold the same 96 × 96 renders as the replay buffer's `data/img` (v3.0
//! one AV1 file of every episode as LeRobot encodes it, each episode at its `from_timestamp`; v2.1
//! one H.264 file per episode), so the video frame shown at a time must decode to the render taken
//! then: close to it, and closer than to the renders before and after it, so that a frame off by
//! one or an episode started at the wrong place fails. Decoding needs ffmpeg; without it that test
//! says so and skips.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::pusht_common;
use crate::skip;

use std::path::{Path, PathBuf};

use pushlab_core::recording::camera::{CameraStream, decode, find_ffmpeg};
use pushlab_core::recording::dataset::{self, ObjectSource};
use pushlab_core::recording::{NoProgress, RecordingSet, load_paths};
use pusht_common::{copy_dir, fixtures, worst_errors};

/// Each frame of `a` against the same frame of `b`: the largest pusher and object distance
/// (metres) and yaw difference.
fn largest_differences(a: &RecordingSet, b: &RecordingSet) -> (f64, f64, f64) {
    assert_eq!(a.recordings.len(), b.recordings.len());
    let (mut pusher, mut object, mut yaw) = (0.0f64, 0.0f64, 0.0f64);
    for (ra, rb) in a.recordings.iter().zip(&b.recordings) {
        assert_eq!(ra.name, rb.name);
        assert_eq!(ra.trajectory.len(), rb.trajectory.len(), "{}", ra.name);
        for (fa, fb) in ra.trajectory.frames.iter().zip(&rb.trajectory.frames) {
            assert!((fa.time - fb.time).abs() < 1e-6, "{} {}", fa.time, fb.time);
            pusher = pusher.max((fa.robot - fb.robot).norm());
            object = object.max((fa.object.position - fb.object.position).norm());
            yaw = yaw.max((fa.object.yaw - fb.object.yaw).abs());
        }
    }
    (pusher, object, yaw)
}

#[test]
fn lerobot_datasets_import_to_the_environments_state_as_the_replay_buffer_does() {
    let replay = dataset::open_with(&fixtures().join("replay.zarr"), None, None, &NoProgress)
        .expect("the buffer opens");
    for version in ["v2.1", "v3.0"] {
        let dir = fixtures().join(format!("lerobot-{version}"));
        assert!(dataset::is_dataset(&dir), "{version}");
        // The parquet files are what the progress bar counts.
        let parquet = dataset::bytes(&dir);
        assert!(parquet > 20_000 && parquet < 60_000, "{version}: {parquet}");
        let table = dataset::read_table(&dir, &NoProgress).expect("reads");
        assert_eq!(
            table.format,
            dataset::DatasetFormat::LeRobot(version.into())
        );
        assert_eq!(table.fps, 10.0);
        assert_eq!(table.episodes.len(), 8, "{version}");
        assert!(table.episodes.iter().all(|rows| rows.len() == 24));
        assert_eq!(table.episodes[3], 72..96);
        assert_eq!(
            table.feature_list(),
            "action (2), episode_index (1), frame_index (1), index (1), next.reward (1), \
             observation.environment_state (16), observation.state (2), task_index (1), \
             timestamp (1)"
        );
        // The renders as a video feature, with each episode's file (read in
        // recordings_lerobot_videos).
        assert_eq!(
            table.cameras,
            vec![("observation.image".to_owned(), "video 96×96×3".to_owned())]
        );
        let (template, second) = if version == "v2.1" {
            (
                "videos/chunk-{episode_chunk:03d}/{video_key}/episode_{episode_index:06d}.mp4",
                "videos/chunk-000/observation.image/episode_000001.mp4",
            )
        } else {
            (
                "videos/{video_key}/chunk-{chunk_index:03d}/file-{file_index:03d}.mp4",
                "videos/observation.image/chunk-000/file-000.mp4",
            )
        };
        let video = &table.videos[0];
        assert_eq!(table.videos.len(), 1);
        assert_eq!(
            (video.name.as_str(), video.path_template.as_str()),
            ("observation.image", template)
        );
        assert_eq!(video.episodes.len(), 8);
        assert!(
            video.episodes[1].file.ends_with(second),
            "{:?}",
            video.episodes[1]
        );
        let times = table.times.as_ref().expect("the timestamp column");
        assert!((times[30] - 0.6).abs() < 1e-6, "{}", times[30]);
        // Push-T's pre-selection: the agent, and the T's 8 corners registered to a pose.
        let choice = dataset::choice::suggest(&table).expect("Push-T's layout");
        assert_eq!(
            choice.object,
            ObjectSource::Keypoints("observation.environment_state".into())
        );
        let report = load_paths(std::slice::from_ref(&dir));
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        let set = &report.sets[0];
        let (pusher, object, yaw) = worst_errors(set, 0.001);
        eprintln!(
            "{version} against truth.json: pusher {pusher:.1e} m, T {object:.1e} m, yaw {yaw:.1e} rad"
        );
        assert!(
            pusher < 1e-4 && object < 1e-4 && yaw < 1e-5,
            "{version}: {pusher} {object} {yaw}"
        );
        let mut worst_residual = 0.0f64;
        for recording in &set.recordings {
            let entry = recording.entry.as_ref().expect("an entry");
            let residual = entry.extra["keypoint_rms_residual_m"]
                .as_f64()
                .expect("the fit's residual");
            assert!(residual < 1e-4, "{}: {residual} m", recording.name);
            worst_residual = worst_residual.max(residual);
            assert!(recording.warnings.is_empty(), "{:?}", recording.warnings);
        }
        assert_eq!(
            set.setting.extra["dataset_format"],
            format!("LeRobot dataset {version}")
        );
        assert_eq!(set.setting.sample_rate_hz, Some(10.0));
        // The same episodes as the replay buffer's, the T's pose from its corners this time.
        let (pusher, object, yaw) = largest_differences(set, &replay);
        eprintln!(
            "{version} against the replay buffer: pusher {pusher:.1e} m, T {object:.1e} m, yaw \
             {yaw:.1e} rad; keypoint fit {worst_residual:.1e} m RMS at worst"
        );
        assert!(
            pusher < 1e-6 && object < 1e-6 && yaw < 1e-6,
            "{version}: {pusher} {object} {yaw}"
        );
    }
}

/// A copy of a LeRobot fixture in a fresh folder under the target's temporary folder, for breaking.
fn copy_of_lerobot(version: &str, test: &str) -> PathBuf {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("pushlab-lerobot-{test}"));
    let _ = std::fs::remove_dir_all(&out);
    let dir = out.join(format!("lerobot-{version}"));
    copy_dir(&fixtures().join(format!("lerobot-{version}")), &dir);
    dir
}

/// `dir`'s `meta/info.json` changed by `change`.
fn edit_info(dir: &Path, change: impl FnOnce(&mut serde_json::Value)) {
    let path = dir.join("meta/info.json");
    let mut info: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).expect("info")).expect("JSON");
    change(&mut info);
    std::fs::write(&path, serde_json::to_string_pretty(&info).expect("JSON")).expect("write");
}

fn read_error(dir: &Path) -> String {
    dataset::read_table(dir, &NoProgress)
        .expect_err("broken")
        .to_string()
}

#[test]
fn broken_lerobot_datasets_are_errors_naming_the_file_and_the_field() {
    // A data file cut short.
    let dir = copy_of_lerobot("v3.0", "truncated");
    let data = dir.join("data/chunk-000/file-000.parquet");
    let bytes = std::fs::read(&data).expect("data");
    std::fs::write(&data, &bytes[..bytes.len() / 2]).expect("write");
    let message = read_error(&dir);
    assert!(
        message.contains("data/chunk-000/file-000.parquet: not a readable parquet file: "),
        "{message}"
    );
    // Its footer intact, its pages not: a corrupt column chunk, named the same way.
    let mut garbled = bytes.clone();
    for byte in &mut garbled[8..bytes.len() / 3] {
        *byte = byte.wrapping_add(77);
    }
    std::fs::write(&data, &garbled).expect("write");
    let message = read_error(&dir);
    assert!(
        message.contains("data/chunk-000/file-000.parquet: not a readable parquet file: "),
        "{message}"
    );
    std::fs::write(&data, &bytes).expect("restore");

    // meta/info.json without its frame rate.
    edit_info(&dir, |info| {
        info.as_object_mut().expect("object").remove("fps");
    });
    let message = read_error(&dir);
    assert!(
        message.ends_with("meta/info.json: field `fps`: missing, expected the frames per second"),
        "{message}"
    );

    // A feature info.json lists that the parquet files do not hold.
    let dir = copy_of_lerobot("v2.1", "missing-feature");
    edit_info(&dir, |info| {
        info["features"]["observation.velocity"] =
            serde_json::json!({"dtype": "float32", "shape": [2], "names": null});
    });
    let message = read_error(&dir);
    assert!(
        message.contains(
            "data/chunk-000/episode_000000.parquet: no column `observation.velocity`, which \
             meta/info.json lists as a feature; the file's columns: observation.state, \
             observation.environment_state, action,"
        ),
        "{message}"
    );

    // A column of another width than info.json's shape, or of another type.
    edit_info(&dir, |info| {
        let features = info["features"].as_object_mut().expect("features");
        features.remove("observation.velocity");
        features["action"]["shape"] = serde_json::json!([3]);
    });
    let message = read_error(&dir);
    assert!(
        message.ends_with(
            "episode_000000.parquet: column `action` row 0 (counting from 0): 2 value(s), \
             expected 3 float32 value(s) (shape [3] in meta/info.json)"
        ),
        "{message}"
    );
    edit_info(&dir, |info| {
        info["features"]["action"]["shape"] = serde_json::json!([2]);
        info["features"]["next.done"]["dtype"] = "int64".into();
    });
    let message = read_error(&dir);
    assert!(
        message.ends_with(
            "column `next.done` row 0 (counting from 0): a boolean (false), expected 1 int64 \
             value(s) (shape [1] in meta/info.json)"
        ),
        "{message}"
    );

    // An episode's file holding another episode's rows: its rows are not where the index says.
    edit_info(&dir, |info| {
        info["features"]["next.done"]["dtype"] = "bool".into();
    });
    let chunk = dir.join("data/chunk-000");
    std::fs::copy(
        chunk.join("episode_000002.parquet"),
        chunk.join("episode_000001.parquet"),
    )
    .expect("copy");
    let message = read_error(&dir);
    assert!(
        message.ends_with(
            "episode_000001.parquet: column `episode_index` row 0 (counting from 0): 2, expected \
             1, the episode whose file this is"
        ),
        "{message}"
    );

    // A version pushlab does not read: recognised, refused naming the ones it reads.
    edit_info(&dir, |info| info["codebase_version"] = "v1.6".into());
    assert!(dataset::is_dataset(&dir));
    let message = read_error(&dir);
    assert!(
        message.ends_with(
            "meta/info.json: field `codebase_version`: \"v1.6\", pushlab reads LeRobot datasets \
             one of v2.0, v2.1, v3.0"
        ),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(dir.parent().expect("parent"));
}

/// Writes an uncompressed parquet file of whole-number columns with the parquet crate's writer.
fn write_parquet(path: &Path, columns: &[(&str, Vec<i64>)]) {
    use parquet::basic::{Repetition, Type as Physical};
    use parquet::data_type::Int64Type;
    use parquet::file::properties::WriterProperties;
    use parquet::file::writer::SerializedFileWriter;
    use parquet::schema::types::Type;
    use std::sync::Arc;
    let fields = (columns.iter())
        .map(|(name, _)| {
            Arc::new(
                Type::primitive_type_builder(name, Physical::INT64)
                    .with_repetition(Repetition::REQUIRED)
                    .build()
                    .expect("a column"),
            )
        })
        .collect();
    let schema = Type::group_type_builder("schema")
        .with_fields(fields)
        .build()
        .expect("a schema");
    std::fs::create_dir_all(path.parent().expect("folder")).expect("mkdir");
    let file = std::fs::File::create(path).expect("create");
    let properties = Arc::new(WriterProperties::builder().build());
    let mut writer = SerializedFileWriter::new(file, Arc::new(schema), properties).expect("writer");
    let mut group = writer.next_row_group().expect("row group");
    for (_, values) in columns {
        let mut column = group.next_column().expect("column").expect("one more");
        (column.typed::<Int64Type>())
            .write_batch(values, None, None)
            .expect("values");
        column.close().expect("close");
    }
    group.close().expect("close");
    writer.close().expect("close");
}

#[test]
fn a_v3_episode_whose_rows_are_apart_is_an_error_naming_the_data_file() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("pushlab-lerobot-apart");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("meta")).expect("mkdir");
    let info = serde_json::json!({
        "codebase_version": "v3.0",
        "fps": 10,
        "data_path": "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet",
        "features": {
            "episode_index": {"dtype": "int64", "shape": [1]},
            "frame_index": {"dtype": "int64", "shape": [1]},
        },
    });
    std::fs::write(dir.join("meta/info.json"), info.to_string()).expect("info");
    write_parquet(
        &dir.join("meta/episodes/chunk-000/file-000.parquet"),
        &[
            ("episode_index", vec![0, 1]),
            ("length", vec![2, 2]),
            ("data/chunk_index", vec![0, 0]),
            ("data/file_index", vec![0, 0]),
        ],
    );
    let data = dir.join("data/chunk-000/file-000.parquet");
    write_parquet(
        &data,
        &[
            ("episode_index", vec![0, 0, 1, 1]),
            ("frame_index", vec![0, 1, 0, 1]),
        ],
    );
    let table = dataset::read_table(&dir, &NoProgress).expect("in order");
    assert_eq!(table.episodes, vec![0..2, 2..4]);
    assert_eq!(table.times, None);
    write_parquet(
        &data,
        &[
            ("episode_index", vec![0, 1, 1, 0]),
            ("frame_index", vec![0, 0, 1, 1]),
        ],
    );
    let message = read_error(&dir);
    let apart = format!(
        "{}: episode_index 0 at row 3 (counting from 0), but episode 0's rows ended at row 0 of \
         {}; expected each episode's rows one after the other",
        data.display(),
        data.display()
    );
    assert_eq!(message, apart);
    // Rows that disagree with the metadata's length.
    write_parquet(
        &data,
        &[
            ("episode_index", vec![0, 1, 1, 1]),
            ("frame_index", vec![0, 0, 1, 2]),
        ],
    );
    let message = read_error(&dir);
    assert!(
        message.contains("file-000.parquet: episode 0 has 1 rows, but ")
            && message.ends_with("meta/episodes says its length is 2"),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_parquet_file_garbled_anywhere_is_an_error_never_a_panic() {
    let dir = copy_of_lerobot("v3.0", "garbled");
    let data = dir.join("data/chunk-000/file-000.parquet");
    let bytes = std::fs::read(&data).expect("data");
    let mut errors = 0;
    // Every 97th byte, and two where the parquet crate panics (its bit reader, its dictionary
    // decoder; found by garbling every byte of the fixture, 3438 of 24697 refused, none aborted).
    for at in (0..bytes.len()).step_by(97).chain([1619, 23261]) {
        let mut garbled = bytes.clone();
        garbled[at] ^= 0x5a;
        std::fs::write(&data, &garbled).expect("write");
        // Most garbled bytes are values: read, changed. The others: this file's error.
        if let Err(error) = dataset::read_table(&dir, &NoProgress) {
            let message = error.to_string();
            assert!(
                message.contains("file-000.parquet: "),
                "byte {at}: {message}"
            );
            errors += 1;
        }
    }
    assert!(errors > 0);
    let _ = std::fs::remove_dir_all(dir.parent().expect("parent"));
}

fn open(name: &str) -> RecordingSet {
    dataset::open_with(&fixtures().join(name), None, None, &NoProgress).expect("opens")
}

/// Frame `index` of `camera` as RGB bytes.
fn rgb(camera: &CameraStream, index: usize) -> Vec<u8> {
    let image = camera.reader().read(index).expect("reads");
    let rgba = decode(&image).expect("decodes");
    assert_eq!((rgba.width, rgba.height), (96, 96));
    (rgba.pixels.chunks_exact(4))
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect()
}

/// Root mean square difference of two images' bytes, levels of 255: a moved object (a few
/// hundred bytes far apart) weighs more than coding noise spread over every byte.
fn difference(a: &[u8], b: &[u8]) -> f64 {
    let total: u64 = (a.iter().zip(b))
        .map(|(&x, &y)| u64::from(x.abs_diff(y)).pow(2))
        .sum();
    (total as f64 / a.len() as f64).sqrt()
}

#[test]
fn each_episodes_video_frame_is_the_render_taken_at_its_time() {
    if find_ffmpeg().is_err() {
        skip::skip("ffmpeg on the PATH (apt install ffmpeg)");
        return;
    }
    let replay = open("replay.zarr");
    for layout in ["lerobot-v2.1", "lerobot-v3.0"] {
        let set = open(layout);
        assert_eq!(set.recordings.len(), replay.recordings.len());
        let (mut worst, mut told_apart): (f64, usize) = (0.0, 0);
        for (episode, recording) in set.recordings.iter().enumerate() {
            assert_eq!(recording.cameras.len(), 1, "{layout}: one video feature");
            let video = &recording.cameras[0];
            assert_eq!(video.name, "observation.image");
            let renders = &replay.recordings[episode].cameras[0];
            // LeRobot's timestamps are float32: the same times to a microsecond.
            let times = video.times().iter().zip(renders.times());
            assert!(
                times.len() == renders.len() && times.clone().all(|(a, b)| (a - b).abs() < 1e-6)
            );
            for frame in [0, 1, 11, 22, 23] {
                let shown = rgb(video, frame);
                let render = rgb(renders, frame);
                let taken = difference(&shown, &render);
                worst = worst.max(taken);
                assert!(
                    taken < 6.0,
                    "{layout} episode {episode} frame {frame}: {taken:.2}"
                );
                // Where the scene moved between two renders more than the coding noise, the frame shown is
                // nearer its own.
                for other in [frame.wrapping_sub(1), frame + 1] {
                    if other >= renders.len() {
                        continue;
                    }
                    let other_render = rgb(renders, other);
                    if difference(&render, &other_render) < 1.5 * taken {
                        continue;
                    }
                    let neighbour = difference(&shown, &other_render);
                    assert!(
                        neighbour > taken,
                        "{layout} episode {episode} frame {frame}: {taken:.2} from its render, \
                         {neighbour:.2} from frame {other}'s"
                    );
                    told_apart += 1;
                }
            }
        }
        assert!(
            told_apart >= 20,
            "{layout}: only {told_apart} frames told from a neighbour"
        );
        eprintln!(
            "{layout}: worst mean difference from the render {worst:.2} levels; \
             {told_apart} frames told from a neighbour"
        );
    }
}

#[test]
fn validate_lists_the_videos_as_cameras() {
    let path = fixtures().join("lerobot-v3.0");
    let table = dataset::read_table(&path, &NoProgress).expect("reads");
    assert_eq!(
        table.cameras,
        vec![("observation.image".to_owned(), "video 96×96×3".to_owned())]
    );
    let video = &table.videos[0];
    assert_eq!(video.size_px, (96, 96));
    // Each episode is 24 frames at 10 Hz: episode e starts 2.4 e s into the one file.
    assert_eq!(video.episodes.len(), 8);
    for (e, span) in video.episodes.iter().enumerate() {
        assert!(
            (span.from_s - e as f64 * 2.4).abs() < 1e-9,
            "{e}: {}",
            span.from_s
        );
    }
    assert!((video.episodes.iter()).all(|s| {
        s.file
            .ends_with("videos/observation.image/chunk-000/file-000.mp4")
    }));
}

#[test]
fn a_path_template_that_leaves_the_dataset_is_refused_naming_the_field() {
    let dir = copy_of_lerobot("v2.1", "escape");
    edit_info(&dir, |info| {
        info["data_path"] = "../../../../etc/episode_{episode_index:06d}.parquet".into();
    });
    let message = read_error(&dir);
    assert!(
        message.contains(
            "meta/info.json: field `data_path`: \"../../../../etc/episode_{episode_index:06d}.parquet\" \
             gives \"../../../../etc/episode_000000.parquet\", which leaves the dataset's folder"
        ),
        "{message}"
    );
    let dir = copy_of_lerobot("v3.0", "escape-video");
    edit_info(&dir, |info| {
        info["video_path"] = "/tmp/{video_key}/file-{file_index:03d}.mp4".into();
    });
    let message = read_error(&dir);
    assert!(
        message.contains("meta/info.json: field `video_path`: \"/tmp/"),
        "{message}"
    );
}

#[test]
fn totals_that_disagree_with_the_files_are_a_note_and_the_files_are_read() {
    let dir = copy_of_lerobot("v2.1", "totals");
    edit_info(&dir, |info| {
        info["total_episodes"] = serde_json::json!(1_000_000_000_000_000u64);
    });
    let table = dataset::read_table(&dir, &NoProgress).expect("the files are read");
    assert_eq!(table.episodes.len(), 8);
    assert_eq!(
        table.notes,
        vec![
            "meta/info.json says total_episodes 1000000000000000 but the files hold 8 episodes: \
             the files are read"
                .to_owned()
        ]
    );
    let untouched =
        dataset::read_table(&fixtures().join("lerobot-v2.1"), &NoProgress).expect("fixture");
    assert!(untouched.notes.is_empty(), "{:?}", untouched.notes);
}
