//! Reading one message again where a pass found it: a camera frame when it is shown.

use super::records::{self, MAX_CHUNK_BYTES, OP_CHUNK, RECORD_HEADER};
use super::source::Source;
use super::{MessageAt, chunk_problem, io_problem};
use crate::recording::bag::problem::BagProblem;

/// The last decompressed chunk, kept so that reading the frames of one chunk one after another
/// decompresses it once.
#[derive(Default)]
pub struct ChunkCache {
    chunk: Option<u64>,
    records: Vec<u8>,
}

/// The payload of a message found by [`read_messages`].
pub fn read_payload<S: Source + ?Sized>(
    source: &S,
    at: &MessageAt,
    cache: &mut ChunkCache,
) -> Result<Vec<u8>, BagProblem> {
    match *at {
        MessageAt::File { offset, len } => source.read_vec(offset, len).map_err(|e| io_problem(&e)),
        MessageAt::Compressed { chunk, offset, len } => {
            if cache.chunk != Some(chunk) {
                cache.chunk = None;
                let mut header = [0u8; RECORD_HEADER as usize];
                source
                    .read_at(chunk, &mut header)
                    .map_err(|e| io_problem(&e))?;
                let record_len = u64::from_le_bytes([
                    header[1], header[2], header[3], header[4], header[5], header[6], header[7],
                    header[8],
                ]);
                if header[0] != OP_CHUNK || record_len > MAX_CHUNK_BYTES {
                    return Err(chunk_problem("the chunk a frame is in is not where it was"));
                }
                let body = source
                    .read_vec(chunk + RECORD_HEADER, record_len)
                    .map_err(|e| io_problem(&e))?;
                let header = records::chunk_header(&body)
                    .ok_or_else(|| chunk_problem("its header is cut short"))?;
                let data = body
                    .get(header.header_len as usize..)
                    .ok_or_else(|| chunk_problem("its header is cut short"))?;
                let mut buffer = Vec::new();
                let records = records::decompress(&header, data, &mut buffer)
                    .map_err(|w| chunk_problem(&w))?
                    .to_vec();
                cache.records = records;
                cache.chunk = Some(chunk);
            }
            usize::try_from(offset)
                .ok()
                .zip(usize::try_from(len).ok())
                .and_then(|(o, l)| cache.records.get(o..o.checked_add(l)?))
                .map(<[u8]>::to_vec)
                .ok_or_else(|| chunk_problem("a frame lies past its chunk's records"))
        }
    }
}
