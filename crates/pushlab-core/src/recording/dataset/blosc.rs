//! Blosc (version 1 frames, as numcodecs and c-blosc 1.x write them inside zarr v2 chunks), decoded
//! in Rust with the crate's own LZ4 and zstd decoders: no C library.
//!
//! A frame is a 16-byte header (format version, codec version, flags, type size, uncompressed size,
//! block size, compressed size), then — unless the buffer was stored as is — one offset per block.
//! Each block holds one stream, or one per byte of the type when it was split, each prefixed by its
//! compressed length (equal to its plain length when stored raw); then the block is un-shuffled
//! (bytes, or bits) back into elements. Only the codecs Diffusion Policy's replay buffers use are
//! read — LZ4 and zstd; blosclz, snappy and zlib frames are refused by name.

use super::problem::DatasetProblem;

const HEADER: usize = 16;
const FLAG_SHUFFLE: u8 = 0x01;
const FLAG_MEMCPYED: u8 = 0x02;
const FLAG_BITSHUFFLE: u8 = 0x04;
const FLAG_DONT_SPLIT: u8 = 0x10;
/// c-blosc splits a block into one stream per byte of the type only for types this small…
const MAX_SPLITS: usize = 16;
/// …and blocks of at least this many elements.
const MIN_BUFFERSIZE: usize = 128;

fn u32_at(bytes: &[u8], at: usize) -> Option<usize> {
    let b: [u8; 4] = bytes.get(at..at + 4)?.try_into().ok()?;
    usize::try_from(u32::from_le_bytes(b)).ok()
}

fn corrupt(why: impl Into<String>) -> DatasetProblem {
    DatasetProblem::Codec(format!("blosc: {}", why.into()))
}

/// The plain bytes of one blosc frame, checked against `expected` bytes (the chunk's size).
pub fn decompress(frame: &[u8], expected: usize) -> Result<Vec<u8>, DatasetProblem> {
    if frame.len() < HEADER {
        return Err(corrupt(format!(
            "{} bytes, shorter than its header",
            frame.len()
        )));
    }
    let (version, flags, typesize) = (frame[0], frame[2], usize::from(frame[3]));
    let nbytes = u32_at(frame, 4).unwrap_or(0);
    let blocksize = u32_at(frame, 8).unwrap_or(0);
    if version == 0 || version > 4 {
        return Err(corrupt(format!(
            "format version {version}, expected 1 to 4"
        )));
    }
    if nbytes != expected {
        return Err(corrupt(format!(
            "holds {nbytes} bytes, the chunk has {expected}"
        )));
    }
    if nbytes == 0 {
        return Ok(Vec::new());
    }
    if flags & FLAG_MEMCPYED != 0 {
        return frame
            .get(HEADER..HEADER + nbytes)
            .map(<[u8]>::to_vec)
            .ok_or_else(|| corrupt("stored frame cut short"));
    }
    if blocksize == 0 || typesize == 0 {
        return Err(corrupt("block size or type size 0"));
    }
    let codec = match flags >> 5 {
        1 => Codec::Lz4,
        4 => Codec::Zstd,
        other => {
            let name = ["blosclz", "lz4", "snappy", "zlib", "zstd"].get(usize::from(other));
            return Err(DatasetProblem::Codec(format!(
                "blosc with the {} codec is not supported (only lz4 and zstd)",
                name.unwrap_or(&"unknown")
            )));
        }
    };
    let nblocks = nbytes.div_ceil(blocksize);
    let mut out = vec![0u8; nbytes];
    // A block is never longer than the chunk: a header's block size is not trusted to allocate.
    let mut scratch = vec![0u8; blocksize.min(nbytes)];
    for block in 0..nblocks {
        let start =
            u32_at(frame, HEADER + 4 * block).ok_or_else(|| corrupt("block offsets cut short"))?;
        let size = blocksize.min(nbytes - block * blocksize);
        let leftover = size < blocksize;
        let splits = if flags & FLAG_DONT_SPLIT == 0
            && typesize <= MAX_SPLITS
            && blocksize / typesize >= MIN_BUFFERSIZE
            && !leftover
        {
            typesize
        } else {
            1
        };
        let stream = size / splits;
        let mut at = start;
        for part in scratch[..size].chunks_mut(stream) {
            let length = u32_at(frame, at).ok_or_else(|| corrupt("stream length cut short"))?;
            at += 4;
            let data = frame
                .get(at..at + length)
                .ok_or_else(|| corrupt(format!("block {block} cut short")))?;
            at += length;
            if length == part.len() {
                part.copy_from_slice(data);
            } else {
                codec.decompress(data, part)?;
            }
        }
        let dest = &mut out[block * blocksize..block * blocksize + size];
        if flags & FLAG_BITSHUFFLE != 0 && size >= typesize {
            bit_unshuffle(&scratch[..size], dest, typesize);
        } else if flags & FLAG_SHUFFLE != 0 && typesize > 1 {
            byte_unshuffle(&scratch[..size], dest, typesize);
        } else {
            dest.copy_from_slice(&scratch[..size]);
        }
    }
    Ok(out)
}

