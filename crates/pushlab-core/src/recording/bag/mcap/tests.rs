#![allow(clippy::unwrap_used)]

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::io::Cursor;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use super::*;

/// Counts the bytes read, to show what a pass leaves unread.
struct Counting<'a> {
    bytes: Bytes<'a>,
    read: AtomicU64,
}

impl Source for Counting<'_> {
    fn len(&self) -> u64 {
        self.bytes.len()
    }

    fn read_at(&self, offset: u64, buf: &mut [u8]) -> std::io::Result<()> {
        self.read.fetch_add(buf.len() as u64, Ordering::Relaxed);
        self.bytes.read_at(offset, buf)
    }
}

/// A bag of 100 Hz poses among 30 Hz "images" of 50 kB, in chunks of about 1 MB, as Foxglove's writer
/// writes it (with or without a summary).
fn camera_bag(summary: bool) -> Vec<u8> {
    let mut out = Cursor::new(Vec::new());
    let mut writer = mcap::WriteOptions::new()
        .compression(None)
        .chunk_size(Some(1 << 20))
        .emit_summary_records(summary)
        .emit_summary_offsets(summary)
        .emit_statistics(summary)
        .emit_chunk_indexes(summary)
        .create(&mut out)
        .unwrap();
    let schema = |name: &str| {
        Some(Arc::new(mcap::Schema {
            id: 0,
            name: name.to_owned(),
            encoding: "ros2msg".to_owned(),
            data: Cow::Borrowed(b""),
        }))
    };
    let pose = writer
        .add_channel(0, "/pose", "cdr", &BTreeMap::new())
        .unwrap();
    let _ = schema;
    let image = writer
        .add_channel(0, "/camera/image/compressed", "cdr", &BTreeMap::new())
        .unwrap();
    for k in 0..300u64 {
        let t = 1_000_000_000 + k * 10_000_000;
        let payload: Vec<u8> = (0..40).map(|i| (k as u8).wrapping_add(i)).collect();
        writer
            .write_to_known_channel(
                &mcap::records::MessageHeader {
                    channel_id: pose,
                    sequence: k as u32,
                    log_time: t,
                    publish_time: t,
                },
                &payload,
            )
            .unwrap();
        if k % 3 == 0 {
            let frame: Vec<u8> = (0..50_000u32).map(|i| (i as u8) ^ (k as u8)).collect();
            writer
                .write_to_known_channel(
                    &mcap::records::MessageHeader {
                        channel_id: image,
                        sequence: k as u32,
                        log_time: t + 1,
                        publish_time: t + 1,
                    },
                    &frame,
                )
                .unwrap();
        }
    }
    writer.finish().unwrap();
    drop(writer);
    out.into_inner()
}

/// A message as a pass showed it: its channel's topic, log time, data and place.
type Seen = (String, u64, Vec<u8>, MessageAt);

/// Keeps what a pass shows.
#[derive(Default)]
struct Recorder {
    wants: BTreeMap<String, Want>,
    seen: Vec<Seen>,
    passed: u64,
}

impl Visitor for Recorder {
    fn want(&mut self, _: u16, channel: &ChannelInfo) -> Want {
        self.wants
            .get(&channel.topic)
            .copied()
            .unwrap_or(Want::Nothing)
    }

    fn message(&mut self, visit: Visit<'_>) -> Result<(), BagProblem> {
        let data = visit.data.to_vec();
        self.seen
            .push((visit.channel.topic.clone(), visit.log_time, data, visit.at));
        Ok(())
    }

    fn progress(&mut self, bytes: u64) -> Result<(), BagProblem> {
        self.passed += bytes;
        Ok(())
    }
}

fn recorder(wants: &[(&str, Want)]) -> Recorder {
    Recorder {
        wants: wants.iter().map(|(t, w)| ((*t).to_owned(), *w)).collect(),
        ..Recorder::default()
    }
}

