//! The live session's faults against a real peer, the Foxglove SDK's WebSocket server: a message
//! that does not decode is said once by topic and counted, never read as a zero pose; a topic whose
//! encoding pushlab cannot read is refused by name when connecting (connecting again would not
//! help); a topic the server withdraws mid-push is said by name. Each as `pushlab live` and the
//! app's Connect see it: both run this `LiveSession`.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::{Duration, Instant};

use foxglove::{ChannelBuilder, Context, PartialMetadata, RawChannel, Schema, WebSocketServer};
use pushlab_core::live::{LiveSession, SessionError, SessionEvent, Stream};
use pushlab_core::recording::bag::encode_pose_stamped;

fn channel(
    context: &std::sync::Arc<Context>,
    topic: &str,
    encoding: &str,
) -> std::sync::Arc<RawChannel> {
    let schema = match encoding {
        "cdr" => Schema::new("geometry_msgs/msg/PoseStamped", "ros2msg", b"".to_vec()),
        _ => Schema::new("pushlab.Pose", "jsonschema", b"{}".to_vec()),
    };
    ChannelBuilder::new(topic)
        .context(context)
        .message_encoding(encoding)
        .schema(schema)
        .build_raw()
        .unwrap()
}

/// Reads events for up to `wait`, returning them.
fn events(session: &mut LiveSession, wait: Duration) -> Vec<SessionEvent> {
    let started = Instant::now();
    let mut seen = Vec::new();
    while started.elapsed() < wait {
        if let Some(event) = session.next(&|| false).unwrap() {
            seen.push(event);
        }
    }
    seen
}

#[test]
fn a_bad_message_a_topic_withdrawn_and_an_unreadable_encoding_are_each_said_by_name() {
    let context = Context::new();
    let server = WebSocketServer::new()
        .name("faulty robot")
        .bind("127.0.0.1", 0)
        .context(&context)
        .start_blocking()
        .unwrap();
    let url = format!("ws://127.0.0.1:{}", server.port());
    let pusher = channel(&context, "/pusher", "cdr");
    let object = channel(&context, "/object", "cdr");
    let odd = channel(&context, "/odd", "cbor");

    // An encoding no reader knows, chosen as the object: refused at once, by name.
    let Err(SessionError::Unreadable { role, topic, why }) =
        LiveSession::open(&url, "/pusher", "/odd", None, &|| false)
    else {
        panic!("a cbor topic cannot be the object");
    };
    assert_eq!((role, topic.as_str()), ("object", "/odd"));
    assert!(why.contains("cbor"), "{why}");
    drop(odd);

    let mut session = LiveSession::open(&url, "/pusher", "/object", None, &|| false).unwrap();
    while !(pusher.has_sinks() && object.has_sinks()) {
        std::thread::sleep(Duration::from_millis(5));
    }
    let stamp = 1_700_000_000_000_000_000u64;
    let at = PartialMetadata::with_log_time(stamp);
    object.log_with_meta(&encode_pose_stamped(stamp, "table", 0.5, 0.25, 0.0), at);
    // Cut short, twice: said once, counted twice, no pose from either.
    let cut = encode_pose_stamped(stamp, "table", 0.1, 0.2, 0.0);
    pusher.log_with_meta(&cut[..cut.len() / 2], at);
    pusher.log_with_meta(&cut[..10], at);
    pusher.log_with_meta(&cut, at);
    let seen = events(&mut session, Duration::from_millis(500));
    let poses: Vec<(Stream, f64)> = (seen.iter())
        .filter_map(|e| match e {
            SessionEvent::Pose { stream, pose, .. } => Some((*stream, pose.x)),
            _ => None,
        })
        .collect();
    assert_eq!(poses, [(Stream::Object, 0.5), (Stream::Pusher, 0.1)]);
    let said: Vec<&String> = (seen.iter())
        .filter_map(|e| match e {
            SessionEvent::Said(s) => Some(s),
            _ => None,
        })
        .collect();
    assert_eq!(said.len(), 1, "{said:?}");
    assert!(said[0].starts_with("pusher /pusher: "), "{}", said[0]);
    assert!(said[0].contains("left out, counted"), "{}", said[0]);
    assert_eq!(session.followed()[0].unreadable(), 2);
    assert_eq!(session.messages(), 4);

    // The object's topic withdrawn mid-push.
    object.close();
    let seen = events(&mut session, Duration::from_millis(500));
    assert!(
        seen.contains(&SessionEvent::Said(
            "the server withdrew the object topic /object".to_owned()
        )),
        "{seen:?}"
    );
    session.finish().unwrap();
    let _ = server.stop();
}
