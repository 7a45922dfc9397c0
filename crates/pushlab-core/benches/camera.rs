//! Cameras (issue 23's two targets):
//!
//! - `camera_seek_jpeg_720p`: seek to a frame of a 1280×720 JPEG image sequence (a native set's
//!   `NAME.images/`, 40 frames of camera-like noise) and have it decoded and ready to draw, through
//!   the decoder the app uses (`camera::FrameDecoder`: its worker reads the file and decodes it,
//!   the caller waits); the cache is cleared before each seek so that every one reads and decodes.
//!   Target ≤ 15 ms.
//! - `bag_import_poses_among_images`: import the pusher and object poses (PoseStamped, 1 kHz each)
//!   of a bag that is 95 % image bytes (a 30 Hz CompressedImage topic of 170 kB frames), written
//!   as `ros2 bag record` leaves such a bag: chunks of about 1 MB with message indexes and a
//!   summary, uncompressed (its default zstd stores chunks of JPEG bytes as they are, since they do
//!   not shrink). Throughput in bytes of bag; target ≥ 2 GB/s.
//!
//! Run: `cargo bench -p pushlab-core --bench camera`. Under `cargo test` (no `--bench`), each runs
//! once on small data: 2 frames, a 2 s bag.

// The platform's sin, cos and hypot are fine for synthetic poses here; the core's own calls
// go through pushlab_core::math (its clippy.toml).
#![allow(clippy::disallowed_methods)]
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::BTreeMap;
use std::hint::black_box;
use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pushlab_core::recording::bag::{
    self, ImportOptions, TopicSpec, encode_compressed_image, encode_pose_stamped,
};
use pushlab_core::recording::camera::FrameDecoder;
use pushlab_core::recording::native::images::read_cameras;

/// Bytes of each "JPEG" of the camera bag: 30 of them a second make 95 % of its bytes.
const JPEG_BYTES: usize = 170_000;

/// Whether criterion measures (`cargo bench`) rather than checks once (`cargo test`).
fn measuring() -> bool {
    std::env::args().any(|a| a == "--bench")
}

/// Pseudo-random bytes, the same on every run.
fn noise(seed: &mut u64, out: &mut [u8]) {
    for byte in out {
        *seed ^= *seed << 13;
        *seed ^= *seed >> 7;
        *seed ^= *seed << 17;
        *byte = (*seed >> 24) as u8;
    }
}

/// `frames` 1280×720 JPEGs of low noise over gradients (about 150 kB each, as a camera's) beside
/// `dir/push.csv`, with their frame list.
fn write_sequence(dir: &Path, frames: usize) {
    let images = dir.join("push.images");
    std::fs::create_dir_all(&images).unwrap();
    std::fs::write(
        dir.join("push.csv"),
        "time,robot_x,robot_y,object_x,object_y,object_theta\n",
    )
    .unwrap();
    let mut list = String::from("time,file\n");
    let mut seed = 0x9E37_79B9_7F4A_7C15;
    let mut grain = vec![0u8; 1280 * 720];
    for k in 0..frames {
        noise(&mut seed, &mut grain);
        let image = image::RgbImage::from_fn(1280, 720, |x, y| {
            let g = grain[(y * 1280 + x) as usize] / 8;
            let channel = |v: u32| (v.min(223) as u8).wrapping_add(g);
            image::Rgb([channel(x / 6), channel(y / 3), channel(k as u32 * 5)])
        });
        let file = format!("{k:04}.jpg");
        image.save(images.join(&file)).unwrap();
        list.push_str(&format!("{},{file}\n", k as f64 / 30.0));
    }
    std::fs::write(images.join("frames.csv"), list).unwrap();
}

