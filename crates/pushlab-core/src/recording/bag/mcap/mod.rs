//! Reading the messages of one MCAP file without holding it in memory, and only those asked for.
//!
//! With a summary (what `ros2 bag record` and every MCAP library write when a recording ends), the
//! chunk indexes say where each chunk is and which channels it holds, and each chunk's message
//! indexes where each message is in it. A chunk holding nothing asked for is never read; a
//! compressed chunk is read and decompressed once; in an uncompressed chunk that also holds what
//! was not asked for (a camera's images beside the poses), only the messages asked for are read, at
//! their offsets — the image bytes are never touched, so importing the poses of a camera bag reads a
//! few percent of it. A chunk read whole has its CRC checked; one read message by message cannot
//! (its CRC covers the whole chunk), and relies on the messages decoding.
//!
//! Without a summary, a file whose chunks have their message indexes after them has its summary
//! rebuilt from a walk of its record headers and is read as an indexed one (`unfinished.rs`);
//! another is read from the start, record by record and chunk by chunk. Either way a file cut short
//! (its recorder stopped before writing the summary, or a disk filled) is read up to its last whole
//! record and the loss said ([`CutShort`]), as Foxglove's `mcap recover` would keep it, unless not
//! one whole record holds a channel.
//!
//! Either way the caller sees, in file order, every message of the channels it wants: their payload,
//! or only its first bytes and where the message lies (`MessageAt`), to read it again later — a
//! camera's frames are indexed so when a bag is opened and read one at a time as they are shown.

mod chunk;
mod linear;
mod payload;
mod prefetch;
mod reader;
mod records;
mod source;
mod summary;
mod unfinished;

pub use self::payload::{ChunkCache, read_payload};
pub use self::reader::read_messages;

pub use self::source::{Bytes, Source};

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

/// What a caller wants of a channel's messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Want {
    Nothing,
    /// Every message's payload.
    Payload,
    /// The first bytes of every payload (a header stamp) and where the message lies.
    Head(usize),
    /// The first bytes of the file's first message on the channel only (a camera's encoding and
    /// size, for a listing); the others are not read.
    First(usize),
}

/// Where a message's payload lies, to read it again with [`read_payload`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MessageAt {
    /// At this offset of the file: in an uncompressed chunk, or outside chunks.
    File { offset: u64, len: u64 },
    /// At `offset` of the decompressed records of the compressed chunk whose record starts at
    /// `chunk`.
    Compressed { chunk: u64, offset: u64, len: u64 },
}

impl MessageAt {
    /// The payload's length in bytes.
    pub fn len(&self) -> u64 {
        match *self {
            MessageAt::File { len, .. } | MessageAt::Compressed { len, .. } => len,
        }
    }
}

/// One message as the caller sees it.
pub struct Visit<'a> {
    pub channel_id: u16,
    pub channel: &'a ChannelInfo,
    pub log_time: u64,
    /// The payload, or its first bytes for [`Want::Head`] and [`Want::First`].
    pub data: &'a [u8],
    pub at: MessageAt,
}

/// What a pass through a file asks and is told.
pub trait Visitor {
    /// What is wanted of a channel's messages; asked once per channel, when it is declared.
    fn want(&mut self, channel_id: u16, channel: &ChannelInfo) -> Want;
    /// A message of a wanted channel, in file order.
    fn message(&mut self, visit: Visit<'_>) -> Result<(), BagProblem>;
    /// Bytes of the file passed since the last call; an error (a cancelled load) stops the pass.
    fn progress(&mut self, _bytes: u64) -> Result<(), BagProblem> {
        Ok(())
    }
}

/// A channel's messages over the whole file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ChannelStats {
    pub count: u64,
    /// First and last log time, nanoseconds (0 without messages).
    pub first: u64,
    pub last: u64,
}

impl ChannelStats {
    fn note(&mut self, log_time: u64) {
        if self.count == 0 {
            self.first = log_time;
            self.last = log_time;
        } else {
            self.first = self.first.min(log_time);
            self.last = self.last.max(log_time);
        }
        self.count += 1;
    }
}

#[cfg(test)]
mod tests;

/// Every channel of a file, with its messages counted.
pub type Channels = std::collections::BTreeMap<u16, (ChannelInfo, ChannelStats)>;

/// What a pass through a file found: every channel with its messages counted, and whether the file
/// was cut short.
#[derive(Clone, Debug)]
pub struct FileRead {
    pub channels: Channels,
    pub cut_short: Option<CutShort>,
}

/// A file that ends inside a record, or before its data-end record, after some whole records: a
/// recording that did not finish (the recorder killed, the disk full) or a damaged file. Its
/// records before the cut are read; the messages of the record cut through are lost, and said so.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CutShort {
    /// Where the last whole record ends: everything before this byte was read.
    pub readable: u64,
    /// The file's length.
    pub file_len: u64,
    /// Whether the record cut through could hold messages (a chunk or a message, or one whose
    /// header is cut too); a cut data-end or summary record loses none.
    pub messages_lost: bool,
}

impl std::fmt::Display for CutShort {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let lost = self.file_len - self.readable;
        if !self.messages_lost {
            write!(
                f,
                "the file ends at byte {} without its data-end record (a recording that did not \
                 finish?); every message in it was read",
                self.file_len
            )
        } else {
            write!(
                f,
                "the file is cut short (a recording that did not finish, or a damaged file): \
                 its last {lost} bytes, from byte {} on, are not a whole record, and the messages \
                 in them are lost; the messages before were read",
                self.readable
            )
        }
    }
}

/// What is kept of a payload for a want.
fn head(payload: &[u8], want: Want) -> &[u8] {
    match want {
        Want::Head(n) | Want::First(n) => &payload[..n.min(payload.len())],
        _ => payload,
    }
}

/// A problem inside a chunk, before its index is known (filled in by [`BagProblem::in_chunk`]).
fn chunk_problem(why: &str) -> BagProblem {
    BagProblem::Chunk {
        index: usize::MAX,
        why: why.to_owned(),
    }
}

fn message_cut_short(len: usize) -> BagProblem {
    chunk_problem(&format!(
        "a message record of {len} bytes, expected at least {}",
        records::MESSAGE_HEADER
    ))
}

fn undeclared(id: u16) -> BagProblem {
    BagProblem::Mcap(format!(
        "a message on channel {id}, which no channel record declared before it"
    ))
}

fn io_problem(e: &std::io::Error) -> BagProblem {
    if e.kind() == std::io::ErrorKind::UnexpectedEof {
        BagProblem::Mcap(format!("the file ends too early: {e}"))
    } else {
        BagProblem::Mcap(format!("cannot read: {e}"))
    }
}
