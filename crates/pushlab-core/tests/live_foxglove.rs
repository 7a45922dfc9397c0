//! The live client against a real peer: the official Foxglove SDK's WebSocket server (the
//! `foxglove` crate), on a free local port. It must negotiate `foxglove.sdk.v1`, list the channels
//! the server advertises, subscribe, read every message with its log time, decode the poses in
//! them (a CDR PoseStamped and a JSON pose), and see a channel withdrawn.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::collections::BTreeMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use foxglove::{ChannelBuilder, Context, PartialMetadata, Schema, WebSocketServer};
use pushlab_core::live::{LiveClient, LiveError, LiveEvent, PoseReading, RecordError, Recorder};
use pushlab_core::recording::bag::{self, encode_pose_stamped};

/// The pose logged as message `k`: its stamp and x, y, yaw.
fn pose(k: u64) -> (u64, f64, f64, f64) {
    (
        1_700_000_000_000_000_000 + k * 50_000_000,
        0.001 * k as f64,
        -0.002 * k as f64,
        0.01 * k as f64,
    )
}

fn json_pose(k: u64) -> Vec<u8> {
    let (stamp, x, y, yaw) = pose(k);
    let (s, c) = (yaw / 2.0).sin_cos();
    format!(
        r#"{{"header":{{"stamp":{{"sec":{},"nanosec":{}}},"frame_id":"table"}},
            "pose":{{"position":{{"x":{x},"y":{y},"z":0}},"orientation":{{"x":0,"y":0,"z":{s},"w":{c}}}}}}}"#,
        stamp / 1_000_000_000,
        stamp % 1_000_000_000
    )
    .into_bytes()
}

