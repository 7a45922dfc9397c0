//! The error a bag's readers return: what is wrong with the bag (or the topics asked of it), or
//! with a file it needs, naming the file.

use std::path::{Path, PathBuf};

use super::problem::BagProblem;
use crate::recording::native::NativeError;
use crate::recording::read::ReadError;

/// Why a ROS 2 bag (an `.mcap` file or a rosbag2 folder) could not be listed or imported.
#[derive(Debug, thiserror::Error)]
pub enum BagError {
    /// A file or folder that could not be read at all, or is too large to open.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// The `setting.json` a choice names is unusable.
    #[error(transparent)]
    Setting(#[from] NativeError),
    /// What is wrong with the bag; `path` is the `.mcap` file the problem is in, or the folder (or
    /// the remembered choice file, for a choice that cannot be used).
    #[error("{}: {problem}", path.display())]
    Problem { path: PathBuf, problem: BagProblem },
}

impl BagError {
    /// The file or folder the error is about.
    pub fn path(&self) -> &Path {
        match self {
            BagError::Read(e) => e.path(),
            BagError::Setting(e) => e.path(),
            BagError::Problem { path, .. } => path,
        }
    }

    /// `problem` found in `path`.
    pub(crate) fn problem(path: &Path, problem: BagProblem) -> Self {
        BagError::Problem {
            path: path.to_path_buf(),
            problem,
        }
    }

    /// `source` met reading `path`.
    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        BagError::Read(ReadError::io(path, source))
    }
}
