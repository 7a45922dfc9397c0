//! The one door to the file system for opening recordings, models, labels and experiment specs.
//!
//! Why a door: the same loader runs on the desktop and in a browser tab. A desktop reads the disk; a
//! page has no disk, only the bytes it fetched (the bundled sample data, a recording given by
//! `?url=`) or that a user dropped on it. On `wasm32` every call here reads and writes an in-memory
//! tree ([`memory`]) that the page fills; elsewhere each is `std::fs`'s, unchanged. Callers keep
//! speaking of paths, so a set's `setting.json`, a labels file beside a recording and a demo's
//! folders mean the same on both targets.
//!
//! Bags stream from their files by positioned reads ([`Positioned`]): of the file on the desktop, of
//! the page's bytes in a tab (already in memory there, shared, not copied).

pub mod memory;

use std::io;
use std::path::{Path, PathBuf};

/// What a path is: its size and whether it is a folder.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Metadata {
    pub len: u64,
    pub is_dir: bool,
}

/// One entry of a folder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    pub path: PathBuf,
    pub is_dir: bool,
}

#[cfg(not(target_arch = "wasm32"))]
mod backend {
    use super::{Entry, Metadata};
    use std::io;
    use std::path::{Path, PathBuf};

    pub fn metadata(path: &Path) -> io::Result<Metadata> {
        let meta = std::fs::metadata(path)?;
        Ok(Metadata {
            len: meta.len(),
            is_dir: meta.is_dir(),
        })
    }

    pub fn read(path: &Path) -> io::Result<Vec<u8>> {
        std::fs::read(path)
    }

    pub fn read_dir(path: &Path) -> io::Result<Vec<Entry>> {
        Ok(std::fs::read_dir(path)?
            .filter_map(Result::ok)
            .map(|e| Entry {
                path: e.path(),
                // Symbolic links to folders are not followed: a loop of links would never end.
                is_dir: e.file_type().is_ok_and(|t| t.is_dir()),
            })
            .collect())
    }

    pub fn canonicalize(path: &Path) -> io::Result<PathBuf> {
        std::fs::canonicalize(path)
    }

    pub fn create_dir_all(path: &Path) -> io::Result<()> {
        std::fs::create_dir_all(path)
    }

    pub fn write_atomically(path: &Path, bytes: &[u8]) -> io::Result<()> {
        crate::atomic_file::write_atomically(path, bytes)
    }

    /// An open file, read at offsets.
    pub struct Positioned {
        #[cfg_attr(
            not(any(unix, windows)),
            expect(dead_code, reason = "no positioned reads here")
        )]
        file: std::fs::File,
        len: u64,
    }

    impl Positioned {
        pub fn open(path: &Path) -> io::Result<Self> {
            let file = std::fs::File::open(path)?;
            let len = file.metadata()?.len();
            Ok(Self { file, len })
        }

        pub fn len(&self) -> u64 {
            self.len
        }

        pub fn read_at(&self, offset: u64, buf: &mut [u8]) -> io::Result<()> {
            #[cfg(unix)]
            {
                use std::os::unix::fs::FileExt;
                self.file.read_exact_at(buf, offset)
            }
            #[cfg(windows)]
            {
                use std::os::windows::fs::FileExt;
                let mut done = 0;
                while done < buf.len() {
                    let n = self
                        .file
                        .seek_read(&mut buf[done..], offset + done as u64)?;
                    if n == 0 {
                        return Err(io::ErrorKind::UnexpectedEof.into());
                    }
                    done += n;
                }
                Ok(())
            }
            #[cfg(not(any(unix, windows)))]
            {
                let _ = (offset, buf);
                Err(io::Error::new(
                    io::ErrorKind::Unsupported,
                    "positioned reads of a file are not available on this platform",
                ))
            }
        }
    }
}

#[cfg(target_arch = "wasm32")]
mod backend {
    use super::memory::TREE;
    use super::{Entry, Metadata};
    use std::io;
    use std::path::{Path, PathBuf};

    pub fn metadata(path: &Path) -> io::Result<Metadata> {
        TREE.metadata(path)
    }

    pub fn read(path: &Path) -> io::Result<Vec<u8>> {
        TREE.read(path)
    }

