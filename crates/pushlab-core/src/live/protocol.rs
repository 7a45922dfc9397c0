//! The Foxglove WebSocket protocol's messages, as a client reads and writes them: JSON text
//! messages with an `op` field, and binary messages whose first byte is an opcode. Pure parsing
//! and formatting, no socket: [`super::client`] moves the bytes.
//!
//! The messages a live push needs: `serverInfo` (the server's name and what it supports),
//! `advertise` and `unadvertise` (channels coming and going at any time), `status`, and the binary
//! Message Data (opcode 1: a subscription id, the log time in nanoseconds, the payload) and Time
//! (opcode 2). A client subscribes with `subscribe`. Other messages (parameters, services,
//! connection graphs) are read and passed over: a server may send them to any client. The spec:
//! <https://github.com/foxglove/ws-protocol/blob/main/docs/spec.md>.

use serde::Deserialize;
use serde_json::json;

/// The subprotocols offered, newest first: `foxglove.sdk.v1` (the Foxglove SDK's server and
/// foxglove_bridge 3.x require it) and the older `foxglove.websocket.v1`. Both carry a channel's
/// schema inline in `advertise`.
pub const SUBPROTOCOLS: [&str; 2] = ["foxglove.sdk.v1", "foxglove.websocket.v1"];

/// A channel a server advertised.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Channel {
    /// The server's id of the channel, which subscriptions name.
    pub id: u64,
    pub topic: String,
    /// The message encoding: `cdr`, `json`, `protobuf`, `ros1`…
    pub encoding: String,
    /// The schema's name: `geometry_msgs/msg/PoseStamped`, `foxglove.PoseInFrame`…
    pub schema_name: String,
    /// The schema text (or base64 for binary schemas such as protobuf's), possibly empty.
    #[serde(default)]
    pub schema: String,
    /// `ros2msg`, `jsonschema`, `protobuf`…; servers of the older protocol may leave it out.
    #[serde(default)]
    pub schema_encoding: Option<String>,
}

/// A text message from the server.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(tag = "op", rename_all = "camelCase")]
pub enum ServerText {
    #[serde(rename_all = "camelCase")]
    ServerInfo {
        name: String,
        #[serde(default)]
        capabilities: Vec<String>,
        #[serde(default)]
        supported_encodings: Vec<String>,
        #[serde(default)]
        session_id: Option<String>,
    },
    Advertise {
        channels: Vec<Channel>,
    },
    #[serde(rename_all = "camelCase")]
    Unadvertise {
        channel_ids: Vec<u64>,
    },
    /// A message for the user: level 0 info, 1 warning, 2 error.
    Status {
        level: u8,
        message: String,
    },
    /// Parameters, services, connection graphs and what later versions add: passed over.
    #[serde(other)]
    Other,
}

/// A binary message from the server.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ServerBinary<'a> {
    /// A message on a subscribed channel.
    MessageData {
        subscription: u32,
        /// When the server logged it, nanoseconds (not the message's own header stamp).
        log_time_ns: u64,
        payload: &'a [u8],
    },
    /// The server's clock, nanoseconds (servers that play back recorded time).
    Time { timestamp_ns: u64 },
    /// Service responses, fetched assets and what later versions add: passed over.
    Other { opcode: u8 },
}

/// Reads a text message.
pub fn parse_text(text: &str) -> Result<ServerText, String> {
    serde_json::from_str(text).map_err(|e| {
        let start: String = text.chars().take(80).collect();
        format!("a text message that is not the protocol's JSON ({e}): {start}")
    })
}

/// Reads a binary message.
pub fn parse_binary(bytes: &[u8]) -> Result<ServerBinary<'_>, String> {
    let Some((&opcode, rest)) = bytes.split_first() else {
        return Err("an empty binary message, expected an opcode".to_owned());
    };
    let short = |what: &str| {
        format!(
            "a binary message of opcode {opcode} of {} bytes, too short for {what}",
            bytes.len()
        )
    };
    match opcode {
        1 => {
            let (id, rest) = rest
                .split_first_chunk::<4>()
                .ok_or_else(|| short("a subscription id and a log time"))?;
            let (time, payload) = rest
                .split_first_chunk::<8>()
                .ok_or_else(|| short("a subscription id and a log time"))?;
            Ok(ServerBinary::MessageData {
                subscription: u32::from_le_bytes(*id),
                log_time_ns: u64::from_le_bytes(*time),
                payload,
            })
        }
        2 => {
            let (time, _) = rest
                .split_first_chunk::<8>()
                .ok_or_else(|| short("a timestamp"))?;
            Ok(ServerBinary::Time {
                timestamp_ns: u64::from_le_bytes(*time),
            })
        }
        opcode => Ok(ServerBinary::Other { opcode }),
    }
}

/// The `subscribe` message for (subscription id, channel id) pairs.
pub fn subscribe(subscriptions: &[(u32, u64)]) -> String {
    let list: Vec<_> = (subscriptions.iter())
        .map(|&(id, channel)| json!({"id": id, "channelId": channel}))
        .collect();
    json!({"op": "subscribe", "subscriptions": list}).to_string()
}

/// The `unsubscribe` message for subscription ids.
pub fn unsubscribe(subscriptions: &[u32]) -> String {
    json!({"op": "unsubscribe", "subscriptionIds": subscriptions}).to_string()
}

/// What a server must list in `serverInfo`'s capabilities for a client to publish to it.
pub const CLIENT_PUBLISH: &str = "clientPublish";

