//! Walking the records of one MCAP file held in memory: schemas, channels and messages, inside
//! chunks or not.
//!
//! Foxglove's `mcap` crate (its sans-IO linear reader) frames the file: it checks the magic bytes,
//! record lengths, truncation and the data end and footer records, and hands over each record's
//! opcode and body. It is built without its compression features, which compile the zstd and lz4 C
//! libraries, so chunks are taken whole and decompressed here with pure-Rust decoders (`ruzstd`,
//! `lz4_flex`), their CRC checked. The few record bodies pushlab needs (schema, channel, message,
//! chunk) are read here too, with every length checked against the bytes present: the crate's own
//! record parser reserves whatever a corrupt string length claims (fuzzing found a 2.5 GB
//! allocation from a 100-byte file). Reading a message in place (no copy, no allocation) is also
//! what keeps a bag of a million poses well under a second.

use std::collections::HashMap;
use std::io::Read;

use mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};

use super::problem::BagProblem;

/// What a channel carries.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ChannelInfo {
    pub topic: String,
    /// The schema's name, e.g. `geometry_msgs/msg/PoseStamped` (empty when the channel has none).
    pub type_name: String,
    /// The message encoding, `cdr` for ROS 2.
    pub encoding: String,
}

/// Largest decompressed chunk accepted: far above any chunk a recorder writes (rosbag2 and the
/// Foxglove writers use a few MB), and it bounds the memory a corrupt size field can claim.
const MAX_CHUNK_BYTES: u64 = 1 << 30;
/// Largest accepted ratio of a chunk's uncompressed to compressed size (real pose data compresses
/// some 3–10×), so that a corrupt size cannot make a tiny file allocate a gigabyte.
const MAX_RATIO: u64 = 4096;

const OP_SCHEMA: u8 = 0x03;
const OP_CHANNEL: u8 = 0x04;
const OP_MESSAGE: u8 = 0x05;
const OP_CHUNK: u8 = 0x06;

/// Calls `on_message(channel, channel_id, log_time_ns, payload)` for every message of the file in
/// file order. `channels` is filled as channel records appear; a message on a channel not yet
/// declared is an error, as the MCAP specification requires the channel first.
pub fn for_each_message(
    bytes: &[u8],
    channels: &mut HashMap<u16, ChannelInfo>,
    mut on_message: impl FnMut(&ChannelInfo, u16, u64, &[u8]) -> Result<(), BagProblem>,
) -> Result<(), BagProblem> {
    let mut schemas: HashMap<u16, String> = HashMap::new();
    let mut reader = LinearReader::new_with_options(
        LinearReaderOptions::default()
            .with_emit_chunks(true)
            .with_record_length_limit(bytes.len()),
    );
    let mut rest = bytes;
    let mut chunk_buffer = Vec::new();
    let mut chunk_index = 0;
    while let Some(event) = reader.next_event() {
        match event.map_err(|e| BagProblem::Mcap(e.to_string()))? {
            LinearReadEvent::ReadRequest(need) => {
                let n = need.min(rest.len());
                reader.insert(n).copy_from_slice(&rest[..n]);
                reader.notify_read(n);
                rest = &rest[n..];
            }
            LinearReadEvent::Record {
                opcode: OP_CHUNK,
                data,
            } => {
                let fail = |why: String| BagProblem::Chunk {
                    index: chunk_index,
                    why,
                };
                let records = decompress(data, &mut chunk_buffer).map_err(fail)?;
                walk_records(records, &mut schemas, channels, &mut on_message, &fail)?;
                chunk_index += 1;
            }
            LinearReadEvent::Record { opcode, data } => {
                let fail = |why: String| BagProblem::Mcap(why);
                read_record(opcode, data, &mut schemas, channels, &mut on_message, &fail)?;
            }
        }
    }
    Ok(())
}

/// Bounded little-endian reads from a record body.
struct Body<'a>(&'a [u8]);

impl<'a> Body<'a> {
    fn bytes(&mut self, n: usize) -> Option<&'a [u8]> {
        let (head, tail) = self.0.split_at_checked(n)?;
        self.0 = tail;
        Some(head)
    }

    fn u16(&mut self) -> Option<u16> {
        Some(u16::from_le_bytes(self.bytes(2)?.try_into().ok()?))
    }

    fn u32(&mut self) -> Option<u32> {
        Some(u32::from_le_bytes(self.bytes(4)?.try_into().ok()?))
    }

    fn u64(&mut self) -> Option<u64> {
        Some(u64::from_le_bytes(self.bytes(8)?.try_into().ok()?))
    }

    /// A `u32`-prefixed UTF-8 string (invalid UTF-8 replaced: names are only shown and compared).
    fn string(&mut self) -> Option<String> {
        let len = self.u32()? as usize;
        Some(String::from_utf8_lossy(self.bytes(len)?).into_owned())
    }
}

