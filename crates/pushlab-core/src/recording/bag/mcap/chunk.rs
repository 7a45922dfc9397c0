//! Reading one chunk of an indexed file: its header, checked against the summary's index of it,
//! and its records whole (decompressed, or checked, against the header's size and CRC). Shared by
//! the reading thread and the workers that decompress ahead of it.

use super::records::{self, ChunkHeader, ChunkIndex, MAX_CHUNK_BYTES, OP_CHUNK, RECORD_HEADER};
use super::source::Source;
use super::{chunk_problem, io_problem};
use crate::recording::bag::problem::BagProblem;

/// A chunk's header, read from the file and checked against its index.
pub(super) fn chunk_header<S: Source + ?Sized>(
    source: &S,
    chunk: &ChunkIndex,
) -> Result<ChunkHeader, BagProblem> {
    let len = RECORD_HEADER + records::chunk_header_len(chunk.compression.len() as u64);
    let bytes = source
        .read_vec(chunk.start, len.min(chunk.length))
        .map_err(|e| io_problem(&e))?;
    let header = (bytes.first() == Some(&OP_CHUNK))
        .then(|| records::chunk_header(&bytes[RECORD_HEADER as usize..]))
        .flatten()
        .filter(|h| h.compression == chunk.compression && h.records_len == chunk.compressed_size)
        .ok_or_else(|| chunk_problem("its header does not match the summary's index of it"))?;
    if RECORD_HEADER + header.header_len + header.records_len > chunk.length {
        return Err(chunk_problem("its records run past its end"));
    }
    Ok(header)
}

/// A chunk's header and its records, read whole and decompressed when compressed.
pub(super) fn read_whole<S: Source + ?Sized>(
    source: &S,
    chunk: &ChunkIndex,
) -> Result<(ChunkHeader, Vec<u8>), BagProblem> {
    let header = chunk_header(source, chunk)?;
    if header.records_len > MAX_CHUNK_BYTES {
        return Err(chunk_problem(&format!(
            "claims {} bytes of records, more than pushlab accepts",
            header.records_len
        )));
    }
    let data = source
        .read_vec(
            chunk.start + RECORD_HEADER + header.header_len,
            header.records_len,
        )
        .map_err(|e| io_problem(&e))?;
    // Decompressed (or, uncompressed, checked) here: its size and CRC against the header.
    let mut buffer = Vec::new();
    records::decompress(&header, &data, &mut buffer).map_err(|w| chunk_problem(&w))?;
    if header.compression.is_empty() {
        return Ok((header, data));
    }
    Ok((header, buffer))
}
