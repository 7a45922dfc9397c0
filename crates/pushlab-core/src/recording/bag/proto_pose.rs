//! A `foxglove.PoseInFrame` sent as protobuf: what the Foxglove SDKs' typed pose channel
//! (`PoseInFrameChannel` in Python, `Channel<PoseInFrame>` in Rust) logs, and so what a live session
//! and its recording hold of it. A hand-written reader of the few fields pushlab uses, since the
//! message's layout is fixed by Foxglove's published schema:
//!
//! ```text
//! PoseInFrame { Timestamp timestamp = 1; string frame_id = 2; Pose pose = 3; }
//! Timestamp   { int64 seconds = 1; int32 nanos = 2; }   (google.protobuf.Timestamp)
//! Pose        { Vector3 position = 1; Quaternion orientation = 2; }
//! Vector3     { double x = 1; double y = 2; double z = 3; }
//! Quaternion  { double x = 1; double y = 2; double z = 3; double w = 4; }
//! ```
//!
//! Protobuf leaves out fields at their default (0), so a missing number is 0 — as in the message the
//! sender wrote — and unknown fields are skipped. A missing timestamp is 0: the log time is then the
//! pose's time, as for any message without a stamp.

use super::cdr::{DecodeError, PlanarPose, yaw_of};

/// One field's value, by protobuf wire type.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Value<'a> {
    Varint(u64),
    Fixed64(u64),
    Bytes(&'a [u8]),
    Fixed32,
}

/// Calls `each` with every field of a message, in order; refuses bytes that are not protobuf.
fn fields<'a>(
    mut bytes: &'a [u8],
    what: &str,
    mut each: impl FnMut(u64, Value<'a>) -> Result<(), DecodeError>,
) -> Result<(), DecodeError> {
    let cut = || format!("{what}: cut short");
    while !bytes.is_empty() {
        let key = varint(&mut bytes).ok_or_else(cut)?;
        let value = match key & 7 {
            0 => Value::Varint(varint(&mut bytes).ok_or_else(cut)?),
            1 => {
                let (head, rest) = bytes.split_first_chunk::<8>().ok_or_else(cut)?;
                bytes = rest;
                Value::Fixed64(u64::from_le_bytes(*head))
            }
            2 => {
                let len = varint(&mut bytes).ok_or_else(cut)?;
                let len = usize::try_from(len)
                    .ok()
                    .filter(|&n| n <= bytes.len())
                    .ok_or_else(cut)?;
                let (head, rest) = bytes.split_at(len);
                bytes = rest;
                Value::Bytes(head)
            }
            5 => {
                bytes = bytes.get(4..).ok_or_else(cut)?;
                Value::Fixed32
            }
            wire => {
                return Err(format!(
                    "{what}: wire type {wire} is not protobuf's 0, 1, 2 or 5"
                ));
            }
        };
        each(key >> 3, value)?;
    }
    Ok(())
}

/// A base-128 varint, at most 10 bytes.
fn varint(bytes: &mut &[u8]) -> Option<u64> {
    let mut value = 0u64;
    for (i, &byte) in bytes.iter().enumerate().take(10) {
        value |= u64::from(byte & 0x7f) << (7 * i);
        if byte & 0x80 == 0 {
            *bytes = &bytes[i + 1..];
            return Some(value);
        }
    }
    None
}

/// The doubles of fields `1..=N` of a message (a `Vector3` or a `Quaternion`), 0 where left out.
fn doubles<const N: usize>(bytes: &[u8], what: &str) -> Result<[f64; N], DecodeError> {
    let mut out = [0.0; N];
    fields(bytes, what, |field, value| {
        let slot = usize::try_from(field).ok().and_then(|f| f.checked_sub(1));
        if let Some(slot) = slot.filter(|&s| s < N) {
            let Value::Fixed64(bits) = value else {
                return Err(format!("{what}: field {field} is not a double"));
            };
            out[slot] = f64::from_bits(bits);
        }
        Ok(())
    })?;
    match out.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(format!("{what}: a value is {v}, expected a finite number")),
        None => Ok(out),
    }
}

