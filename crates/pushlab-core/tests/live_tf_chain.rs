//! A robot arm's tip followed live through its TF tree, against a real peer (the Foxglove SDK's
//! WebSocket server): `world → base` on `/tf` at 50 Hz, `base → tool0` on `/tf` at 100 Hz in
//! messages of their own, `tool0 → tip` on `/tf_static`, and the object as a PoseStamped. The
//! frames the live grid gives are, bit for bit, the first frames the recording's import gives for
//! `/tf:tip` — the chain composed, timed and interpolated by the same rules — and the session says
//! which chain it follows.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::sync::Arc;
use std::time::{Duration, Instant};

use foxglove::{ChannelBuilder, Context, PartialMetadata, RawChannel, Schema, WebSocketServer};
use pushlab_core::live::{LiveGrid, LiveSession, SessionEvent};
use pushlab_core::recording::bag::{
    ImportOptions, TopicSpec, Transform, encode_pose_stamped, encode_tf_message, import,
};

fn channel(context: &Arc<Context>, topic: &str, schema: &str) -> Arc<RawChannel> {
    ChannelBuilder::new(topic)
        .context(context)
        .message_encoding("cdr")
        .schema(Schema::new(schema, "ros2msg", b"".to_vec()))
        .build_raw()
        .unwrap()
}

fn tf(stamp_ns: u64, parent: &str, child: &str, xyz: [f64; 3], yaw: f64) -> Vec<u8> {
    let (s, c) = (yaw / 2.0).sin_cos();
    encode_tf_message(&[Transform {
        stamp_ns,
        parent: parent.as_bytes(),
        child: child.as_bytes(),
        translation: xyz,
        rotation: [0.0, 0.0, s, c],
    }])
}

