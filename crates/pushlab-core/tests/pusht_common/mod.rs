//! What the Push-T dataset tests share: the gym-pusht fixtures, pymunk's truth and comparisons
//! against it, a folder copier for breaking copies.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use nalgebra::{Point2, Vector2};
use pushlab_core::geometry::PushT;
use pushlab_core::recording::RecordingSet;

pub fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/pusht")
}

pub fn truth() -> serde_json::Value {
    let text = std::fs::read_to_string(fixtures().join("truth.json")).expect("truth.json");
    serde_json::from_str(&text).expect("valid JSON")
}

/// The largest distance (metres) between each imported frame and pymunk's state of that frame, the
/// block's local origin moved to the T's area centroid, and the largest yaw difference.
pub fn worst_errors(set: &RecordingSet, scale: f64) -> (f64, f64, f64) {
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

pub fn copy_dir(from: &Path, to: &Path) {
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
