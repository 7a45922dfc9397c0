//! A small reader of ROS 2's CDR (XCDR1, as rmw writes it) for the few message types a pusher or an
//! object is published as. Only the fields pushlab uses are kept; the rest are skipped by size, so a
//! message is read without knowing or parsing its schema text.
//!
//! CDR: a 4-byte encapsulation header (`00 01` little-endian, `00 00` big-endian, then 2 option
//! bytes), then the fields in order, each aligned to its own size counted from the end of the header;
//! a string is a `u32` length that includes the terminating NUL, then the bytes; a sequence is a
//! `u32` count, then the elements.

use crate::math;

/// The message types pushlab reads, by their ROS 2 type name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PoseType {
    /// `geometry_msgs/msg/PoseStamped`
    PoseStamped,
    /// `tf2_msgs/msg/TFMessage` (a list of `geometry_msgs/msg/TransformStamped`)
    TfMessage,
    /// `nav_msgs/msg/Odometry`
    Odometry,
    /// `geometry_msgs/msg/Pose2D` (no header: time is the log time)
    Pose2D,
    /// A JSON-encoded pose, whatever its schema's name (see [`super::json_pose`]): what Foxglove
    /// servers and rosbridge send as JSON, and what `pushlab live` records of it.
    JsonPose,
    /// A protobuf `foxglove.PoseInFrame` (see [`super::proto_pose`]): what the Foxglove SDKs' typed
    /// pose channel sends.
    ProtoPoseInFrame,
}

impl PoseType {
    /// The type for a schema name, accepting ROS 1 style names without `/msg/` as well.
    pub fn from_schema(name: &str) -> Option<Self> {
        match name.replace("/msg/", "/").as_str() {
            "geometry_msgs/PoseStamped" => Some(Self::PoseStamped),
            "tf2_msgs/TFMessage" => Some(Self::TfMessage),
            "nav_msgs/Odometry" => Some(Self::Odometry),
            "geometry_msgs/Pose2D" => Some(Self::Pose2D),
            _ => None,
        }
    }

    /// How a channel of this message encoding and schema is read, if it can be: CDR by the type's
    /// name, JSON as a JSON pose, protobuf if it is a `foxglove.PoseInFrame`.
    pub fn for_channel(encoding: &str, type_name: &str) -> Option<Self> {
        match encoding {
            "cdr" => Self::from_schema(type_name),
            "json" => Some(Self::JsonPose),
            "protobuf" if type_name == "foxglove.PoseInFrame" => Some(Self::ProtoPoseInFrame),
            _ => None,
        }
    }

    /// The ROS 2 type name (what a JSON pose is, for one).
    pub fn name(self) -> &'static str {
        match self {
            Self::PoseStamped => "geometry_msgs/msg/PoseStamped",
            Self::TfMessage => "tf2_msgs/msg/TFMessage",
            Self::Odometry => "nav_msgs/msg/Odometry",
            Self::Pose2D => "geometry_msgs/msg/Pose2D",
            Self::JsonPose => "JSON pose",
            Self::ProtoPoseInFrame => "foxglove.PoseInFrame",
        }
    }
}

/// A planar pose read from one message: the header stamp (nanoseconds, 0 when the message has
/// none or it is zero), position and yaw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanarPose {
    pub stamp_ns: u64,
    pub x: f64,
    pub y: f64,
    pub yaw: f64,
}

/// Why a message could not be read, in words for the error message.
pub type DecodeError = String;

/// A cursor over one CDR message.
pub(super) struct Cdr<'a> {
    /// The bytes after the encapsulation header (alignment counts from here).
    body: &'a [u8],
    pos: usize,
    little: bool,
}

impl<'a> Cdr<'a> {
    pub(super) fn new(bytes: &'a [u8]) -> Result<Self, DecodeError> {
        let Some((header, body)) = bytes.split_first_chunk::<4>() else {
            return Err(format!(
                "{} bytes, shorter than the 4-byte CDR header",
                bytes.len()
            ));
        };
        let little = match header[..2] {
            [0, 1] | [0, 3] => true,
            [0, 0] | [0, 2] => false,
            _ => {
                return Err(format!(
                    "encapsulation {:02x} {:02x}, expected plain CDR (00 00 or 00 01)",
                    header[0], header[1]
                ));
            }
        };
        Ok(Self {
            body,
            pos: 0,
            little,
        })
    }

