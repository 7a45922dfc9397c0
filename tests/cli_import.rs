//! `pushlab import` and `pushlab validate` on ROS 2 bags, end to end: the built binary on the bags
//! in crates/pushlab-core/tests/bags (written by the Python `rosbags` and `mcap` libraries), the set
//! it writes loaded back, and the refusals (missing or unreadable topics, corrupt bags, wrong
//! arguments) with their exit codes and messages.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::cli_common;

use std::path::{Path, PathBuf};

use cli_common::{Run, pushlab, temp_dir};

fn bag(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("crates/pushlab-core/tests/bags")
        .join(name)
        .display()
        .to_string()
}

/// A setting.json for the imports, in a fresh folder; returns (folder, setting path).
fn setting(name: &str) -> (PathBuf, String) {
    let dir = temp_dir("pushlab-import", name);
    let path = dir.join("box.json");
    std::fs::write(
        &path,
        r#"{"name": "bag-box", "object": {"shape": "box", "width": 0.1, "length": 0.12},
            "pusher_radius": 0.005, "material": "wood on MDF", "trajectories": []}"#,
    )
    .unwrap();
    (dir, path.display().to_string())
}

/// Runs `pushlab import BAG --pusher P --object O --setting S --out OUT EXTRA…`.
fn import(bag: &str, pusher: &str, object: &str, setting: &str, out: &str, extra: &[&str]) -> Run {
    let mut args = vec![
        "import",
        bag,
        "--pusher",
        pusher,
        "--object",
        object,
        "--setting",
        setting,
        "--out",
        out,
    ];
    args.extend_from_slice(extra);
    pushlab(&args)
}

fn s(path: &Path) -> String {
    path.display().to_string()
}

