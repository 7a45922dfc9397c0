//! A pose sent as JSON (what Foxglove servers and rosbridge send for a JSON-encoded channel, and
//! what `pushlab live` records of it), in one of two shapes:
//!
//! ```json
//! {"header": {"stamp": {"sec": 12, "nanosec": 5000}, "frame_id": "table"},
//!  "pose": {"position": {"x": 0.1, "y": 0.2, "z": 0}, "orientation": {"x": 0, "y": 0, "z": 0, "w": 1}}}
//! {"timestamp": {"sec": 12, "nsec": 5000}, "frame_id": "table",
//!  "pose": {"position": {…}, "orientation": {…}}}
//! ```
//!
//! The first is a `PoseStamped` as rosbridge and foxglove_bridge write JSON; the second is
//! `foxglove.PoseInFrame`. A missing stamp is 0 (the log time is then the pose's time, as for a
//! CDR message without one). A bag and a live session read it through this one function.

use serde_json::Value;

use super::cdr::{DecodeError, PlanarPose, yaw_of};

/// The pose in a JSON message of either shape.
pub fn decode(payload: &[u8]) -> Result<PlanarPose, DecodeError> {
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
