//! Reading a file without a summary from its start: record by record, each chunk read whole (and
//! decompressed when compressed), up to the data-end record. Without the summary's chunk indexes,
//! the compressed chunks are found first by walking the record headers (a few bytes read per
//! record), so that they are decompressed ahead on the workers as in an indexed file.

use std::collections::BTreeMap;
use std::sync::atomic::AtomicUsize;

use super::prefetch::Prefetch;
use super::records::{
    self, ChunkIndex, MAGIC, MAX_CHUNK_BYTES, MESSAGE_HEADER, OP_CHANNEL, OP_CHUNK, OP_DATA_END,
    OP_FOOTER, OP_MESSAGE, OP_MESSAGE_INDEX, OP_SCHEMA, RECORD_HEADER,
};
use super::source::Source;
use super::{
    ChannelInfo, ChannelStats, Channels, CutShort, FileRead, MessageAt, Visit, Visitor, Want, head,
    io_problem, message_cut_short, undeclared,
};
use crate::recording::bag::problem::BagProblem;

/// Largest schema or channel record accepted (a ROS 2 message definition is a few kB).
pub(super) const MAX_DEFINITION_BYTES: u64 = 16 << 20;

/// A pass from the start of a file without a summary: record by record, each chunk read whole,
/// the compressed ones decompressed ahead (`chunks`: as [`walk`] found them). A file cut short is
/// read up to its last whole record, unless no channel was declared before the cut (nothing to
/// read: the cut is the file's problem).
pub(super) fn read<S: Source + ?Sized>(
    source: &S,
    chunks: &[ChunkIndex],
    visitor: &mut dyn Visitor,
) -> Result<FileRead, BagProblem> {
    let ahead: Vec<usize> = (chunks.iter().enumerate())
        .filter(|(_, c)| !c.compression.is_empty())
        .map(|(index, _)| index)
        .collect();
    let next = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        let mut prefetched = Prefetch::start(scope, source, chunks, &ahead, &next);
        read_records(source, &mut prefetched, visitor)
    })
}

/// What a walk of the record headers of a file without a summary finds, up to its data-end record
/// or the first record that is not whole.
pub(super) struct Walk {
    /// The chunks, in order, as an index would list them, with the message index records that
    /// follow each (none when the writer wrote none; none for a last chunk whose indexes may be
    /// cut short).
    pub chunks: Vec<ChunkIndex>,
    /// Schema and channel records outside chunks: their opcode, where their body starts, length.
    pub definitions: Vec<(u8, u64, u64)>,
    /// Whether a message record lies outside chunks.
    pub loose_messages: bool,
    /// Where the walk stopped, and the record there: `None` at the data-end or footer record; a
    /// [`Record::Whole`] chunk whose header could not be read, or the first record not whole.
    pub stopped: Option<(u64, Record)>,
}

/// Walks the record headers of a file without a summary (a few bytes read per record): the
/// chunks and what [`Walk`] says. What [`read_records`] then finds wrong with a chunk is its to say.
pub(super) fn walk<S: Source + ?Sized>(source: &S) -> Walk {
    // Enough of a chunk's body for its header with a compression name of up to 64 bytes.
    let header_read = records::chunk_header_len(64);
    let mut walk = Walk {
        chunks: Vec::new(),
        definitions: Vec::new(),
        loose_messages: false,
        stopped: None,
    };
    // The chunk whose message indexes the records just walked were.
    let mut indexes_of: Option<usize> = None;
    let mut at = MAGIC.len() as u64;
    loop {
        let record = record_at(source, at);
        let Record::Whole { op, len } = record else {
            walk.stopped = Some((at, record));
            break;
        };
        let body = at + RECORD_HEADER;
        match op {
            OP_DATA_END | OP_FOOTER => break,
            OP_CHUNK => {
                let header = source.read_vec(body, len.min(header_read));
                let Some(chunk) = header.ok().as_deref().and_then(records::chunk_header) else {
                    // Whole but unreadable: the pass from the start says what is wrong with it.
                    walk.stopped = Some((at, record));
                    break;
                };
                walk.chunks.push(ChunkIndex {
                    start: at,
                    length: RECORD_HEADER + len,
                    message_index_offsets: BTreeMap::new(),
                    message_index_length: 0,
                    compression: chunk.compression,
                    compressed_size: chunk.records_len,
                    uncompressed_size: chunk.uncompressed_size,
                });
                indexes_of = Some(walk.chunks.len() - 1);
            }
            OP_MESSAGE_INDEX => {
                let channel = source.read_vec(body, 2.min(len)).ok();
                match (indexes_of, channel.as_deref()) {
                    (Some(index), Some(&[low, high])) => {
                        let chunk = &mut walk.chunks[index];
                        (chunk.message_index_offsets).insert(u16::from_le_bytes([low, high]), at);
                        chunk.message_index_length += RECORD_HEADER + len;
                    }
                    _ => indexes_of = None,
                }
            }
            OP_SCHEMA | OP_CHANNEL => walk.definitions.push((op, body, len)),
            OP_MESSAGE => walk.loose_messages = true,
            _ => {}
        }
        if !matches!(op, OP_CHUNK | OP_MESSAGE_INDEX) {
            indexes_of = None;
        }
        at = body + len;
    }
    // Indexes the walk stopped in, or before a record whose header is cut (another index?), may
    // be missing a channel's: the chunk is counted from its records instead.
    let indexes_cut = matches!(
        walk.stopped,
        Some((
            _,
            Record::HeaderCut
                | Record::BodyCut {
                    op: OP_MESSAGE_INDEX,
                    ..
                }
        ))
    );
    if indexes_cut && let Some(last) = indexes_of.and_then(|index| walk.chunks.get_mut(index)) {
        last.message_index_offsets.clear();
        last.message_index_length = 0;
    }
    walk
}

