//! The summary section at an MCAP file's end: its schemas, channels and chunk indexes, found from
//! the footer without reading the data before it.

use std::collections::{BTreeMap, HashMap};

use super::records::{
    self, Body, ChunkIndex, FOOTER_BODY, MAGIC, OP_CHANNEL, OP_CHUNK_INDEX, OP_FOOTER, OP_SCHEMA,
    OP_STATISTICS, RECORD_HEADER,
};
use super::source::Source;
use super::{ChannelInfo, io_problem};
use crate::recording::bag::problem::BagProblem;

/// Largest summary section read: a bag of 10,000 chunks has a summary of about 1 MB.
const MAX_SUMMARY_BYTES: u64 = 256 << 20;

/// What the summary says.
pub struct Summary {
    pub channels: BTreeMap<u16, ChannelInfo>,
    /// In file order.
    pub chunks: Vec<ChunkIndex>,
    /// The statistics record's message count, when the file has one.
    pub message_count: Option<u64>,
}

/// The summary of the file, or `None` when it has none (a recording that did not finish, a writer
/// that wrote none): then the file is read from the start.
pub fn read<S: Source + ?Sized>(source: &S) -> Result<Option<Summary>, BagProblem> {
    let len = source.len();
    let tail = MAGIC.len() as u64 + RECORD_HEADER + FOOTER_BODY;
    if len < MAGIC.len() as u64 + tail {
        return Ok(None);
    }
    let end = source
        .read_vec(len - tail, tail)
        .map_err(|e| io_problem(&e))?;
    let (footer, magic) = end.split_at(end.len() - MAGIC.len());
    let mut b = Body(footer);
    let (Some(op), Some(body_len)) = (b.bytes(1), b.u64()) else {
        return Ok(None);
    };
    if magic != MAGIC || op != [OP_FOOTER] || body_len != FOOTER_BODY {
        return Ok(None);
    }
    let Some((summary_start, _summary_offset_start, crc)) = records::footer(b.rest()) else {
        return Ok(None);
    };
    let footer_start = len - tail;
    if summary_start == 0 {
        return Ok(None);
    }
    if summary_start > footer_start || footer_start - summary_start > MAX_SUMMARY_BYTES {
        return Err(BagProblem::Mcap(format!(
            "the footer puts the summary at byte {summary_start}, outside the file's {len} bytes"
        )));
    }
    // The CRC covers the summary and summary-offset sections and the footer up to its CRC field.
    let covered = source
        .read_vec(
            summary_start,
            footer_start + RECORD_HEADER + 16 - summary_start,
        )
        .map_err(|e| io_problem(&e))?;
    if crc != 0 && crc32fast::hash(&covered) != crc {
        return Err(BagProblem::Mcap(
            "the summary section's CRC does not match: the file is corrupt".to_owned(),
        ));
    }
    let section = &covered[..(footer_start - summary_start) as usize];
    parse(section, summary_start, len).map(Some)
}

fn parse(section: &[u8], start: u64, file_len: u64) -> Result<Summary, BagProblem> {
    let bad = |what: &str| BagProblem::Mcap(format!("the summary's {what} is cut short"));
    let mut schemas: HashMap<u16, String> = HashMap::new();
    let mut channel_records = Vec::new();
    let mut chunks = Vec::new();
    let mut message_count = None;
    for record in records::walk(section) {
        let (_, op, body) = record.map_err(|why| BagProblem::Mcap(format!("its summary {why}")))?;
        match op {
            OP_SCHEMA => {
                let (id, name) = records::schema(body).ok_or_else(|| bad("schema record"))?;
                schemas.insert(id, name);
            }
            OP_CHANNEL => {
                channel_records.push(records::channel(body).ok_or_else(|| bad("channel record"))?);
            }
            OP_CHUNK_INDEX => {
                let chunk = records::chunk_index(body).ok_or_else(|| bad("chunk index"))?;
                let end = chunk.start.checked_add(chunk.length);
                if end.is_none_or(|end| end > start) || chunk.start >= file_len {
                    return Err(BagProblem::Mcap(format!(
                        "the summary indexes a chunk at bytes {}–{} of the data section, which ends at {start}",
                        chunk.start,
                        chunk.start.saturating_add(chunk.length)
                    )));
                }
                chunks.push(chunk);
            }
            OP_STATISTICS => message_count = records::statistics_message_count(body),
            _ => {}
        }
    }
    let channels = channel_records
        .into_iter()
        .map(|(id, schema, topic, encoding)| {
            let type_name = schemas.get(&schema).cloned().unwrap_or_default();
            (
                id,
                ChannelInfo {
                    topic,
                    type_name,
                    encoding,
                },
            )
        })
        .collect();
    chunks.sort_by_key(|c: &ChunkIndex| c.start);
    Ok(Summary {
        channels,
        chunks,
        message_count,
    })
}