    fn take<const N: usize>(&mut self, what: &str) -> Result<[u8; N], DecodeError> {
        let start = self.pos.next_multiple_of(N);
        let bytes = self
            .body
            .get(start..start + N)
            .and_then(|b| <[u8; N]>::try_from(b).ok())
            .ok_or_else(|| {
                format!(
                    "ends at byte {} in the {what}, expected {N} more bytes",
                    self.body.len() + 4
                )
            })?;
        self.pos = start + N;
        Ok(bytes)
    }

    pub(super) fn u32(&mut self, what: &str) -> Result<u32, DecodeError> {
        let b = self.take::<4>(what)?;
        Ok(if self.little {
            u32::from_le_bytes(b)
        } else {
            u32::from_be_bytes(b)
        })
    }

    fn f64(&mut self, what: &str) -> Result<f64, DecodeError> {
        let b = self.take::<8>(what)?;
        Ok(if self.little {
            f64::from_le_bytes(b)
        } else {
            f64::from_be_bytes(b)
        })
    }

    pub(super) fn u8(&mut self, what: &str) -> Result<u8, DecodeError> {
        Ok(self.take::<1>(what)?[0])
    }

    /// What is left of the message after the fields read so far.
    pub(super) fn rest(&self) -> &'a [u8] {
        self.body.get(self.pos..).unwrap_or(&[])
    }

    /// A `sequence<uint8>`: its bytes, borrowed.
    pub(super) fn bytes(&mut self, what: &str) -> Result<&'a [u8], DecodeError> {
        let len = self.u32(what)? as usize;
        let bytes = self
            .body
            .get(self.pos..self.pos.saturating_add(len))
            .ok_or_else(|| {
                format!(
                    "the {what} claims {len} bytes but only {} are left",
                    self.body.len() - self.pos
                )
            })?;
        self.pos += len;
        Ok(bytes)
    }

    /// A string's bytes without the terminating NUL.
    pub(super) fn string(&mut self, what: &str) -> Result<&'a [u8], DecodeError> {
        let bytes = self.bytes(what)?;
        Ok(bytes.strip_suffix(&[0]).unwrap_or(bytes))
    }

    /// `builtin_interfaces/Time` as nanoseconds (negative stamps count as zero: unset).
    #[inline]
    pub(super) fn stamp(&mut self) -> Result<u64, DecodeError> {
        let sec = self.u32("header stamp")? as i32;
        let nanosec = self.u32("header stamp")?;
        Ok(if sec < 0 {
            0
        } else {
            sec as u64 * 1_000_000_000 + u64::from(nanosec)
        })
    }

    /// `std_msgs/Header`: the stamp; the frame id is skipped.
    pub(super) fn header(&mut self) -> Result<u64, DecodeError> {
        let stamp = self.stamp()?;
        self.string("header frame_id")?;
        Ok(stamp)
    }

    /// `Point`/`Vector3` then `Quaternion`: x, y and the yaw.
    fn pose(&mut self) -> Result<(f64, f64, f64), DecodeError> {
        let x = self.f64("position")?;
        let y = self.f64("position")?;
        self.f64("position")?;
        let mut q = [0.0; 4];
        for v in &mut q {
            *v = self.f64("orientation")?;
        }
        Ok((x, y, yaw_of(q)))
    }
}

/// The rotation about z of a quaternion `[x, y, z, w]` (not necessarily normalised), in (−π, π].
pub fn yaw_of([x, y, z, w]: [f64; 4]) -> f64 {
    math::atan2(2.0 * (w * z + x * y), w * w + x * x - y * y - z * z)
}

/// Reads a pose from a CDR message of a header-carrying single-pose type (not
/// [`PoseType::TfMessage`], nor a JSON or protobuf pose: `super::message::decode` reads every type).
pub fn decode(kind: PoseType, bytes: &[u8]) -> Result<PlanarPose, DecodeError> {
    let mut cdr = Cdr::new(bytes)?;
    let (stamp_ns, (x, y, yaw)) = match kind {
        PoseType::PoseStamped => (cdr.header()?, cdr.pose()?),
        PoseType::Odometry => {
            let stamp = cdr.header()?;
            cdr.string("child_frame_id")?;
            (stamp, cdr.pose()?)
        }
        PoseType::Pose2D => (0, (cdr.f64("x")?, cdr.f64("y")?, cdr.f64("theta")?)),
        PoseType::TfMessage => {
            return Err("a TFMessage needs a child frame".to_owned());
        }
        PoseType::JsonPose | PoseType::ProtoPoseInFrame => {
            return Err(format!("a {} is not a CDR message", kind.name()));
        }
    };
    Ok(PlanarPose {
        stamp_ns,
        x,
        y,
        yaw,
    })
}