/// A record as its header says, read at where it starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Record {
    /// Its header and body lie within the file.
    Whole { op: u8, len: u64 },
    /// The file ends inside its header (or it cannot be read).
    HeaderCut,
    /// Its body runs past the file's end.
    BodyCut { op: u8, len: u64 },
}

/// The record starting at byte `at`: the one reading of a record's header, so that the walk for
/// the chunks ahead and the pass over the records stop at the same place.
fn record_at<S: Source + ?Sized>(source: &S, at: u64) -> Record {
    let mut header = [0u8; RECORD_HEADER as usize];
    if at + RECORD_HEADER > source.len() || source.read_at(at, &mut header).is_err() {
        return Record::HeaderCut;
    }
    let op = header[0];
    let len = u64::from_le_bytes([
        header[1], header[2], header[3], header[4], header[5], header[6], header[7], header[8],
    ]);
    let whole = (at + RECORD_HEADER)
        .checked_add(len)
        .is_some_and(|end| end <= source.len());
    if whole {
        Record::Whole { op, len }
    } else {
        Record::BodyCut { op, len }
    }
}

/// The records in order, chunks taken decompressed from `prefetched` when it has them.
fn read_records<S: Source + ?Sized>(
    source: &S,
    prefetched: &mut Prefetch,
    visitor: &mut dyn Visitor,
) -> Result<FileRead, BagProblem> {
    let mut pass = Linear {
        definitions: Definitions::default(),
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
        let (op, len) = match record_at(source, at) {
            Record::Whole { op, len } => (op, len),
            Record::HeaderCut if !pass.channels.is_empty() => break Some(cut(at < source.len())),
            Record::HeaderCut => {
                return Err(BagProblem::Mcap(format!(
                    "the file ends at byte {} before its data-end record: it is cut short (a \
                     recording that did not finish?)",
                    source.len()
                )));
            }
            Record::BodyCut { op, .. } if !pass.channels.is_empty() => {
                break Some(cut(matches!(op, OP_CHUNK | OP_MESSAGE)));
            }
            Record::BodyCut { len, .. } => {
                return Err(BagProblem::Mcap(format!(
                    "a record at byte {at} claims {len} bytes, past the end of the file"
                )));
            }
        };
        let body_start = at + RECORD_HEADER;
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
                let fail = |why: String| BagProblem::Chunk {
                    index: chunk_index,
                    why,
                };
                let taken = prefetched.take(chunk_index).transpose();
                let taken = taken.map_err(|e| e.in_chunk(chunk_index))?;
                let body;
                let (header, decompressed) = match &taken {
                    Some((header, decompressed)) => (header.clone(), decompressed.as_slice()),
                    None => {
                        body = source
                            .read_vec(body_start, len)
                            .map_err(|e| io_problem(&e))?;
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
                        let decompressed =
                            records::decompress(&header, records, &mut buffer).map_err(fail)?;
                        (header, decompressed)
                    }
                };
                let records_start = body_start + header.header_len;
                let compressed = !header.compression.is_empty();
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
    definitions: Definitions,
    channels: Channels,
    wants: BTreeMap<u16, Want>,
}

/// The schemas declared so far, in file order, to name the type of each channel declared after
/// them: what a pass from the start and a rebuilt summary (`unfinished.rs`) both read records with.
#[derive(Default)]
pub(super) struct Definitions {
    schemas: BTreeMap<u16, String>,
}

impl Definitions {
    /// Reads a schema or channel record's body: the channel a channel record declares, with its
    /// schema's name as its type.
    pub(super) fn add(
        &mut self,
        op: u8,
        body: &[u8],
    ) -> Result<Option<(u16, ChannelInfo)>, String> {
        if op == OP_SCHEMA {
            let (id, name) =
                records::schema(body).ok_or_else(|| "a schema record is cut short".to_owned())?;
            self.schemas.insert(id, name);
            return Ok(None);
        }
        let (id, schema, topic, encoding) =
            records::channel(body).ok_or_else(|| "a channel record is cut short".to_owned())?;
        let channel = ChannelInfo {
            topic,
            type_name: self.schemas.get(&schema).cloned().unwrap_or_default(),
            encoding,
        };
        Ok(Some((id, channel)))
    }
}

impl Linear {
    fn definition(&mut self, op: u8, body: &[u8], visitor: &mut dyn Visitor) -> Result<(), String> {
        if let Some((id, channel)) = self.definitions.add(op, body)? {
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
