//! A planar pose from one message of a live channel, the way a bag's messages give one: the header
//! stamp, x, y and the yaw of the quaternion. CDR messages (`geometry_msgs/msg/PoseStamped`,
//! `nav_msgs/msg/Odometry`, `geometry_msgs/msg/Pose2D`, a child frame of `tf2_msgs/msg/TFMessage`)
//! JSON poses (two documented shapes, `recording::bag::json_pose`) and protobuf
//! `foxglove.PoseInFrame` (`recording::bag::proto_pose`, what the SDKs' typed channel sends) go
//! through the bag reader's
//! decoders, so that a live session and the bag it is recorded to read the same numbers.
//!
//! A TF child frame is read through its chain of parents by [`super::tf_chain::LiveChain`], as a
//! bag's `/tf` is.

use super::protocol::Channel;
use crate::recording::bag::{PlanarPose, PoseType, decode_pose};

/// How a channel's messages are read as a pose.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PoseReading {
    /// A message of a single-pose type: CDR, a JSON pose (`PoseType::JsonPose`) or a protobuf
    /// `foxglove.PoseInFrame` (`PoseType::ProtoPoseInFrame`).
    Single(PoseType),
    /// A CDR `TFMessage`: the transform of this child frame.
    Tf { child: String },
}

impl PoseReading {
    /// How `channel` is read, with `child` the frame asked of a TF channel; why not, in words.
    pub fn for_channel(channel: &Channel, child: Option<&str>) -> Result<Self, String> {
        match channel.encoding.as_str() {
            "json" => Ok(Self::Single(PoseType::JsonPose)),
            "cdr" => match (PoseType::from_schema(&channel.schema_name), child) {
                (Some(PoseType::TfMessage), Some(child)) => Ok(Self::Tf {
                    child: child.to_owned(),
                }),
                (Some(PoseType::TfMessage), None) => Err(format!(
                    "{} is a TFMessage: name the child frame (TOPIC:CHILD_FRAME)",
                    channel.topic
                )),
                (Some(kind), _) => Ok(Self::Single(kind)),
                (None, _) => Err(format!(
                    "{} is a {}, expected a PoseStamped, an Odometry, a Pose2D or a TFMessage",
                    channel.topic, channel.schema_name
                )),
            },
            "protobuf" => match PoseType::for_channel("protobuf", &channel.schema_name) {
                Some(kind) => Ok(Self::Single(kind)),
                None => Err(format!(
                    "{} is a protobuf {}, expected a foxglove.PoseInFrame",
                    channel.topic, channel.schema_name
                )),
            },
            other => Err(format!(
                "{} is encoded as {other}, expected cdr, json or protobuf",
                channel.topic
            )),
        }
    }

    /// The pose in one message of a single-pose type; `None` for a TF frame, which is read through
    /// its chain ([`super::tf_chain::LiveChain`]).
    pub fn read_single(&self, payload: &[u8]) -> Result<Option<PlanarPose>, String> {
        match self {
            Self::Single(kind) => decode_pose(*kind, payload).map(Some),
            Self::Tf { .. } => Ok(None),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::bag::encode_pose_stamped;

    fn channel(encoding: &str, schema: &str) -> Channel {
        Channel {
            id: 1,
            topic: "/object".into(),
            encoding: encoding.into(),
            schema_name: schema.into(),
            schema: String::new(),
            schema_encoding: None,
        }
    }

    #[test]
    fn a_cdr_pose_reads_as_a_bags_does() {
        let reading =
            PoseReading::for_channel(&channel("cdr", "geometry_msgs/msg/PoseStamped"), None)
                .expect("readable");
        let pose = reading
            .read_single(&encode_pose_stamped(
                1_500_000_000,
                "table",
                0.25,
                -0.5,
                0.3,
            ))
            .expect("decodes")
            .expect("a pose");
        assert_eq!(pose.stamp_ns, 1_500_000_000);
        assert_eq!((pose.x, pose.y), (0.25, -0.5));
        assert!((pose.yaw - 0.3).abs() < 1e-12, "{}", pose.yaw);
    }

    #[test]
    fn json_poses_in_both_shapes_read_with_their_stamps() {
        let (s, c) = (0.2f64.sin(), 0.2f64.cos());
        let stamped = format!(
            r#"{{"header":{{"stamp":{{"sec":3,"nanosec":7}},"frame_id":"t"}},
                "pose":{{"position":{{"x":1.5,"y":2,"z":0}},"orientation":{{"x":0,"y":0,"z":{s},"w":{c}}}}}}}"#
        );
        let pose = decode_pose(PoseType::JsonPose, stamped.as_bytes()).expect("PoseStamped JSON");
        assert_eq!(pose.stamp_ns, 3_000_000_007);
        assert_eq!((pose.x, pose.y), (1.5, 2.0));
        assert!((pose.yaw - 0.4).abs() < 1e-12);
        let in_frame = r#"{"timestamp":{"sec":1,"nsec":2},"frame_id":"t",
            "pose":{"position":{"x":0,"y":0,"z":0},"orientation":{"x":0,"y":0,"z":0,"w":1}}}"#;
        assert_eq!(
            decode_pose(PoseType::JsonPose, in_frame.as_bytes())
                .expect("PoseInFrame")
                .stamp_ns,
            1_000_000_002
        );
        let error =
            decode_pose(PoseType::JsonPose, br#"{"pose":{"position":{"x":1}}}"#).expect_err("no y");
        assert!(error.contains("/pose/orientation/x"), "{error}");
    }

    #[test]
    fn channels_that_hold_no_pose_say_why() {
        let error = PoseReading::for_channel(&channel("cdr", "sensor_msgs/msg/Image"), None)
            .expect_err("an image");
        assert!(
            error.contains("/object is a sensor_msgs/msg/Image, expected"),
            "{error}"
        );
        let error = PoseReading::for_channel(&channel("cdr", "tf2_msgs/msg/TFMessage"), None)
            .expect_err("no child");
        assert!(error.contains("name the child frame"), "{error}");
        let error = PoseReading::for_channel(&channel("protobuf", "foxglove.SceneUpdate"), None)
            .expect_err("a protobuf scene");
        assert!(
            error.contains(
                "/object is a protobuf foxglove.SceneUpdate, expected a foxglove.PoseInFrame"
            ),
            "{error}"
        );
        let error = PoseReading::for_channel(&channel("flatbuffer", "foxglove.PoseInFrame"), None)
            .expect_err("flatbuffer");
        assert!(error.contains("encoded as flatbuffer"), "{error}");
        assert_eq!(
            PoseReading::for_channel(&channel("protobuf", "foxglove.PoseInFrame"), None),
            Ok(PoseReading::Single(PoseType::ProtoPoseInFrame))
        );
    }
}
