//! The two ways through a file — by its indexes, or from the start — and reading one message again.

use std::collections::BTreeMap;
use std::sync::atomic::AtomicUsize;

use super::chunk::{chunk_header, read_whole};
use super::prefetch::Prefetch;
use super::records::{
    self, ChunkHeader, ChunkIndex, MAGIC, MESSAGE_HEADER, OP_MESSAGE, OP_MESSAGE_INDEX,
    RECORD_HEADER,
};
use super::source::Source;
use super::summary::{self, Summary};
use super::{
    ChannelStats, Channels, FileRead, MessageAt, Visit, Visitor, Want, chunk_problem, head,
    io_problem, message_cut_short, undeclared,
};
use super::{linear, unfinished};
use crate::recording::bag::problem::BagProblem;

/// Unwanted bytes between two wanted messages of a chunk read in one go rather than two reads.
const COALESCE_GAP: u64 = 4096;

/// Reads the file, telling the visitor every message of the channels it wants, in file order, and
/// the bytes passed. Returns every channel with its message count and log-time span, and where a
/// file without a summary was cut short.
pub fn read_messages<S: Source + ?Sized>(
    source: &S,
    visitor: &mut dyn Visitor,
) -> Result<FileRead, BagProblem> {
    check_magic(source)?;
    let (summary, cut_short) = match summary::read(source)? {
        Some(summary) if indexes_every_message(&summary) => (summary, None),
        Some(_) => return linear::read(source, &linear::walk(source).chunks, visitor),
        None => match unfinished::rebuilt_summary(source, linear::walk(source)) {
            Ok(rebuilt) => rebuilt,
            // The pass from the start, from the same walk of the record headers.
            Err(walk) => return linear::read(source, &walk.chunks, visitor),
        },
    };
    Ok(FileRead {
        channels: Indexed::new(source, summary, visitor).run(visitor)?,
        cut_short,
    })
}

fn check_magic<S: Source + ?Sized>(source: &S) -> Result<(), BagProblem> {
    let mut magic = [0u8; 8];
    if source.len() < 8 || source.read_at(0, &mut magic).is_err() || &magic != MAGIC {
        return Err(BagProblem::Mcap(
            "it does not start with the MCAP magic bytes".to_owned(),
        ));
    }
    Ok(())
}

/// Whether the chunk indexes reach every message: a file with messages outside chunks (allowed,
/// but no recorder writes them beside chunks) is read from the start.
fn indexes_every_message(summary: &Summary) -> bool {
    !summary.chunks.is_empty() || summary.message_count == Some(0)
}

/// A pass through the chunks the summary indexes.
struct Indexed<'a, S: Source + ?Sized> {
    source: &'a S,
    chunks: Vec<ChunkIndex>,
    channels: Channels,
    wants: BTreeMap<u16, Want>,
}

impl<'a, S: Source + ?Sized> Indexed<'a, S> {
    fn new(source: &'a S, summary: Summary, visitor: &mut dyn Visitor) -> Self {
        let wants = (summary.channels.iter())
            .map(|(&id, channel)| (id, visitor.want(id, channel)))
            .collect();
        let channels = (summary.channels.into_iter())
            .map(|(id, channel)| (id, (channel, ChannelStats::default())))
            .collect();
        Self {
            source,
            chunks: summary.chunks,
            channels,
            wants,
        }
    }

    fn want(&self, channel: u16) -> Want {
        self.wants.get(&channel).copied().unwrap_or(Want::Nothing)
    }

    /// Notes that a message of `channel` was visited: a channel wanted for its first message is
    /// wanted no more.
    fn visited(&mut self, channel: u16) {
        if let Some(want @ Want::First(_)) = self.wants.get_mut(&channel) {
            *want = Want::Nothing;
        }
    }

