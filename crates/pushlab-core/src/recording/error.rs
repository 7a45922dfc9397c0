//! What can go wrong reading or writing recordings.
//!
//! Every error names the file it is about and, where it can, the line or field and what was expected,
//! so that a user can open the file and fix it without reading pushlab's code.

use std::path::{Path, PathBuf};

use super::bag::BagProblem;
use super::dataset::DatasetProblem;
use super::mit_push::MitProblem;
use super::native::CsvProblem;
use crate::json_problem::JsonProblem;

/// Why a recording (or a whole set) could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file or folder could not be read at all.
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
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
    /// A CSV passed on its own has no `setting.json` beside it.
    #[error("{}: no setting.json in the same folder, expected a native recording set", path.display())]
    NoSetting { path: PathBuf },
    /// An MIT Push Dataset file that cannot be used.
    #[error("{}: {problem}", path.display())]
    Mit { path: PathBuf, problem: MitProblem },
    /// A ROS 2 bag (an `.mcap` file or a rosbag2 folder) that cannot be used; `path` is the `.mcap`
    /// file the problem is in, or the folder.
    #[error("{}: {problem}", path.display())]
    Bag { path: PathBuf, problem: BagProblem },
    /// A Push-T dataset (a zarr replay buffer or a LeRobot dataset) that cannot be used; `path` is the
    /// file the problem is in (an array's `.zarray` or chunk, a parquet file), or the dataset.
    #[error("{}: {problem}", path.display())]
    Dataset {
        path: PathBuf,
        problem: DatasetProblem,
    },
    /// A path that is none of the things pushlab can open.
    #[error(
        "{}: not a recording: expected a native set folder (with setting.json), a folder of sets, a CSV inside a set, or an MIT Push Dataset .json/.h5 file",
        path.display()
    )]
    NotRecognised { path: PathBuf },
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
    /// The user stopped the load before this file.
    #[error("{}: opening cancelled", path.display())]
    Cancelled { path: PathBuf },
    /// A folder in which no recording was found.
    #[error("{}: no recordings found (no setting.json and no MIT Push Dataset files inside)", path.display())]
    NothingFound { path: PathBuf },
}

impl LoadError {
    /// The file or folder the error is about.
    pub fn path(&self) -> &Path {
        match self {
            LoadError::Io { path, .. }
            | LoadError::Csv { path, .. }
            | LoadError::FrameList { path, .. }
            | LoadError::SettingJson { path, .. }
            | LoadError::SettingField { path, .. }
            | LoadError::MissingTrajectory { path }
            | LoadError::NoSetting { path }
            | LoadError::Mit { path, .. }
            | LoadError::Bag { path, .. }
            | LoadError::Dataset { path, .. }
            | LoadError::NotRecognised { path }
            | LoadError::TooLarge { path, .. }
            | LoadError::NothingFound { path }
            | LoadError::Cancelled { path } => path,
        }
    }

    /// Whether the file or folder does not exist (it vanished, or was never there).
    pub fn is_not_found(&self) -> bool {
        matches!(self, LoadError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound)
    }

    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        LoadError::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// Bytes as gigabytes with one decimal (10⁹ bytes, as file managers show them).
fn gigabytes(bytes: u64) -> String {
    format!("{:.1} GB", bytes as f64 / 1e9)
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
