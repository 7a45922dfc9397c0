//! A camera frame as stored (JPEG or PNG bytes, or raw pixels with their layout) and as shown (RGBA,
//! 8 bits a channel), and the one decoder between them.
//!
//! Every size is checked before anything is allocated: a corrupt header cannot make a frame claim
//! gigabytes. An encoding pushlab does not read is named in the error, never guessed.

use std::fmt;

/// Largest frame accepted, pixels per side and pixels in all (a 16K camera is far above any).
pub const MAX_SIDE: u32 = 16_384;
pub const MAX_PIXELS: u64 = 64 << 20;

/// A frame as stored.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EncodedImage {
    pub format: ImageFormat,
    pub bytes: Vec<u8>,
}

/// How a frame's bytes are encoded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    Jpeg,
    Png,
    /// Pixels row by row, `step` bytes a row (`sensor_msgs/Image`).
    Raw {
        encoding: RawEncoding,
        width: u32,
        height: u32,
        step: u32,
        big_endian: bool,
    },
}

/// The raw pixel layouts pushlab reads (ROS's `sensor_msgs/image_encodings` names).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RawEncoding {
    Rgb8,
    Bgr8,
    Rgba8,
    Bgra8,
    Mono8,
    Mono16,
}

impl RawEncoding {
    /// Every encoding, as ROS names them.
    pub const ALL: [(RawEncoding, &'static str); 6] = [
        (RawEncoding::Rgb8, "rgb8"),
        (RawEncoding::Bgr8, "bgr8"),
        (RawEncoding::Rgba8, "rgba8"),
        (RawEncoding::Bgra8, "bgra8"),
        (RawEncoding::Mono8, "mono8"),
        (RawEncoding::Mono16, "mono16"),
    ];

    /// The encoding ROS calls `name` (case-insensitive, as `8UC1`-style aliases are not).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|(_, n)| n.eq_ignore_ascii_case(name))
            .map(|(e, _)| e)
    }

    /// Its ROS name.
    pub fn name(self) -> &'static str {
        Self::ALL
            .into_iter()
            .find(|(e, _)| *e == self)
            .map_or("?", |(_, n)| n)
    }

    /// Bytes a pixel.
    pub fn bytes_per_pixel(self) -> u32 {
        match self {
            RawEncoding::Mono8 => 1,
            RawEncoding::Mono16 => 2,
            RawEncoding::Rgb8 | RawEncoding::Bgr8 => 3,
            RawEncoding::Rgba8 | RawEncoding::Bgra8 => 4,
        }
    }
}

impl fmt::Display for ImageFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ImageFormat::Jpeg => f.write_str("jpeg"),
            ImageFormat::Png => f.write_str("png"),
            ImageFormat::Raw { encoding, .. } => f.write_str(encoding.name()),
        }
    }
}

/// A frame ready to draw: RGBA, 8 bits a channel, row by row without padding.
#[derive(Clone, PartialEq, Eq)]
pub struct RgbaImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<u8>,
}

impl fmt::Debug for RgbaImage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "RgbaImage({}×{})", self.width, self.height)
    }
}

impl RgbaImage {
    /// The pixel at `(x, y)`, `[r, g, b, a]`.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let at = 4 * (y as usize * self.width as usize + x as usize);
        self.pixels.get(at..at + 4)?.try_into().ok()
    }

    /// Bytes it holds.
    pub fn byte_size(&self) -> usize {
        self.pixels.len()
    }
}

/// Why a frame cannot be shown.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ImageProblem {
    #[error("not a readable {format} image: {why}")]
    Corrupt { format: &'static str, why: String },
    #[error("{width}×{height} pixels, more than pushlab shows (at most {MAX_SIDE} a side)")]
    TooLarge { width: u64, height: u64 },
    #[error(
        "{encoding} pixels of {width}×{height} with {step} bytes a row need {needed} bytes, but the \
         frame holds {found}"
    )]
    RawTooShort {
        encoding: &'static str,
        width: u32,
        height: u32,
        step: u32,
        needed: u64,
        found: usize,
    },
}

/// The frame as RGBA.
pub fn decode(image: &EncodedImage) -> Result<RgbaImage, ImageProblem> {
    match &image.format {
        ImageFormat::Jpeg => decode_compressed(&image.bytes, image::ImageFormat::Jpeg, "jpeg"),
        ImageFormat::Png => decode_compressed(&image.bytes, image::ImageFormat::Png, "png"),
        &ImageFormat::Raw {
            encoding,
            width,
            height,
            step,
            big_endian,
        } => decode_raw(&image.bytes, encoding, width, height, step, big_endian),
    }
}