#[derive(Clone, Copy)]
enum Codec {
    Lz4,
    Zstd,
}

impl Codec {
    /// Decodes one stream into exactly `out.len()` bytes.
    fn decompress(self, data: &[u8], out: &mut [u8]) -> Result<(), DatasetProblem> {
        let written = match self {
            Codec::Lz4 => lz4_flex::block::decompress_into(data, out)
                .map_err(|e| corrupt(format!("lz4: {e}")))?,
            Codec::Zstd => {
                let mut decoder = ruzstd::decoding::FrameDecoder::new();
                decoder
                    .decode_all(data, out)
                    .map_err(|e| corrupt(format!("zstd: {e}")))?
            }
        };
        if written == out.len() {
            Ok(())
        } else {
            Err(corrupt(format!(
                "a stream gave {written} bytes, expected {}",
                out.len()
            )))
        }
    }
}

/// Byte shuffle undone: the input holds byte 0 of every element, then byte 1 of every element…;
/// bytes past the last whole element are kept as they are.
fn byte_unshuffle(src: &[u8], dest: &mut [u8], typesize: usize) {
    let elements = src.len() / typesize;
    for byte in 0..typesize {
        for element in 0..elements {
            dest[element * typesize + byte] = src[byte * elements + element];
        }
    }
    let whole = elements * typesize;
    dest[whole..].copy_from_slice(&src[whole..]);
}

/// Bit shuffle undone (bitshuffle's `trans_bit_elem`): the input is one row of bits per bit of the
/// element (byte `j`, bit `k` → row `8j + k`), each row holding that bit of every element, least
/// significant first. Only whole groups of 8 elements are shuffled; the rest is kept as is.
fn bit_unshuffle(src: &[u8], dest: &mut [u8], typesize: usize) {
    let elements = src.len() / typesize / 8 * 8;
    dest.fill(0);
    for byte in 0..typesize {
        for bit in 0..8 {
            let row = (byte * 8 + bit) * elements;
            for element in 0..elements {
                let at = row + element;
                let value = (src[at / 8] >> (at % 8)) & 1;
                dest[element * typesize + byte] |= value << bit;
            }
        }
    }
    let whole = elements * typesize;
    dest[whole..].copy_from_slice(&src[whole..]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_and_bit_shuffles_undo_their_own_layout() {
        // Four 2-byte elements, byte-shuffled: low bytes first, then high bytes.
        let mut plain = [0u8; 8];
        byte_unshuffle(&[1, 2, 3, 4, 10, 20, 30, 40], &mut plain, 2);
        assert_eq!(plain, [1, 10, 2, 20, 3, 30, 4, 40]);
        // Eight 1-byte elements 0..8 bit-shuffled: row k holds bit k of each element.
        let shuffled = [0b1010_1010, 0b1100_1100, 0b1111_0000, 0, 0, 0, 0, 0];
        let mut plain = [0u8; 8];
        bit_unshuffle(&shuffled, &mut plain, 1);
        assert_eq!(plain, [0, 1, 2, 3, 4, 5, 6, 7]);
    }

    #[test]
    fn bad_frames_are_refused_not_panicked_on() {
        assert!(decompress(&[2, 1, 0x21, 4], 16).is_err());
        let mut header = [0u8; 16];
        header[0] = 2;
        header[2] = 0x21; // lz4, not stored
        header[3] = 4;
        header[4] = 16; // 16 bytes
        header[8] = 16; // one block
        assert!(decompress(&header, 16).is_err());
        header[2] = 0x61; // zlib
        let refusal = decompress(&header, 16).expect_err("zlib").to_string();
        assert!(refusal.contains("zlib codec is not supported"), "{refusal}");
    }
}