    pub fn read_dir(path: &Path) -> io::Result<Vec<Entry>> {
        TREE.read_dir(path)
    }

    pub fn canonicalize(path: &Path) -> io::Result<PathBuf> {
        TREE.metadata(path).map(|_| super::memory::normal(path))
    }

    pub fn create_dir_all(path: &Path) -> io::Result<()> {
        TREE.create_dir_all(path);
        Ok(())
    }

    pub fn write_atomically(path: &Path, bytes: &[u8]) -> io::Result<()> {
        TREE.write(path, bytes.to_vec());
        Ok(())
    }

    /// A file of the page, read at offsets: its bytes, shared with the tree.
    pub struct Positioned {
        bytes: std::sync::Arc<Vec<u8>>,
    }

    impl Positioned {
        pub fn open(path: &Path) -> io::Result<Self> {
            TREE.shared(path).map(|bytes| Self { bytes })
        }

        pub fn len(&self) -> u64 {
            self.bytes.len() as u64
        }

        pub fn read_at(&self, offset: u64, buf: &mut [u8]) -> io::Result<()> {
            super::read_slice_at(&self.bytes, offset, buf)
        }
    }
}

/// The size of the file at `path`, and whether it is a folder.
pub fn metadata(path: &Path) -> io::Result<Metadata> {
    backend::metadata(path)
}

/// Whether `path` is a file (not a folder); `false` when it cannot be read.
pub fn is_file(path: &Path) -> bool {
    metadata(path).is_ok_and(|m| !m.is_dir)
}

/// Whether `path` is a folder; `false` when it cannot be read.
pub fn is_dir(path: &Path) -> bool {
    metadata(path).is_ok_and(|m| m.is_dir)
}

/// Whether anything is at `path`.
pub fn exists(path: &Path) -> bool {
    metadata(path).is_ok()
}

/// The whole file.
pub fn read(path: &Path) -> io::Result<Vec<u8>> {
    backend::read(path)
}

/// The whole file as UTF-8 text.
pub fn read_to_string(path: &Path) -> io::Result<String> {
    String::from_utf8(read(path)?).map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e))
}

/// The entries of a folder, in no particular order.
pub fn read_dir(path: &Path) -> io::Result<Vec<Entry>> {
    backend::read_dir(path)
}

/// The absolute path with links resolved (on the desktop), or the path made plain (in a page).
pub fn canonicalize(path: &Path) -> io::Result<PathBuf> {
    backend::canonicalize(path)
}

/// Creates the folder and its parents.
pub fn create_dir_all(path: &Path) -> io::Result<()> {
    backend::create_dir_all(path)
}

/// Writes a whole file so that a crash leaves the old one or the new one
/// ([`crate::atomic_file::write_atomically`] on the desktop).
pub fn write_atomically(path: &Path, bytes: &[u8]) -> io::Result<()> {
    backend::write_atomically(path, bytes)
}

/// A file opened for reads at offsets, with no shared cursor (readers on several threads share
/// one): a bag's chunks are read where its index says, never the whole file at once.
pub struct Positioned(backend::Positioned);

impl Positioned {
    /// Opens the file at `path`.
    pub fn open(path: &Path) -> io::Result<Self> {
        backend::Positioned::open(path).map(Self)
    }

    /// The file's length in bytes, when it was opened.
    pub fn len(&self) -> u64 {
        self.0.len()
    }

    /// Whether the file is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Fills `buf` from `offset`; an error when the file ends first.
    pub fn read_at(&self, offset: u64, buf: &mut [u8]) -> io::Result<()> {
        self.0.read_at(offset, buf)
    }
}

/// Fills `buf` from `offset` of bytes in memory; an error when they end first (a page's file, a
/// bag held in memory).
pub fn read_slice_at(bytes: &[u8], offset: u64, buf: &mut [u8]) -> io::Result<()> {
    let start = usize::try_from(offset).map_err(|_| io::ErrorKind::UnexpectedEof)?;
    let slice = start
        .checked_add(buf.len())
        .and_then(|end| bytes.get(start..end))
        .ok_or(io::ErrorKind::UnexpectedEof)?;
    buf.copy_from_slice(slice);
    Ok(())
}
