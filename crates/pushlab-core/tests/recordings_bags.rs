//! ROS 2 bag import on bags written by independent writers (tests/bags/make_fixtures.py: the Python
//! `rosbags` library and Foxglove's Python `mcap` writer) from tests/bags/push.csv, and on corrupt
//! bags, which must be refused with an error that names the file, never a panic.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use pushlab_core::recording::bag::{self, BagImport, ImportOptions, TopicSpec};
use pushlab_core::recording::{BagProblem, LoadError, load_paths};

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
    let warnings = &import.pushes[0].warnings;
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("1 of 121 pose(s) without a header stamp")),
        "{warnings:?}"
    );
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("yaw wraps at ±π 1 time(s)")),
        "{warnings:?}"
    );
    assert!(
        warnings.iter().any(|w| w.contains("unequal rates")),
        "{warnings:?}"
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
            .map(|p| (p.trajectory.clone(), p.start_unix_s, p.warnings.clone()))
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
    // Pose2D has no header: every pusher pose takes its log time, and that is said.
    assert!(
        import.pushes[0]
            .warnings
            .iter()
            .any(|w| w.contains("121 of 121 pose(s) without a header stamp")),
        "{:?}",
        import.pushes[0].warnings
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

fn problem(result: Result<BagImport, LoadError>) -> (PathBuf, BagProblem) {
    match result {
        Err(LoadError::Bag { path, problem }) => (path, problem),
        Err(other) => panic!("expected a bag error, got {other}"),
        Ok(import) => panic!("expected a bag error, got {} push(es)", import.pushes.len()),
    }
}

#[test]
fn a_missing_topic_is_refused_with_the_bags_topics() {
    let path = fixture("pose_stamped");
    let (_, p) = problem(bag::import(
        &path,
        &spec("/pusher/pose"),
        &spec("/box/pose"),
        ImportOptions::default(),
    ));
    let text = p.to_string();
    assert!(matches!(p, BagProblem::MissingTopic { .. }), "{text}");
    assert!(
        text.contains("/pusher/pose (geometry_msgs/msg/PoseStamped, 121 messages)"),
        "{text}"
    );
    assert!(
        text.contains("/note (std_msgs/msg/String, 7 messages)"),
        "{text}"
    );
}

#[test]
fn an_unreadable_type_is_refused_with_the_bags_topics() {
    let (_, p) = problem(bag::import(
        &fixture("pose_stamped"),
        &spec("/pusher/pose"),
        &spec("/note"),
        ImportOptions::default(),
    ));
    let text = p.to_string();
    assert!(matches!(p, BagProblem::UnsupportedType { .. }), "{text}");
    assert!(text.contains("std_msgs/msg/String"), "{text}");
}

#[test]
fn tf_needs_a_child_frame_that_exists() {
    let (_, p) = problem(bag::import(
        &fixture("tf"),
        &spec("/tf"),
        &spec("/tf:box"),
        ImportOptions::default(),
    ));
    assert!(matches!(p, BagProblem::NeedChildFrame { .. }), "{p}");
    assert!(p.to_string().contains("base_link, pusher_tip, box"), "{p}");
    let (_, p) = problem(bag::import(
        &fixture("tf"),
        &spec("/tf:pusher_tip"),
        &spec("/tf:cube"),
        ImportOptions::default(),
    ));
    assert!(matches!(p, BagProblem::NoChildFrame { .. }), "{p}");
    assert!(
        p.to_string()
            .contains("child frames seen: base_link, pusher_tip, box"),
        "{p}"
    );
}

/// A bag with a message too short to be a PoseStamped, written with the Rust `mcap` writer.
#[test]
fn an_undecodable_message_names_file_topic_and_index() {
    let dir = std::env::temp_dir().join(format!("pushlab-bag-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("short.mcap");
    let mut writer = mcap::Writer::new(std::io::BufWriter::new(
        std::fs::File::create(&path).unwrap(),
    ))
    .unwrap();
    let schema = writer
        .add_schema("geometry_msgs/msg/PoseStamped", "ros2msg", b"")
        .unwrap();
    let channel = writer
        .add_channel(schema, "/pose", "cdr", &BTreeMap::new())
        .unwrap();
    for i in 0..5u32 {
        let mut data = bag::encode_pose_stamped(1_000_000_000 + u64::from(i), "w", 0.0, 0.0, 0.0);
        if i == 3 {
            data.truncate(30);
        }
        let header = mcap::records::MessageHeader {
            channel_id: channel,
            sequence: i,
            log_time: u64::from(i),
            publish_time: u64::from(i),
        };
        writer.write_to_known_channel(&header, &data).unwrap();
    }
    writer.finish().unwrap();
    drop(writer);
    let (file, p) = problem(bag::import(
        &path,
        &spec("/pose"),
        &spec("/pose"),
        ImportOptions::default(),
    ));
    assert_eq!(file, path);
    assert!(
        matches!(&p, BagProblem::Decode { topic, index: 3, .. } if topic == "/pose"),
        "{p}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Imports `bytes` written to a temporary `.mcap` file.
fn import_bytes(name: &str, bytes: &[u8]) -> Result<BagImport, LoadError> {
    import_bytes_with(name, bytes, ImportOptions::default())
}

fn import_bytes_with(
    name: &str,
    bytes: &[u8],
    options: ImportOptions,
) -> Result<BagImport, LoadError> {
    let dir = std::env::temp_dir().join(format!("pushlab-bag-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.mcap"));
    std::fs::write(&path, bytes).unwrap();
    let result = bag::import(&path, &spec("/pusher/pose"), &spec("/object/pose"), options);
    let _ = std::fs::remove_dir_all(&dir);
    result
}

/// Offset of the first chunk's records (after the magic, the header record and the chunk header).
fn first_chunk_records(bytes: &[u8]) -> usize {
    let header_len = u64::from_le_bytes(bytes[9..17].try_into().unwrap()) as usize;
    let chunk = 8 + 9 + header_len;
    assert_eq!(bytes[chunk], 0x06, "a chunk record follows the header");
    let compression_len =
        u32::from_le_bytes(bytes[chunk + 9 + 28..chunk + 9 + 32].try_into().unwrap()) as usize;
    chunk + 9 + 32 + compression_len + 8
}

/// Where a file's data section ends: at its data-end record, before the summary and footer.
fn data_end(bytes: &[u8]) -> usize {
    let mut at = 8;
    loop {
        let len = u64::from_le_bytes(bytes[at + 1..at + 9].try_into().unwrap()) as usize;
        if bytes[at] == 0x0F {
            return at + 9 + len;
        }
        at += 9 + len;
    }
}

/// The byte a cut-short warning says the lost part starts at.
fn said_from(warning: &str) -> usize {
    let from = warning.split("from byte ").nth(1).expect("a byte");
    from.split(' ').next().unwrap().parse().unwrap()
}

#[test]
fn a_bag_cut_short_imports_what_it_holds_before_the_cut_and_says_what_was_lost() {
    let bytes = std::fs::read(fixture("zstd.mcap")).unwrap();
    let end = data_end(&bytes);
    assert!(end < bytes.len() - 100, "the fixture has a summary");
    let whole = import_bytes("whole", &bytes).unwrap();
    let frames = whole.pushes[0].trajectory.len();
    // Cut before a whole record declares a channel: nothing to import, refused.
    for len in [0, 4, 8, 20, 100, 1000] {
        let (_, p) = problem(import_bytes(&format!("cut{len}"), &bytes[..len]));
        assert!(
            matches!(p, BagProblem::Mcap(_) | BagProblem::Chunk { .. }),
            "{len}: {p}"
        );
    }
    // Cut in the middle (a recorder killed): the frames before the cut, the same as the whole
    // file's, and a warning saying where the file is cut and that the rest is lost.
    let half = bytes.len() / 2;
    let cut = import_bytes("half", &bytes[..half]).unwrap();
    assert_eq!(cut.pushes.len(), 1);
    let push = &cut.pushes[0];
    let kept = push.trajectory.len();
    assert!(
        kept > 10 && kept < frames * 3 / 4,
        "{kept} of {frames} frames"
    );
    assert_eq!(push.start_unix_s, whole.pushes[0].start_unix_s);
    for (a, b) in push
        .trajectory
        .frames
        .iter()
        .zip(&whole.pushes[0].trajectory.frames)
    {
        assert_eq!(a, b);
    }
    let said: Vec<&String> = push
        .warnings
        .iter()
        .filter(|w| w.contains("cut short"))
        .collect();
    assert_eq!(said.len(), 1, "{:?}", push.warnings);
    assert!(said[0].starts_with("the file is cut short"), "{}", said[0]);
    assert!(
        said[0].contains(&format!(
            "the file is cut short (a recording that did not finish, or a damaged file): its \
             last {} bytes, from byte ",
            half - said_from(said[0])
        )) && said[0].ends_with("are not a whole record, and the messages in them are lost; the messages before were read"),
        "{}",
        said[0]
    );
    // Split at a pause, a bag cut in its second push: the first is whole and says nothing of it.
    let gap = std::fs::read(fixture("gap.mcap")).unwrap();
    let split = ImportOptions {
        rate_hz: None,
        split_gap_s: Some(0.5),
    };
    let gap_whole = import_bytes_with("gap", &gap, split).unwrap().pushes;
    let gap_cut = import_bytes_with("gap-cut", &gap[..gap.len() * 4 / 5], split)
        .unwrap()
        .pushes;
    assert_eq!((gap_whole.len(), gap_cut.len()), (2, 2));
    assert_eq!(gap_cut[0].trajectory, gap_whole[0].trajectory);
    assert_eq!(gap_cut[0].warnings, gap_whole[0].warnings);
    assert!(gap_cut[1].trajectory.len() < gap_whole[1].trajectory.len());
    assert!(
        gap_cut[1]
            .warnings
            .iter()
            .any(|w| w.starts_with("the file is cut short"))
    );
    // Cut in its data-end record: every message read, none lost.
    let cut = import_bytes("end", &bytes[..end - 1]).unwrap();
    assert_eq!(cut.pushes[0].trajectory, whole.pushes[0].trajectory);
    assert!(
        cut.pushes[0]
            .warnings
            .iter()
            .any(|w| w.ends_with("without its data-end record (a recording that did not finish?); every message in it was read")),
        "{:?}",
        cut.pushes[0].warnings
    );
    // Cut in its summary or footer, a file still holds every message: read from the start, with
    // nothing to say.
    for len in [end, end + 10, bytes.len() - 9, bytes.len() - 1] {
        let cut = import_bytes(&format!("cut{len}"), &bytes[..len]).unwrap();
        assert_eq!(cut.pushes.len(), whole.pushes.len(), "{len}");
        for (a, b) in cut.pushes.iter().zip(&whole.pushes) {
            assert_eq!(a.trajectory, b.trajectory, "{len}");
            assert_eq!(a.warnings, b.warnings, "{len}");
        }
    }
}

#[test]
fn wrong_magic_is_refused() {
    let mut bytes = std::fs::read(fixture("lz4.mcap")).unwrap();
    bytes[1] = b'X';
    let (_, p) = problem(import_bytes("magic", &bytes));
    assert!(p.to_string().contains("not a readable MCAP file"), "{p}");
}

#[test]
fn a_chunk_with_a_bad_crc_is_refused() {
    let mut bytes = std::fs::read(fixture("crc.mcap")).unwrap();
    let at = first_chunk_records(&bytes) + 200;
    bytes[at] ^= 0x55;
    let (_, p) = problem(import_bytes("crc", &bytes));
    assert!(matches!(p, BagProblem::Chunk { index: 0, .. }), "{p}");
    assert!(p.to_string().contains("CRC"), "{p}");
}

#[test]
fn corrupt_compressed_chunks_are_refused() {
    for name in ["zstd.mcap", "lz4.mcap"] {
        let original = std::fs::read(fixture(name)).unwrap();
        let start = first_chunk_records(&original);
        // Whole (read by its indexes) and without its summary (read from the front, the chunks
        // decompressed ahead on workers): the first chunk named either way.
        for end in [original.len(), data_end(&original)] {
            for offset in [0, 40, 300, 700] {
                let mut bytes = original[..end].to_vec();
                bytes[start + offset] ^= 0xa5;
                let result = import_bytes(&format!("{name}{offset}-{end}"), &bytes);
                assert!(result.is_err(), "{name} +{offset} imported");
                let (_, p) = problem(result);
                assert!(
                    matches!(p, BagProblem::Chunk { index: 0, .. }),
                    "{name} +{offset}: {p}"
                );
            }
        }
    }
}

/// Inputs the fuzzer found (`tests/nasty/mcap/fuzz_*`): each must be refused with an error, not a
/// panic or an allocation of what a corrupt length claims.
#[test]
fn nasty_mcap_files_are_refused() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/nasty/mcap");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let bytes = std::fs::read(&path).unwrap();
        let result = bag::import_bytes(
            &bytes,
            &path,
            &spec("/pusher/pose"),
            &spec("/object/pose"),
            ImportOptions::default(),
        );
        let (file, _) = problem(result);
        assert_eq!(file, path);
        assert!(
            bag::topics_bytes(&bytes, &path).is_err(),
            "{}",
            path.display()
        );
        count += 1;
    }
    assert!(count >= 1);
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
