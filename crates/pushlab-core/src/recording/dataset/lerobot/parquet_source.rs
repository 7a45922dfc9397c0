//! A parquet file as the parquet crate reads it, through the one door to files
//! ([`crate::files::Positioned`]): read at offsets, a row group at a time, never whole. A LeRobot
//! v3.0 file holds many episodes, and a page's file is already in memory (shared, not copied).
//!
//! Why not the parquet crate's own `File` reader: it opens the disk, which a page has not.

use std::io::{self, BufReader, Read};
use std::path::Path;
use std::sync::Arc;

use bytes::Bytes;
use parquet::errors::{ParquetError, Result};
use parquet::file::reader::{ChunkReader, Length};

use crate::files::Positioned;

/// A parquet file opened for reads at offsets.
pub struct ParquetSource(Arc<Positioned>);

impl ParquetSource {
    /// Opens the file at `path`.
    pub fn open(path: &Path) -> io::Result<Self> {
        Positioned::open(path).map(|file| Self(Arc::new(file)))
    }
}

impl Length for ParquetSource {
    fn len(&self) -> u64 {
        self.0.len()
    }
}

/// The bytes of the file from an offset on, as `Read`.
pub struct ReadFrom {
    file: Arc<Positioned>,
    at: u64,
}

impl Read for ReadFrom {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let left = self.file.len().saturating_sub(self.at);
        let n = usize::try_from(left).map_or(buf.len(), |left| left.min(buf.len()));
        if n == 0 {
            return Ok(0);
        }
        self.file.read_at(self.at, &mut buf[..n])?;
        self.at += n as u64;
        Ok(n)
    }
}

impl ChunkReader for ParquetSource {
    type T = BufReader<ReadFrom>;

    fn get_read(&self, start: u64) -> Result<Self::T> {
        Ok(BufReader::new(ReadFrom {
            file: Arc::clone(&self.0),
            at: start,
        }))
    }

    fn get_bytes(&self, start: u64, length: usize) -> Result<Bytes> {
        // A length read from a damaged footer is checked against the file before it sizes a buffer.
        let fits = (start.checked_add(length as u64)).is_some_and(|end| end <= self.0.len());
        if !fits {
            return Err(ParquetError::EOF(format!(
                "{length} bytes at offset {start} run past the end of the {}-byte file",
                self.0.len()
            )));
        }
        let mut buf = vec![0; length];
        (self.0.read_at(start, &mut buf)).map_err(|e| ParquetError::External(Box::new(e)))?;
        Ok(Bytes::from(buf))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_at_offsets_and_refuses_reads_past_the_end() {
        let path =
            std::env::temp_dir().join(format!("pushlab-parquet-source-{}", std::process::id()));
        std::fs::write(&path, b"0123456789").expect("a file");
        let source = ParquetSource::open(&path).expect("opens");
        assert_eq!(source.len(), 10);
        assert_eq!(&source.get_bytes(3, 4).expect("inside")[..], b"3456");
        let mut rest = String::new();
        source
            .get_read(7)
            .expect("a reader")
            .read_to_string(&mut rest)
            .expect("reads");
        assert_eq!(rest, "789");
        let past = source.get_bytes(8, usize::MAX).expect_err("past the end");
        assert!(
            past.to_string()
                .contains("run past the end of the 10-byte file"),
            "{past}"
        );
        std::fs::remove_file(&path).ok();
    }
}
