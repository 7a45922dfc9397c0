//! ROS 2 bag import on bags written by independent writers (tests/bags/make_fixtures.py: the Python
//! `rosbags` library and Foxglove's Python `mcap` writer) from tests/bags/push.csv, and on corrupt
//! bags, which must be refused with an error that names the file, never a panic.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use pushlab_core::recording::bag::{self, BagImport, ImportOptions, TopicSpec};
use pushlab_core::recording::{BagError, BagProblem, load_paths};

/// The refusals and the bag cut short.
mod bags_refused;

/// Unix time the fixtures stamp the CSV's time 0 at.
const BASE_S: f64 = 1_700_000_000.0;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/bags")
        .join(name)
}

fn spec(text: &str) -> TopicSpec {
    text.parse().unwrap()
}

/// The CSV rows `[t, robot_x, robot_y, object_x, object_y, object_theta]`, θ unwrapped.
fn csv_rows() -> Vec<[f64; 6]> {
    let text = std::fs::read_to_string(fixture("push.csv")).unwrap();
    let mut rows: Vec<[f64; 6]> = text
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|f| f.parse().unwrap()).collect();
            v.try_into().unwrap()
        })
        .collect();
    for i in 1..rows.len() {
        let step = rows[i][5] - rows[i - 1][5];
        rows[i][5] -= (step / std::f64::consts::TAU).round() * std::f64::consts::TAU;
    }
    rows
}

/// The CSV linearly interpolated at time `t`.
fn csv_at(rows: &[[f64; 6]], t: f64) -> [f64; 6] {
    let i = rows.partition_point(|r| r[0] <= t).clamp(1, rows.len() - 1);
    let (a, b) = (rows[i - 1], rows[i]);
    let w = ((t - a[0]) / (b[0] - a[0])).clamp(0.0, 1.0);
    std::array::from_fn(|k| a[k] + w * (b[k] - a[k]))
}

