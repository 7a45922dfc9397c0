//! `pushlab live` against a real peer: the Foxglove SDK's WebSocket server, in this test process,
//! logging a pusher (JSON) and an object (CDR PoseStamped) every 10 ms. The command must print a
//! line a second with the latest poses, write every message to `--record`, and the recording must
//! open with `pushlab validate` as a bag with both topics; a topic that is not advertised, or an
//! existing file to record to, is an error naming it.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod cli_common;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use cli_common::{pushlab, temp_dir};
use foxglove::{ChannelBuilder, Context, PartialMetadata, Schema, WebSocketServer};
use pushlab_core::recording::bag::encode_pose_stamped;

/// A server logging poses until the returned flag is set; its address.
fn robot() -> (String, Arc<AtomicBool>, std::thread::JoinHandle<()>) {
    let context = Context::new();
    let server = WebSocketServer::new()
        .name("test robot")
        .bind("127.0.0.1", 0)
        .context(&context)
        .start_blocking()
        .expect("the SDK's server starts");
    let pusher = ChannelBuilder::new("/pusher")
        .context(&context)
        .message_encoding("json")
        .schema(Schema::new("pushlab.Pose", "jsonschema", b"{}".to_vec()))
        .build_raw()
        .unwrap();
    let object = ChannelBuilder::new("/object")
        .context(&context)
        .message_encoding("cdr")
        .schema(Schema::new(
            "geometry_msgs/msg/PoseStamped",
            "ros2msg",
            b"".to_vec(),
        ))
        .build_raw()
        .unwrap();
    let url = format!("ws://127.0.0.1:{}", server.port());
    let stop = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    let logging = std::thread::spawn(move || {
        // The context lives as long as the robot logs: its channels are advertised while it does.
        let _context = context;
        let mut k = 0u64;
        while !flag.load(Ordering::Relaxed) {
            let stamp = 1_700_000_000_000_000_000 + k * 10_000_000;
            let json = format!(
                r#"{{"header":{{"stamp":{{"sec":{},"nanosec":{}}}}},"pose":{{"position":{{"x":0.25,"y":-0.5,"z":0}},"orientation":{{"x":0,"y":0,"z":0,"w":1}}}}}}"#,
                stamp / 1_000_000_000,
                stamp % 1_000_000_000
            );
            let at = PartialMetadata::with_log_time(stamp);
            pusher.log_with_meta(json.as_bytes(), at);
            object.log_with_meta(&encode_pose_stamped(stamp, "table", 0.125, 0.5, 0.0), at);
            k += 1;
            std::thread::sleep(Duration::from_millis(10));
        }
        let _ = server.stop();
    });
    (url, stop, logging)
}

#[test]
fn live_prints_the_poses_and_records_every_message_to_a_bag() {
    let (url, stop, logging) = robot();
    let dir = temp_dir("pushlab-live", "record");
    let out = dir.join("session.mcap");
    let out_s = out.display().to_string();
    let run = pushlab(&[
        "live",
        &url,
        "--pusher",
        "/pusher",
        "--object",
        "/object",
        "--record",
        &out_s,
        "--duration",
        "2.5",
        "--json",
    ]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    assert!(
        run.stdout.contains(&format!(
            "connected to {url} (test robot, foxglove.sdk.v1): 2 channel(s), recording to {out_s}"
        )),
        "{}",
        run.stdout
    );
    let lines: Vec<serde_json::Value> = (run.stdout.lines())
        .filter(|l| l.starts_with('{'))
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert!(
        lines.len() >= 3,
        "a line a second and one at the end: {}",
        run.stdout
    );
    let last = lines.last().unwrap();
    assert_eq!(last["pusher"]["x"], 0.25);
    assert_eq!(last["object"]["y"], 0.5);
    let messages = last["messages"].as_u64().unwrap();
    assert!(messages > 100, "{messages} messages in 2.5 s at 2 × 100/s");
    assert!(
        run.stdout.contains(&format!(
            "recorded {messages} message(s) on 2 channel(s) to {out_s}"
        )),
        "{}",
        run.stdout
    );

    // The recording is a bag: both topics, every message.
    let validate = pushlab(&["validate", &out_s]);
    assert_eq!(validate.code, 0, "{}\n{}", validate.stdout, validate.stderr);
    assert!(
        validate
            .stdout
            .contains("/object geometry_msgs/msg/PoseStamped, "),
        "{}",
        validate.stdout
    );
    let counts: u64 = (validate.stdout.lines())
        .filter_map(|l| {
            l.split(", ")
                .nth(1)?
                .strip_suffix(" messages")?
                .parse::<u64>()
                .ok()
        })
        .sum();
    assert_eq!(counts, messages, "{}", validate.stdout);

    // The recording imports as any bag, the JSON pusher read as the live session read it.
    let setting = dir.join("box.json");
    std::fs::write(
        &setting,
        r#"{"name": "live-box", "object": {"shape": "box", "width": 0.1, "length": 0.12},
            "pusher_radius": 0.005, "trajectories": []}"#,
    )
    .unwrap();
    let set = dir.join("set");
    let import = pushlab(&[
        "import",
        &out_s,
        "--pusher",
        "/pusher",
        "--object",
        "/object",
        "--setting",
        setting.to_str().unwrap(),
        "--out",
        set.to_str().unwrap(),
    ]);
    assert_eq!(import.code, 0, "{}\n{}", import.stdout, import.stderr);
    let csv = std::fs::read_dir(&set)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "csv"))
        .expect("a push written");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("time,robot_x,robot_y,object_x,object_y,object_theta")
    );
    let first: Vec<f64> = (lines.next().unwrap().split(','))
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(first[1..], [0.25, -0.5, 0.125, 0.5, 0.0], "{text:.200}");

    // Never over an existing file; a topic that is not advertised is named with those that are.
    let again = pushlab(&[
        "live",
        &url,
        "--pusher",
        "/pusher",
        "--object",
        "/object",
        "--record",
        &out_s,
        "--duration",
        "1",
    ]);
    assert_eq!(again.code, 1);
    assert!(again.stderr.contains("already exists"), "{}", again.stderr);
    let missing = pushlab(&[
        "live",
        &url,
        "--pusher",
        "/pusher",
        "--object",
        "/box",
        "--duration",
        "1",
    ]);
    assert_eq!(missing.code, 1);
    assert!(
        missing
            .stderr
            .contains("no topic /box advertised within 5 s; the server's topics: ")
            && missing
                .stderr
                .contains("/object (geometry_msgs/msg/PoseStamped)"),
        "{}",
        missing.stderr
    );
    stop.store(true, Ordering::Relaxed);
    logging.join().unwrap();
}