/// A channel a client advertises to publish on (the spec's client `advertise`): the client's own
/// id, the topic, the message encoding, and the schema by name, encoding and text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ClientChannel {
    pub id: u32,
    pub topic: String,
    pub encoding: String,
    pub schema_name: String,
    pub schema_encoding: String,
    pub schema: String,
}

/// The client's `advertise` message for `channels`.
pub fn client_advertise(channels: &[ClientChannel]) -> String {
    let list: Vec<_> = (channels.iter())
        .map(|c| {
            json!({"id": c.id, "topic": c.topic, "encoding": c.encoding,
                   "schemaName": c.schema_name, "schemaEncoding": c.schema_encoding,
                   "schema": c.schema})
        })
        .collect();
    json!({"op": "advertise", "channels": list}).to_string()
}

/// The client's `unadvertise` message for its channel ids.
pub fn client_unadvertise(channel_ids: &[u32]) -> String {
    json!({"op": "unadvertise", "channelIds": channel_ids}).to_string()
}

/// The client's binary Message Data (opcode 1): its channel id, then the payload.
pub fn client_message_data(channel: u32, payload: &[u8]) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(5 + payload.len());
    bytes.push(1);
    bytes.extend(channel.to_le_bytes());
    bytes.extend(payload);
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_servers_text_messages_are_read_as_the_spec_writes_them() {
        let info = parse_text(
            r#"{"op":"serverInfo","name":"robot","capabilities":["time"],
                "supportedEncodings":["json","cdr"],"metadata":{},"sessionId":"1"}"#,
        );
        assert_eq!(
            info,
            Ok(ServerText::ServerInfo {
                name: "robot".into(),
                capabilities: vec!["time".into()],
                supported_encodings: vec!["json".into(), "cdr".into()],
                session_id: Some("1".into()),
            })
        );
        let advertise = parse_text(
            r#"{"op":"advertise","channels":[{"id":7,"topic":"/pusher","encoding":"cdr",
                "schemaName":"geometry_msgs/msg/PoseStamped","schema":"…","schemaEncoding":"ros2msg"}]}"#,
        )
        .expect("advertise");
        let ServerText::Advertise { channels } = advertise else {
            panic!("{advertise:?}");
        };
        assert_eq!(channels[0].id, 7);
        assert_eq!(channels[0].schema_encoding.as_deref(), Some("ros2msg"));
        assert_eq!(
            parse_text(r#"{"op":"unadvertise","channelIds":[7, 8]}"#),
            Ok(ServerText::Unadvertise {
                channel_ids: vec![7, 8]
            })
        );
        assert_eq!(
            parse_text(r#"{"op":"parameterValues","parameters":[]}"#),
            Ok(ServerText::Other)
        );
        let error = parse_text("not json").expect_err("not JSON");
        assert!(error.contains("not the protocol's JSON"), "{error}");
    }

    #[test]
    fn message_data_is_a_subscription_a_log_time_and_the_payload() {
        let mut bytes = vec![1u8];
        bytes.extend(3u32.to_le_bytes());
        bytes.extend(1_700_000_000_123_456_789u64.to_le_bytes());
        bytes.extend(b"pose");
        assert_eq!(
            parse_binary(&bytes),
            Ok(ServerBinary::MessageData {
                subscription: 3,
                log_time_ns: 1_700_000_000_123_456_789,
                payload: b"pose",
            })
        );
        let error = parse_binary(&bytes[..9]).expect_err("cut");
        assert!(error.contains("of 9 bytes, too short"), "{error}");
        assert_eq!(parse_binary(&[4, 0]), Ok(ServerBinary::Other { opcode: 4 }));
        assert!(parse_binary(&[]).is_err());
    }

    #[test]
    fn subscribe_names_each_subscription_and_its_channel() {
        let text = subscribe(&[(1, 7), (2, 9)]);
        let value: serde_json::Value = serde_json::from_str(&text).expect("JSON");
        assert_eq!(value["op"], "subscribe");
        assert_eq!(value["subscriptions"][1]["channelId"], 9);
        assert_eq!(value["subscriptions"][1]["id"], 2);
    }

    #[test]
    fn a_client_channel_is_advertised_and_published_to_as_the_spec_writes_it() {
        let channel = ClientChannel {
            id: 3,
            topic: "/pusher_target".into(),
            encoding: "cdr".into(),
            schema_name: "geometry_msgs/msg/PoseStamped".into(),
            schema_encoding: "ros2msg".into(),
            schema: "std_msgs/Header header\ngeometry_msgs/Pose pose".into(),
        };
        let value: serde_json::Value =
            serde_json::from_str(&client_advertise(&[channel])).expect("JSON");
        assert_eq!(value["op"], "advertise");
        let c = &value["channels"][0];
        assert_eq!(
            (
                c["id"].as_u64(),
                c["topic"].as_str(),
                c["encoding"].as_str()
            ),
            (Some(3), Some("/pusher_target"), Some("cdr"))
        );
        assert_eq!(c["schemaName"], "geometry_msgs/msg/PoseStamped");
        assert_eq!(c["schemaEncoding"], "ros2msg");
        let value: serde_json::Value =
            serde_json::from_str(&client_unadvertise(&[3])).expect("JSON");
        assert_eq!(value["channelIds"][0], 3);
        assert_eq!(
            client_message_data(0x0403_0201, b"xy"),
            [1, 1, 2, 3, 4, b'x', b'y']
        );
    }
}
