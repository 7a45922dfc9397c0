//! ROS 2 bag import speed: an MCAP file of 1,000,000 `geometry_msgs/msg/PoseStamped` messages
//! (500,000 for the pusher and 500,000 for the object, 1 kHz each for 500 s, uncompressed chunks
//! with CRCs, as `ros2 bag record` writes them by default), written in the setup with the Rust
//! `mcap` writer. Target (issue 15): under 2 s, reading, decoding, cleaning and resampling.
//!
//! Run: `cargo bench -p pushlab-core --bench bag`. Under `cargo test` it runs once on 10,000
//! messages.

// The platform's sin, cos and hypot are fine for synthetic poses here; the core's own calls
// go through pushlab_core::math (its clippy.toml).
#![allow(clippy::disallowed_methods)]
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::BTreeMap;
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use pushlab_core::recording::bag::{self, ImportOptions, TopicSpec, encode_pose_stamped};

const MESSAGES: u64 = 1_000_000;
/// Under `cargo test` (no `--bench`) the bench runs once on a bag this much smaller, so that the
/// test run does not write a 131 MB file.
const TEST_MODE_DIVISOR: u64 = 100;
const RATE_HZ: u64 = 1_000;

fn write_bag(path: &Path, messages: u64) {
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut writer = mcap::Writer::new(file).unwrap();
    let schema = writer
        .add_schema("geometry_msgs/msg/PoseStamped", "ros2msg", b"")
        .unwrap();
    let none = BTreeMap::new();
    let pusher = writer
        .add_channel(schema, "/pusher/pose", "cdr", &none)
        .unwrap();
    let object = writer
        .add_channel(schema, "/object/pose", "cdr", &none)
        .unwrap();
    let base = 1_700_000_000_000_000_000u64;
    for i in 0..messages / 2 {
        let ns = base + i * (1_000_000_000 / RATE_HZ);
        let t = i as f64 / RATE_HZ as f64;
        for (channel, x, y, yaw) in [
            (pusher, 0.3 + 0.01 * t, (0.7 * t).sin() * 0.01, 0.0),
            (
                object,
                0.35 + 0.01 * t,
                (0.3 * t).cos() * 0.02,
                (0.05 * t).sin() * 3.0,
            ),
        ] {
            let data = encode_pose_stamped(ns + 1_000, "world", x, y, yaw);
            let header = mcap::records::MessageHeader {
                channel_id: channel,
                sequence: i as u32,
                log_time: ns,
                publish_time: ns,
            };
            writer.write_to_known_channel(&header, &data).unwrap();
        }
    }
    writer.finish().unwrap();
}

fn bench(c: &mut Criterion) {
    let dir = std::env::temp_dir().join(format!("pushlab-bench-bag-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("poses.mcap");
    let measuring = std::env::args().any(|a| a == "--bench");
    write_bag(
        &path,
        if measuring {
            MESSAGES
        } else {
            MESSAGES / TEST_MODE_DIVISOR
        },
    );
    let pusher: TopicSpec = "/pusher/pose".parse().unwrap();
    let object: TopicSpec = "/object/pose".parse().unwrap();
    let once = bag::import(&path, &pusher, &object, ImportOptions::default()).unwrap();
    eprintln!(
        "bag: {:.0} MB, {} frame(s) at {} Hz",
        std::fs::metadata(&path).unwrap().len() as f64 / 1e6,
        once.pushes[0].trajectory.len(),
        once.rate_hz
    );
    let mut group = c.benchmark_group("bag");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(15));
    group.bench_function("bag_import_1m", |b| {
        b.iter(|| {
            black_box(bag::import(&path, &pusher, &object, ImportOptions::default()).unwrap())
        });
    });
    group.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);