fn import(path: &Path, pusher: &str, object: &str) -> BagImport {
    bag::import(path, &spec(pusher), &spec(object), ImportOptions::default())
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Every frame within interpolation error of the CSV (the object is published at half the rate and
/// interpolated: over 20 ms the CSV's curves bend by well under 0.1 mm).
fn assert_matches_csv(import: &BagImport, time_offset_s: f64) {
    // The grid covers the interval both streams cover: 0 … 1.2 s at 50 Hz.
    assert_matches_csv_from(import, time_offset_s, 0.0, 61);
}

/// [`assert_matches_csv`] for a push of `frames` frames that starts at the CSV's time `csv_start_s`.
fn assert_matches_csv_from(
    import: &BagImport,
    time_offset_s: f64,
    csv_start_s: f64,
    frames: usize,
) {
    let rows = csv_rows();
    assert_eq!(import.pushes.len(), 1);
    let push = &import.pushes[0];
    assert_eq!(import.rate_hz, 50.0, "the slower stream's rate");
    let count = frames;
    let frames = &push.trajectory.frames;
    assert_eq!(frames.len(), count, "{}", frames.len());
    let start = push.start_unix_s - BASE_S - time_offset_s;
    assert!((start - csv_start_s).abs() < 1e-6, "starts at {start}");
    for frame in frames {
        let want = csv_at(&rows, start + frame.time);
        let got = [
            frame.robot.x,
            frame.robot.y,
            frame.object.position.x,
            frame.object.position.y,
            frame.object.yaw,
        ];
        for (k, (g, w)) in got.iter().zip(&want[1..]).enumerate() {
            assert!(
                (g - w).abs() < 1e-4,
                "t = {:.3} column {k}: {g} vs the CSV's {w}",
                frame.time
            );
        }
    }
}

#[test]
fn pose_stamped_rosbag2_folder_matches_its_csv() {
    let import = import(&fixture("pose_stamped"), "/pusher/pose", "/object/pose");
    assert_matches_csv(&import, 0.0);
    // Nothing is lost: a log time for the missing stamp, the yaw unwrapped and the streams put
    // on one clock are notes, and there is no warning.
    let push = &import.pushes[0];
    assert!(push.warnings.is_empty(), "{:?}", push.warnings);
    let notes = &push.notes;
    assert!(
        notes
            .iter()
            .any(|w| w.contains("1 of 121 pose(s) without a header stamp")),
        "{notes:?}"
    );
    assert!(
        notes
            .iter()
            .any(|w| w.contains("yaw wraps at ±π 1 time(s)")),
        "{notes:?}"
    );
    assert!(
        notes.iter().any(|w| w.contains("unequal rates")),
        "{notes:?}"
    );
}

#[test]
fn a_single_mcap_file_of_a_folder_imports_the_same() {
    let folder = import(&fixture("pose_stamped"), "/pusher/pose", "/object/pose");
    let file = import(
        &fixture("pose_stamped/pose_stamped.mcap"),
        "/pusher/pose",
        "/object/pose",
    );
    let parts = |i: &BagImport| -> Vec<_> {
        (i.pushes.iter())
            .map(|p| {
                let remarks = (p.warnings.clone(), p.notes.clone());
                (p.trajectory.clone(), p.start_unix_s, remarks)
            })
            .collect()
    };
    assert_eq!(parts(&folder), parts(&file));
}

#[test]
fn tf_transforms_are_chosen_by_child_frame() {
    let import = import(&fixture("tf"), "/tf:pusher_tip", "/tf:box");
    assert_matches_csv(&import, 0.0);
}

#[test]
fn a_transform_tree_is_resolved_to_the_root() {
    // tip hangs under tool0 (static, tilted), which moves under base_link, which is static under
    // world; object is published under world directly.
    let import = import(&fixture("tf_tree"), "/tf:tip", "/tf:object");
    assert_matches_csv(&import, 0.0);
    assert!(
        !import.pushes[0]
            .warnings
            .iter()
            .any(|w| w.contains("dropped")),
        "{:?}",
        import.pushes[0].warnings
    );
}

#[test]
fn a_moving_parent_is_interpolated_at_the_frames_own_stamps() {
    // object_on_table is published 5 ms before each table pose: the table is interpolated between
    // two of its poses. Its first pose, before the table's first, is dropped, so the push starts at
    // the object's second pose, 20 ms in.
    let import = import(&fixture("tf_tree"), "/tf:tip", "/tf:object_on_table");
    assert_matches_csv_from(&import, 0.0, 0.02, 60);
    let warnings = &import.pushes[0].warnings;
    assert!(
        warnings.iter().any(|w| w.contains(
            "/tf:object_on_table: 1 of 61 pose(s) dropped: their time is outside the span of \
             world → table (0.005 … 1.205 s)"
        )),
        "{warnings:?}"
    );
}

#[test]
fn chains_to_different_roots_are_refused_naming_both() {
    let (path, p) = problem(bag::import(
        &fixture("tf_tree"),
        &spec("/tf:tip"),
        &spec("/tf:stray"),
        ImportOptions::default(),
    ));
    assert_eq!(path, fixture("tf_tree"));
    assert!(matches!(p, BagProblem::DifferentRoots { .. }), "{p}");
    assert_eq!(
        p.to_string(),
        "pusher `/tf:tip`'s chain (tip → tool0 → base_link → world) ends in `world`, object \
         `/tf:stray`'s (stray → odom) in `odom`; expected both in one fixed frame"
    );
}

#[test]
fn an_unknown_frame_in_a_tree_lists_the_frames_seen() {
    let (_, p) = problem(bag::import(
        &fixture("tf_tree"),
        &spec("/tf:tip"),
        &spec("/tf:cube"),
        ImportOptions::default(),
    ));
    assert!(matches!(p, BagProblem::NoChildFrame { .. }), "{p}");
    assert!(
        p.to_string().contains(
            "no transform with child frame `cube`; child frames seen: tool0, stray, object, \
             object_on_table, table, base_link, tip"
        ),
        "{p}"
    );
}

#[test]
fn a_chain_that_never_moves_has_no_times() {
    let (_, p) = problem(bag::import(
        &fixture("tf_tree"),
        &spec("/tf:base_link"),
        &spec("/tf:object"),
        ImportOptions::default(),
    ));
    assert!(matches!(p, BagProblem::StaticChain { .. }), "{p}");
    assert!(
        p.to_string().contains("(base_link → world) is static"),
        "{p}"
    );
}

#[test]
fn odometry_and_pose2d_match_their_csv() {
    let import = import(&fixture("odometry"), "/pusher/pose2d", "/object/odom");
    assert_matches_csv(&import, 0.0);
    // Pose2D has no header: every pusher pose takes its log time, and that is noted.
    assert!(
        import.pushes[0]
            .notes
            .iter()
            .any(|w| w.contains("121 of 121 pose(s) without a header stamp")),
        "{:?}",
        import.pushes[0].notes
    );
}

#[test]
fn zstd_lz4_and_plain_chunks_match_their_csv() {
    for name in ["zstd.mcap", "lz4.mcap", "crc.mcap"] {
        let import = import(&fixture(name), "/pusher/pose", "/object/pose");
        assert_matches_csv(&import, 0.0);
    }
}

#[test]
fn topics_are_listed_with_types_counts_and_rates() {
    let listing = bag::topics(&fixture("pose_stamped")).unwrap();
    assert!(listing.cut_short.is_empty());
    let topics = listing.topics;
    let by_name: BTreeMap<&str, _> = topics.iter().map(|t| (t.topic.as_str(), t)).collect();
    assert_eq!(by_name.len(), 3);
    let pusher = by_name["/pusher/pose"];
    assert_eq!(pusher.type_name, "geometry_msgs/msg/PoseStamped");
    assert_eq!(pusher.count, 121);
    assert!((pusher.rate_hz() - 100.0).abs() < 0.01);
    assert_eq!(by_name["/object/pose"].count, 61);
    assert_eq!(by_name["/note"].type_name, "std_msgs/msg/String");
    assert!(by_name["/note"].pose_type().is_none());
}

#[test]
fn split_gap_cuts_a_bag_where_the_streams_pause() {
    // The fixtures have no pause: one push, whatever the gap.
    let import = bag::import(
        &fixture("zstd.mcap"),
        &spec("/pusher/pose"),
        &spec("/object/pose"),
        ImportOptions {
            rate_hz: Some(100.0),
            split_gap_s: Some(0.5),
        },
    )
    .unwrap();
    assert_eq!(import.pushes.len(), 1);
    assert_eq!(import.pushes[0].trajectory.len(), 121);
}

fn problem(result: Result<BagImport, BagError>) -> (PathBuf, BagProblem) {
    match result {
        Err(BagError::Problem { path, problem }) => (path, problem),
        Err(other) => panic!("expected a bag error, got {other}"),
        Ok(import) => panic!("expected a bag error, got {} push(es)", import.pushes.len()),
    }
}

#[test]
fn opening_a_bag_like_a_recording_says_how_to_import_it_and_lists_its_topics() {
    // A rosbag2 folder, an .mcap file, and a folder holding bags among other things.
    for path in [fixture("pose_stamped"), fixture("zstd.mcap")] {
        let report = load_paths(std::slice::from_ref(&path));
        assert!(report.sets.is_empty());
        assert_eq!(report.errors.len(), 1, "{:?}", report.errors);
        let message = report.errors[0].to_string();
        assert!(
            message.starts_with(&path.display().to_string()),
            "{message}"
        );
        assert!(message.contains("pushlab import BAG"), "{message}");
        assert!(
            message.contains("/pusher/pose (geometry_msgs/msg/PoseStamped)"),
            "{message}"
        );
    }
    let report = load_paths(&[fixture("pose_stamped")]);
    assert!(
        report.errors[0]
            .to_string()
            .contains("/note (std_msgs/msg/String, not readable)")
    );
    // The fixtures folder: every bag reported once, the folder's .mcap files not twice.
    let report = load_paths(&[fixture("")]);
    let bags = report
        .errors
        .iter()
        .filter(|e| e.to_string().contains("a ROS 2 bag"))
        .count();
    assert_eq!(bags, 10, "{:?}", report.errors);
    // A broken bag says what is wrong with it instead.
    let dir = std::env::temp_dir().join(format!("pushlab-bag-open-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let broken = dir.join("broken.mcap");
    std::fs::write(&broken, b"not an mcap file at all").expect("write");
    let report = load_paths(std::slice::from_ref(&broken));
    let message = report.errors[0].to_string();
    assert!(!message.contains("pushlab import"), "{message}");
    assert!(message.contains("broken.mcap"), "{message}");
    let _ = std::fs::remove_dir_all(&dir);
}
