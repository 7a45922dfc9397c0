//! The MCAP records pushlab reads, parsed from their bodies with every length checked against the
//! bytes present, and chunk decompression.
//!
//! Foxglove's `mcap` crate is not used for record bodies: its parser reserves whatever a corrupt
//! string length claims (fuzzing found a 2.5 GB allocation from a 100-byte file), and its readers
//! hold a chunk whole where pushlab reads single messages out of it. Chunks are decompressed with
//! pure-Rust decoders (`ruzstd`, `lz4_flex`) rather than the crate's C-library features.

use std::collections::BTreeMap;
use std::io::Read;

/// The magic bytes an MCAP file starts and ends with.
pub const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

pub const OP_FOOTER: u8 = 0x02;
pub const OP_SCHEMA: u8 = 0x03;
pub const OP_CHANNEL: u8 = 0x04;
pub const OP_MESSAGE: u8 = 0x05;
pub const OP_CHUNK: u8 = 0x06;
pub const OP_MESSAGE_INDEX: u8 = 0x07;
pub const OP_CHUNK_INDEX: u8 = 0x08;
pub const OP_STATISTICS: u8 = 0x0B;
pub const OP_DATA_END: u8 = 0x0F;

/// A record's opcode and length: 9 bytes before its body.
pub const RECORD_HEADER: u64 = 9;
/// A message record's fixed fields before its payload: channel id, sequence, log and publish time.
pub const MESSAGE_HEADER: u64 = 22;
/// The footer record's body: summary start, summary offset start, summary CRC.
pub const FOOTER_BODY: u64 = 20;

/// Largest decompressed chunk accepted: far above any chunk a recorder writes (rosbag2 and the
/// Foxglove writers use a few MB), and it bounds the memory a corrupt size field can claim.
pub const MAX_CHUNK_BYTES: u64 = 1 << 30;
/// Largest accepted ratio of a chunk's uncompressed to compressed size (real pose data compresses
/// some 3–10×), so that a corrupt size cannot make a tiny file allocate a gigabyte.
const MAX_RATIO: u64 = 4096;

/// Bounded little-endian reads from a record body.
pub struct Body<'a>(pub &'a [u8]);

impl<'a> Body<'a> {
    pub fn bytes(&mut self, n: usize) -> Option<&'a [u8]> {
        let (head, tail) = self.0.split_at_checked(n)?;
        self.0 = tail;
        Some(head)
    }

    pub fn u16(&mut self) -> Option<u16> {
        Some(u16::from_le_bytes(self.bytes(2)?.try_into().ok()?))
    }

    pub fn u32(&mut self) -> Option<u32> {
        Some(u32::from_le_bytes(self.bytes(4)?.try_into().ok()?))
    }

    pub fn u64(&mut self) -> Option<u64> {
        Some(u64::from_le_bytes(self.bytes(8)?.try_into().ok()?))
    }

    /// A `u32`-prefixed UTF-8 string (invalid UTF-8 replaced: names are only shown and compared).
    pub fn string(&mut self) -> Option<String> {
        let len = self.u32()? as usize;
        Some(String::from_utf8_lossy(self.bytes(len)?).into_owned())
    }

    /// A `u32`-byte-length-prefixed block, as maps and arrays are stored.
    pub fn block(&mut self) -> Option<Body<'a>> {
        let len = self.u32()? as usize;
        Some(Body(self.bytes(len)?))
    }

    /// What is left.
    pub fn rest(&self) -> &'a [u8] {
        self.0
    }
}

/// A schema record: its id and name (the ROS 2 message type).
pub fn schema(body: &[u8]) -> Option<(u16, String)> {
    let mut b = Body(body);
    Some((b.u16()?, b.string()?))
}

/// A channel record: id, schema id, topic and message encoding.
pub fn channel(body: &[u8]) -> Option<(u16, u16, String, String)> {
    let mut b = Body(body);
    Some((b.u16()?, b.u16()?, b.string()?, b.string()?))
}

/// A message record's channel id and log time, and its payload.
pub fn message(body: &[u8]) -> Option<(u16, u64, &[u8])> {
    let mut b = Body(body);
    let (channel, _sequence, log_time, _publish) = (b.u16()?, b.u32()?, b.u64()?, b.u64()?);
    Some((channel, log_time, b.rest()))
}

/// A chunk record's header: what precedes its records.
#[derive(Clone, Debug, PartialEq)]
pub struct ChunkHeader {
    pub uncompressed_size: u64,
    pub crc: u32,
    pub compression: String,
    pub records_len: u64,
    /// Bytes of the body before the records.
    pub header_len: u64,
}

/// The header of a chunk record's body (its first bytes suffice).
pub fn chunk_header(body: &[u8]) -> Option<ChunkHeader> {
    let mut b = Body(body);
    let (_start, _end) = (b.u64()?, b.u64()?);
    let uncompressed_size = b.u64()?;
    let crc = b.u32()?;
    let compression = b.string()?;
    let records_len = b.u64()?;
    Some(ChunkHeader {
        uncompressed_size,
        crc,
        header_len: (body.len() - b.rest().len()) as u64,
        compression,
        records_len,
    })
}

/// Bytes of a chunk body's header for a compression name of `compression_len` bytes.
pub fn chunk_header_len(compression_len: u64) -> u64 {
    8 + 8 + 8 + 4 + 4 + compression_len + 8
}

