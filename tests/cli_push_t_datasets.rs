//! Push-T datasets through the command line: `pushlab validate` lists a replay buffer's episodes
//! and features, `pushlab import` writes one push per episode at a scale, never touching the input,
//! and refuses what it cannot do with a message naming it.

#![allow(clippy::unwrap_used)]

use crate::cli_common;

use std::path::{Path, PathBuf};

use cli_common::{Run, pushlab, temp_dir};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/pushlab-core/tests/pusht")
}

/// A folder that does not exist yet, in a fresh temporary folder: where `import --out` writes.
fn new_set_dir(name: &str) -> PathBuf {
    temp_dir("pushlab-cli-pusht", name).join("set")
}

fn text(output: &Run) -> String {
    format!("{}{}", output.stdout, output.stderr)
}

#[test]
fn validate_lists_a_replay_buffers_episodes_and_features() {
    let zarr = fixtures().join("replay.zarr");
    let output = pushlab(&["validate", zarr.to_str().unwrap()]);
    let out = text(&output);
    assert!(output.code == 0, "{out}");
    assert!(
        out.contains("zarr replay buffer, 8 episode(s), 192 frames at 10 Hz; features: action (2), keypoint (16), state (5); cameras: img (images 96×96×3)"),
        "{out}"
    );
    assert!(out.contains(": 7: 24 frames, 2.30 s"), "{out}");
    assert!(
        out.contains("pusher state, object pose:state:2 (Push-T's layout), 0.001 m/px"),
        "{out}"
    );
    assert!(
        out.contains("8 recording(s) loaded (0 with warnings), 0 error(s)"),
        "{out}"
    );
}

