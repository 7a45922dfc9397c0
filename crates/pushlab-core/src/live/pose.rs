//! A planar pose from one message of a live channel, the way a bag's messages give one: the header
//! stamp, x, y and the yaw of the quaternion. CDR messages (`geometry_msgs/msg/PoseStamped`,
//! `nav_msgs/msg/Odometry`, `geometry_msgs/msg/Pose2D`, a child frame of `tf2_msgs/msg/TFMessage`)
//! go through the bag reader's decoders, so that a live session and the bag it is recorded to read
//! the same numbers. JSON messages are a pose in one of two documented shapes:
//!
//! ```json
//! {"header": {"stamp": {"sec": 12, "nanosec": 5000}, "frame_id": "table"},
//!  "pose": {"position": {"x": 0.1, "y": 0.2, "z": 0}, "orientation": {"x": 0, "y": 0, "z": 0, "w": 1}}}
//! {"timestamp": {"sec": 12, "nsec": 5000}, "frame_id": "table",
//!  "pose": {"position": {…}, "orientation": {…}}}
//! ```
//!
//! The first is a `PoseStamped` as rosbridge and foxglove_bridge write JSON; the second is
//! `foxglove.PoseInFrame`. A missing stamp is 0: the receive time is then the frame's time.
//!
//! A TF child frame is taken in its parent's frame as published (one link): a chain of frames is
//! not composed here yet, unlike a bag's `/tf`.

use serde_json::Value;

use super::protocol::Channel;
use crate::recording::bag::{PlanarPose, PoseType, decode_pose, decode_tf, yaw_of};

/// How a channel's messages are read as a pose.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PoseReading {
    /// A CDR message of a single-pose type.
    Cdr(PoseType),
    /// A CDR `TFMessage`: the transform of this child frame.
    Tf { child: String },
    /// A JSON pose (see the module documentation).
    Json,
}

impl PoseReading {
    /// How `channel` is read, with `child` the frame asked of a TF channel; why not, in words.
    pub fn for_channel(channel: &Channel, child: Option<&str>) -> Result<Self, String> {
        match channel.encoding.as_str() {
            "json" => Ok(Self::Json),
            "cdr" => match (PoseType::from_schema(&channel.schema_name), child) {
                (Some(PoseType::TfMessage), Some(child)) => Ok(Self::Tf {
                    child: child.to_owned(),
                }),
                (Some(PoseType::TfMessage), None) => Err(format!(
                    "{} is a TFMessage: name the child frame (TOPIC:CHILD_FRAME)",
                    channel.topic
                )),
                (Some(kind), _) => Ok(Self::Cdr(kind)),
                (None, _) => Err(format!(
                    "{} is a {}, expected a PoseStamped, an Odometry, a Pose2D or a TFMessage",
                    channel.topic, channel.schema_name
                )),
            },
            other => Err(format!(
                "{} is encoded as {other}, expected cdr or json",
                channel.topic
            )),
        }
    }

    /// The pose in one message; `None` for a TF message without the child frame.
    pub fn read(&self, payload: &[u8]) -> Result<Option<PlanarPose>, String> {
        match self {
            Self::Cdr(kind) => decode_pose(*kind, payload).map(Some),
            Self::Tf { child } => {
                let mut found = None;
                decode_tf(payload, |t| {
                    if t.child == child.as_bytes() {
                        found = Some(PlanarPose {
                            stamp_ns: t.stamp_ns,
                            x: t.translation[0],
                            y: t.translation[1],
                            yaw: yaw_of(t.rotation),
                        });
                    }
                })?;
                Ok(found)
            }
            Self::Json => read_json(payload).map(Some),
        }
    }
}

/// A JSON pose in either documented shape.
fn read_json(payload: &[u8]) -> Result<PlanarPose, String> {
    let value: Value = serde_json::from_slice(payload).map_err(|e| format!("not JSON: {e}"))?;
    let stamp = value.pointer("/header/stamp").or(value.get("timestamp"));
    let stamp_ns = match stamp {
        None => 0,
        Some(stamp) => {
            let sec = whole(stamp, "sec")?;
            let nanos = match stamp.get("nanosec") {
                Some(_) => whole(stamp, "nanosec")?,
                None => whole(stamp, "nsec")?,
            };
            sec * 1_000_000_000 + nanos
        }
    };
    let number = |pointer: &str| {
        value
            .pointer(pointer)
            .and_then(Value::as_f64)
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("field {pointer}: missing or not a finite number"))
    };
    let q = [
        number("/pose/orientation/x")?,
        number("/pose/orientation/y")?,
        number("/pose/orientation/z")?,
        number("/pose/orientation/w")?,
    ];
    Ok(PlanarPose {
        stamp_ns,
        x: number("/pose/position/x")?,
        y: number("/pose/position/y")?,
        yaw: yaw_of(q),
    })
}

/// A stamp's whole-number field.
fn whole(stamp: &Value, key: &str) -> Result<u64, String> {
    stamp
        .get(key)
        .and_then(Value::as_u64)
        .ok_or_else(|| format!("field stamp.{key}: missing or not a whole number"))
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
            .read(&encode_pose_stamped(
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
        let pose = read_json(stamped.as_bytes()).expect("PoseStamped JSON");
        assert_eq!(pose.stamp_ns, 3_000_000_007);
        assert_eq!((pose.x, pose.y), (1.5, 2.0));
        assert!((pose.yaw - 0.4).abs() < 1e-12);
        let in_frame = r#"{"timestamp":{"sec":1,"nsec":2},"frame_id":"t",
            "pose":{"position":{"x":0,"y":0,"z":0},"orientation":{"x":0,"y":0,"z":0,"w":1}}}"#;
        assert_eq!(
            read_json(in_frame.as_bytes())
                .expect("PoseInFrame")
                .stamp_ns,
            1_000_000_002
        );
        let error = read_json(br#"{"pose":{"position":{"x":1}}}"#).expect_err("no y");
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
        let error = PoseReading::for_channel(&channel("protobuf", "foxglove.PoseInFrame"), None)
            .expect_err("protobuf");
        assert!(error.contains("encoded as protobuf"), "{error}");
    }
}
