//! A single-pose message of any encoding pushlab reads: CDR by its type ([`super::cdr`]), a JSON
//! pose ([`super::json_pose`]) or a protobuf `foxglove.PoseInFrame` ([`super::proto_pose`]). The one door the bag reader and `live` read poses through, so that a
//! live session and its recording read the same numbers.

use super::cdr::{self, DecodeError, PlanarPose, PoseType};
use super::{json_pose, proto_pose};

/// The pose in one message of a single-pose type (not [`PoseType::TfMessage`]).
pub fn decode(kind: PoseType, bytes: &[u8]) -> Result<PlanarPose, DecodeError> {
    match kind {
        PoseType::JsonPose => json_pose::decode(bytes),
        PoseType::ProtoPoseInFrame => proto_pose::decode(bytes),
        _ => cdr::decode(kind, bytes),
    }
}
