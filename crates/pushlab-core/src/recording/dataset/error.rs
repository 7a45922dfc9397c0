//! The error a dataset's readers return, naming the file: the array's `.zarray` or chunk, the
//! parquet file, `meta/info.json`, or the dataset.

use std::path::{Path, PathBuf};

use super::problem::DatasetProblem;
use crate::recording::NOT_A_RECORDING;
use crate::recording::read::ReadError;

/// Why a Push-T dataset (a zarr replay buffer or a LeRobot dataset) could not be read or imported.
#[derive(Debug, thiserror::Error)]
pub enum DatasetError {
    /// A file or folder that could not be read at all, or is too large to open.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// What is wrong with the dataset; `path` is the file the problem is in (an array's `.zarray`
    /// or chunk, a parquet file), or the dataset.
    #[error("{}: {problem}", path.display())]
    Problem {
        path: PathBuf,
        problem: DatasetProblem,
    },
    /// A folder that is no dataset pushlab reads.
    #[error("{}: {}", path.display(), NOT_A_RECORDING)]
    NotRecognised { path: PathBuf },
}

impl DatasetError {
    /// The file or folder the error is about.
    pub fn path(&self) -> &Path {
        match self {
            DatasetError::Read(e) => e.path(),
            DatasetError::Problem { path, .. } | DatasetError::NotRecognised { path } => path,
        }
    }

    /// `source` met reading `path`.
    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        DatasetError::Read(ReadError::io(path, source))
    }
}
