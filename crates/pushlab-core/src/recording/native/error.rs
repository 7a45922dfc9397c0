//! What can go wrong reading or writing a native recording set, each error naming its file.

use std::path::{Path, PathBuf};

use super::problem::CsvProblem;
use crate::json_problem::JsonProblem;
use crate::recording::read::ReadError;

/// Why a native set, one of its CSV files or a camera's frame list could not be read.
#[derive(Debug, thiserror::Error)]
pub enum NativeError {
    /// A file or folder that could not be read at all, or is too large to open.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// A native CSV file is malformed at a given line (1-based, the header is line 1).
    #[error("{} line {line}: {problem}", path.display())]
    Csv {
        path: PathBuf,
        line: usize,
        problem: CsvProblem,
    },
    /// A camera's frame list (`NAME.images/frames.csv`) is malformed at a line (1-based).
    #[error("{} line {line}: {why}", path.display())]
    FrameList {
        path: PathBuf,
        line: usize,
        why: String,
    },
    /// `setting.json` is not valid JSON or does not match the schema.
    #[error("{}: not a valid setting.json: {problem}", path.display())]
    SettingJson { path: PathBuf, problem: JsonProblem },
    /// `setting.json` parses but a field has an unusable value.
    #[error("{}: field `{field}`: {problem}", path.display())]
    SettingField {
        path: PathBuf,
        field: String,
        problem: String,
    },
    /// `setting.json` lists a trajectory whose CSV is not in the folder.
    #[error("{}: listed in setting.json but the file does not exist", path.display())]
    MissingTrajectory { path: PathBuf },
}

impl NativeError {
    /// The file or folder the error is about.
    pub fn path(&self) -> &Path {
        match self {
            NativeError::Read(e) => e.path(),
            NativeError::Csv { path, .. }
            | NativeError::FrameList { path, .. }
            | NativeError::SettingJson { path, .. }
            | NativeError::SettingField { path, .. }
            | NativeError::MissingTrajectory { path } => path,
        }
    }

    /// `source` met reading `path`.
    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        NativeError::Read(ReadError::io(path, source))
    }
}

/// Why a recording set could not be written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    #[error("{}: cannot write: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("setting.json lists {entries} trajectories but {trajectories} were given")]
    CountMismatch { entries: usize, trajectories: usize },
    #[error("trajectory file name '{0}' must be a plain file name ending in .csv (no folders)")]
    BadFileName(String),
    #[error("trajectory '{file}' frame {frame}: {problem}")]
    BadTrajectory {
        file: String,
        frame: usize,
        problem: String,
    },
    #[error("cannot serialise setting.json: {0}")]
    Json(String),
}