fn decode_compressed(
    bytes: &[u8],
    format: image::ImageFormat,
    name: &'static str,
) -> Result<RgbaImage, ImageProblem> {
    let corrupt = |why: String| ImageProblem::Corrupt { format: name, why };
    let mut reader = image::ImageReader::with_format(std::io::Cursor::new(bytes), format);
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_SIDE);
    limits.max_image_height = Some(MAX_SIDE);
    limits.max_alloc = Some(4 * MAX_PIXELS);
    reader.limits(limits);
    let decoded = reader.decode().map_err(|e| match e {
        image::ImageError::Limits(_) => {
            let (width, height) = dimensions(bytes).unwrap_or((0, 0));
            ImageProblem::TooLarge {
                width: u64::from(width),
                height: u64::from(height),
            }
        }
        other => corrupt(other.to_string()),
    })?;
    // 16-bit grey (a depth camera's `mono16`, as `pushlab import` stores it) is stretched from
    // its darkest to its brightest value, as the raw frame is: not cut to its top 8 bits, which
    // leaves depth in millimetres nearly black.
    if let image::DynamicImage::ImageLuma16(grey) = &decoded {
        return Ok(stretched_mono16(grey.width(), grey.height(), grey.as_raw()));
    }
    let rgba = decoded.into_rgba8();
    Ok(RgbaImage {
        width: rgba.width(),
        height: rgba.height(),
        pixels: rgba.into_raw(),
    })
}