#[test]
fn a_rosbag2_folder_imports_into_a_set_that_loads() {
    let (dir, setting) = setting("folder");
    let out = dir.join("set");
    let run = import(
        &bag("pose_stamped"),
        "/pusher/pose",
        "/object/pose",
        &setting,
        &s(&out),
        &[],
    );
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stdout
            .contains("pose_stamped.csv: 61 frames at 50 Hz, 1.20 s"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout
            .contains("note: /pusher/pose: 1 of 121 pose(s) without a header stamp"),
        "{}",
        run.stdout
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("setting.json")).unwrap()).unwrap();
    assert_eq!(json["material"], "wood on MDF");
    assert_eq!(json["sample_rate_hz"], 50.0);
    assert_eq!(json["trajectories"][0]["file"], "pose_stamped.csv");
    assert_eq!(json["trajectories"][0]["bag_pusher"], "/pusher/pose");
    assert_eq!(json["trajectories"][0]["start_unix_s"], 1_700_000_000.0);
    let validate = pushlab(&["validate", &s(&out)]);
    assert_eq!(validate.code, 0, "{}", validate.stdout);
    assert!(validate.stdout.contains("ok: "), "{}", validate.stdout);
    assert!(
        validate.stdout.contains("(61 frames, 1.20 s)"),
        "{}",
        validate.stdout
    );
    // A second import into the same folder needs --overwrite.
    let again = |extra: &[&str]| {
        import(
            &bag("zstd.mcap"),
            "/pusher/pose",
            "/object/pose",
            &setting,
            &s(&out),
            extra,
        )
    };
    let run = again(&[]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("pass --overwrite"), "{}", run.stderr);
    assert_eq!(again(&["--overwrite"]).code, 0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn tf_child_frames_and_odometry_import() {
    let (dir, setting) = setting("kinds");
    for (name, pusher, object) in [
        ("tf", "/tf:pusher_tip", "/tf:box"),
        ("odometry", "/pusher/pose2d", "/object/odom"),
        ("lz4.mcap", "/pusher/pose", "/object/pose"),
    ] {
        let out = dir.join(name);
        let run = import(&bag(name), pusher, object, &setting, &s(&out), &[]);
        assert_eq!(run.code, 0, "{name}: {}{}", run.stdout, run.stderr);
        assert!(
            run.stdout.contains("61 frames at 50 Hz"),
            "{name}: {}",
            run.stdout
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn split_gap_makes_one_push_per_piece() {
    let (dir, setting) = setting("split");
    let out = dir.join("set");
    let run_with = |extra: &[&str]| {
        let mut all = vec!["--overwrite"];
        all.extend_from_slice(extra);
        import(
            &bag("gap.mcap"),
            "/pusher/pose",
            "/object/pose",
            &setting,
            &s(&out),
            &all,
        )
    };
    let run = run_with(&["--split-gap", "0.5"]);
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stdout.contains("gap_001.csv: 61 frames"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout.contains("gap_002.csv: 61 frames"),
        "{}",
        run.stdout
    );
    assert!(run.stdout.contains("2 push(es) from"), "{}", run.stdout);
    // Without --split-gap the pause is interpolated across, and said so.
    let run = run_with(&[]);
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    assert!(run.stdout.contains("1 push(es) from"), "{}", run.stdout);
    assert!(
        run.stdout.contains("gap(s) over 50 ms (longest 1300.0 ms)"),
        "{}",
        run.stdout
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn missing_or_unreadable_topics_exit_1_with_the_bags_topics() {
    let (dir, setting) = setting("refused");
    let out = s(&dir.join("set"));
    for (object, expected) in [
        ("/box/pose", "no topic `/box/pose` in the bag"),
        ("/note", "topic `/note` carries std_msgs/msg/String"),
    ] {
        let run = import(
            &bag("pose_stamped"),
            "/pusher/pose",
            object,
            &setting,
            &out,
            &[],
        );
        assert_eq!(run.code, 1, "{object}");
        assert!(run.stderr.contains(expected), "{}", run.stderr);
        assert!(
            run.stderr
                .contains("/pusher/pose (geometry_msgs/msg/PoseStamped, 121 messages)"),
            "{}",
            run.stderr
        );
        assert!(
            run.stderr
                .contains("/note (std_msgs/msg/String, 7 messages)"),
            "{}",
            run.stderr
        );
    }
    assert!(!dir.join("set").exists(), "nothing written");
    let run = import(&bag("tf"), "/tf", "/tf:box", &setting, &out, &[]);
    assert_eq!(run.code, 1);
    assert!(
        run.stderr.contains("name the child frame, as `/tf:FRAME`"),
        "{}",
        run.stderr
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn wrong_arguments_exit_2() {
    let (dir, setting) = setting("usage");
    for pusher in ["/tf:", ""] {
        let run = import(&bag("tf"), pusher, "/tf:box", &setting, "x", &[]);
        assert_eq!(run.code, 2, "{pusher:?}: {}", run.stderr);
    }
    let run = pushlab(&["import", &bag("tf"), "--pusher", "/tf:a"]);
    assert_eq!(run.code, 2);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn validate_lists_a_bags_topics() {
    let run = pushlab(&["validate", &bag("pose_stamped"), &bag("tf/tf.mcap")]);
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    let lines: Vec<&str> = run.stdout.lines().collect();
    assert_eq!(lines.len(), 6, "{lines:#?}");
    assert!(
        lines[0].ends_with(": /note std_msgs/msg/String, 7 messages, 5.0 Hz"),
        "{}",
        lines[0]
    );
    assert!(
        lines[2].ends_with(
            ": /pusher/pose geometry_msgs/msg/PoseStamped, 121 messages, 100.0 Hz, readable"
        ),
        "{}",
        lines[2]
    );
    assert!(lines[3].contains("3 topic(s), 2 readable"), "{}", lines[3]);
    assert!(
        lines[4].ends_with(
            ": /tf tf2_msgs/msg/TFMessage, 121 messages, 100.0 Hz, readable, child frames: \
             base_link, pusher_tip, box"
        ),
        "{}",
        lines[4]
    );
}

#[test]
fn a_bag_that_is_not_there_is_said_to_be_missing() {
    let (dir, setting) = setting("missing");
    let missing = dir.join("typo.mcap");
    let out = s(&dir.join("set"));
    let expected = format!(
        "pushlab: {}: cannot read: No such file or directory",
        missing.display()
    );
    for run in [
        pushlab(&["import", &s(&missing), "--out", &out]),
        import(&s(&missing), "/pusher", "/object", &setting, &out, &[]),
    ] {
        assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
        assert!(run.stderr.starts_with(&expected), "{}", run.stderr);
    }
    assert!(!dir.join("set").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn corrupt_bags_are_refused_with_exit_1() {
    let dir = temp_dir("pushlab-import", "corrupt");
    let bytes = std::fs::read(bag("zstd.mcap")).unwrap();
    // Cut inside its first chunk, before any channel: nothing to read.
    let cut = dir.join("cut.mcap");
    std::fs::write(&cut, &bytes[..100]).unwrap();
    let mut wrong = bytes.clone();
    wrong[0] = b'X';
    let magic = dir.join("magic.mcap");
    std::fs::write(&magic, &wrong).unwrap();
    for path in [&cut, &magic] {
        let run = pushlab(&["validate", &s(path)]);
        assert_eq!(run.code, 1, "{}", run.stdout);
        assert!(
            run.stdout
                .starts_with(&format!("error: {}: ", path.display())),
            "{}",
            run.stdout
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_bag_cut_short_imports_up_to_the_cut_with_a_warning() {
    let (dir, setting) = setting("cut-short");
    let bytes = std::fs::read(bag("zstd.mcap")).unwrap();
    let half = dir.join("half.mcap");
    std::fs::write(&half, &bytes[..bytes.len() / 2]).unwrap();
    // Listed before a choice: the counts are of what is before the cut, and it says so.
    let listed = pushlab(&["validate", &s(&half)]);
    assert_eq!(listed.code, 0, "{}{}", listed.stdout, listed.stderr);
    assert!(
        listed.stdout.contains(&format!(
            "warning: {}: the file is cut short (a recording that did not finish",
            half.display()
        )),
        "{}",
        listed.stdout
    );
    let out = dir.join("set");
    let run = import(
        &s(&half),
        "/pusher/pose",
        "/object/pose",
        &setting,
        &s(&out),
        &[],
    );
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    let said = format!("{}{}", run.stdout, run.stderr);
    assert!(
        said.contains(
            "warning: the file is cut short (a recording that did not finish, or a damaged file)"
        ),
        "{said}"
    );
    // The frames before the cut are written; the bag is left as it was.
    let csv = std::fs::read_to_string(out.join("half.csv")).unwrap();
    assert!(csv.lines().count() > 10, "{csv}");
    assert_eq!(std::fs::read(&half).unwrap(), &bytes[..bytes.len() / 2]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_choice_remembered_beside_the_bag_is_used_by_import_and_validate() {
    let (dir, setting) = setting("remembered");
    let bag_path = dir.join("tf.mcap");
    std::fs::copy(bag("tf/tf.mcap"), &bag_path).unwrap();
    let out = dir.join("set");
    // Nothing remembered yet: said, with where it would be.
    let run = pushlab(&["import", &s(&bag_path), "--out", &s(&out)]);
    assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stderr.contains(&format!(
            "no topics given and none remembered beside the bag (expected {}.pushlab-bag.json)",
            bag_path.display()
        )),
        "{}",
        run.stderr
    );
    // Only some of the three: clap refuses.
    let run = pushlab(&[
        "import",
        &s(&bag_path),
        "--pusher",
        "/tf:pusher_tip",
        "--out",
        &s(&out),
    ]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    // As the app writes it.
    std::fs::write(
        dir.join("tf.mcap.pushlab-bag.json"),
        format!(
            r#"{{"format": "pushlab-bag-choice", "version": 1, "pusher": "/tf:pusher_tip",
                "object": "/tf:box", "setting_file": "{}"}}"#,
            Path::new(&setting).file_name().unwrap().to_string_lossy()
        ),
    )
    .unwrap();
    let run = pushlab(&["import", &s(&bag_path), "--out", &s(&out)]);
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("setting.json")).unwrap()).unwrap();
    assert_eq!(json["trajectories"][0]["bag_object"], "/tf:box");
    assert_eq!(json["name"], "bag-box");
    // validate lists the topics with /tf's child frames, then checks the bag as a recording.
    let run = pushlab(&["validate", &s(&bag_path)]);
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stdout
            .contains("readable, child frames: base_link, pusher_tip, box"),
        "{}",
        run.stdout
    );
    // Resampling streams of unequal rates onto one clock loses nothing: the bag is ok, with notes.
    let line = (run.stdout.lines())
        .find(|l| l.starts_with(&format!("ok: {} (", bag_path.display())))
        .unwrap_or_else(|| panic!("no ok line for the bag in {}", run.stdout));
    assert!(
        line.contains(" — notes: ") && line.contains("streams have unequal rates"),
        "{line}"
    );
    assert!(
        run.stdout.contains("1 recording(s) loaded"),
        "{}",
        run.stdout
    );
}
