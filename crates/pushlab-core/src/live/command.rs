//! The pusher's target as a robot's server takes it: a `geometry_msgs/msg/PoseStamped` (the
//! target's position in the pose streams' frame, no rotation) on a channel the client advertises
//! by the Foxglove protocol's client publish. CDR where the server takes it (a ROS 2 bridge
//! does), JSON where it takes only JSON; a server that does not offer client publish at all, or
//! takes neither encoding, is refused by name before anything is advertised.

use nalgebra::Point2;
use serde_json::json;

use super::client::ServerOffers;
use super::protocol::{CLIENT_PUBLISH, Channel, ClientChannel};
use crate::recording::bag::encode_pose_stamped;

/// The command's type, as ROS 2 names it.
pub const POSE_STAMPED: &str = "geometry_msgs/msg/PoseStamped";

/// The command's `ros2msg` schema with its dependencies, as rosbag2 writes it into a bag.
const POSE_STAMPED_ROS2MSG: &str = "std_msgs/Header header
geometry_msgs/Pose pose
================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
================================================================================
MSG: geometry_msgs/Pose
geometry_msgs/Point position
geometry_msgs/Quaternion orientation
================================================================================
MSG: geometry_msgs/Point
float64 x
float64 y
float64 z
================================================================================
MSG: geometry_msgs/Quaternion
float64 x
float64 y
float64 z
float64 w
";

/// The same shape as a JSON schema, for a server that takes JSON.
const POSE_STAMPED_JSON_SCHEMA: &str = r#"{"type":"object","properties":{"header":{"type":"object","properties":{"stamp":{"type":"object","properties":{"sec":{"type":"integer"},"nanosec":{"type":"integer"}}},"frame_id":{"type":"string"}}},"pose":{"type":"object","properties":{"position":{"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}}},"orientation":{"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},"w":{"type":"number"}}}}}}}"#;

/// Why a server cannot be sent commands; each names the server.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CommandRefused {
    #[error(
        "{url}: the server does not offer client publish (its capabilities: {capabilities}); pushlab sends the pusher's target only by the protocol's client publish, so it cannot drive this robot"
    )]
    NoClientPublish { url: String, capabilities: String },
    #[error(
        "{url}: the server takes neither cdr nor json messages from clients (it takes: {encodings}); pushlab sends the pusher's target as a geometry_msgs/msg/PoseStamped in one of them"
    )]
    NoEncoding { url: String, encodings: String },
    #[error("{url}: the server never said what it supports (no serverInfo message)")]
    NoServerInfo { url: String },
}

/// How the target is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CommandEncoding {
    Cdr,
    Json,
}

impl CommandEncoding {
    pub fn name(self) -> &'static str {
        match self {
            CommandEncoding::Cdr => "cdr",
            CommandEncoding::Json => "json",
        }
    }
}

/// The command topic, as agreed with one server.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CommandTopic {
    topic: String,
    frame_id: String,
    encoding: CommandEncoding,
}

impl CommandTopic {
    /// The command topic on the server at `url` that said `offers`: refused unless it offers
    /// client publish and takes CDR or JSON (CDR preferred: what a ROS 2 bridge decodes).
    pub fn agree(
        url: &str,
        topic: &str,
        frame_id: &str,
        offers: Option<&ServerOffers>,
    ) -> Result<Self, CommandRefused> {
        let offers = offers.ok_or_else(|| CommandRefused::NoServerInfo {
            url: url.to_owned(),
        })?;
        let list = |items: &[String]| match items.is_empty() {
            true => "none".to_owned(),
            false => items.join(", "),
        };
        if !offers.capabilities.iter().any(|c| c == CLIENT_PUBLISH) {
            return Err(CommandRefused::NoClientPublish {
                url: url.to_owned(),
                capabilities: list(&offers.capabilities),
            });
        }
        let takes = |e: &str| offers.supported_encodings.iter().any(|s| s == e);
        let encoding = if takes("cdr") {
            CommandEncoding::Cdr
        } else if takes("json") {
            CommandEncoding::Json
        } else {
            return Err(CommandRefused::NoEncoding {
                url: url.to_owned(),
                encodings: list(&offers.supported_encodings),
            });
        };
        Ok(Self {
            topic: topic.to_owned(),
            frame_id: frame_id.to_owned(),
            encoding,
        })
    }

    pub fn topic(&self) -> &str {
        &self.topic
    }