#[test]
fn import_writes_one_push_per_episode_at_the_scale_asked() {
    let zarr = fixtures().join("replay.zarr");
    let before = std::fs::read(zarr.join("data/state/0.0")).unwrap();
    let out_dir = new_set_dir("import");
    let output = pushlab(&[
        "import",
        zarr.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
        "--scale",
        "0.002",
        "--episodes",
        "2..5",
    ]);
    let out = text(&output);
    assert!(output.code == 0, "{out}");
    assert!(out.contains("episode_002.csv: 24 frames, 2.30 s"), "{out}");
    assert!(out.contains("3 episode(s) of"), "{out}");
    let setting: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("setting.json")).unwrap())
            .unwrap();
    assert_eq!(setting["object"]["preset"], "push-t");
    assert_eq!(setting["object"]["metres_per_px"], 0.002);
    assert_eq!(setting["pusher_radius"], 0.03);
    assert_eq!(setting["trajectories"][0]["episode"], 2);
    assert!(out_dir.join("episode_004.csv").is_file() && !out_dir.join("episode_005.csv").exists());
    assert_eq!(
        std::fs::read(zarr.join("data/state/0.0")).unwrap(),
        before,
        "input untouched"
    );
    // The buffer's images: each push's camera, 24 PNG frames and their times beside its CSV.
    assert!(out.contains("camera img: 24 frame(s) -> "), "{out}");
    let images = out_dir.join("episode_003.images");
    let frames = std::fs::read_to_string(images.join("frames.csv")).unwrap();
    assert_eq!(frames.lines().count(), 25, "{frames}");
    assert!(
        frames.lines().nth(2).unwrap().starts_with("0.1,"),
        "{frames}"
    );
    let png = std::fs::read(images.join("000023.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    // The written set loads back, its cameras with it.
    let output = pushlab(&["validate", out_dir.to_str().unwrap()]);
    assert!(output.code == 0, "{}", text(&output));
    // Again without --overwrite: refused; a range past the end: refused, naming the count.
    let again = pushlab(&[
        "import",
        zarr.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert!(
        text(&again).contains("pass --overwrite"),
        "{}",
        text(&again)
    );
    let past = new_set_dir("past");
    let output = pushlab(&[
        "import",
        zarr.to_str().unwrap(),
        "--out",
        past.to_str().unwrap(),
        "--episodes",
        "8..12",
    ]);
    assert_eq!(output.code, 1);
    assert!(
        text(&output).contains("no episodes in 8..12; the dataset has 8 (0..8)"),
        "{}",
        text(&output)
    );
    let output = pushlab(&[
        "import",
        zarr.to_str().unwrap(),
        "--out",
        "x",
        "--episodes",
        "5..2",
    ]);
    assert_eq!(output.code, 2);
    assert!(
        text(&output).contains("holds no episode"),
        "{}",
        text(&output)
    );
    std::fs::remove_dir_all(&out_dir).ok();
}

#[test]
fn validate_lists_a_lerobot_datasets_episodes_and_features() {
    let dir = fixtures().join("lerobot-v3.0");
    let output = pushlab(&["validate", dir.to_str().unwrap()]);
    let out = text(&output);
    assert!(output.code == 0, "{out}");
    assert!(
        out.contains(
            "LeRobot dataset v3.0, 8 episode(s), 192 frames at 10 Hz; features: action (2), \
             episode_index (1), frame_index (1), index (1), next.reward (1), \
             observation.environment_state (16), observation.state (2), task_index (1), \
             timestamp (1); cameras: observation.image (video 96×96×3)\n"
        ),
        "{out}"
    );
    assert!(out.contains(": 7: 24 frames, 2.30 s"), "{out}");
    assert!(
        out.contains(
            "pusher observation.state, object keypoints:observation.environment_state (Push-T's \
             layout), 0.001 m/px"
        ),
        "{out}"
    );
    assert!(
        out.contains("8 recording(s) loaded (0 with warnings), 0 error(s)"),
        "{out}"
    );
}

#[test]
fn import_writes_a_lerobot_datasets_episodes_as_pushes() {
    let dir = fixtures().join("lerobot-v2.1");
    let data = dir.join("data/chunk-000/episode_000005.parquet");
    let before = std::fs::read(&data).unwrap();
    let out_dir = new_set_dir("import-lerobot");
    let output = pushlab(&[
        "import",
        dir.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
        "--episodes",
        "5..8",
    ]);
    let out = text(&output);
    assert!(output.code == 0, "{out}");
    assert!(out.contains("episode_005.csv: 24 frames, 2.30 s"), "{out}");
    assert!(out.contains("3 episode(s) of"), "{out}");
    let setting: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("setting.json")).unwrap())
            .unwrap();
    assert_eq!(setting["object"]["preset"], "push-t");
    assert_eq!(setting["dataset_format"], "LeRobot dataset v2.1");
    assert_eq!(
        setting["dataset_object"],
        "keypoints:observation.environment_state"
    );
    assert_eq!(setting["trajectories"][2]["episode"], 7);
    // Named after the folder, its version whole.
    assert_eq!(setting["name"], "lerobot-v2.1");
    assert!(out_dir.join("episode_007.csv").is_file() && !out_dir.join("episode_004.csv").exists());
    assert_eq!(std::fs::read(&data).unwrap(), before, "input untouched");
    let output = pushlab(&["validate", out_dir.to_str().unwrap()]);
    assert!(output.code == 0, "{}", text(&output));
    std::fs::remove_dir_all(&out_dir).ok();
}

/// `from` copied to `to`, folders and all.
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

#[test]
fn validate_says_a_damaged_datasets_error_once_and_its_disagreeing_totals_as_a_note() {
    let zarr = temp_dir("pushlab-cli-pusht", "damaged").join("replay.zarr");
    copy_dir(&fixtures().join("replay.zarr"), &zarr);
    let chunk = zarr.join("data/state/0.0");
    let bytes = std::fs::read(&chunk).unwrap();
    std::fs::write(&chunk, &bytes[..40]).unwrap();
    let output = pushlab(&["validate", zarr.to_str().unwrap()]);
    let out = text(&output);
    assert_eq!(output.code, 1, "{out}");
    assert_eq!(out.matches("data/state/0.0: blosc:").count(), 1, "{out}");
    assert!(
        out.contains("0 recording(s) loaded (0 with warnings), 1 error(s)"),
        "{out}"
    );

    let lerobot = temp_dir("pushlab-cli-pusht", "totals").join("lerobot-v2.1");
    copy_dir(&fixtures().join("lerobot-v2.1"), &lerobot);
    let info_path = lerobot.join("meta/info.json");
    let mut info: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&info_path).unwrap()).unwrap();
    info["total_frames"] = 5.into();
    std::fs::write(&info_path, info.to_string()).unwrap();
    let output = pushlab(&["validate", lerobot.to_str().unwrap()]);
    let out = text(&output);
    assert_eq!(output.code, 0, "{out}");
    assert!(
        out.contains(&format!(
            "note: {}: meta/info.json says total_frames 5 but the files hold 192 frames: the \
             files are read",
            lerobot.display()
        )),
        "{out}"
    );
}
