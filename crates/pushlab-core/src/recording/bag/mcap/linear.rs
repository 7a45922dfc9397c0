//! Reading a file without a summary from its start: record by record, each chunk read whole (and
//! decompressed when compressed), up to the data-end record.

use std::collections::BTreeMap;

use super::records::{
    self, MAGIC, MAX_CHUNK_BYTES, MESSAGE_HEADER, OP_CHANNEL, OP_CHUNK, OP_DATA_END, OP_FOOTER,
    OP_MESSAGE, OP_SCHEMA, RECORD_HEADER,
};
use super::source::Source;
use super::{
    ChannelInfo, ChannelStats, Channels, CutShort, FileRead, MessageAt, Visit, Visitor, Want, head,
    io_problem, message_cut_short, undeclared,
};
use crate::recording::bag::problem::BagProblem;

/// Largest schema or channel record accepted (a ROS 2 message definition is a few kB).
const MAX_DEFINITION_BYTES: u64 = 16 << 20;

/// A pass from the start of a file without a summary: record by record, each chunk read whole. A
/// file cut short is read up to its last whole record, unless no channel was declared before the
/// cut (nothing to read: the cut is the file's problem).
pub(super) fn read<S: Source + ?Sized>(
    source: &S,
    visitor: &mut dyn Visitor,
) -> Result<FileRead, BagProblem> {
    let mut pass = Linear {
        schemas: BTreeMap::new(),
        channels: BTreeMap::new(),
        wants: BTreeMap::new(),
    };
    let mut buffer = Vec::new();
    let mut at = MAGIC.len() as u64;
    let mut chunk_index = 0;
    let cut_short = loop {
        let cut = |messages_lost| CutShort {
            readable: at,
            file_len: source.len(),
            messages_lost,
        };
        let mut header = [0u8; RECORD_HEADER as usize];
        if at + RECORD_HEADER > source.len() || source.read_at(at, &mut header).is_err() {
            if !pass.channels.is_empty() {
                break Some(cut(at < source.len()));
            }
            return Err(BagProblem::Mcap(format!(
                "the file ends at byte {} before its data-end record: it is cut short (a recording \
                 that did not finish?)",
                source.len()
            )));
        }
        let op = header[0];
        let len = u64::from_le_bytes([
            header[1], header[2], header[3], header[4], header[5], header[6], header[7], header[8],
        ]);
        let body_start = at + RECORD_HEADER;
        if body_start
            .checked_add(len)
            .is_none_or(|end| end > source.len())
        {
            if !pass.channels.is_empty() {
                break Some(cut(matches!(op, OP_CHUNK | OP_MESSAGE)));
            }
            return Err(BagProblem::Mcap(format!(
                "a record at byte {at} claims {len} bytes, past the end of the file"
            )));
        }
        match op {
            OP_DATA_END | OP_FOOTER => break None,
            OP_SCHEMA | OP_CHANNEL => {
                if len > MAX_DEFINITION_BYTES {
                    return Err(BagProblem::Mcap(format!(
                        "a schema or channel record of {len} bytes, more than pushlab accepts"
                    )));
                }
                let body = source
                    .read_vec(body_start, len)
                    .map_err(|e| io_problem(&e))?;
                pass.definition(op, &body, visitor)
                    .map_err(BagProblem::Mcap)?;
            }
            OP_MESSAGE => {
                let body = source
                    .read_vec(body_start, len)
                    .map_err(|e| io_problem(&e))?;
                let at = |offset: u64, len: u64| MessageAt::File {
                    offset: body_start + offset,
                    len,
                };
                pass.message(&body, 0, &at, visitor).map_err(|e| match e {
                    BagProblem::Chunk { why, .. } => BagProblem::Mcap(why),
                    other => other,
                })?;
            }
            OP_CHUNK => {
                if len > MAX_CHUNK_BYTES {
                    return Err(BagProblem::Chunk {
                        index: chunk_index,
                        why: format!("{len} bytes long, more than pushlab accepts"),
                    });
                }
                let body = source
                    .read_vec(body_start, len)
                    .map_err(|e| io_problem(&e))?;
                let fail = |why: String| BagProblem::Chunk {
                    index: chunk_index,
                    why,
                };
                let header = records::chunk_header(&body)
                    .ok_or_else(|| fail("its header is cut short".into()))?;
                let records = usize::try_from(header.records_len)
                    .ok()
                    .and_then(|n| body.get(header.header_len as usize..)?.get(..n))
                    .ok_or_else(|| {
                        fail(format!(
                            "claims {} bytes of records but holds {}",
                            header.records_len,
                            body.len() as u64 - header.header_len.min(body.len() as u64)
                        ))
                    })?;
                let records_start = body_start + header.header_len;
                let compressed = !header.compression.is_empty();
                let decompressed =
                    records::decompress(&header, records, &mut buffer).map_err(fail)?;
                for record in records::walk(decompressed) {
                    let (offset, op, body) = record.map_err(fail)?;
                    match op {
                        OP_SCHEMA | OP_CHANNEL => {
                            pass.definition(op, body, visitor).map_err(fail)?
                        }
                        OP_MESSAGE => {
                            let place = |payload: u64, len: u64| {
                                if compressed {
                                    MessageAt::Compressed {
                                        chunk: at,
                                        offset: payload,
                                        len,
                                    }
                                } else {
                                    MessageAt::File {
                                        offset: records_start + payload,
                                        len,
                                    }
                                }
                            };
                            pass.message(body, offset + RECORD_HEADER, &place, visitor)
                                .map_err(|e| e.in_chunk(chunk_index))?;
                        }
                        _ => {}
                    }
                }
                chunk_index += 1;
            }
            _ => {}
        }
        visitor.progress(RECORD_HEADER + len)?;
        at = body_start + len;
    };
    Ok(FileRead {
        channels: pass.channels,
        cut_short,
    })
}