    pub fn frame_id(&self) -> &str {
        &self.frame_id
    }

    pub fn encoding(&self) -> CommandEncoding {
        self.encoding
    }

    /// The client channel advertised for it, under the client's id `id`.
    pub fn client_channel(&self, id: u32) -> ClientChannel {
        let (schema_encoding, schema) = match self.encoding {
            CommandEncoding::Cdr => ("ros2msg", POSE_STAMPED_ROS2MSG),
            CommandEncoding::Json => ("jsonschema", POSE_STAMPED_JSON_SCHEMA),
        };
        ClientChannel {
            id,
            topic: self.topic.clone(),
            encoding: self.encoding.name().to_owned(),
            schema_name: POSE_STAMPED.to_owned(),
            schema_encoding: schema_encoding.to_owned(),
            schema: schema.to_owned(),
        }
    }

    /// The same channel as a recording names it (`id` kept apart from the server's channel ids
    /// by the caller), so that what was sent replays beside what was received.
    pub fn recorded_channel(&self, id: u64) -> Channel {
        let c = self.client_channel(0);
        Channel {
            id,
            topic: c.topic,
            encoding: c.encoding,
            schema_name: c.schema_name,
            schema: c.schema,
            schema_encoding: Some(c.schema_encoding),
        }
    }

    /// The message of a target at `target`, stamped `stamp_ns` (Unix time).
    pub fn encode(&self, stamp_ns: u64, target: Point2<f64>) -> Vec<u8> {
        match self.encoding {
            CommandEncoding::Cdr => {
                encode_pose_stamped(stamp_ns, &self.frame_id, target.x, target.y, 0.0)
            }
            CommandEncoding::Json => json!({
                "header": {
                    "stamp": {"sec": stamp_ns / 1_000_000_000, "nanosec": stamp_ns % 1_000_000_000},
                    "frame_id": self.frame_id,
                },
                "pose": {
                    "position": {"x": target.x, "y": target.y, "z": 0.0},
                    "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0},
                },
            })
            .to_string()
            .into_bytes(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::bag::{PoseType, decode_pose};

    fn offers(capabilities: &[&str], encodings: &[&str]) -> ServerOffers {
        ServerOffers {
            capabilities: capabilities.iter().map(|s| s.to_string()).collect(),
            supported_encodings: encodings.iter().map(|s| s.to_string()).collect(),
        }
    }

    #[test]
    fn a_server_without_client_publish_is_refused_by_name() {
        let url = "ws://robot:8765";
        let refused = CommandTopic::agree(url, "/target", "", Some(&offers(&["time"], &["cdr"])));
        let why = refused.expect_err("no client publish").to_string();
        assert!(
            why.starts_with(
                "ws://robot:8765: the server does not offer client publish (its capabilities: time)"
            ),
            "{why}"
        );
        let refused = CommandTopic::agree(
            url,
            "/target",
            "",
            Some(&offers(&[CLIENT_PUBLISH], &["protobuf"])),
        );
        let why = refused.expect_err("no encoding").to_string();
        assert!(
            why.contains("takes neither cdr nor json messages from clients (it takes: protobuf)"),
            "{why}"
        );
        assert!(CommandTopic::agree(url, "/target", "", None).is_err());
    }

    #[test]
    fn the_target_decodes_as_the_pose_it_is_with_either_encoding() {
        let target = Point2::new(0.125, -0.25);
        for (takes, expected) in [
            (&["json", "cdr"][..], CommandEncoding::Cdr),
            (&["json"][..], CommandEncoding::Json),
        ] {
            let topic = CommandTopic::agree(
                "ws://r",
                "/t",
                "table",
                Some(&offers(&[CLIENT_PUBLISH], takes)),
            )
            .expect("agreed");
            assert_eq!(topic.encoding(), expected);
            let bytes = topic.encode(1_700_000_000_250_000_000, target);
            let pose_type = PoseType::for_channel(expected.name(), POSE_STAMPED).expect("a pose");
            let pose = decode_pose(pose_type, &bytes).expect("decodes");
            assert_eq!((pose.x, pose.y, pose.yaw), (0.125, -0.25, 0.0));
            assert_eq!(pose.stamp_ns, 1_700_000_000_250_000_000);
            assert_eq!(topic.client_channel(7).schema_name, POSE_STAMPED);
        }
    }
}