/// 16-bit grey values, row by row, shown from the darkest to the brightest.
fn stretched_mono16(width: u32, height: u32, values: &[u16]) -> RgbaImage {
    let (low, high) = (values.iter()).fold((u16::MAX, 0), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    let span = f32::from(high.saturating_sub(low).max(1));
    let pixels = (values.iter())
        .flat_map(|&v| {
            let g = (f32::from(v.saturating_sub(low)) / span * 255.0).round() as u8;
            [g, g, g, 255]
        })
        .collect();
    RgbaImage {
        width,
        height,
        pixels,
    }
}

fn decode_raw(
    bytes: &[u8],
    encoding: RawEncoding,
    width: u32,
    height: u32,
    step: u32,
    big_endian: bool,
) -> Result<RgbaImage, ImageProblem> {
    check_raw(bytes, encoding, width, height, step)?;
    let (w, h, step) = (width as usize, height as usize, step as usize);
    if encoding == RawEncoding::Mono16 {
        // Depth or IR: shown from its darkest to its brightest value, as a 16-bit PNG is.
        let value = |b: &[u8]| {
            if big_endian {
                u16::from_be_bytes([b[0], b[1]])
            } else {
                u16::from_le_bytes([b[0], b[1]])
            }
        };
        let values: Vec<u16> = (0..h)
            .flat_map(|y| bytes[y * step..y * step + 2 * w].chunks_exact(2).map(value))
            .collect();
        return Ok(stretched_mono16(width, height, &values));
    }
    let mut pixels = Vec::with_capacity(4 * w * h);
    for y in 0..h {
        let line = &bytes[y * step..];
        for x in 0..w {
            let px = match encoding {
                RawEncoding::Rgb8 => [line[3 * x], line[3 * x + 1], line[3 * x + 2], 255],
                RawEncoding::Bgr8 => [line[3 * x + 2], line[3 * x + 1], line[3 * x], 255],
                RawEncoding::Rgba8 => [
                    line[4 * x],
                    line[4 * x + 1],
                    line[4 * x + 2],
                    line[4 * x + 3],
                ],
                RawEncoding::Bgra8 => [
                    line[4 * x + 2],
                    line[4 * x + 1],
                    line[4 * x],
                    line[4 * x + 3],
                ],
                // Mono16 was shown above; the pattern only keeps the match whole.
                RawEncoding::Mono8 | RawEncoding::Mono16 => [line[x], line[x], line[x], 255],
            };
            pixels.extend_from_slice(&px);
        }
    }
    Ok(RgbaImage {
        width,
        height,
        pixels,
    })
}

/// A frame as it is stored in a set: JPEG and PNG as they are, raw pixels as a PNG that keeps them
/// (8-bit RGB, RGBA or grey; 16-bit grey for `mono16`).
pub fn to_stored(image: EncodedImage) -> Result<EncodedImage, ImageProblem> {
    let &ImageFormat::Raw {
        encoding,
        width,
        height,
        step,
        big_endian,
    } = &image.format
    else {
        return Ok(image);
    };
    let corrupt = |e: image::ImageError| ImageProblem::Corrupt {
        format: "png",
        why: e.to_string(),
    };
    let mut out = std::io::Cursor::new(Vec::new());
    if encoding == RawEncoding::Mono16 {
        check_raw(&image.bytes, encoding, width, height, step)?;
        let (w, h, step) = (width as usize, height as usize, step as usize);
        let values: Vec<u16> = (0..h)
            .flat_map(|y| image.bytes[y * step..y * step + 2 * w].chunks_exact(2))
            .map(|b| {
                if big_endian {
                    u16::from_be_bytes([b[0], b[1]])
                } else {
                    u16::from_le_bytes([b[0], b[1]])
                }
            })
            .collect();
        let grey = image::ImageBuffer::<image::Luma<u16>, _>::from_raw(width, height, values)
            .ok_or_else(|| ImageProblem::TooLarge {
                width: u64::from(width),
                height: u64::from(height),
            })?;
        grey.write_to(&mut out, image::ImageFormat::Png)
            .map_err(corrupt)?;
    } else {
        let rgba = decode(&image)?;
        let buffer = image::RgbaImage::from_raw(rgba.width, rgba.height, rgba.pixels).ok_or(
            ImageProblem::TooLarge {
                width: u64::from(width),
                height: u64::from(height),
            },
        )?;
        let dynamic = image::DynamicImage::ImageRgba8(buffer);
        let kept = match encoding {
            RawEncoding::Mono8 => image::DynamicImage::ImageLuma8(dynamic.to_luma8()),
            RawEncoding::Rgb8 | RawEncoding::Bgr8 => {
                image::DynamicImage::ImageRgb8(dynamic.to_rgb8())
            }
            _ => dynamic,
        };
        kept.write_to(&mut out, image::ImageFormat::Png)
            .map_err(corrupt)?;
    }
    Ok(EncodedImage {
        format: ImageFormat::Png,
        bytes: out.into_inner(),
    })
}

/// Refuses raw pixels larger than pushlab shows, or fewer bytes than their layout needs.
fn check_raw(
    bytes: &[u8],
    encoding: RawEncoding,
    width: u32,
    height: u32,
    step: u32,
) -> Result<(), ImageProblem> {
    if width > MAX_SIDE || height > MAX_SIDE || u64::from(width) * u64::from(height) > MAX_PIXELS {
        return Err(ImageProblem::TooLarge {
            width: u64::from(width),
            height: u64::from(height),
        });
    }
    let row = u64::from(width) * u64::from(encoding.bytes_per_pixel());
    let needed = if height == 0 {
        0
    } else {
        u64::from(step) * u64::from(height - 1) + row
    };
    if u64::from(step) < row || (bytes.len() as u64) < needed {
        return Err(ImageProblem::RawTooShort {
            encoding: encoding.name(),
            width,
            height,
            step,
            needed: needed.max(row * u64::from(height)),
            found: bytes.len(),
        });
    }
    Ok(())
}

/// The width and height a JPEG or PNG file says it has, read from its header (its first frame
/// marker or `IHDR`), without decoding it: what `pushlab validate` lists.
pub fn dimensions(bytes: &[u8]) -> Option<(u32, u32)> {
    if let Some(ihdr) = bytes.strip_prefix(b"\x89PNG\r\n\x1a\n") {
        let width = u32::from_be_bytes(ihdr.get(8..12)?.try_into().ok()?);
        let height = u32::from_be_bytes(ihdr.get(12..16)?.try_into().ok()?);
        return Some((width, height));
    }
    let mut rest = bytes.strip_prefix(&[0xFF, 0xD8])?;
    loop {
        let (&[marker_start, marker], tail) = rest.split_first_chunk::<2>()?;
        if marker_start != 0xFF {
            return None;
        }
        if marker == 0xFF {
            rest = &rest[1..];
            continue;
        }
        let len = usize::from(u16::from_be_bytes(tail.get(..2)?.try_into().ok()?));
        // Start-of-frame markers (baseline, progressive, …), not DHT/JPG/DAC.
        if matches!(marker, 0xC0..=0xCF) && !matches!(marker, 0xC4 | 0xC8 | 0xCC) {
            let height = u16::from_be_bytes(tail.get(3..5)?.try_into().ok()?);
            let width = u16::from_be_bytes(tail.get(5..7)?.try_into().ok()?);
            return Some((u32::from(width), u32::from(height)));
        }
        rest = tail.get(len..)?;
    }
}

/// What the first bytes say a compressed frame is, when they say.
pub fn sniff(bytes: &[u8]) -> Option<ImageFormat> {
    if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
        Some(ImageFormat::Jpeg)
    } else if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        Some(ImageFormat::Png)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn encoded(format: image::ImageFormat, width: u32, height: u32) -> Vec<u8> {
        let image = image::RgbImage::from_fn(width, height, |x, y| {
            image::Rgb([(x * 8) as u8, (y * 8) as u8, 128])
        });
        let mut out = std::io::Cursor::new(Vec::new());
        image.write_to(&mut out, format).unwrap();
        out.into_inner()
    }

    #[test]
    fn png_and_jpeg_decode_to_their_size_and_colours() {
        for (format, ours, tolerance) in [
            (image::ImageFormat::Png, ImageFormat::Png, 0),
            (image::ImageFormat::Jpeg, ImageFormat::Jpeg, 12),
        ] {
            let bytes = encoded(format, 32, 24);
            assert_eq!(dimensions(&bytes), Some((32, 24)), "{format:?}");
            assert_eq!(sniff(&bytes), Some(ours.clone()));
            let rgba = decode(&EncodedImage {
                format: ours,
                bytes,
            })
            .unwrap();
            assert_eq!((rgba.width, rgba.height), (32, 24));
            let [r, g, b, a] = rgba.pixel(20, 10).unwrap();
            for (got, want) in [(r, 160), (g, 80), (b, 128), (a, 255)] {
                assert!(
                    got.abs_diff(want) <= tolerance,
                    "{format:?}: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn raw_layouts_become_rgba_and_short_frames_are_named() {
        let raw = |encoding, bytes: Vec<u8>, step| EncodedImage {
            format: ImageFormat::Raw {
                encoding,
                width: 2,
                height: 1,
                step,
                big_endian: false,
            },
            bytes,
        };
        let bgr = decode(&raw(RawEncoding::Bgr8, vec![1, 2, 3, 4, 5, 6, 0, 0], 8)).unwrap();
        assert_eq!(bgr.pixels, [3, 2, 1, 255, 6, 5, 4, 255]);
        let mono16 = decode(&raw(RawEncoding::Mono16, vec![0, 1, 0, 2], 4)).unwrap();
        assert_eq!(mono16.pixels, [0, 0, 0, 255, 255, 255, 255, 255]);
        let short = decode(&raw(RawEncoding::Rgba8, vec![0; 7], 8)).unwrap_err();
        assert!(short.to_string().contains("rgba8 pixels of 2×1"), "{short}");
    }

    #[test]
    fn raw_frames_are_stored_as_png_without_loss() {
        let mono16 = EncodedImage {
            format: ImageFormat::Raw {
                encoding: RawEncoding::Mono16,
                width: 2,
                height: 1,
                step: 4,
                big_endian: false,
            },
            bytes: vec![0x34, 0x12, 0xFF, 0xFF],
        };
        let shown_raw = decode(&mono16).unwrap();
        let stored = to_stored(mono16).unwrap();
        assert_eq!(stored.format, ImageFormat::Png);
        // Shown from the stored PNG as from the raw frame: depth stretched, not cut to 8 bits.
        assert_eq!(decode(&stored).unwrap().pixels, shown_raw.pixels);
        assert_eq!(shown_raw.pixel(0, 0), Some([0, 0, 0, 255]));
        let back = image::load_from_memory(&stored.bytes)
            .unwrap()
            .into_luma16();
        assert_eq!(back.into_raw(), [0x1234, 0xFFFF]);
        let bgr = EncodedImage {
            format: ImageFormat::Raw {
                encoding: RawEncoding::Bgr8,
                width: 1,
                height: 1,
                step: 3,
                big_endian: false,
            },
            bytes: vec![1, 2, 3],
        };
        let back = image::load_from_memory(&to_stored(bgr).unwrap().bytes)
            .unwrap()
            .into_rgb8();
        assert_eq!(back.into_raw(), [3, 2, 1]);
    }

    #[test]
    fn a_corrupt_jpeg_is_an_error_not_a_panic() {
        let mut bytes = encoded(image::ImageFormat::Jpeg, 64, 48);
        bytes.truncate(bytes.len() / 3);
        let problem = decode(&EncodedImage {
            format: ImageFormat::Jpeg,
            bytes,
        });
        // A cut JPEG may decode with grey rows (as browsers show it) or be refused; never a panic.
        if let Err(p) = problem {
            assert!(
                p.to_string().starts_with("not a readable jpeg image"),
                "{p}"
            );
        }
        let junk = decode(&EncodedImage {
            format: ImageFormat::Jpeg,
            bytes: b"\xFF\xD8\xFF not a jpeg".to_vec(),
        })
        .unwrap_err();
        assert!(
            junk.to_string().starts_with("not a readable jpeg image"),
            "{junk}"
        );
    }
}