/// One `geometry_msgs/msg/TransformStamped` of a TFMessage, borrowed from the message bytes: the
/// parent frame (header frame id), the child frame and the full 3-D transform, because a link of a
/// transform tree may be tilted even when the end of the chain is planar.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform<'a> {
    /// Header stamp, nanoseconds (0 when unset).
    pub stamp_ns: u64,
    pub parent: &'a [u8],
    pub child: &'a [u8],
    /// The child's origin in the parent frame, metres.
    pub translation: [f64; 3],
    /// The child's orientation in the parent frame, `[x, y, z, w]` as published (not normalised).
    pub rotation: [f64; 4],
}

/// Reads a `tf2_msgs/msg/TFMessage` and calls `each` with every transform in it.
pub fn decode_tf<'a>(
    bytes: &'a [u8],
    mut each: impl FnMut(Transform<'a>),
) -> Result<(), DecodeError> {
    let mut cdr = Cdr::new(bytes)?;
    let count = cdr.u32("transforms count")?;
    // Each transform is at least 84 bytes: refuse a count the message cannot hold before looping.
    if count as usize > cdr.body.len() / 84 + 1 {
        return Err(format!(
            "claims {count} transforms in {} bytes",
            cdr.body.len() + 4
        ));
    }
    for _ in 0..count {
        let stamp_ns = cdr.stamp()?;
        let parent = cdr.string("header frame_id")?;
        let child = cdr.string("child_frame_id")?;
        let mut translation = [0.0; 3];
        for v in &mut translation {
            *v = cdr.f64("translation")?;
        }
        let mut rotation = [0.0; 4];
        for v in &mut rotation {
            *v = cdr.f64("rotation")?;
        }
        each(Transform {
            stamp_ns,
            parent,
            child,
            translation,
            rotation,
        });
    }
    Ok(())
}

/// A little-endian `geometry_msgs/msg/PoseStamped` as rclcpp serialises it (z = 0, rotation about
/// z by `yaw`): for tests and benchmarks that write bags of their own.
pub fn encode_pose_stamped(stamp_ns: u64, frame_id: &str, x: f64, y: f64, yaw: f64) -> Vec<u8> {
    let mut body = Vec::with_capacity(80 + frame_id.len());
    body.extend(((stamp_ns / 1_000_000_000) as u32).to_le_bytes());
    body.extend(((stamp_ns % 1_000_000_000) as u32).to_le_bytes());
    body.extend((frame_id.len() as u32 + 1).to_le_bytes());
    body.extend(frame_id.as_bytes());
    body.push(0);
    body.resize(body.len().next_multiple_of(8), 0);
    let (s, c) = math::sin_cos(yaw / 2.0);
    for v in [x, y, 0.0, 0.0, 0.0, s, c] {
        body.extend(v.to_le_bytes());
    }
    let mut bytes = vec![0, 1, 0, 0];
    bytes.extend(body);
    bytes
}

