//! Camera messages: `sensor_msgs/msg/CompressedImage` (JPEG or PNG bytes and a format string) and
//! `sensor_msgs/msg/Image` (raw pixels with their encoding, size and row step), read from CDR into
//! a frame as stored.

use super::cdr::Cdr;
use crate::recording::camera::{EncodedImage, FrameProblem, ImageFormat, RawEncoding, sniff};

/// The camera message types pushlab reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageKind {
    /// `sensor_msgs/msg/CompressedImage`
    Compressed,
    /// `sensor_msgs/msg/Image`
    Raw,
}

impl ImageKind {
    /// The kind for a schema name (ROS 1 style names without `/msg/` too).
    pub fn from_schema(name: &str) -> Option<Self> {
        match name.replace("/msg/", "/").as_str() {
            "sensor_msgs/CompressedImage" => Some(Self::Compressed),
            "sensor_msgs/Image" => Some(Self::Raw),
            _ => None,
        }
    }

    /// The ROS 2 type name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Compressed => "sensor_msgs/msg/CompressedImage",
            Self::Raw => "sensor_msgs/msg/Image",
        }
    }
}

/// The header stamp of a camera message (nanoseconds; 0 when unset), from its first 12 bytes.
pub fn stamp(head: &[u8]) -> Result<u64, String> {
    Cdr::new(head)?.stamp()
}

/// Bytes of a message's start that hold its stamp.
pub const STAMP_BYTES: usize = 12;

/// The frame a camera message carries, and its header stamp.
pub fn decode(kind: ImageKind, payload: &[u8]) -> Result<(u64, EncodedImage), FrameProblem> {
    let mut cdr = Cdr::new(payload).map_err(FrameProblem::Message)?;
    let stamp = cdr.header().map_err(FrameProblem::Message)?;
    let image = match kind {
        ImageKind::Compressed => {
            let format = cdr.string("format").map_err(FrameProblem::Message)?;
            let data = cdr.bytes("data").map_err(FrameProblem::Message)?;
            let format = String::from_utf8_lossy(format).into_owned();
            let lower = format.to_ascii_lowercase();
            let kind = if lower.contains("jpeg") || lower.contains("jpg") {
                Some(ImageFormat::Jpeg)
            } else if lower.contains("png") {
                Some(ImageFormat::Png)
            } else {
                None
            };
            let format = kind
                .or_else(|| sniff(data))
                .ok_or(FrameProblem::UnknownEncoding(format))?;
            EncodedImage {
                format,
                bytes: data.to_vec(),
            }
        }
        ImageKind::Raw => {
            let height = cdr.u32("height").map_err(FrameProblem::Message)?;
            let width = cdr.u32("width").map_err(FrameProblem::Message)?;
            let encoding = cdr.string("encoding").map_err(FrameProblem::Message)?;
            let big_endian = cdr.u8("is_bigendian").map_err(FrameProblem::Message)? != 0;
            let step = cdr.u32("step").map_err(FrameProblem::Message)?;
            let data = cdr.bytes("data").map_err(FrameProblem::Message)?;
            let name = String::from_utf8_lossy(encoding);
            let encoding = RawEncoding::from_name(&name)
                .ok_or_else(|| FrameProblem::UnknownEncoding(name.into_owned()))?;
            EncodedImage {
                format: ImageFormat::Raw {
                    encoding,
                    width,
                    height,
                    step,
                    big_endian,
                },
                bytes: data.to_vec(),
            }
        }
    };
    Ok((stamp, image))
}

/// What the start of a camera message says of its frames, for listing: the encoding and the size
/// (`None` where the first bytes do not hold them).
pub fn describe(kind: ImageKind, head: &[u8]) -> (String, Option<(u32, u32)>) {
    let Ok(mut cdr) = Cdr::new(head) else {
        return ("?".to_owned(), None);
    };
    if cdr.header().is_err() {
        return ("?".to_owned(), None);
    }
    match kind {
        ImageKind::Compressed => {
            let format = cdr
                .string("format")
                .map(|f| String::from_utf8_lossy(f).into_owned());
            // The data sequence's length, then its first bytes: a JPEG's frame header or a PNG's IHDR.
            let data = cdr.u32("data").ok().and(Some(cdr.rest()));
            let size = data.and_then(crate::recording::camera::dimensions);
            (format.unwrap_or_else(|_| "?".to_owned()), size)
        }
        ImageKind::Raw => {
            let (Ok(height), Ok(width), Ok(encoding)) =
                (cdr.u32("height"), cdr.u32("width"), cdr.string("encoding"))
            else {
                return ("?".to_owned(), None);
            };
            (
                String::from_utf8_lossy(encoding).into_owned(),
                Some((width, height)),
            )
        }
    }
}

/// A little-endian `sensor_msgs/msg/CompressedImage` as rclcpp serialises it: for tests and
/// benchmarks that write bags of their own.
pub fn encode_compressed_image(
    stamp_ns: u64,
    frame_id: &str,
    format: &str,
    data: &[u8],
) -> Vec<u8> {
    let mut body = Vec::with_capacity(32 + frame_id.len() + format.len() + data.len());
    body.extend(((stamp_ns / 1_000_000_000) as u32).to_le_bytes());
    body.extend(((stamp_ns % 1_000_000_000) as u32).to_le_bytes());
    for text in [frame_id, format] {
        while body.len() % 4 != 0 {
            body.push(0);
        }
        body.extend((text.len() as u32 + 1).to_le_bytes());
        body.extend(text.as_bytes());
        body.push(0);
    }
    while body.len() % 4 != 0 {
        body.push(0);
    }
    body.extend((data.len() as u32).to_le_bytes());
    body.extend(data);
    let mut message = vec![0, 1, 0, 0];
    message.extend(body);
    message
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn a_compressed_image_gives_its_stamp_bytes_and_format() {
        let jpeg = [0xFF, 0xD8, 0xFF, 0xE0, 1, 2, 3];
        let message = encode_compressed_image(1_700_000_000_250_000_000, "cam", "jpeg", &jpeg);
        let (stamp, image) = decode(ImageKind::Compressed, &message).unwrap();
        assert_eq!(stamp, 1_700_000_000_250_000_000);
        assert_eq!(
            (image.format, image.bytes.as_slice()),
            (ImageFormat::Jpeg, &jpeg[..])
        );
        assert_eq!(super::stamp(&message[..STAMP_BYTES]).unwrap(), stamp);
    }

    #[test]
    fn unknown_encodings_and_cut_messages_are_named() {
        let message = encode_compressed_image(1, "cam", "tiff", b"II*\0");
        let e = decode(ImageKind::Compressed, &message).unwrap_err();
        assert_eq!(e.to_string().split('`').nth(1), Some("tiff"));
        let cut = &message[..message.len() - 2];
        let e = decode(ImageKind::Compressed, cut).unwrap_err();
        assert!(e.to_string().contains("the data claims 4 bytes"), "{e}");
    }
}