#[test]
fn the_poses_of_a_camera_bag_are_read_without_reading_its_images() {
    let bag = camera_bag(true);
    let source = Counting {
        bytes: Bytes(&bag),
        read: AtomicU64::new(0),
    };
    let mut poses = recorder(&[("/pose", Want::Payload)]);
    let channels = read_messages(&source, &mut poses).unwrap().channels;
    assert_eq!(poses.seen.len(), 300);
    for (k, (topic, time, data, _)) in poses.seen.iter().enumerate() {
        assert_eq!(topic, "/pose");
        assert_eq!(*time, 1_000_000_000 + k as u64 * 10_000_000);
        assert_eq!(data[0], k as u8);
    }
    let read = source.read.load(Ordering::Relaxed);
    assert!(
        read * 20 < bag.len() as u64,
        "read {read} of {} bytes for the poses",
        bag.len()
    );
    assert!(poses.passed > bag.len() as u64 * 9 / 10 && poses.passed < bag.len() as u64);
    // Every channel is counted from the indexes, the images too.
    let counts: Vec<(String, u64)> = channels
        .values()
        .map(|(c, s)| (c.topic.clone(), s.count))
        .collect();
    assert_eq!(
        counts,
        [
            ("/pose".to_owned(), 300),
            ("/camera/image/compressed".to_owned(), 100)
        ]
    );
}

#[test]
fn without_a_summary_the_same_messages_are_read_from_the_start() {
    let wants = [
        ("/pose", Want::Payload),
        ("/camera/image/compressed", Want::Head(12)),
    ];
    let (mut indexed, mut linear) = (recorder(&wants), recorder(&wants));
    let with = camera_bag(true);
    let without = camera_bag(false);
    read_messages(&Bytes(&with), &mut indexed).unwrap();
    let channels = read_messages(&Bytes(&without), &mut linear)
        .unwrap()
        .channels;
    assert_eq!(indexed.seen.len(), 400);
    let strip = |r: &Recorder| -> Vec<(String, u64, Vec<u8>)> {
        r.seen
            .iter()
            .map(|(t, n, d, _)| (t.clone(), *n, d.clone()))
            .collect()
    };
    assert_eq!(strip(&indexed), strip(&linear));
    assert_eq!(channels.values().map(|(_, s)| s.count).sum::<u64>(), 400);
    assert!(linear.passed > without.len() as u64 * 9 / 10 && linear.passed < without.len() as u64);
}

/// Where each record of a file's data section starts, from the header record to the data-end.
fn record_starts(bytes: &[u8]) -> Vec<usize> {
    let mut starts = Vec::new();
    let mut at = 8;
    while at + 9 <= bytes.len() {
        starts.push(at);
        if bytes[at] == 0x0F {
            break;
        }
        let len = u64::from_le_bytes(bytes[at + 1..at + 9].try_into().unwrap()) as usize;
        at += 9 + len;
    }
    starts
}

#[test]
fn a_file_cut_short_is_read_up_to_its_last_whole_record() {
    let wants = [
        ("/pose", Want::Payload),
        ("/camera/image/compressed", Want::Head(12)),
    ];
    let whole = camera_bag(true);
    let mut all = recorder(&wants);
    read_messages(&Bytes(&whole), &mut all).unwrap();
    let starts = record_starts(&whole);
    let chunks: Vec<usize> = starts
        .iter()
        .copied()
        .filter(|&at| whole[at] == 0x06)
        .collect();
    assert!(chunks.len() >= 4, "{} chunks", chunks.len());
    // Cut inside the third chunk: the first two are read, the rest is lost and said so.
    let third = chunks[2];
    let cut_at = third + 5000;
    let mut cut = recorder(&wants);
    let read = read_messages(&Bytes(&whole[..cut_at]), &mut cut).unwrap();
    let expected = CutShort {
        readable: third as u64,
        file_len: cut_at as u64,
        messages_lost: true,
    };
    assert_eq!(read.cut_short, Some(expected));
    assert_eq!(
        expected.to_string(),
        format!(
            "the file is cut short (a recording that did not finish, or a damaged file): its last \
             5000 bytes, from byte {third} on, are not a whole record, and the messages in them are \
             lost; the messages before were read"
        )
    );
    assert!(!cut.seen.is_empty() && cut.seen.len() < all.seen.len());
    assert_eq!(cut.seen[..], all.seen[..cut.seen.len()]);
    // Cut between two records: every record was read, none lost.
    let mut at_boundary = recorder(&wants);
    let read = read_messages(&Bytes(&whole[..third]), &mut at_boundary).unwrap();
    let expected = CutShort {
        readable: third as u64,
        file_len: third as u64,
        messages_lost: false,
    };
    assert_eq!(read.cut_short, Some(expected));
    assert_eq!(
        expected.to_string(),
        format!(
            "the file ends at byte {third} without its data-end record (a recording that did not \
             finish?); every message in it was read"
        )
    );
    assert_eq!(at_boundary.seen, cut.seen);
    // Cut before any channel is declared: nothing to read, refused.
    let first = chunks[0];
    assert!(read_messages(&Bytes(&whole[..first + 100]), &mut recorder(&wants)).is_err());
}

