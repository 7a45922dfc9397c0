//! The one door to the file system for opening recordings, models, labels and experiment specs.
//!
//! Why a door: the same loader runs on the desktop and in a browser tab. A desktop reads the disk; a
//! page has no disk, only the bytes it fetched (the bundled sample data, a recording given by
//! `?url=`) or that a user dropped on it. On `wasm32` every call here reads and writes an in-memory
//! tree ([`memory`]) that the page fills; elsewhere each is `std::fs`'s, unchanged. Callers keep
//! speaking of paths, so a set's `setting.json`, a labels file beside a recording and a demo's
//! folders mean the same on both targets.
//!
//! Bags, datasets and cameras still read through `std::fs` (they stream from seekable files); in a
//! page they fail with the platform's "unsupported" error, which the loader reports by file.

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