    fn run(mut self, visitor: &mut dyn Visitor) -> Result<Channels, BagProblem> {
        let chunks = std::mem::take(&mut self.chunks);
        // Compressed chunks holding something wanted are read whole; their decompression, most
        // of the time of a zstd camera bag, runs ahead on worker threads while this one visits.
        let ahead: Vec<usize> = (chunks.iter().enumerate())
            .filter(|(_, c)| !c.compression.is_empty())
            .filter(|(_, c)| {
                c.message_index_offsets.is_empty()
                    || (c.message_index_offsets.keys()).any(|id| self.want(*id) != Want::Nothing)
            })
            .map(|(index, _)| index)
            .collect();
        let (source, next) = (self.source, AtomicUsize::new(0));
        std::thread::scope(|scope| {
            let mut prefetched = Prefetch::start(scope, source, &chunks, &ahead, &next);
            self.visit_chunks(&chunks, &mut prefetched, visitor)
        })?;
        Ok(self.channels)
    }

    fn visit_chunks(
        &mut self,
        chunks: &[ChunkIndex],
        prefetched: &mut Prefetch,
        visitor: &mut dyn Visitor,
    ) -> Result<(), BagProblem> {
        for (index, chunk) in chunks.iter().enumerate() {
            let fail = |why: String| BagProblem::Chunk { index, why };
            let entries = self.message_indexes(chunk).map_err(fail)?;
            for &(log_time, _, channel) in &entries {
                let (_, stats) = self.channels.get_mut(&channel).ok_or_else(|| {
                    fail(format!(
                        "indexes channel {channel}, which the summary does not declare"
                    ))
                })?;
                stats.note(log_time);
            }
            let wanted = |c: &u16| self.want(*c) != Want::Nothing;
            if !chunk.message_index_offsets.keys().any(wanted)
                && !chunk.message_index_offsets.is_empty()
            {
                visitor.progress(chunk.length)?;
                continue;
            }
            let whole = !chunk.compression.is_empty()
                || chunk.message_index_offsets.is_empty()
                || (chunk.message_index_offsets.keys()).all(|c| self.want(*c) == Want::Payload);
            if whole {
                let read = match prefetched.take(index) {
                    Some(read) => read,
                    None => read_whole(self.source, chunk),
                };
                let (header, records) = read.map_err(|e| e.in_chunk(index))?;
                self.visit_records(chunk, &header, &records, visitor)
                    .map_err(|e| e.in_chunk(index))?;
            } else {
                self.messages_of(chunk, &entries, visitor)
                    .map_err(|e| e.in_chunk(index))?;
            }
            visitor.progress(chunk.length)?;
        }
        Ok(())
    }

    /// The message indexes after a chunk: `(log time, offset in the records, channel)` of every
    /// message, sorted by offset.
    fn message_indexes(&self, chunk: &ChunkIndex) -> Result<Vec<(u64, u64, u16)>, String> {
        let Some(&first) = chunk.message_index_offsets.values().min() else {
            return Ok(Vec::new());
        };
        let block = self
            .source
            .read_vec(first, chunk.message_index_length)
            .map_err(|e| format!("its message indexes cannot be read: {e}"))?;
        let mut entries = Vec::new();
        for record in records::walk(&block) {
            let (offset, op, body) = record.map_err(|why| format!("its message indexes: {why}"))?;
            if op != OP_MESSAGE_INDEX {
                continue;
            }
            let (channel, list) = records::message_index(body)
                .ok_or_else(|| "a message index record is cut short".to_owned())?;
            if chunk.message_index_offsets.get(&channel) != Some(&(first + offset)) {
                return Err(format!(
                    "the message index of channel {channel} is not where the chunk index puts it"
                ));
            }
            entries.extend(list.into_iter().map(|(t, at)| (t, at, channel)));
        }
        entries.sort_by_key(|&(_, at, _)| at);
        Ok(entries)
    }

    /// The chunk's header, read from the file and checked against its index.
    fn chunk_header(&self, chunk: &ChunkIndex) -> Result<ChunkHeader, BagProblem> {
        chunk_header(self.source, chunk)
    }

