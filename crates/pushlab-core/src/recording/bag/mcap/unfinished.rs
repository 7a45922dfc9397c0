//! A file without a summary whose chunks have their message indexes after them — most often a
//! recording cut short, its recorder killed before it wrote the summary — read as an indexed file.
//!
//! Why: read from the start, every chunk of such a file is read whole, and a zstd one decompressed,
//! even to list its topics (a 2.9 GB camera bag cut short: seconds, where its indexed original
//! lists in milliseconds). But the message index records a writer puts after each chunk say which
//! channels it holds and when each message was logged, and a walk of the record headers finds the
//! chunks and those indexes reading a few bytes per record. So the summary is rebuilt from the walk
//! — the channels from the records outside chunks and from the first chunks that declare them — and
//! the file read as an indexed one: a chunk holding nothing asked for is never read. Where a file
//! is not so (no message indexes, messages outside chunks, a chunk whose header cannot be read, a
//! cut before any channel), it is read from the start as before, which also says what is wrong.

use std::collections::BTreeMap;

use super::chunk::read_whole;
use super::linear::{Definitions, MAX_DEFINITION_BYTES, Record, Walk};
use super::records::{self, MAX_CHUNK_BYTES, OP_CHANNEL, OP_CHUNK, OP_MESSAGE, OP_SCHEMA};
use super::source::Source;
use super::summary::Summary;
use super::{ChannelInfo, CutShort};

/// The summary of a file without one, rebuilt from the walk of its record headers and its message
/// indexes, and where the file was cut short; the walk back when the summary cannot be rebuilt
/// (see the module documentation), for the pass from the start.
pub(super) fn rebuilt_summary<S: Source + ?Sized>(
    source: &S,
    walk: Walk,
) -> Result<(Summary, Option<CutShort>), Walk> {
    match channels_and_cut(source, &walk) {
        Some((channels, cut_short)) => {
            let summary = Summary {
                channels,
                chunks: walk.chunks,
                message_count: None,
            };
            Ok((summary, cut_short))
        }
        None => Err(walk),
    }
}

/// The channels the walked file declares and where it was cut short, when every channel its
/// message indexes name is declared.
fn channels_and_cut<S: Source + ?Sized>(
    source: &S,
    walk: &Walk,
) -> Option<(BTreeMap<u16, ChannelInfo>, Option<CutShort>)> {
    let Walk {
        chunks,
        definitions,
        loose_messages,
        stopped,
    } = walk;
    // Every chunk but a last one cut through its indexes has message indexes.
    let indexed = |index: usize| !chunks[index].message_index_offsets.is_empty();
    let last_unindexed = chunks.len().checked_sub(1).filter(|&last| !indexed(last));
    // Lengths a damaged file claims are not allocated: the pass from the start refuses them.
    let too_long = (chunks.iter()).any(|c| c.message_index_length > MAX_CHUNK_BYTES)
        || (definitions.iter()).any(|&(_, _, len)| len > MAX_DEFINITION_BYTES);
    if chunks.is_empty()
        || *loose_messages
        || too_long
        || (0..chunks.len()).any(|i| !indexed(i) && Some(i) != last_unindexed)
        || matches!(stopped, Some((_, Record::Whole { .. })))
    {
        return None;
    }
    let mut declared = Declared::default();
    for &(op, body, len) in definitions {
        declared.add(op, &source.read_vec(body, len).ok()?)?;
    }
    // The channels are declared in the chunks where they are first used (or before them): read
    // those chunks, and a last chunk whose indexes were cut, for their schema and channel records.
    for (index, chunk) in chunks.iter().enumerate() {
        let undeclared =
            (chunk.message_index_offsets.keys()).any(|id| !declared.channels.contains_key(id));
        if undeclared || Some(index) == last_unindexed {
            let (_, records) = read_whole(source, chunk).ok()?;
            for record in records::walk(&records) {
                let (_, op, body) = record.ok()?;
                if matches!(op, OP_SCHEMA | OP_CHANNEL) {
                    declared.add(op, body)?;
                }
            }
        }
    }
    let all_declared = (chunks.iter())
        .flat_map(|c| c.message_index_offsets.keys())
        .all(|id| declared.channels.contains_key(id));
    if !all_declared || declared.channels.is_empty() {
        return None;
    }
    let cut_short = stopped.map(|(at, record)| CutShort {
        readable: at,
        file_len: source.len(),
        messages_lost: match record {
            Record::HeaderCut => at < source.len(),
            Record::BodyCut { op, .. } => matches!(op, OP_CHUNK | OP_MESSAGE),
            Record::Whole { .. } => false,
        },
    });
    Some((declared.channels, cut_short))
}

/// The channels declared so far, each as first declared.
#[derive(Default)]
struct Declared {
    definitions: Definitions,
    channels: BTreeMap<u16, ChannelInfo>,
}

impl Declared {
    /// Reads a schema or channel record's body; `None` when it is cut short.
    fn add(&mut self, op: u8, body: &[u8]) -> Option<()> {
        if let Some((id, channel)) = self.definitions.add(op, body).ok()? {
            self.channels.entry(id).or_insert(channel);
        }
        Some(())
    }
}