fn camera_seek(c: &mut Criterion) {
    let frames = if measuring() { 40 } else { 2 };
    let dir = std::env::temp_dir().join(format!("pushlab-bench-seek-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    write_sequence(&dir, frames);
    let stream = Arc::new(read_cameras(&dir.join("push.csv")).unwrap().remove(0));
    assert_eq!(stream.len(), frames);
    let decoder = FrameDecoder::default();
    let mut k = 0;
    c.bench_function("camera_seek_jpeg_720p", |b| {
        b.iter(|| {
            k = (k + 7) % frames;
            decoder.clear();
            let time = stream.times()[k];
            let frame = stream.frame_at(time).unwrap();
            let image = decoder.wait_for(&stream, frame, Duration::from_secs(10));
            let image = image.expect("decoded in time").expect("a readable frame");
            assert_eq!((image.width, image.height), (1280, 720));
            black_box(image)
        })
    });
    let _ = std::fs::remove_dir_all(&dir);
}

/// Writes the bag of `seconds` and returns its size in bytes.
fn write_camera_bag(path: &Path, seconds: u64) -> u64 {
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut writer = mcap::WriteOptions::new()
        .compression(None)
        .chunk_size(Some(1 << 20))
        .create(file)
        .unwrap();
    let none = BTreeMap::new();
    let pose = (writer.add_schema("geometry_msgs/msg/PoseStamped", "ros2msg", b"")).unwrap();
    let image = (writer.add_schema("sensor_msgs/msg/CompressedImage", "ros2msg", b"")).unwrap();
    let pusher = writer
        .add_channel(pose, "/pusher/pose", "cdr", &none)
        .unwrap();
    let object = writer
        .add_channel(pose, "/object/pose", "cdr", &none)
        .unwrap();
    let camera = writer
        .add_channel(image, "/camera/image/compressed", "cdr", &none)
        .unwrap();
    let base = 1_700_000_000_000_000_000u64;
    let mut seed = 0x2545_F491_4F6C_DD1D;
    let mut jpeg = vec![0u8; JPEG_BYTES];
    for ms in 0..seconds * 1000 {
        let ns = base + ms * 1_000_000;
        let t = ms as f64 / 1000.0;
        for (channel, x, y, yaw) in [
            (pusher, 0.3 + 0.01 * t, (0.7 * t).sin() * 0.01, 0.0),
            (
                object,
                0.35 + 0.01 * t,
                (0.3 * t).cos() * 0.02,
                (0.05 * t).sin(),
            ),
        ] {
            let data = encode_pose_stamped(ns, "world", x, y, yaw);
            let header = mcap::records::MessageHeader {
                channel_id: channel,
                sequence: ms as u32,
                log_time: ns,
                publish_time: ns,
            };
            writer.write_to_known_channel(&header, &data).unwrap();
        }
        if ms % 33 == 0 {
            noise(&mut seed, &mut jpeg[..64]);
            let data = encode_compressed_image(ns, "camera", "jpeg", &jpeg);
            let header = mcap::records::MessageHeader {
                channel_id: camera,
                sequence: (ms / 33) as u32,
                log_time: ns,
                publish_time: ns,
            };
            writer.write_to_known_channel(&header, &data).unwrap();
        }
    }
    writer.finish().unwrap();
    drop(writer);
    std::fs::metadata(path).unwrap().len()
}

fn bag_import_among_images(c: &mut Criterion) {
    let seconds = if measuring() { 60 } else { 2 };
    let dir = std::env::temp_dir().join(format!("pushlab-bench-cambag-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("camera.mcap");
    let bytes = write_camera_bag(&path, seconds);
    let pusher: TopicSpec = "/pusher/pose".parse().unwrap();
    let object: TopicSpec = "/object/pose".parse().unwrap();
    let once = bag::import(&path, &pusher, &object, ImportOptions::default()).unwrap();
    let topics = &once.topics;
    let image_bytes: u64 = (topics.iter())
        .filter(|t| t.is_camera())
        .map(|t| t.count * JPEG_BYTES as u64)
        .sum();
    eprintln!(
        "camera bag: {:.0} MB, {:.0} % image bytes, {} frames at {} Hz",
        bytes as f64 / 1e6,
        100.0 * image_bytes as f64 / bytes as f64,
        once.pushes[0].trajectory.len(),
        once.rate_hz
    );
    let mut group = c.benchmark_group("camera_bag");
    group.throughput(Throughput::Bytes(bytes));
    if measuring() {
        group
            .sample_size(10)
            .measurement_time(Duration::from_secs(10));
    }
    group.bench_function("bag_import_poses_among_images", |b| {
        b.iter(|| {
            black_box(bag::import(&path, &pusher, &object, ImportOptions::default()).unwrap())
        })
    });
    group.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, camera_seek, bag_import_among_images);
criterion_main!(benches);