/// What a pass from the start has learned of the file so far.
struct Linear {
    schemas: BTreeMap<u16, String>,
    channels: Channels,
    wants: BTreeMap<u16, Want>,
}

impl Linear {
    fn definition(&mut self, op: u8, body: &[u8], visitor: &mut dyn Visitor) -> Result<(), String> {
        if op == OP_SCHEMA {
            let (id, name) =
                records::schema(body).ok_or_else(|| "a schema record is cut short".to_owned())?;
            self.schemas.insert(id, name);
        } else {
            let (id, schema, topic, encoding) =
                records::channel(body).ok_or_else(|| "a channel record is cut short".to_owned())?;
            let channel = ChannelInfo {
                topic,
                type_name: self.schemas.get(&schema).cloned().unwrap_or_default(),
                encoding,
            };
            self.wants.insert(id, visitor.want(id, &channel));
            self.channels
                .entry(id)
                .or_insert((channel, ChannelStats::default()));
        }
        Ok(())
    }

    /// A message record's body; `body_offset` is where it starts, for `place` to locate its payload.
    fn message(
        &mut self,
        body: &[u8],
        body_offset: u64,
        place: &dyn Fn(u64, u64) -> MessageAt,
        visitor: &mut dyn Visitor,
    ) -> Result<(), BagProblem> {
        let (channel_id, log_time, payload) =
            records::message(body).ok_or_else(|| message_cut_short(body.len()))?;
        let (channel, stats) = self
            .channels
            .get_mut(&channel_id)
            .ok_or_else(|| undeclared(channel_id))?;
        stats.note(log_time);
        let want = self
            .wants
            .get(&channel_id)
            .copied()
            .unwrap_or(Want::Nothing);
        if want == Want::Nothing {
            return Ok(());
        }
        visitor.message(Visit {
            channel_id,
            channel,
            log_time,
            data: head(payload, want),
            at: place(body_offset + MESSAGE_HEADER, payload.len() as u64),
        })?;
        if let Want::First(_) = want {
            self.wants.insert(channel_id, Want::Nothing);
        }
        Ok(())
    }
}