#[test]
fn the_foxglove_sdks_server_streams_poses_the_client_reads() {
    let context = Context::new();
    let server = WebSocketServer::new()
        .name("pushlab test robot")
        .bind("127.0.0.1", 0)
        .context(&context)
        .start_blocking()
        .expect("the SDK's server starts");
    let pusher = ChannelBuilder::new("/pusher")
        .context(&context)
        .message_encoding("json")
        .schema(Schema::new("pushlab.Pose", "jsonschema", b"{}".to_vec()))
        .build_raw()
        .expect("pusher channel");
    let object = ChannelBuilder::new("/object")
        .context(&context)
        .message_encoding("cdr")
        .schema(Schema::new(
            "geometry_msgs/msg/PoseStamped",
            "ros2msg",
            b"std_msgs/Header header\ngeometry_msgs/Pose pose\n".to_vec(),
        ))
        .build_raw()
        .expect("object channel");

    let url = format!("ws://127.0.0.1:{}", server.port());
    let mut client = LiveClient::connect(&url, Duration::from_millis(200)).expect("connects");
    assert_eq!(client.subprotocol(), "foxglove.sdk.v1");
    let deadline = Instant::now() + Duration::from_secs(10);
    let mut name = None;
    while (name.is_none() || client.channel_of("/object").is_none()) && Instant::now() < deadline {
        if let Some(LiveEvent::ServerInfo { name: n }) = client.next_event().expect("reads") {
            name = Some(n);
        }
    }
    assert_eq!(name.as_deref(), Some("pushlab test robot"));
    let (pusher_id, object_id) = (
        client.channel_of("/pusher").expect("advertised").id,
        client.channel_of("/object").expect("advertised").id,
    );
    let object_channel = client.channel_of("/object").unwrap().clone();
    assert_eq!(object_channel.schema_name, "geometry_msgs/msg/PoseStamped");
    assert_eq!(object_channel.schema_encoding.as_deref(), Some("ros2msg"));
    let readings = [
        (
            pusher_id,
            PoseReading::for_channel(client.channel_of("/pusher").unwrap(), None).unwrap(),
        ),
        (
            object_id,
            PoseReading::for_channel(&object_channel, None).unwrap(),
        ),
    ];
    client.subscribe(pusher_id).unwrap();
    client.subscribe(object_id).unwrap();

    // The robot logs a pose on each channel every 5 ms until told to stop (a message logged before
    // the subscription reached the server is not sent: the test checks what arrives).
    let stop = Arc::new(AtomicBool::new(false));
    let robot = {
        let stop = Arc::clone(&stop);
        let (pusher, object) = (Arc::clone(&pusher), Arc::clone(&object));
        std::thread::spawn(move || {
            let mut k = 0;
            while !stop.load(Ordering::Relaxed) && k < 2000 {
                let (stamp, x, y, yaw) = pose(k);
                let at = PartialMetadata::with_log_time(stamp + 1_000);
                pusher.log_with_meta(&json_pose(k), at);
                object.log_with_meta(&encode_pose_stamped(stamp, "table", x, y, yaw), at);
                k += 1;
                std::thread::sleep(Duration::from_millis(5));
            }
        })
    };
    // Every message is recorded as it arrives; a copy of the file taken after a flush is what a
    // crash at that moment leaves.
    let dir = std::env::temp_dir().join(format!("pushlab-live-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let record_path = dir.join("session.mcap");
    let mut recorder = Recorder::create(&record_path).expect("a new file");
    let mut crashed: Option<Vec<u8>> = None;
    let mut received: BTreeMap<u64, Vec<(u64, u64)>> = BTreeMap::new();
    while received.values().map(Vec::len).sum::<usize>() < 40 && Instant::now() < deadline {
        let Some(LiveEvent::Message {
            channel,
            log_time_ns,
            payload,
        }) = client.next_event().expect("reads")
        else {
            continue;
        };
        let reading = &readings
            .iter()
            .find(|(id, _)| *id == channel)
            .expect("ours")
            .1;
        let got = reading
            .read_single(&payload)
            .expect("decodes")
            .expect("a pose");
        let k = (got.stamp_ns - pose(0).0) / 50_000_000;
        let (stamp, x, y, yaw) = pose(k);
        assert_eq!(got.stamp_ns, stamp, "the header stamp, not the log time");
        assert!(
            (got.x - x).abs() < 1e-12 && (got.y - y).abs() < 1e-12,
            "{got:?} vs {k}"
        );
        assert!((got.yaw - yaw).abs() < 1e-9, "{got:?} vs {k}");
        received
            .entry(channel)
            .or_default()
            .push((k, log_time_ns - stamp));
        let advertised = client.channel(channel).expect("advertised");
        recorder
            .write(advertised, log_time_ns, &payload)
            .expect("recorded");
        if recorder.messages() == 20 {
            recorder.flush().expect("flushed");
            crashed = Some(std::fs::read(&record_path).unwrap());
        }
    }
    for id in [pusher_id, object_id] {
        let messages = received.get(&id).map_or(&[][..], Vec::as_slice);
        assert!(messages.len() >= 10, "channel {id}: {messages:?}");
        assert!(
            messages.windows(2).all(|w| w[1].0 == w[0].0 + 1),
            "in order, none lost: {messages:?}"
        );
        assert!(
            messages.iter().all(|&(_, lag)| lag == 1_000),
            "the log time kept: {messages:?}"
        );
    }

    // The recording: both topics, every message received, at the server's log times.
    let recorded = recorder.finish().expect("finished");
    assert_eq!(
        (recorded.channels as usize, recorded.messages),
        (2, 40.max(recorded.messages))
    );
    let listing = bag::topics(&record_path).expect("the recording opens as a bag");
    assert!(listing.cut_short.is_empty(), "{:?}", listing.cut_short);
    for (topic, id, type_name) in [
        ("/pusher", pusher_id, "pushlab.Pose"),
        ("/object", object_id, "geometry_msgs/msg/PoseStamped"),
    ] {
        let info = listing
            .topics
            .iter()
            .find(|t| t.topic == topic)
            .expect(topic);
        assert_eq!(info.type_name, type_name);
        assert_eq!(info.count, received[&id].len() as u64, "{topic}");
        assert_eq!(info.first_ns, pose(received[&id][0].0).0 + 1_000, "{topic}");
    }
    // The crash copy opens too, cut short, with the 20 messages flushed before it.
    let crash = crashed.expect("a copy after 20 messages");
    let listing = bag::topics_bytes(&crash, &dir.join("crashed.mcap")).expect("opens cut short");
    assert!(!listing.cut_short.is_empty(), "said cut short");
    assert_eq!(listing.topics.iter().map(|t| t.count).sum::<u64>(), 20);
    // A file that exists is never written over.
    let error = Recorder::create(&record_path).err().expect("exists");
    assert!(matches!(error, RecordError::Exists { .. }), "{error}");
    assert!(error.to_string().contains("already exists"), "{error}");
    let _ = std::fs::remove_dir_all(&dir);

    // The object's channel withdrawn: the client forgets it.
    object.close();
    let mut withdrawn = false;
    while !withdrawn && Instant::now() < deadline {
        withdrawn = matches!(client.next_event().expect("reads"),
            Some(LiveEvent::Unadvertised(ids)) if ids.contains(&object_id));
    }
    assert!(withdrawn, "the unadvertise reached the client");
    assert!(client.channel_of("/object").is_none());
    stop.store(true, Ordering::Relaxed);
    robot.join().unwrap();
    client.close();
    let _ = server.stop();
}

#[test]
fn an_address_without_a_server_or_not_ws_is_an_error_naming_it() {
    // A port that was free a moment ago: nothing listens there.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let url = format!("ws://127.0.0.1:{port}");
    let error = LiveClient::connect(&url, Duration::from_millis(500))
        .err()
        .expect("refused");
    assert!(matches!(error, LiveError::Connect { .. }), "{error}");
    assert!(
        error
            .to_string()
            .starts_with(&format!("{url}: cannot connect: ")),
        "{error}"
    );
    let error = LiveClient::connect("http://127.0.0.1:1", Duration::from_millis(200))
        .err()
        .expect("not ws");
    assert!(
        error.to_string().contains("expected ws://HOST:PORT"),
        "{error}"
    );

    // An HTTP server that is not a WebSocket one answers the upgrade with a plain 200.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let http = std::thread::spawn(move || {
        use std::io::{Read, Write};
        let (mut stream, _) = listener.accept().unwrap();
        let mut buffer = [0u8; 2048];
        let _ = stream.read(&mut buffer);
        let _ = stream.write_all(b"HTTP/1.1 200 OK\r\ncontent-length: 2\r\n\r\nhi");
    });
    let url = format!("ws://127.0.0.1:{port}");
    let error = LiveClient::connect(&url, Duration::from_secs(2))
        .err()
        .expect("not a server");
    assert!(
        error
            .to_string()
            .starts_with(&format!("{url}: not a Foxglove WebSocket server: ")),
        "{error}"
    );
    http.join().unwrap();
}
