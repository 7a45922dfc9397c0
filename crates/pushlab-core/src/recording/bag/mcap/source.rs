//! Where an MCAP file's bytes come from: a file read at offsets (never whole), or bytes in memory
//! (tests, the fuzzer). Every read is bounded by the caller and checked against the source's length.

use std::io;

use crate::files::Positioned;

/// Bytes read at offsets.
pub trait Source: Sync {
    /// The source's length in bytes.
    fn len(&self) -> u64;

    /// Fills `buf` from `offset`; an error when the source ends first.
    fn read_at(&self, offset: u64, buf: &mut [u8]) -> io::Result<()>;

    /// `len` bytes from `offset` into a new vector, refusing reads past the end before allocating.
    fn read_vec(&self, offset: u64, len: u64) -> io::Result<Vec<u8>> {
        let end = offset.checked_add(len).filter(|&end| end <= self.len());
        if end.is_none() {
            return Err(io::Error::new(
                io::ErrorKind::UnexpectedEof,
                format!(
                    "{len} bytes at offset {offset} run past the end of the {}-byte file",
                    self.len()
                ),
            ));
        }
        let mut buf = vec![0; len as usize];
        self.read_at(offset, &mut buf)?;
        Ok(buf)
    }
}

/// A bag's file, read at offsets (of the file on the desktop, of the page's bytes in a tab).
impl Source for Positioned {
    fn len(&self) -> u64 {
        Positioned::len(self)
    }

    fn read_at(&self, offset: u64, buf: &mut [u8]) -> io::Result<()> {
        Positioned::read_at(self, offset, buf)
    }
}

/// Bytes in memory.
pub struct Bytes<'a>(pub &'a [u8]);

impl Source for Bytes<'_> {
    fn len(&self) -> u64 {
        self.0.len() as u64
    }

    fn read_at(&self, offset: u64, buf: &mut [u8]) -> io::Result<()> {
        crate::files::read_slice_at(self.0, offset, buf)
    }
}
