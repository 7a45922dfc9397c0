//! A test robot that takes commands: the Foxglove SDK's WebSocket server with client publish,
//! running the sandbox's simulator (the box of seed 4 at the origin). Its pusher follows the newest
//! target it is sent at the sandbox's speed; the object moves as the simulator pushes it; both
//! poses are published as CDR PoseStamped every 20 ms. Shared by the core's drive tests and the
//! CLI's (`pushlab control ws://…`).

#![allow(dead_code, clippy::unwrap_used, clippy::expect_used)]

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use foxglove::websocket::{Capability, Client, ClientChannel, ServerListener};
use foxglove::{ChannelBuilder, Context, PartialMetadata, RawChannel, Schema, WebSocketServer};
use nalgebra::Point2;
use pushlab_core::live::session::unix_now_ns;
use pushlab_core::recording::bag::{PoseType, decode_pose, encode_pose_stamped};
use pushlab_core::sandbox::table::Sandbox;
use pushlab_core::sandbox::{Mystery, MysteryObject};

/// What the robot's server received on the command topic: (when, the target).
#[derive(Default)]
pub struct Received {
    pub advertised: AtomicUsize,
    pub targets: Mutex<Vec<(Instant, Point2<f64>)>>,
}

impl ServerListener for Received {
    fn on_client_advertise(&self, _client: Client, channel: &ClientChannel) {
        assert_eq!(channel.topic, "/pusher_target");
        assert_eq!(channel.schema_name, "geometry_msgs/msg/PoseStamped");
        self.advertised.fetch_add(1, Ordering::SeqCst);
    }

    fn on_message_data(&self, _client: Client, channel: &ClientChannel, payload: &[u8]) {
        let kind = PoseType::for_channel(&channel.encoding, &channel.schema_name).unwrap();
        let pose = decode_pose(kind, payload).expect("a PoseStamped");
        let at = Point2::new(pose.x, pose.y);
        self.targets.lock().unwrap().push((Instant::now(), at));
    }
}

/// How the test robot behaves.
#[derive(Clone, Copy)]
pub struct Robot {
    pub client_publish: bool,
    /// Stop publishing poses after this long (the tracker dies; the server stays).
    pub poses_for: Option<Duration>,
    /// The server goes away after this long and comes back 0.3 s later on the same port.
    pub restart_after: Option<Duration>,
}

pub const PLAIN: Robot = Robot {
    client_publish: true,
    poses_for: None,
    restart_after: None,
};

/// A running robot: its address, what each of its servers received, the poses it published
/// (and its pusher where the last were), and the flag that stops it.
pub struct Running {
    pub url: String,
    pub received: Vec<Arc<Received>>,
    pub published: Arc<AtomicUsize>,
    /// Where the pusher was at the last poses published, and when.
    pub pusher: Arc<Mutex<(Point2<f64>, Instant)>>,
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Drop for Running {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn server(
    port: u16,
    robot: Robot,
    listener: Arc<Received>,
) -> (
    Arc<Context>,
    foxglove::WebSocketServerHandle,
    [Arc<RawChannel>; 2],
) {
    let context = Context::new();
    let mut builder = WebSocketServer::new()
        .name("sandbox robot")
        .bind("127.0.0.1", port)
        .context(&context)
        .listener(listener);
    if robot.client_publish {
        builder = builder
            .capabilities([Capability::ClientPublish])
            .supported_encodings(["cdr", "json"]);
    }
    let handle = builder.start_blocking().expect("the SDK's server starts");
    let channel = |topic: &str| {
        ChannelBuilder::new(topic)
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
    let channels = [channel("/pusher"), channel("/object")];
    (context, handle, channels)
}

/// Starts the robot: the sandbox's box of seed 4 at the origin, its pusher following the newest
/// target at the sandbox's speed, both poses published every 20 ms.
pub fn start(robot: Robot) -> Running {
    let first = Arc::new(Received::default());
    let second = Arc::new(Received::default());
    let (context, handle, channels) = server(0, robot, Arc::clone(&first));
    let port = handle.port();
    let stop = Arc::new(AtomicBool::new(false));
    let published = Arc::new(AtomicUsize::new(0));
    let pusher_shared = Arc::new(Mutex::new((Point2::origin(), Instant::now())));
    let (flag, count, shared, again) = (
        Arc::clone(&stop),
        Arc::clone(&published),
        Arc::clone(&pusher_shared),
        Arc::clone(&second),
    );
    let receivers = [Arc::clone(&first), Arc::clone(&second)];
    let thread = std::thread::spawn(move || {
        let mut sandbox = Sandbox::new(Mystery::draw(4, MysteryObject::Box).unwrap(), None);
        let mut live = Some((context, handle, channels));
        let mut listener = Arc::clone(&receivers[0]);
        let started = Instant::now();
        let mut seen = 0;
        while !flag.load(Ordering::SeqCst) {
            if let Some(after) = robot.restart_after
                && started.elapsed() >= after
                && Arc::ptr_eq(&listener, &receivers[0])
            {
                if let Some((context, handle, channels)) = live.take() {
                    let _ = handle.stop();
                    drop((channels, context));
                }
                std::thread::sleep(Duration::from_millis(300));
                listener = Arc::clone(&again);
                live = Some(server(port, robot, Arc::clone(&again)));
            }
            let targets = listener.targets.lock().unwrap().clone();
            if targets.len() > seen {
                seen = targets.len();
                sandbox.hold(targets[seen - 1].1);
            }
            sandbox.advance(0.02);
            let tracking = robot.poses_for.is_none_or(|d| started.elapsed() < d);
            if let Some((_, _, [pusher, object])) = &live
                && tracking
                && pusher.has_sinks()
                && object.has_sinks()
            {
                let stamp = unix_now_ns();
                let at = PartialMetadata::with_log_time(stamp);
                let p = sandbox.pusher();
                let o = sandbox.object_pose();
                *shared.lock().unwrap() = (p, Instant::now());
                pusher.log_with_meta(&encode_pose_stamped(stamp, "table", p.x, p.y, 0.0), at);
                object.log_with_meta(
                    &encode_pose_stamped(stamp, "table", o.position.x, o.position.y, o.yaw),
                    at,
                );
                count.fetch_add(2, Ordering::SeqCst);
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    });
    Running {
        url: format!("ws://127.0.0.1:{port}"),
        received: vec![first, second],
        published,
        pusher: pusher_shared,
        stop,
        thread: Some(thread),
    }
}
