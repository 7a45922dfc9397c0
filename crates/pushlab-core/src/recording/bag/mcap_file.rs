//! Walking the records of one MCAP file held in memory: schemas, channels and messages, inside
//! chunks or not.
//!
//! Foxglove's `mcap` crate parses the records and checks the magic bytes and record lengths; it is
//! built without its compression features, which compile the zstd and lz4 C libraries. Chunks are
//! therefore taken whole from its linear reader and decompressed here with pure-Rust decoders
//! (`ruzstd`, `lz4_flex`), their CRC checked, and their records walked directly: a message record
//! is four fixed fields and the payload, and reading it in place (no copy, no allocation) is what
//! keeps a bag of a million poses well under a second.

use std::collections::HashMap;
use std::io::Read;

use mcap::records::Record;

use crate::recording::error::BagProblem;

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

/// Calls `on_message(channel, channel_id, log_time_ns, payload)` for every message of the file in
/// file order. `channels` is filled as channel records appear; a message on a channel not yet
/// declared is an error, as the MCAP specification requires the channel first.
pub fn for_each_message(
    bytes: &[u8],
    channels: &mut HashMap<u16, ChannelInfo>,
    mut on_message: impl FnMut(&ChannelInfo, u16, u64, &[u8]) -> Result<(), BagProblem>,
) -> Result<(), BagProblem> {
    let mut schemas: HashMap<u16, String> = HashMap::new();
    let reader = mcap::read::LinearReader::new(bytes).map_err(mcap_problem)?;
    let mut chunk_buffer = Vec::new();
    let mut chunk_index = 0;
    for record in reader {
        match record.map_err(mcap_problem)? {
            Record::Schema { header, .. } => {
                schemas.insert(header.id, header.name);
            }
            Record::Channel(channel) => add_channel(&schemas, channels, channel),
            Record::Message { header, data } => {
                let channel = channel_of(channels, header.channel_id)?;
                on_message(channel, header.channel_id, header.log_time, &data)?;
            }
            Record::Chunk { header, data } => {
                let fail = |why: String| BagProblem::Chunk {
                    index: chunk_index,
                    why,
                };
                let records = decompress(&header, &data, &mut chunk_buffer).map_err(fail)?;
                walk_chunk(records, &mut schemas, channels, &mut on_message, &fail)?;
                chunk_index += 1;
            }
            _ => {}
        }
    }
    Ok(())
}

#[allow(clippy::needless_pass_by_value)] // a `map_err` callback
fn mcap_problem(err: mcap::McapError) -> BagProblem {
    BagProblem::Mcap(err.to_string())
}

fn add_channel(
    schemas: &HashMap<u16, String>,
    channels: &mut HashMap<u16, ChannelInfo>,
    channel: mcap::records::Channel,
) {
    let type_name = schemas.get(&channel.schema_id).cloned().unwrap_or_default();
    channels.insert(
        channel.id,
        ChannelInfo {
            topic: channel.topic,
            type_name,
            encoding: channel.message_encoding,
        },
    );
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
fn decompress<'a>(
    header: &mcap::records::ChunkHeader,
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
    if header.uncompressed_crc != 0 {
        let crc = crc32fast::hash(records);
        if crc != header.uncompressed_crc {
            return Err(format!(
                "CRC is {crc:08x}, but its header says {:08x}: the file is corrupt",
                header.uncompressed_crc
            ));
        }
    }
    Ok(records)
}

/// Walks the records of a decompressed chunk: `opcode: u8`, `length: u64`, then the body.
fn walk_chunk(
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
        match op {
            OP_MESSAGE => {
                // channel id u16, sequence u32, log time u64, publish time u64, then the payload.
                let Some((fixed, payload)) = body.split_first_chunk::<22>() else {
                    return Err(fail(format!(
                        "a message record of {len} bytes, expected at least 22"
                    )));
                };
                let channel_id = u16::from_le_bytes([fixed[0], fixed[1]]);
                let mut log_time = [0; 8];
                log_time.copy_from_slice(&fixed[6..14]);
                let channel = channel_of(channels, channel_id)?;
                on_message(channel, channel_id, u64::from_le_bytes(log_time), payload)?;
            }
            OP_SCHEMA | OP_CHANNEL => match mcap::parse_record(op, body) {
                Ok(Record::Schema { header, .. }) => {
                    schemas.insert(header.id, header.name);
                }
                Ok(Record::Channel(channel)) => add_channel(schemas, channels, channel),
                Ok(_) => {}
                Err(e) => return Err(fail(format!("a schema or channel record: {e}"))),
            },
            _ => {}
        }
    }
    Ok(())
}
