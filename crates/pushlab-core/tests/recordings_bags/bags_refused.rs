//! Bags that must be refused or read only in part: a missing topic or type, an undecodable message,
//! a file cut short mid-write, wrong magic, bad CRCs, corrupt compression and the fuzzer's inputs —
//! each with an error that names the file, never a panic.

use std::collections::BTreeMap;
use std::path::Path;

use pushlab_core::recording::bag::{self, BagImport, ImportOptions};
use pushlab_core::recording::{BagError, BagProblem};

use super::{fixture, problem, spec};

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
fn import_bytes(name: &str, bytes: &[u8]) -> Result<BagImport, BagError> {
    import_bytes_with(name, bytes, ImportOptions::default())
}

fn import_bytes_with(
    name: &str,
    bytes: &[u8],
    options: ImportOptions,
) -> Result<BagImport, BagError> {
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
    assert_eq!(
        (&gap_cut[0].warnings, &gap_cut[0].notes),
        (&gap_whole[0].warnings, &gap_whole[0].notes)
    );
    assert!(gap_cut[1].trajectory.len() < gap_whole[1].trajectory.len());
    assert!(
        gap_cut[1]
            .warnings
            .iter()
            .any(|w| w.starts_with("the file is cut short"))
    );
    // Cut in its data-end record: every message read, none lost — a note, not a warning.
    let cut = import_bytes("end", &bytes[..end - 1]).unwrap();
    assert_eq!(cut.pushes[0].trajectory, whole.pushes[0].trajectory);
    assert_eq!(cut.pushes[0].warnings, whole.pushes[0].warnings);
    assert!(
        cut.pushes[0]
            .notes
            .iter()
            .any(|w| w.ends_with("without its data-end record (a recording that did not finish?); every message in it was read")),
        "{:?}",
        cut.pushes[0].notes
    );
    // Cut in its summary or footer, a file still holds every message: read from the start, with
    // nothing to say.
    for len in [end, end + 10, bytes.len() - 9, bytes.len() - 1] {
        let cut = import_bytes(&format!("cut{len}"), &bytes[..len]).unwrap();
        assert_eq!(cut.pushes.len(), whole.pushes.len(), "{len}");
        for (a, b) in cut.pushes.iter().zip(&whole.pushes) {
            assert_eq!(a.trajectory, b.trajectory, "{len}");
            assert_eq!((&a.warnings, &a.notes), (&b.warnings, &b.notes), "{len}");
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
