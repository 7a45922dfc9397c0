//! What the fuzz targets share: each reader run on the fuzzer's bytes under the made-up file name it
//! needs, and the promises checked on whatever it accepts. Every target is one call into here, so
//! that the targets differ only in the reader they exercise.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use pushlab_core::geometry::Outline;
use pushlab_core::labels::{export, file as labels_file};
use pushlab_core::learn::OnlineConfig;
use pushlab_core::model::{ContactGeometry, ObjectMotion, OnlineParams, Sample, SampleInput};
use pushlab_core::model_file::ModelFile;
use pushlab_core::recording::mit_push::import_bytes;
use pushlab_core::recording::native::{parse_csv, parse_setting};
use pushlab_core::trajectory::Trajectory;

pub mod datasets;

/// The parameters an MIT file's name carries; the readers need one to import.
const MIT_STEM: &str = "motion_surface=abs_shape=tri1_a=0_v=20_i=0.000_s=0.500_t=0.000";

/// What every accepted trajectory promises: strictly increasing time and finite poses.
fn check_trajectory(trajectory: &Trajectory) {
    let frames = &trajectory.frames;
    assert!(frames.windows(2).all(|w| w[1].time > w[0].time));
    assert!(frames.iter().all(|f| {
        f.object.yaw.is_finite()
            && f.object.position.iter().all(|c| c.is_finite())
            && f.robot.iter().all(|c| c.is_finite())
    }));
}

/// The native CSV reader and the `setting.json` reader.
pub fn csv(data: &[u8]) {
    if let Ok(parsed) = parse_csv(data, Path::new("fuzz.csv")) {
        assert!(parsed.trajectory.frames.len() >= 2);
        check_trajectory(&parsed.trajectory);
    }
    let _ = parse_setting(data, Path::new("setting.json"));
}

/// The MIT Push Dataset importer (parse, clean, resample) for a file of this extension.
pub fn mit_push(data: &[u8], extension: &str) {
    let name = format!("{MIT_STEM}.{extension}");
    if let Ok(push) = import_bytes(data, Path::new(&name)) {
        check_trajectory(&push.trajectory);
    }
}

/// The labels file: what is accepted writes back to the same labels, and exports without a panic.
pub fn labels(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let path = Path::new("pushlab-labels.json");
    let Ok(set) = labels_file::parse(text, path) else {
        return;
    };
    let written = labels_file::to_json(&set);
    let back = labels_file::parse(&written, path).expect("pushlab reads what it writes");
    assert_eq!(back, set);
    let times: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    let _ = export::to_csv(&set, &times);
}

/// The model file: what is accepted writes back to the same model, and predicts and learns online
/// with a finite `θ` (a non-finite step is never taken).
pub fn model(data: &[u8]) {
    let path = Path::new("model.json");
    let Ok(file) = ModelFile::from_json(path, data) else {
        return;
    };
    let written = file.to_json(path).expect("an accepted model writes");
    let back = ModelFile::from_json(path, &written).expect("pushlab reads what it writes");
    assert_eq!(back, file);
    let Ok(outline) = Outline::rectangle(0.1, 0.2) else {
        return;
    };
    let geometry = Arc::new(ContactGeometry::new(&outline, 0.005));
    let Ok(learner) = file.combined.on_object(Some(&geometry)) else {
        return;
    };
    let sample = Sample {
        input: SampleInput {
            robot_in_object: [-0.06, 0.01],
            robot_motion_in_object: [0.004, 0.0005],
        },
        target: ObjectMotion {
            translation: [0.003, 0.0002],
            rotation: 0.01,
        },
        frame: 0,
    };
    let theta0 = learner.theta0();
    for lr in [0.005, 1e6] {
        let config = OnlineConfig {
            lr,
            ..OnlineConfig::default()
        };
        let step = learner.online_step(&sample, &theta0, &config.descent());
        let theta: OnlineParams = step.theta_after;
        assert!(
            theta.com_offset.iter().all(|c| c.is_finite()) && theta.h.is_finite(),
            "θ after one step at lr {lr}: {theta:?}"
        );
    }
}

/// The ROS 2 bag importer (MCAP records, chunk decompression and CRCs, CDR, cleaning and
/// resampling) on one `.mcap` file, with a PoseStamped-style pusher topic and a `/tf` object (the
/// seeds' topics), and the topic listing.
pub fn mcap(data: &[u8]) {
    use pushlab_core::recording::bag::{self, ImportOptions, TopicSpec};
    let path = Path::new("fuzz.mcap");
    let spec = |text: &str| -> TopicSpec { text.parse().expect("a valid topic spec") };
    for (pusher, object) in [("/pusher/pose", "/object/pose"), ("/tf:pusher_tip", "/tf:box")] {
        let options = ImportOptions {
            rate_hz: None,
            split_gap_s: Some(0.5),
        };
        if let Ok(import) = bag::import_bytes(data, path, &spec(pusher), &spec(object), options) {
            assert!(!import.pushes.is_empty());
            for push in &import.pushes {
                check_trajectory(&push.trajectory);
            }
        }
    }
    let _ = bag::topics_bytes(data, path);
}

/// A camera message (`sensor_msgs/msg/CompressedImage` or `Image`, CDR) read as either kind, its
/// frame decoded to RGBA and its start described for listing: every refusal an error, never a
/// panic, and an accepted frame as large as it says.
pub fn image_message(data: &[u8]) {
    use pushlab_core::recording::bag::{ImageKind, decode_image_message, describe_image_message};
    use pushlab_core::recording::camera::decode;
    for kind in [ImageKind::Compressed, ImageKind::Raw] {
        let _ = describe_image_message(kind, data);
        if let Ok((_, encoded)) = decode_image_message(kind, data)
            && let Ok(image) = decode(&encoded)
        {
            assert_eq!(
                image.pixels.len(),
                4 * image.width as usize * image.height as usize
            );
        }
    }
}

/// Push-T's zarr replay buffers (`.zarray` metadata, blosc, zstd and LZ4 chunks, `episode_ends`,
/// the images): one file of the fixture buffer replaced by the input (see [`datasets`]).
pub fn zarr(data: &[u8]) {
    datasets::zarr(data);
}

/// LeRobot datasets v2.1 and v3.0 (`meta/info.json`, `meta/episodes.jsonl`, the episode metadata
/// and data parquet files): one file of a fixture dataset replaced by the input (see [`datasets`]).
pub fn lerobot(data: &[u8]) {
    datasets::lerobot(data);
}