    /// Visits what is wanted of a chunk's records (decompressed, when the chunk is compressed);
    /// counts the messages of a chunk without message indexes.
    fn visit_records(
        &mut self,
        chunk: &ChunkIndex,
        header: &ChunkHeader,
        records: &[u8],
        visitor: &mut dyn Visitor,
    ) -> Result<(), BagProblem> {
        let records_start = chunk.start + RECORD_HEADER + header.header_len;
        let compressed = !header.compression.is_empty();
        let unindexed = chunk.message_index_offsets.is_empty();
        for record in records::walk(records) {
            let (offset, op, body) = record.map_err(|w| chunk_problem(&w))?;
            if op != OP_MESSAGE {
                continue;
            }
            let (channel_id, log_time, payload) =
                records::message(body).ok_or_else(|| message_cut_short(body.len()))?;
            if unindexed {
                let (_, stats) =
                    (self.channels.get_mut(&channel_id)).ok_or_else(|| undeclared(channel_id))?;
                stats.note(log_time);
            }
            let want = self.want(channel_id);
            if want == Want::Nothing {
                continue;
            }
            let payload_offset = offset + RECORD_HEADER + MESSAGE_HEADER;
            let len = payload.len() as u64;
            let at = if compressed {
                MessageAt::Compressed {
                    chunk: chunk.start,
                    offset: payload_offset,
                    len,
                }
            } else {
                MessageAt::File {
                    offset: records_start + payload_offset,
                    len,
                }
            };
            let (channel, _) = self
                .channels
                .get(&channel_id)
                .ok_or_else(|| undeclared(channel_id))?;
            visitor.message(Visit {
                channel_id,
                channel,
                log_time,
                data: head(payload, want),
                at,
            })?;
            self.visited(channel_id);
        }
        Ok(())
    }

    /// Reads only the wanted messages of an uncompressed chunk, at the offsets its message indexes
    /// give, a run of nearby ones in one read.
    fn messages_of(
        &mut self,
        chunk: &ChunkIndex,
        entries: &[(u64, u64, u16)],
        visitor: &mut dyn Visitor,
    ) -> Result<(), BagProblem> {
        let header = self.chunk_header(chunk)?;
        let records_start = chunk.start + RECORD_HEADER + header.header_len;
        let records_end = header.records_len;
        let mut k = 0;
        while k < entries.len() {
            let (_, offset, channel_id) = entries[k];
            match self.want(channel_id) {
                Want::Nothing => k += 1,
                Want::Head(n) | Want::First(n) => {
                    self.head_of(records_start, records_end, entries[k], n, visitor)?;
                    self.visited(channel_id);
                    k += 1;
                }
                Want::Payload => {
                    // A run of wanted messages, each starting at most COALESCE_GAP bytes after the
                    // end of the one before (the start of the record after it), read in one go.
                    let mut last = k;
                    let read_to = loop {
                        let end = self.record_end(records_start, records_end, entries, last)?;
                        let next = (last + 1..entries.len())
                            .find(|&j| self.want(entries[j].2) != Want::Nothing);
                        match next {
                            Some(j)
                                if self.want(entries[j].2) == Want::Payload
                                    && entries[j].1 <= end.saturating_add(COALESCE_GAP) =>
                            {
                                last = j;
                            }
                            _ => break end,
                        }
                    };
                    let bytes = (self.source)
                        .read_vec(records_start + offset, read_to - offset)
                        .map_err(|e| io_problem(&e))?;
                    for &(log_time, at, channel_id) in &entries[k..=last] {
                        if self.want(channel_id) != Want::Payload {
                            continue;
                        }
                        let body = record_body(&bytes, at - offset)?;
                        self.visit_body(
                            body,
                            (log_time, at, channel_id),
                            records_start,
                            Want::Payload,
                            visitor,
                        )?;
                    }
                    k = last + 1;
                }
            }
        }
        Ok(())
    }

    /// Reads only the first `n` bytes of a message's payload (a camera frame's header stamp).
    fn head_of(
        &self,
        records_start: u64,
        records_end: u64,
        (log_time, offset, channel_id): (u64, u64, u16),
        n: usize,
        visitor: &mut dyn Visitor,
    ) -> Result<(), BagProblem> {
        let wanted = RECORD_HEADER + MESSAGE_HEADER + n as u64;
        let available = records_end.saturating_sub(offset).min(wanted);
        let bytes = (self.source)
            .read_vec(records_start + offset, available)
            .map_err(|e| io_problem(&e))?;
        let (op, rest) = bytes
            .split_first_chunk::<9>()
            .ok_or_else(|| chunk_problem("a message index points past the chunk's records"))?;
        let len = u64::from_le_bytes([op[1], op[2], op[3], op[4], op[5], op[6], op[7], op[8]]);
        if op[0] != OP_MESSAGE || len < MESSAGE_HEADER || offset + RECORD_HEADER + len > records_end
        {
            return Err(chunk_problem(
                "a message index points at a record that is not a message of the chunk",
            ));
        }
        let body = &rest[..rest.len().min(len as usize)];
        let entry = (log_time, offset, channel_id);
        self.visit_indexed(
            body,
            entry,
            records_start,
            len - MESSAGE_HEADER,
            |head| head,
            visitor,
        )
    }

