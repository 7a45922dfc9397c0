//! The error the MIT Push Dataset reader returns, naming the file.

use std::path::{Path, PathBuf};

use super::problem::MitProblem;
use crate::recording::read::ReadError;

/// Why an MIT Push Dataset file could not be imported.
#[derive(Debug, thiserror::Error)]
pub enum MitError {
    /// The file could not be read at all, or is too large to open.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// What is wrong with the file (or its name).
    #[error("{}: {problem}", path.display())]
    Problem { path: PathBuf, problem: MitProblem },
}

impl MitError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            MitError::Read(e) => e.path(),
            MitError::Problem { path, .. } => path,
        }
    }
}
