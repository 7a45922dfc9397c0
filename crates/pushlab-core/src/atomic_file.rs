//! Atomic file writes: every file pushlab writes for a user (recordings, labels, models, exports) goes
//! through here, so a crash or a kill at any moment leaves either the old file or the new one.

use std::fs;
use std::io::{self, Write};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

/// Writes `bytes` to `path` through a flushed temporary file in the same folder and a rename, keeping
/// the old file's permissions and flushing the folder entry.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_with_interrupt(path, bytes, &mut |_| Ok(()))
}

/// The steps of an atomic save at which a test may interrupt it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SaveStage {
    /// The temporary file is complete and flushed; the rename has not happened.
    TempWritten,
}

/// Writes `bytes` to `path` through a flushed temporary file in the same folder and a rename.
/// `interrupt` is called between the steps; an error from it aborts the save like a real failure.
pub(crate) fn write_with_interrupt(
    path: &Path,
    bytes: &[u8],
    interrupt: &mut dyn FnMut(SaveStage) -> io::Result<()>,
) -> io::Result<()> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "the path names no file"))?;
    // Hidden, and unique per process and save, so concurrent saves never share a temporary file.
    let temp = folder.join(format!(
        ".{}.tmp-{}-{}",
        name.to_string_lossy(),
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let result = (|| {
        {
            let mut file = fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&temp)?;
            if let Ok(old) = fs::metadata(path) {
                file.set_permissions(old.permissions())?;
            }
            file.write_all(bytes)?;
            file.sync_all()?;
        } // closed before the rename
        interrupt(SaveStage::TempWritten)?;
        fs::rename(&temp, path)
    })();
    if result.is_err() {
        // Best effort: a leftover hidden temporary file is harmless, the error below is what matters.
        let _ = fs::remove_file(&temp);
    }
    result?;
    sync_folder(folder);
    Ok(())
}

/// Flushes the folder entry so the rename itself survives a power cut. Not every platform can open
/// a folder for syncing; the data is already safe in either file, so failure is ignored.
fn sync_folder(folder: &Path) {
    #[cfg(unix)]
    if let Ok(dir) = fs::File::open(folder) {
        let _ = dir.sync_all();
    }
    #[cfg(not(unix))]
    let _ = folder;
}
