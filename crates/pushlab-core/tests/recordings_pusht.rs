//! Push-T datasets written by the real gym-pusht environment (`tests/pusht/make_fixtures.py`):
//! the imported poses against the environment's own state (`truth.json`, float64 from pymunk).

use std::path::{Path, PathBuf};

use nalgebra::{Point2, Vector2};
use pushlab_core::geometry::PushT;
use pushlab_core::recording::dataset::{self, DatasetChoice, ObjectSource};
use pushlab_core::recording::{LoadError, NoProgress, RecordingSet, load_paths};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/pusht")
}

fn truth() -> serde_json::Value {
    let text = std::fs::read_to_string(fixtures().join("truth.json")).expect("truth.json");
    serde_json::from_str(&text).expect("valid JSON")
}

/// The largest distance (metres) between each imported frame and pymunk's state of that frame, the
/// block's local origin moved to the T's area centroid, and the largest yaw difference.
fn worst_errors(set: &RecordingSet, scale: f64) -> (f64, f64, f64) {
    let truth = truth();
    let episodes = truth["episodes"].as_array().expect("episodes");
    assert_eq!(set.recordings.len(), episodes.len());
    let (mut pusher, mut object, mut yaw) = (0.0f64, 0.0f64, 0.0f64);
    for (recording, episode) in set.recordings.iter().zip(episodes) {
        let frames = &recording.trajectory.frames;
        let agent = episode["agent"].as_array().expect("agent");
        assert_eq!(frames.len(), agent.len(), "{}", recording.name);
        for (k, frame) in frames.iter().enumerate() {
            let at = |key: &str, i: usize| episode[key][k][i].as_f64().expect("number");
            let angle = episode["angle"][k].as_f64().expect("angle");
            let origin = Vector2::new(at("block", 0), at("block", 1));
            let centroid =
                origin + nalgebra::Rotation2::new(angle) * Vector2::from(PushT::CENTROID_PX);
            let agent = Point2::new(at("agent", 0), at("agent", 1)) * scale;
            pusher = pusher.max((frame.robot - agent).norm());
            object = object.max((frame.object.position.coords - centroid * scale).norm());
            let turn = frame.object.yaw - angle;
            yaw = yaw
                .max((turn - (turn / std::f64::consts::TAU).round() * std::f64::consts::TAU).abs());
            assert!((frame.time - k as f64 / 10.0).abs() < 1e-6);
        }
    }
    (pusher, object, yaw)
}

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

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("mkdir");
    for entry in std::fs::read_dir(from).expect("read_dir").flatten() {
        let path = entry.path();
        if path.is_dir() {
            copy_dir(&path, &to.join(entry.file_name()));
        } else {
            std::fs::copy(&path, to.join(entry.file_name())).expect("copy");
        }
    }
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

    let meta = zarr.join("data/action/.zarray");
    let text = std::fs::read_to_string(&meta).expect("meta");
    std::fs::write(&meta, text.replace("<f4", "<c8")).expect("write");
    std::fs::copy(fixtures().join("replay.zarr/data/state/1.0"), &chunk).expect("restore");
    let error = dataset::read_table(&zarr, &NoProgress).expect_err("dtype");
    assert!(matches!(error, LoadError::Dataset { .. }));
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
        // The renders as a video feature, listed with where its files are; not read here.
        assert_eq!(
            table.cameras,
            vec![("observation.image".to_owned(), "video 96×96×3".to_owned())]
        );
        let template = if version == "v2.1" {
            "videos/chunk-{episode_chunk:03d}/{video_key}/episode_{episode_index:06d}.mp4"
        } else {
            "videos/{video_key}/chunk-{chunk_index:03d}/file-{file_index:03d}.mp4"
        };
        assert_eq!(
            table.videos,
            vec![dataset::VideoFeature {
                name: "observation.image".into(),
                path_template: template.into(),
            }]
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
