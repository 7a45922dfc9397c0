//! Reading a recording file whole, after checking that it fits in memory.
//!
//! A file is parsed from memory, and what it becomes (frames, an online run, plots) takes about as
//! much again, twice: a 55 MB CSV of a million frames needs some 170 MB. A file too large for the
//! memory that is free is refused up front with its size and what it would need — before, a
//! recording larger than memory was read until the system killed the program.

use std::path::{Path, PathBuf};

/// Why a file could not be read whole, before any reader of a format looks at its bytes. Every
/// reader returns it inside its own error, and the loader inside [`super::LoadError`].
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The file or folder could not be read at all.
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A file too large for the memory that is free (see `MEMORY_PER_FILE_BYTE`).
    #[error(
        "{}: too large to open: the file is {} and opening it needs about {} of memory, but {} \
         free; split the recording into shorter files or free memory",
        path.display(),
        gigabytes(*bytes),
        gigabytes(*needed),
        available.map_or("less is".to_owned(), |a| format!("{} are", gigabytes(a)))
    )]
    TooLarge {
        path: PathBuf,
        bytes: u64,
        /// Memory opening it needs, bytes.
        needed: u64,
        /// Free memory when it was checked, bytes.
        available: Option<u64>,
    },
}

impl ReadError {
    /// The file or folder the error is about.
    pub fn path(&self) -> &Path {
        match self {
            ReadError::Io { path, .. } | ReadError::TooLarge { path, .. } => path,
        }
    }

    /// Whether the file or folder does not exist (it vanished, or was never there).
    pub fn is_not_found(&self) -> bool {
        matches!(self, ReadError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound)
    }

    /// `source` met reading `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        ReadError::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// Bytes as gigabytes with one decimal (10⁹ bytes, as file managers show them).
fn gigabytes(bytes: u64) -> String {
    format!("{:.1} GB", bytes as f64 / 1e9)
}

/// Bytes of memory opening a recording needs per byte of its file: the file's bytes while it is
/// parsed, its frames (48 bytes for a ~55-byte CSV line) and what the app keeps per frame.
pub const MEMORY_PER_FILE_BYTE: u64 = 3;

/// A file kept beside `source` (a bag, a dataset folder) and named after it, `NAME{suffix}`, such as
/// a remembered import choice; `fallback` names it when `source` has no file name (a root).
pub(crate) fn file_beside(source: &Path, suffix: &str, fallback: &str) -> PathBuf {
    let name = source
        .file_name()
        .map_or_else(|| fallback.into(), |n| n.to_string_lossy().into_owned());
    source.with_file_name(format!("{name}{suffix}"))
}

/// The whole file at `path`, or an error naming it: unreadable, or too large for the free memory.
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>, ReadError> {
    let size = crate::files::metadata(path)
        .map_err(|e| ReadError::io(path, e))?
        .len;
    fits_in_memory(path, size, available_memory())?;
    let mut bytes = Vec::new();
    let too_large = || ReadError::TooLarge {
        path: path.to_path_buf(),
        bytes: size,
        needed: size.saturating_mul(MEMORY_PER_FILE_BYTE),
        available: available_memory(),
    };
    bytes
        .try_reserve_exact(usize::try_from(size).map_err(|_| too_large())?)
        .map_err(|_| too_large())?;
    read_into(path, &mut bytes).map_err(|e| ReadError::io(path, e))?;
    Ok(bytes)
}

/// Reads the file at `path` into `bytes`, whose room was reserved for it.
#[cfg(not(target_arch = "wasm32"))]
fn read_into(path: &Path, bytes: &mut Vec<u8>) -> std::io::Result<()> {
    use std::io::Read;
    std::fs::File::open(path).and_then(|mut file| file.read_to_end(bytes))?;
    Ok(())
}

/// Reads the file at `path` from the page's files into `bytes`.
#[cfg(target_arch = "wasm32")]
fn read_into(path: &Path, bytes: &mut Vec<u8>) -> std::io::Result<()> {
    bytes.extend_from_slice(&crate::files::read(path)?);
    Ok(())
}

/// Refuses a file of `size` bytes when opening it would need more than `available` bytes.
fn fits_in_memory(path: &Path, size: u64, available: Option<u64>) -> Result<(), ReadError> {
    match available {
        Some(free) if size.saturating_mul(MEMORY_PER_FILE_BYTE) > free => {
            Err(ReadError::TooLarge {
                path: path.to_path_buf(),
                bytes: size,
                needed: size.saturating_mul(MEMORY_PER_FILE_BYTE),
                available,
            })
        }
        _ => Ok(()),
    }
}

/// Memory the system can give without swapping (Linux's `MemAvailable`), bytes; `None` where it
/// cannot be read.
pub fn available_memory() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_larger_than_memory_is_refused_before_it_is_read() {
        let error = fits_in_memory(Path::new("big/push.csv"), 40 << 30, Some(16 << 30))
            .expect_err("120 GB needed, 16 GB free");
        assert_eq!(
            error.to_string(),
            "big/push.csv: too large to open: the file is 42.9 GB and opening it needs about \
             128.8 GB of memory, but 17.2 GB are free; split the recording into shorter files or \
             free memory"
        );
        assert!(fits_in_memory(Path::new("a.csv"), 5 << 30, Some(16 << 30)).is_ok());
        assert!(
            fits_in_memory(Path::new("a.csv"), 40 << 30, None).is_ok(),
            "unknown: try"
        );
    }

    #[test]
    fn a_sparse_terabyte_file_is_refused_without_reading_it() {
        let dir = std::env::temp_dir().join(format!("pushlab-too-large-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let path = dir.join("huge.csv");
        // A terabyte that takes no disk: a sparse file.
        std::fs::File::create(&path)
            .and_then(|f| f.set_len(1 << 40))
            .expect("sparse file");
        let error = read_file(&path).expect_err("a terabyte does not fit");
        let message = error.to_string();
        assert!(
            message.contains("huge.csv: too large to open: the file is 1099.5 GB"),
            "{message}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