fn read_record(
    opcode: u8,
    body: &[u8],
    schemas: &mut HashMap<u16, String>,
    channels: &mut HashMap<u16, ChannelInfo>,
    on_message: &mut impl FnMut(&ChannelInfo, u16, u64, &[u8]) -> Result<(), BagProblem>,
    fail: &impl Fn(String) -> BagProblem,
) -> Result<(), BagProblem> {
    let mut b = Body(body);
    match opcode {
        OP_MESSAGE => {
            // channel id u16, sequence u32, log time u64, publish time u64, then the payload.
            let (Some(channel_id), Some(_), Some(log_time), Some(_)) =
                (b.u16(), b.u32(), b.u64(), b.u64())
            else {
                return Err(fail(format!(
                    "a message record of {} bytes, expected at least 22",
                    body.len()
                )));
            };
            let channel = channel_of(channels, channel_id)?;
            on_message(channel, channel_id, log_time, b.0)?;
        }
        OP_SCHEMA => {
            let (Some(id), Some(name)) = (b.u16(), b.string()) else {
                return Err(fail("a schema record is cut short".to_owned()));
            };
            schemas.insert(id, name);
        }
        OP_CHANNEL => {
            let (Some(id), Some(schema_id), Some(topic), Some(encoding)) =
                (b.u16(), b.u16(), b.string(), b.string())
            else {
                return Err(fail("a channel record is cut short".to_owned()));
            };
            let type_name = schemas.get(&schema_id).cloned().unwrap_or_default();
            channels.insert(
                id,
                ChannelInfo {
                    topic,
                    type_name,
                    encoding,
                },
            );
        }
        _ => {}
    }
    Ok(())
}

fn channel_of(channels: &HashMap<u16, ChannelInfo>, id: u16) -> Result<&ChannelInfo, BagProblem> {
    channels.get(&id).ok_or_else(|| {
        BagProblem::Mcap(format!(
            "a message on channel {id}, which no channel record declared before it"
        ))
    })
}

/// The chunk's records, decompressed into `buffer` when compressed, after checking their length and
/// CRC (a CRC of 0 means the writer did not compute one).
fn decompress<'a>(chunk: &'a [u8], buffer: &'a mut Vec<u8>) -> Result<&'a [u8], String> {
    // start time u64, end time u64, uncompressed size u64, uncompressed CRC u32, compression
    // string, compressed size u64, then the compressed records.
    let mut b = Body(chunk);
    let (Some(_), Some(_), Some(size), Some(crc), Some(compression), Some(compressed_size)) =
        (b.u64(), b.u64(), b.u64(), b.u32(), b.string(), b.u64())
    else {
        return Err("its header is cut short".to_owned());
    };
    let Some(data) = usize::try_from(compressed_size)
        .ok()
        .and_then(|n| b.bytes(n))
    else {
        return Err(format!(
            "claims {compressed_size} bytes of records but holds {}",
            b.0.len()
        ));
    };
    let records: &[u8] = if compression.is_empty() {
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
        match compression.as_str() {
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
    if crc != 0 {
        let computed = crc32fast::hash(records);
        if computed != crc {
            return Err(format!(
                "CRC is {computed:08x}, but its header says {crc:08x}: the file is corrupt"
            ));
        }
    }
    Ok(records)
}

/// Walks the records of a decompressed chunk: `opcode: u8`, `length: u64`, then the body.
fn walk_records(
    mut records: &[u8],
    schemas: &mut HashMap<u16, String>,
    channels: &mut HashMap<u16, ChannelInfo>,
    on_message: &mut impl FnMut(&ChannelInfo, u16, u64, &[u8]) -> Result<(), BagProblem>,
    fail: &impl Fn(String) -> BagProblem,
) -> Result<(), BagProblem> {
    while !records.is_empty() {
        let Some((&[op, l0, l1, l2, l3, l4, l5, l6, l7], rest)) = records.split_first_chunk::<9>()
        else {
            return Err(fail("ends in the middle of a record header".to_owned()));
        };
        let len = u64::from_le_bytes([l0, l1, l2, l3, l4, l5, l6, l7]);
        if len > rest.len() as u64 {
            return Err(fail(format!(
                "a record claims {len} bytes but only {} are left in the chunk",
                rest.len()
            )));
        }
        let (body, rest) = rest.split_at(len as usize);
        records = rest;
        read_record(op, body, schemas, channels, on_message, fail)?;
    }
    Ok(())
}