#[test]
fn a_tip_on_a_tf_tree_is_learned_live_as_its_recording_imports() {
    let context = Context::new();
    let server = WebSocketServer::new()
        .name("arm")
        .bind("127.0.0.1", 0)
        .context(&context)
        .start_blocking()
        .unwrap();
    let url = format!("ws://127.0.0.1:{}", server.port());
    let tf_topic = channel(&context, "/tf", "tf2_msgs/msg/TFMessage");
    let tf_static = channel(&context, "/tf_static", "tf2_msgs/msg/TFMessage");
    let object = channel(&context, "/object", "geometry_msgs/msg/PoseStamped");

    let arm = std::thread::spawn(move || {
        while !(tf_topic.has_sinks() && tf_static.has_sinks() && object.has_sinks()) {
            std::thread::sleep(Duration::from_millis(5));
        }
        let t0 = 1_700_000_000_000_000_000u64;
        for k in 0..150u64 {
            let ns = t0 + k * 10_000_000;
            let at = |ns| PartialMetadata::with_log_time(ns);
            let t = k as f64 * 0.01;
            if k % 10 == 2 {
                // Sent again now and then, as a latched topic is to each new subscriber.
                tf_static.log_with_meta(&tf(0, "tool0", "tip", [0.05, 0.0, 0.0], 0.0), at(ns));
            }
            if k % 2 == 0 {
                let base = [0.2 + 0.1 * t, -0.05 * t + 0.01 * (3.0 * t).sin(), 0.0];
                tf_topic.log_with_meta(&tf(ns, "world", "base", base, 0.4 * t), at(ns));
            }
            let tool_ns = ns + 3_000_000;
            let tool = [0.3 + 0.2 * t, 0.1 * (2.0 * t).cos(), 0.5];
            tf_topic.log_with_meta(&tf(tool_ns, "base", "tool0", tool, -0.3 * t), at(tool_ns));
            let object_pose = encode_pose_stamped(ns + 1_000_000, "world", 0.6, 0.1 * t, 0.2);
            object.log_with_meta(&object_pose, at(ns + 1_000_000));
            std::thread::sleep(Duration::from_millis(10));
        }
        std::thread::sleep(Duration::from_millis(300));
        let _ = server.stop();
    });

    let dir = std::env::temp_dir().join(format!("pushlab-live-tf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let record = dir.join("arm.mcap");
    let _ = std::fs::remove_file(&record);
    let mut session =
        LiveSession::open(&url, "/tf:tip", "/object", Some(&record), &|| false).expect("connects");
    let rate = 50.0;
    let mut grid = LiveGrid::new(rate);
    let mut frames = Vec::new();
    let mut said = Vec::new();
    let started = Instant::now();
    while started.elapsed() < Duration::from_secs(10) {
        match session.next(&|| false).unwrap() {
            Some(SessionEvent::Pose {
                stream,
                pose,
                log_time_ns,
            }) => {
                grid.push(stream, &pose, log_time_ns).unwrap();
                frames.extend(grid.take_frames());
            }
            Some(SessionEvent::Said(s)) => said.push(s),
            Some(SessionEvent::Lost(_)) => break,
            _ => {}
        }
    }
    arm.join().unwrap();
    session.finish().unwrap();
    assert!(
        said.contains(&"pusher /tf: following tip through tool0 → base → world".to_owned()),
        "{said:?}"
    );
    assert!(frames.len() > 50, "{} frames", frames.len());

    let spec = |s: &str| s.parse::<TopicSpec>().unwrap();
    let options = ImportOptions {
        rate_hz: Some(rate),
        split_gap_s: None,
    };
    let imported = import(&record, &spec("/tf:tip"), &spec("/object"), options).unwrap();
    let trajectory = &imported.pushes[0].trajectory;
    assert!(trajectory.len() >= frames.len());
    for (k, live) in frames.iter().enumerate() {
        let from_file = &trajectory.frames[k];
        assert_eq!(
            format!("{live:?}"),
            format!("{from_file:?}"),
            "frame {k}: live and imported differ"
        );
    }
    // The pusher moved: not one pose repeated.
    assert_ne!(
        format!("{:?}", frames[0]),
        format!("{:?}", frames[frames.len() - 1])
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Listing a server's topics (the Connect form's List topics) offers each frame of its TF tree:
/// the moving ones `/tf` carries and the static ones `/tf_static` carries, reached through `/tf`.
#[test]
fn listing_a_servers_topics_offers_every_frame_of_its_tf_tree() {
    let context = Context::new();
    let server = WebSocketServer::new()
        .name("arm")
        .bind("127.0.0.1", 0)
        .context(&context)
        .start_blocking()
        .unwrap();
    let url = format!("ws://127.0.0.1:{}", server.port());
    let tf_topic = channel(&context, "/tf", "tf2_msgs/msg/TFMessage");
    let tf_static = channel(&context, "/tf_static", "tf2_msgs/msg/TFMessage");
    let _object = channel(&context, "/object", "geometry_msgs/msg/PoseStamped");
    let stop = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    let arm = std::thread::spawn(move || {
        let mut ns = 1_700_000_000_000_000_000u64;
        while !flag.load(std::sync::atomic::Ordering::Relaxed) {
            let at = PartialMetadata::with_log_time(ns);
            tf_topic.log_with_meta(&tf(ns, "world", "base", [0.0; 3], 0.0), at);
            tf_topic.log_with_meta(&tf(ns, "base", "tool0", [0.3, 0.0, 0.5], 0.0), at);
            tf_static.log_with_meta(&tf(0, "tool0", "tip", [0.05, 0.0, 0.0], 0.0), at);
            ns += 20_000_000;
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = server.stop();
    });
    let listed = pushlab_core::live::list_topics(&url, Duration::from_millis(600), &|| false);
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    arm.join().unwrap();
    let (name, topics) = listed.unwrap();
    assert_eq!(name.as_deref(), Some("arm"));
    let offered: Vec<String> = pushlab_core::recording::bag::choice::candidates(&topics)
        .iter()
        .map(ToString::to_string)
        .collect();
    assert_eq!(offered, ["/tf:base", "/tf:tool0", "/tf:tip", "/object"]);
}
