#![allow(clippy::unwrap_used)]

use super::*;
use crate::recording::ObjectShape;

fn topic(name: &str, type_name: &str, frames: &[&str]) -> TopicInfo {
    TopicInfo {
        topic: name.to_owned(),
        type_name: type_name.to_owned(),
        encoding: "cdr".to_owned(),
        count: 100,
        first_ns: 0,
        last_ns: 1_000_000_000,
        camera: None,
        child_frames: frames.iter().map(|f| (*f).to_owned()).collect(),
    }
}

const POSE: &str = "geometry_msgs/msg/PoseStamped";
const TF: &str = "tf2_msgs/msg/TFMessage";

fn spec(text: &str) -> Option<TopicSpec> {
    Some(text.parse().unwrap())
}

fn entered() -> Setting {
    let mut setting = Setting::of_object(
        "bench-box",
        ObjectShape::Box {
            width: 0.09,
            length: 0.06,
        },
        0.005,
    );
    setting.material = Some("abs".to_owned());
    setting
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pushlab-choice-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn names_that_say_their_role_are_preselected() {
    let topics = [
        topic("/camera/image", "sensor_msgs/msg/Image", &[]),
        topic("/object/pose", POSE, &[]),
        topic("/robot/pusher_tip", POSE, &[]),
        topic("/rosout", "rcl_interfaces/msg/Log", &[]),
    ];
    assert_eq!(
        suggest(&topics),
        (spec("/robot/pusher_tip"), spec("/object/pose"))
    );
}

#[test]
fn child_frames_of_tf_are_candidates_and_can_be_preselected() {
    let topics = [topic("/tf", TF, &["base_link", "tool0", "box_1"])];
    assert_eq!(
        candidates(&topics),
        vec![
            spec("/tf:base_link").unwrap(),
            spec("/tf:tool0").unwrap(),
            spec("/tf:box_1").unwrap()
        ]
    );
    // "tool0" is the only name that says pusher, "box_1" the only one that says object.
    assert_eq!(suggest(&topics), (spec("/tf:tool0"), spec("/tf:box_1")));
}

#[test]
fn frames_reached_through_tf_static_are_offered_on_the_moving_topic() {
    let topics = [
        topic("/object/pose", POSE, &[]),
        topic("/tf", TF, &["tool0"]),
        topic("/tf_static", TF, &["base_link", "tip"]),
    ];
    assert_eq!(
        candidates(&topics),
        vec![
            spec("/object/pose").unwrap(),
            spec("/tf:tool0").unwrap(),
            spec("/tf:base_link").unwrap(),
            spec("/tf:tip").unwrap()
        ]
    );
    // "tool0" and "tip" both say pusher: not obvious, so not chosen.
    assert_eq!(suggest(&topics), (None, spec("/object/pose")));
}

#[test]
fn nothing_is_guessed_when_names_are_ambiguous_or_silent() {
    let two_pushers = [
        topic("/pusher/pose", POSE, &[]),
        topic("/finger/pose", POSE, &[]),
        topic("/object/pose", POSE, &[]),
    ];
    assert_eq!(suggest(&two_pushers), (None, spec("/object/pose")));
    let silent = [topic("/a", POSE, &[]), topic("/b", POSE, &[])];
    assert_eq!(suggest(&silent), (None, None));
    // An unreadable topic is never offered, whatever its name.
    let unreadable = [topic("/pusher/image", "sensor_msgs/msg/Image", &[])];
    assert_eq!(suggest(&unreadable), (None, None));
}

#[test]
fn of_two_streams_one_named_the_other_takes_the_other_role() {
    let topics = [
        topic("/mocap/rigid_body_3", POSE, &[]),
        topic("/ee_pose", "nav_msgs/msg/Odometry", &[]),
    ];
    assert_eq!(
        suggest(&topics),
        (spec("/ee_pose"), spec("/mocap/rigid_body_3"))
    );
}

#[test]
fn a_choice_file_sits_beside_the_bag_file_or_folder() {
    assert_eq!(
        choice_path(Path::new("/data/run1.mcap")),
        Path::new("/data/run1.mcap.pushlab-bag.json")
    );
    assert_eq!(
        choice_path(Path::new("/data/rosbag2_2026_11_24")),
        Path::new("/data/rosbag2_2026_11_24.pushlab-bag.json")
    );
}

#[test]
fn a_remembered_choice_reads_back_as_written() {
    let dir = temp_dir("roundtrip");
    let bag = dir.join("run1.mcap");
    std::fs::write(dir.join(SETTING_FILE), b"{}").unwrap();
    let from_file = BagChoice {
        pusher: "/tf:tip".parse().unwrap(),
        object: "/object/pose".parse().unwrap(),
        setting: SettingSource::File(dir.join(SETTING_FILE)),
        options: ImportOptions {
            rate_hz: Some(100.0),
            split_gap_s: Some(0.5),
        },
        cameras: vec!["/camera/image_raw/compressed".to_owned()],
    };
    assert_eq!(remembered(&bag).unwrap(), None);
    let written = remember(&bag, &from_file).unwrap();
    let text = std::fs::read_to_string(&written).unwrap();
    // Stored relative, so that the folder can move.
    assert!(
        text.contains("\"setting_file\": \"setting.json\""),
        "{text}"
    );
    assert!(text.contains("/camera/image_raw/compressed"), "{text}");
    assert_eq!(remembered(&bag).unwrap(), Some(from_file));

    let mut setting = entered();
    let typed = BagChoice {
        pusher: "/pusher".parse().unwrap(),
        object: "/object".parse().unwrap(),
        setting: SettingSource::Entered(setting.clone()),
        options: ImportOptions::default(),
        cameras: Vec::new(),
    };
    remember(&bag, &typed).unwrap();
    assert_eq!(remembered(&bag).unwrap(), Some(typed.clone()));
    // Trajectories of an entered setting are not kept: the import makes them.
    setting.trajectories.push(old_entry());
    let with_entries = BagChoice {
        setting: SettingSource::Entered(setting),
        ..typed.clone()
    };
    remember(&bag, &with_entries).unwrap();
    assert_eq!(remembered(&bag).unwrap(), Some(typed));
    std::fs::remove_dir_all(dir).unwrap();
}

fn old_entry() -> crate::recording::TrajectoryEntry {
    crate::recording::TrajectoryEntry {
        file: "old.csv".to_owned(),
        contact_offset: None,
        push_angle_deg: None,
        extra: serde_json::Map::new(),
    }
}

fn parse_error(json: &str) -> String {
    parse(
        json.as_bytes(),
        Path::new("/data/run1.mcap.pushlab-bag.json"),
    )
    .unwrap_err()
    .to_string()
}

#[test]
fn a_broken_choice_file_says_which_file_and_field() {
    let head = r#""format": "pushlab-bag-choice", "version": 1"#;
    let cases = [
        (
            r#"{"format": "other", "version": 1, "pusher": "/a", "object": "/b", "setting_file": "s.json"}"#
                .to_owned(),
            r#""format" is "other", expected "pushlab-bag-choice""#,
        ),
        (
            r#"{"format": "pushlab-bag-choice", "version": 7, "pusher": "/a", "object": "/b", "setting_file": "s.json"}"#
                .to_owned(),
            "version 7 is not supported",
        ),
        (
            format!(r#"{{{head}, "pusher": "/a", "object": "/b"}}"#),
            "expected exactly one of `setting_file` and `setting`",
        ),
        (
            format!(r#"{{{head}, "pusher": "/tf:", "object": "/b", "setting_file": "s.json"}}"#),
            "field `pusher`: '/tf:': expected TOPIC or TOPIC:CHILD_FRAME",
        ),
        (
            format!(
                r#"{{{head}, "pusher": "/a", "object": "/b", "setting_file": "s.json", "split_gap_s": -1}}"#
            ),
            "field `split_gap_s`: -1, expected a positive number",
        ),
        (
            format!(
                r#"{{{head}, "pusher": "/a", "object": "/b", "setting": {{"name": "x", "object": {{"shape": "box", "width": -0.1, "length": 0.1}}, "pusher_radius": 0.005}}}}"#
            ),
            "field `setting.object`",
        ),
        (
            format!(r#"{{{head}, "pusher": "/a", "object": "/b", "setting_file": "s.json", "colour": 3}}"#),
            "unknown field `colour`",
        ),
        (
            format!(r#"{{{head}, "pusher": "/a", "object": "/b", "setting_file": "s.json", "cameras": ["/c", 7]}}"#),
            "cameras[1]: invalid type: integer `7`, expected a string (line 1, column",
        ),
    ];
    for (json, expected) in cases {
        let message = parse_error(&json);
        assert!(
            message.starts_with("/data/run1.mcap.pushlab-bag.json: not a pushlab bag choice: "),
            "{message}"
        );
        assert!(
            message.contains(expected),
            "{message}\nexpected: {expected}"
        );
    }
}

#[test]
fn the_settings_beside_a_bag_are_found_nearest_first() {
    let dir = temp_dir("beside");
    let folder = dir.join("rosbag2_run");
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::write(folder.join("metadata.yaml"), b"").unwrap();
    assert!(settings_beside(&folder).is_empty());
    std::fs::write(dir.join(SETTING_FILE), b"{}").unwrap();
    std::fs::write(folder.join(SETTING_FILE), b"{}").unwrap();
    assert_eq!(
        settings_beside(&folder),
        vec![folder.join(SETTING_FILE), dir.join(SETTING_FILE)]
    );
    assert_eq!(
        settings_beside(&dir.join("run2.mcap")),
        vec![dir.join(SETTING_FILE)]
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn cameras_named_camera_or_image_are_pre_selected() {
    const COMPRESSED: &str = "sensor_msgs/msg/CompressedImage";
    const RAW: &str = "sensor_msgs/msg/Image";
    let topics = [
        topic("/overhead_cam/compressed", COMPRESSED, &[]),
        topic("/depth/image_raw", RAW, &[]),
        topic("/debug/overlay", RAW, &[]),
        topic("/pusher/pose", POSE, &[]),
        // Named like a camera, but not images pushlab reads.
        topic("/camera/info", "sensor_msgs/msg/CameraInfo", &[]),
    ];
    assert_eq!(
        suggest_cameras(&topics),
        ["/overhead_cam/compressed", "/depth/image_raw"]
    );
}