/// The pose in a protobuf `foxglove.PoseInFrame`.
pub fn decode(payload: &[u8]) -> Result<PlanarPose, DecodeError> {
    let (mut stamp_ns, mut position, mut orientation) = (0u64, [0.0; 3], [0.0; 4]);
    let mut has_pose = false;
    fields(payload, "PoseInFrame", |field, value| {
        match (field, value) {
            (1, Value::Bytes(timestamp)) => {
                let (mut seconds, mut nanos) = (0u64, 0u64);
                fields(timestamp, "PoseInFrame.timestamp", |f, v| {
                    match (f, v) {
                        (1, Value::Varint(s)) => seconds = s,
                        (2, Value::Varint(n)) => nanos = n,
                        _ => {}
                    }
                    Ok(())
                })?;
                if i64::try_from(seconds).is_err() || nanos >= 1_000_000_000 {
                    return Err(format!(
                        "PoseInFrame.timestamp: {seconds} s {nanos} ns, expected a time after 1970"
                    ));
                }
                stamp_ns = seconds
                    .checked_mul(1_000_000_000)
                    .and_then(|ns| ns.checked_add(nanos))
                    .ok_or("PoseInFrame.timestamp: too far in the future")?;
            }
            (3, Value::Bytes(pose)) => {
                has_pose = true;
                fields(pose, "PoseInFrame.pose", |f, v| {
                    match (f, v) {
                        (1, Value::Bytes(b)) => position = doubles(b, "PoseInFrame.pose.position")?,
                        (2, Value::Bytes(b)) => {
                            orientation = doubles(b, "PoseInFrame.pose.orientation")?;
                        }
                        _ => {}
                    }
                    Ok(())
                })?;
            }
            (1 | 3, _) => return Err(format!("PoseInFrame: field {field} is not a message")),
            _ => {}
        }
        Ok(())
    })?;
    if !has_pose {
        return Err("PoseInFrame: no pose (field 3)".to_owned());
    }
    Ok(PlanarPose {
        stamp_ns,
        x: position[0],
        y: position[1],
        yaw: yaw_of(orientation),
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    /// What the Foxglove Python SDK 0.30.3 encodes for `PoseInFrame(timestamp=Timestamp(sec=
    /// 1700000000, nsec=5), frame_id="table", pose=Pose(position=Vector3(x=0.25, y=-0.5, z=0),
    /// orientation=Quaternion(x=0, y=0, z=sin(π/8), w=cos(π/8))))`: a 45° yaw.
    const FROM_PYTHON: &str = "0a080880e2cfaa06100512057461626c651a280a1209000000000000d03f11000000000000e0bf12121963a9aea6e27dd83f21468d32cf6b90ed3f";

    fn hex(text: &str) -> Vec<u8> {
        (0..text.len())
            .step_by(2)
            .map(|i| u8::from_str_radix(&text[i..i + 2], 16).unwrap())
            .collect()
    }

    #[test]
    fn the_python_sdks_pose_in_frame_reads_as_logged() {
        let pose = decode(&hex(FROM_PYTHON)).unwrap();
        assert_eq!(pose.stamp_ns, 1_700_000_000_000_000_005);
        assert_eq!((pose.x, pose.y), (0.25, -0.5));
        assert!(
            (pose.yaw - std::f64::consts::FRAC_PI_4).abs() < 1e-12,
            "{}",
            pose.yaw
        );
    }

    #[test]
    fn every_cut_of_it_is_refused_or_read_never_panicked_on() {
        let bytes = hex(FROM_PYTHON);
        for end in 0..bytes.len() {
            let _ = decode(&bytes[..end]);
        }
        assert_eq!(
            decode(&bytes[..bytes.len() - 3]).unwrap_err(),
            "PoseInFrame: cut short"
        );
        assert_eq!(decode(&[]).unwrap_err(), "PoseInFrame: no pose (field 3)");
        assert!(
            decode(&[0x0b]).unwrap_err().contains("wire type 3"),
            "a group"
        );
    }
}