/// What a pass over `bytes` finds: the bytes it read, the messages it saw, the channels and cut it
/// returned; `linear` reads from the start, else as `read_messages` does.
fn pass_over(bytes: &[u8], wants: &[(&str, Want)], linear: bool) -> (u64, Vec<Seen>, FileRead) {
    let source = Counting {
        bytes: Bytes(bytes),
        read: AtomicU64::new(0),
    };
    let mut seen = recorder(wants);
    let read = if linear {
        super::linear::read(&source, &super::linear::walk(&source).chunks, &mut seen)
    } else {
        read_messages(&source, &mut seen)
    };
    (
        source.read.load(Ordering::Relaxed),
        seen.seen,
        read.unwrap(),
    )
}

#[test]
fn a_file_cut_short_with_message_indexes_is_read_as_an_indexed_one() {
    // What listing a bag's topics asks: a camera's first frame, nothing of the poses.
    let listing = [("/camera/image/compressed", Want::First(16))];
    let poses = [("/pose", Want::Payload)];
    let whole = camera_bag(false);
    let starts = record_starts(&whole);
    let chunks: Vec<usize> = (starts.iter().copied())
        .filter(|&at| whole[at] == 0x06)
        .collect();
    // Cut inside the fourth chunk; cut inside the second message index after the third; not cut.
    let indexes: Vec<usize> = (starts.iter().copied())
        .filter(|&at| at > chunks[2] && at < chunks[3] && whole[at] == 0x07)
        .collect();
    assert_eq!(
        indexes.len(),
        2,
        "an index per channel after the third chunk"
    );
    for len in [chunks[3] + 5000, indexes[1] + 12, whole.len()] {
        let file = &whole[..len];
        for wants in [&listing[..], &poses[..]] {
            let (read, seen, found) = pass_over(file, wants, false);
            let (read_from_start, seen_from_start, found_from_start) = pass_over(file, wants, true);
            assert_eq!(seen, seen_from_start, "cut at {len}");
            assert_eq!(found.channels, found_from_start.channels, "cut at {len}");
            assert_eq!(found.cut_short, found_from_start.cut_short, "cut at {len}");
            if wants == &listing[..] {
                // The first chunk (for the channels it declares, and the camera's first frame),
                // then only the record headers and message indexes of the rest — but a last chunk
                // whose indexes are cut, read for its declarations and to count its messages;
                // from the start, every chunk.
                let last_read_whole = if len == indexes[1] + 12 {
                    2 * (chunks[3] - chunks[2])
                } else {
                    0
                };
                let most = chunks[1] + last_read_whole + 64 * 1024;
                assert!(read < most as u64, "{read} bytes read of {len}");
                assert!(read_from_start > len as u64 * 9 / 10);
            }
        }
    }
}

#[test]
fn a_frame_read_again_is_its_whole_payload() {
    let bag = camera_bag(true);
    let mut frames = recorder(&[("/camera/image/compressed", Want::Head(12))]);
    read_messages(&Bytes(&bag), &mut frames).unwrap();
    let mut cache = ChunkCache::default();
    for (k, (_, _, head, at)) in frames.seen.iter().enumerate() {
        assert_eq!(head.len(), 12);
        assert_eq!(at.len(), 50_000);
        let payload = read_payload(&Bytes(&bag), at, &mut cache).unwrap();
        assert_eq!(&payload[..12], &head[..]);
        let k = (3 * k) as u8;
        assert!(payload.iter().enumerate().all(|(i, &b)| b == (i as u8) ^ k));
    }
}

#[test]
fn a_damaged_file_without_a_summary_is_refused_or_read_never_panicked_on() {
    // Bytes of the record headers, chunk headers and message indexes changed at random, the file
    // cut anywhere: whichever pass reads it, it ends in messages or an error.
    let whole = camera_bag(false);
    let starts = record_starts(&whole);
    let mut rng = crate::rng::SplitMix64::new(7);
    let wants = [
        ("/camera/image/compressed", Want::First(16)),
        ("/pose", Want::Payload),
    ];
    for _ in 0..300 {
        let mut bytes = whole.clone();
        for _ in 0..4 {
            let record = starts[(rng.next_u64() % starts.len() as u64) as usize];
            let at = record + (rng.next_u64() % 40) as usize;
            if at < bytes.len() {
                bytes[at] = rng.next_u64() as u8;
            }
        }
        let len = 8 + (rng.next_u64() % (bytes.len() as u64 - 8)) as usize;
        let _ = read_messages(&Bytes(&bytes[..len]), &mut recorder(&wants));
    }
}