    /// Visits a whole message record read through its index entry.
    fn visit_body(
        &self,
        body: &[u8],
        (log_time, offset, channel_id): (u64, u64, u16),
        records_start: u64,
        want: Want,
        visitor: &mut dyn Visitor,
    ) -> Result<(), BagProblem> {
        let len = body.len().saturating_sub(MESSAGE_HEADER as usize) as u64;
        let entry = (log_time, offset, channel_id);
        self.visit_indexed(body, entry, records_start, len, |p| head(p, want), visitor)
    }

    /// Checks that `body` (all of a message record's body, or its start) is the message its index
    /// entry names, then visits `data` of its payload, which is `len` bytes at its offset.
    fn visit_indexed(
        &self,
        body: &[u8],
        (log_time, offset, channel_id): (u64, u64, u16),
        records_start: u64,
        len: u64,
        data: impl FnOnce(&[u8]) -> &[u8],
        visitor: &mut dyn Visitor,
    ) -> Result<(), BagProblem> {
        let (id, stamp, payload) =
            records::message(body).ok_or_else(|| message_cut_short(body.len()))?;
        if id != channel_id || stamp != log_time {
            return Err(chunk_problem(
                "a message index points at a message of another channel or time",
            ));
        }
        let (channel, _) = self
            .channels
            .get(&channel_id)
            .ok_or_else(|| undeclared(channel_id))?;
        visitor.message(Visit {
            channel_id,
            channel,
            log_time,
            data: data(payload),
            at: MessageAt::File {
                offset: records_start + offset + RECORD_HEADER + MESSAGE_HEADER,
                len,
            },
        })
    }

    /// Where the record of `entries[last]` ends: at the next message's offset, or, for the
    /// chunk's last message, where its record header says.
    fn record_end(
        &self,
        records_start: u64,
        records_end: u64,
        entries: &[(u64, u64, u16)],
        last: usize,
    ) -> Result<u64, BagProblem> {
        let offset = entries[last].1;
        let end = match entries.get(last + 1) {
            Some(next) => Some(next.1),
            None => {
                let mut header = [0u8; RECORD_HEADER as usize];
                (self.source)
                    .read_at(records_start + offset, &mut header)
                    .map_err(|e| io_problem(&e))?;
                let len = u64::from_le_bytes([
                    header[1], header[2], header[3], header[4], header[5], header[6], header[7],
                    header[8],
                ]);
                offset
                    .checked_add(RECORD_HEADER)
                    .and_then(|o| o.checked_add(len))
            }
        };
        end.filter(|&end| end > offset && end <= records_end)
            .ok_or_else(|| chunk_problem("a message record runs past the chunk's records"))
    }
}

/// The body of the record starting at `at` of `bytes`.
fn record_body(bytes: &[u8], at: u64) -> Result<&[u8], BagProblem> {
    let rest = usize::try_from(at).ok().and_then(|at| bytes.get(at..));
    let (op, body) = rest
        .and_then(|r| r.split_first_chunk::<9>())
        .ok_or_else(|| chunk_problem("a message index points past the bytes of its run"))?;
    let len = u64::from_le_bytes([op[1], op[2], op[3], op[4], op[5], op[6], op[7], op[8]]);
    if op[0] != OP_MESSAGE {
        return Err(chunk_problem(
            "a message index points at a record that is not a message",
        ));
    }
    usize::try_from(len)
        .ok()
        .and_then(|len| body.get(..len))
        .ok_or_else(|| chunk_problem("a message record runs past the next message"))
}