/// A little-endian `tf2_msgs/msg/TFMessage` holding `transforms` as rclcpp serialises it: for tests
/// and benchmarks that publish or write transform trees of their own.
pub fn encode_tf_message(transforms: &[Transform<'_>]) -> Vec<u8> {
    let mut body: Vec<u8> = Vec::new();
    let align = |body: &mut Vec<u8>, to: usize| body.resize(body.len().next_multiple_of(to), 0);
    body.extend((transforms.len() as u32).to_le_bytes());
    for t in transforms {
        align(&mut body, 4);
        body.extend(((t.stamp_ns / 1_000_000_000) as u32).to_le_bytes());
        body.extend(((t.stamp_ns % 1_000_000_000) as u32).to_le_bytes());
        for name in [t.parent, t.child] {
            align(&mut body, 4);
            body.extend((name.len() as u32 + 1).to_le_bytes());
            body.extend(name);
            body.push(0);
        }
        align(&mut body, 8);
        for v in t.translation.iter().chain(&t.rotation) {
            body.extend(v.to_le_bytes());
        }
    }
    let mut bytes = vec![0, 1, 0, 0];
    bytes.extend(body);
    bytes
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn pose_stamped_gives_stamp_position_and_yaw() {
        let bytes = encode_pose_stamped(2_000_000_005, "world", 1.0, -2.0, 0.3);
        let pose = decode(PoseType::PoseStamped, &bytes).unwrap();
        assert_eq!(pose.stamp_ns, 2_000_000_005);
        assert_eq!((pose.x, pose.y), (1.0, -2.0));
        assert!((pose.yaw - 0.3).abs() < 1e-12);
    }

    #[test]
    fn a_tf_message_written_reads_back() {
        let written = [
            Transform {
                stamp_ns: 3_000_000_007,
                parent: b"world",
                child: b"base_link",
                translation: [1.0, 2.0, 3.0],
                rotation: [0.0, 0.0, 0.6, 0.8],
            },
            Transform {
                stamp_ns: 4_000_000_000,
                parent: b"base_link",
                child: b"tool",
                translation: [-1.0, 0.5, 0.0],
                rotation: [0.0, 0.0, 0.0, 1.0],
            },
        ];
        let mut read = Vec::new();
        decode_tf(&encode_tf_message(&written), |t| {
            read.push((
                t.stamp_ns,
                t.parent.to_vec(),
                t.child.to_vec(),
                t.translation,
                t.rotation,
            ))
        })
        .unwrap();
        let want: Vec<_> = (written.iter())
            .map(|t| {
                (
                    t.stamp_ns,
                    t.parent.to_vec(),
                    t.child.to_vec(),
                    t.translation,
                    t.rotation,
                )
            })
            .collect();
        assert_eq!(read, want);
    }

    #[test]
    fn truncated_messages_are_errors_not_panics() {
        let bytes = encode_pose_stamped(2_000_000_005, "world", 1.0, -2.0, 0.0);
        for len in 0..bytes.len() {
            assert!(
                decode(PoseType::PoseStamped, &bytes[..len]).is_err(),
                "{len}"
            );
            assert!(decode(PoseType::Odometry, &bytes[..len]).is_err(), "{len}");
            let _ = decode_tf(&bytes[..len], |_| {});
        }
    }

    #[test]
    fn tf_transforms_give_parent_child_and_the_3d_transform() {
        // One little-endian TransformStamped: stamp, "world", "tip", translation, rotation.
        let mut body = Vec::new();
        body.extend(1u32.to_le_bytes());
        body.extend(3u32.to_le_bytes());
        body.extend(7u32.to_le_bytes());
        for name in ["world", "tip"] {
            body.resize(body.len().next_multiple_of(4), 0);
            body.extend((name.len() as u32 + 1).to_le_bytes());
            body.extend(name.as_bytes());
            body.push(0);
        }
        body.resize(body.len().next_multiple_of(8), 0);
        for v in [1.0, 2.0, 3.0, 0.5, 0.5, 0.5, 0.5f64] {
            body.extend(v.to_le_bytes());
        }
        let mut bytes = vec![0, 1, 0, 0];
        bytes.extend(body);
        let mut got = Vec::new();
        decode_tf(&bytes, |t| {
            got.push((
                t.stamp_ns,
                t.parent.to_vec(),
                t.child.to_vec(),
                t.translation,
                t.rotation,
            ));
        })
        .unwrap();
        assert_eq!(
            got,
            [(
                3_000_000_007,
                b"world".to_vec(),
                b"tip".to_vec(),
                [1.0, 2.0, 3.0],
                [0.5; 4]
            )]
        );
    }

    #[test]
    fn yaw_of_handles_unnormalised_quaternions() {
        let (s, c) = (0.4f64.sin(), 0.4f64.cos());
        assert!((yaw_of([0.0, 0.0, 3.0 * s, 3.0 * c]) - 0.8).abs() < 1e-12);
    }

    #[test]
    fn schema_names_with_and_without_msg() {
        assert_eq!(
            PoseType::from_schema("nav_msgs/msg/Odometry"),
            Some(PoseType::Odometry)
        );
        assert_eq!(
            PoseType::from_schema("geometry_msgs/Pose2D"),
            Some(PoseType::Pose2D)
        );
        assert_eq!(PoseType::from_schema("sensor_msgs/msg/Image"), None);
    }
}