/// One chunk as the summary indexes it.
#[derive(Clone, Debug, PartialEq)]
pub struct ChunkIndex {
    /// Where the chunk record starts in the file.
    pub start: u64,
    /// Its length in the file, record header included.
    pub length: u64,
    /// Where each channel's message index record starts in the file.
    pub message_index_offsets: BTreeMap<u16, u64>,
    /// Bytes of message index records after the chunk.
    pub message_index_length: u64,
    pub compression: String,
    pub compressed_size: u64,
    pub uncompressed_size: u64,
}

/// A chunk index record.
pub fn chunk_index(body: &[u8]) -> Option<ChunkIndex> {
    let mut b = Body(body);
    let (_start_time, _end_time) = (b.u64()?, b.u64()?);
    let (start, length) = (b.u64()?, b.u64()?);
    let mut map = b.block()?;
    let mut message_index_offsets = BTreeMap::new();
    while !map.rest().is_empty() {
        message_index_offsets.insert(map.u16()?, map.u64()?);
    }
    Some(ChunkIndex {
        start,
        length,
        message_index_offsets,
        message_index_length: b.u64()?,
        compression: b.string()?,
        compressed_size: b.u64()?,
        uncompressed_size: b.u64()?,
    })
}

/// A message index record: its channel and `(log time, offset in the chunk's records)` pairs.
pub fn message_index(body: &[u8]) -> Option<(u16, Vec<(u64, u64)>)> {
    let mut b = Body(body);
    let channel = b.u16()?;
    let mut entries = b.block()?;
    let mut list = Vec::with_capacity(entries.rest().len() / 16);
    while !entries.rest().is_empty() {
        list.push((entries.u64()?, entries.u64()?));
    }
    Some((channel, list))
}

/// The statistics record's total message count.
pub fn statistics_message_count(body: &[u8]) -> Option<u64> {
    Body(body).u64()
}

/// The footer's summary start and summary CRC.
pub fn footer(body: &[u8]) -> Option<(u64, u64, u32)> {
    let mut b = Body(body);
    Some((b.u64()?, b.u64()?, b.u32()?))
}

/// A chunk's records, decompressed into `buffer` when compressed, after checking their length and
/// CRC (a CRC of 0 means the writer did not compute one).
pub fn decompress<'a>(
    header: &ChunkHeader,
    data: &'a [u8],
    buffer: &'a mut Vec<u8>,
) -> Result<&'a [u8], String> {
    let size = header.uncompressed_size;
    let records: &[u8] = if header.compression.is_empty() {
        data
    } else {
        let limit = (data.len() as u64)
            .saturating_mul(MAX_RATIO)
            .saturating_add(1 << 16);
        if size > MAX_CHUNK_BYTES.min(limit) {
            return Err(format!(
                "claims {size} bytes uncompressed from {} compressed, more than pushlab accepts",
                data.len()
            ));
        }
        buffer.clear();
        // Bounded just above: `size` fits in memory.
        let size = size as usize;
        match header.compression.as_str() {
            "zstd" => {
                buffer.reserve_exact(size);
                ruzstd::decoding::FrameDecoder::new()
                    .decode_all_to_vec(data, buffer)
                    .map_err(|e| format!("zstd data is corrupt: {e}"))?;
            }
            "lz4" => {
                lz4_flex::frame::FrameDecoder::new(data)
                    .take(size as u64 + 1)
                    .read_to_end(buffer)
                    .map_err(|e| format!("lz4 data is corrupt: {e}"))?;
            }
            other => {
                return Err(format!(
                    "compressed with `{other}`, expected none, zstd or lz4"
                ));
            }
        }
        buffer
    };
    if records.len() as u64 != size {
        return Err(format!(
            "holds {} bytes of records, but its header says {size}",
            records.len()
        ));
    }
    if header.crc != 0 {
        let computed = crc32fast::hash(records);
        if computed != header.crc {
            return Err(format!(
                "CRC is {computed:08x}, but its header says {:08x}: the file is corrupt",
                header.crc
            ));
        }
    }
    Ok(records)
}

/// The records of a decompressed chunk, `(offset, opcode, body)`: `opcode: u8`, `length: u64`, then
/// the body; an error where a record runs past the chunk's end.
pub fn walk(records: &[u8]) -> impl Iterator<Item = Result<(u64, u8, &[u8]), String>> + '_ {
    let mut at = 0usize;
    std::iter::from_fn(move || {
        let rest = &records[at..];
        if rest.is_empty() {
            return None;
        }
        let Some((&[op, l0, l1, l2, l3, l4, l5, l6, l7], tail)) = rest.split_first_chunk::<9>()
        else {
            at = records.len();
            return Some(Err("ends in the middle of a record header".to_owned()));
        };
        let len = u64::from_le_bytes([l0, l1, l2, l3, l4, l5, l6, l7]);
        if len > tail.len() as u64 {
            at = records.len();
            return Some(Err(format!(
                "a record claims {len} bytes but only {} are left in the chunk",
                tail.len()
            )));
        }
        let offset = at as u64;
        at += 9 + len as usize;
        Some(Ok((offset, op, &tail[..len as usize])))
    })
}
