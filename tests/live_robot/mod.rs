//! Test robots for the live tests: the Foxglove SDK's WebSocket server in the test process, with a
//! pusher's channel (JSON poses) and an object's (CDR PoseStamped), logging as each test needs —
//! holding still, pushing a sample-data push, or going away and coming back.

#![allow(dead_code, clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use foxglove::{
    ChannelBuilder, Context, PartialMetadata, RawChannel, Schema, WebSocketServer,
    WebSocketServerHandle,
};
use pushlab_core::recording::bag::encode_pose_stamped;

/// A robot's server on `port` (0: any free one) with its two channels: the pusher's JSON and the
/// object's CDR PoseStamped, advertised in that order or, with `object_first`, the other.
pub fn start_robot(
    port: u16,
    object_first: bool,
) -> (
    Arc<Context>,
    WebSocketServerHandle,
    Arc<RawChannel>,
    Arc<RawChannel>,
) {
    let context = Context::new();
    let server = WebSocketServer::new()
        .name("test robot")
        .bind("127.0.0.1", port)
        .context(&context)
        .start_blocking()
        .expect("the SDK's server starts");
    let pusher = || {
        ChannelBuilder::new("/pusher")
            .context(&context)
            .message_encoding("json")
            .schema(Schema::new("pushlab.Pose", "jsonschema", b"{}".to_vec()))
            .build_raw()
            .unwrap()
    };
    let object = || {
        ChannelBuilder::new("/object")
            .context(&context)
            .message_encoding("cdr")
            .schema(Schema::new(
                "geometry_msgs/msg/PoseStamped",
                "ros2msg",
                b"".to_vec(),
            ))
            .build_raw()
            .unwrap()
    };
    let (pusher, object) = if object_first {
        let o = object();
        (pusher(), o)
    } else {
        (pusher(), object())
    };
    (context, server, pusher, object)
}

/// What a test robot does with its two channels (the pusher's JSON, the object's CDR PoseStamped)
/// until the flag is set.
pub type Logging = Box<dyn FnOnce(&RawChannel, &RawChannel, &AtomicBool) + Send>;

/// A server whose robot logs as `log` says until the returned flag is set; its address.
pub fn robot_with(log: Logging) -> (String, Arc<AtomicBool>, std::thread::JoinHandle<()>) {
    let (context, server, pusher, object) = start_robot(0, false);
    let url = format!("ws://127.0.0.1:{}", server.port());
    let stop = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    let logging = std::thread::spawn(move || {
        // The context lives as long as the robot logs: its channels are advertised while it does.
        let _context = context;
        log(&pusher, &object, &flag);
        let _ = server.stop();
    });
    (url, stop, logging)
}

/// A JSON pose (the documented PoseStamped shape) stamped `stamp` ns.
pub fn json_pose(stamp: u64, x: f64, y: f64) -> String {
    format!(
        r#"{{"header":{{"stamp":{{"sec":{},"nanosec":{}}}}},"pose":{{"position":{{"x":{x},"y":{y},"z":0}},"orientation":{{"x":0,"y":0,"z":0,"w":1}}}}}}"#,
        stamp / 1_000_000_000,
        stamp % 1_000_000_000
    )
}

/// A robot holding still, logging the same poses every 10 ms.
pub fn robot() -> (String, Arc<AtomicBool>, std::thread::JoinHandle<()>) {
    robot_with(Box::new(|pusher, object, stop| {
        log_still(pusher, object, stop, None, Instant::now());
    }))
}

/// Logs the still poses every 10 ms until `stop` is set or `until` passes, stamped with the time
/// since `origin` (as a robot's clock runs on while its server is away).
pub fn log_still(
    pusher: &RawChannel,
    object: &RawChannel,
    stop: &AtomicBool,
    until: Option<Instant>,
    origin: Instant,
) {
    while !stop.load(Ordering::Relaxed) && until.is_none_or(|u| Instant::now() < u) {
        let since = u64::try_from(origin.elapsed().as_nanos()).unwrap();
        let stamp = 1_700_000_000_000_000_000 + since;
        let at = PartialMetadata::with_log_time(stamp);
        pusher.log_with_meta(json_pose(stamp, 0.25, -0.5).as_bytes(), at);
        object.log_with_meta(&encode_pose_stamped(stamp, "table", 0.125, 0.5, 0.0), at);
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// A robot pushing: a push of the sample data (10 Hz), sent once the client subscribed to both
/// channels, the object's stamps 3 ms after the pusher's, a row every `pause`.
pub fn pushing_robot(pause: Duration) -> (String, Arc<AtomicBool>, std::thread::JoinHandle<()>) {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("sample-data/box1-paper-ur-front/online_000.csv"),
    )
    .unwrap();
    let rows: Vec<Vec<f64>> = (text.lines().skip(1))
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    robot_with(Box::new(move |pusher, object, stop| {
        let subscribed = || pusher.has_sinks() && object.has_sinks();
        while !subscribed() && !stop.load(Ordering::Relaxed) {
            std::thread::sleep(Duration::from_millis(5));
        }
        for r in &rows {
            let stamp = 1_700_000_000_000_000_000 + (r[0] * 1e9).round() as u64;
            pusher.log_with_meta(
                json_pose(stamp, r[1], r[2]).as_bytes(),
                PartialMetadata::with_log_time(stamp),
            );
            let late = stamp + 3_000_000;
            object.log_with_meta(
                &encode_pose_stamped(late, "table", r[3], r[4], r[5]),
                PartialMetadata::with_log_time(late),
            );
            std::thread::sleep(pause);
        }
        while !stop.load(Ordering::Relaxed) {
            std::thread::sleep(Duration::from_millis(10));
        }
    }))
}

/// A robot whose server goes away after a second and comes back on the same port 0.7 s later,
/// advertising its channels in the other order (so their ids change), logging the still poses.
pub fn restarting_robot() -> (String, Arc<AtomicBool>, std::thread::JoinHandle<()>) {
    let first = start_robot(0, false);
    let port = first.1.port();
    let url = format!("ws://127.0.0.1:{port}");
    let stop = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    let logging = std::thread::spawn(move || {
        let origin = Instant::now();
        let (context, server, pusher, object) = first;
        let until = Some(Instant::now() + Duration::from_secs(1));
        log_still(&pusher, &object, &flag, until, origin);
        let _ = server.stop();
        drop((pusher, object, context));
        std::thread::sleep(Duration::from_millis(700));
        let (_context, server, pusher, object) = start_robot(port, true);
        log_still(&pusher, &object, &flag, None, origin);
        let _ = server.stop();
    });
    (url, stop, logging)
}

/// A camera channel on `context`: CDR `sensor_msgs/msg/CompressedImage` on `/camera`.
pub fn camera_channel(context: &Arc<Context>) -> Arc<RawChannel> {
    ChannelBuilder::new("/camera")
        .context(context)
        .message_encoding("cdr")
        .schema(Schema::new(
            "sensor_msgs/msg/CompressedImage",
            "ros2msg",
            b"".to_vec(),
        ))
        .build_raw()
        .unwrap()
}
