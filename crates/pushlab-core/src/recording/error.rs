//! What can go wrong reading recordings: the loader's error, wrapping what each format's reader
//! returns.
//!
//! Every error names the file it is about and, where it can, the line or field and what was expected,
//! so that a user can open the file and fix it without reading pushlab's code. Imports run one way:
//! each reader (`native`, `mit_push`, `bag`, `dataset`) returns its own error and knows nothing of
//! this module; the loader wraps them here.

use std::path::{Path, PathBuf};

use super::NOT_A_RECORDING;
use super::bag::{BagError, BagProblem};
use super::dataset::DatasetError;
use super::mit_push::MitError;
use super::native::NativeError;
use super::read::ReadError;

/// Why a recording (or a whole set) could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// A file or folder that could not be read at all, or is too large for the memory that is free.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// A native set that cannot be used: a malformed CSV or frame list, a `setting.json` that is
    /// invalid or lists a file that is not there.
    #[error(transparent)]
    Native(#[from] NativeError),
    /// An MIT Push Dataset file that cannot be used.
    #[error(transparent)]
    Mit(#[from] MitError),
    /// A ROS 2 bag (an `.mcap` file or a rosbag2 folder) that cannot be used. A bag whose reading
    /// was cancelled is [`LoadError::Cancelled`] instead.
    #[error(transparent)]
    Bag(BagError),
    /// A Push-T dataset (a zarr replay buffer or a LeRobot dataset) that cannot be used.
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    /// A CSV passed on its own has no `setting.json` beside it.
    #[error("{}: no setting.json in the same folder, expected a native recording set", path.display())]
    NoSetting { path: PathBuf },
    /// A path that is none of the things pushlab can open.
    #[error("{}: {}", path.display(), NOT_A_RECORDING)]
    NotRecognised { path: PathBuf },
    /// The user stopped the load before this file.
    #[error("{}: opening cancelled", path.display())]
    Cancelled { path: PathBuf },
    /// A folder in which no recording was found.
    #[error("{}: no recordings found (no setting.json and no MIT Push Dataset files inside)", path.display())]
    NothingFound { path: PathBuf },
}

impl From<BagError> for LoadError {
    /// A bag's error, except that a cancelled read is the load's [`LoadError::Cancelled`], as it
    /// is for every other file.
    fn from(error: BagError) -> Self {
        match error {
            BagError::Problem {
                path,
                problem: BagProblem::Cancelled,
            } => LoadError::Cancelled { path },
            error => LoadError::Bag(error),
        }
    }
}

impl LoadError {
    /// The file or folder the error is about.
    pub fn path(&self) -> &Path {
        match self {
            LoadError::Read(e) => e.path(),
            LoadError::Native(e) => e.path(),
            LoadError::Mit(e) => e.path(),
            LoadError::Bag(e) => e.path(),
            LoadError::Dataset(e) => e.path(),
            LoadError::NoSetting { path }
            | LoadError::NotRecognised { path }
            | LoadError::NothingFound { path }
            | LoadError::Cancelled { path } => path,
        }
    }

    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        LoadError::Read(ReadError::io(path, source))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::dataset::DatasetProblem;
    use crate::recording::mit_push::MitProblem;
    use crate::recording::native::CsvProblem;

    fn path() -> PathBuf {
        PathBuf::from("d/x")
    }

    /// Each message as the loader said it before each reader had its own error (when every kind
    /// was a variant of `LoadError`), through the wrapping, with the file it names.
    #[test]
    fn every_error_reads_as_it_did_and_names_its_file() {
        let io = || std::io::Error::new(std::io::ErrorKind::NotFound, "gone");
        let said: Vec<(LoadError, &str)> = vec![
            (LoadError::io(&path(), io()), "d/x: cannot read: gone"),
            (
                ReadError::TooLarge {
                    path: path(),
                    bytes: 2_000_000_000,
                    needed: 6_000_000_000,
                    available: None,
                }
                .into(),
                "d/x: too large to open: the file is 2.0 GB and opening it needs about 6.0 GB of \
                 memory, but less is free; split the recording into shorter files or free memory",
            ),
            (
                NativeError::Csv {
                    path: path(),
                    line: 3,
                    problem: CsvProblem::TooFewRows { rows: 1 },
                }
                .into(),
                "d/x line 3: only 1 data rows, expected at least 2",
            ),
            (
                NativeError::FrameList {
                    path: path(),
                    line: 2,
                    why: "why".into(),
                }
                .into(),
                "d/x line 2: why",
            ),
            (
                NativeError::SettingField {
                    path: path(),
                    field: "h".into(),
                    problem: "is 0".into(),
                }
                .into(),
                "d/x: field `h`: is 0",
            ),
            (
                NativeError::MissingTrajectory { path: path() }.into(),
                "d/x: listed in setting.json but the file does not exist",
            ),
            (
                NativeError::Read(ReadError::io(&path(), io())).into(),
                "d/x: cannot read: gone",
            ),
            (
                LoadError::NoSetting { path: path() },
                "d/x: no setting.json in the same folder, expected a native recording set",
            ),
            (
                MitError::Problem {
                    path: path(),
                    problem: MitProblem::TooFewRows {
                        key: "tip_pose",
                        rows: 5,
                        min: 10,
                    },
                }
                .into(),
                "d/x: `tip_pose` has only 5 usable rows, expected at least 10",
            ),
            (
                BagError::Problem {
                    path: path(),
                    problem: BagProblem::NoMcapFiles,
                }
                .into(),
                "d/x: a rosbag2 folder, but it holds no .mcap file (expected the files \
                 metadata.yaml lists)",
            ),
            (
                DatasetError::Problem {
                    path: path(),
                    problem: DatasetProblem::Field {
                        field: "dtype".into(),
                        why: "why".into(),
                    },
                }
                .into(),
                "d/x: field `dtype`: why",
            ),
            (
                LoadError::NotRecognised { path: path() },
                "d/x: not a recording: expected a native set folder (with setting.json), a folder \
                 of sets, a CSV inside a set, or an MIT Push Dataset .json/.h5 file",
            ),
            (
                DatasetError::NotRecognised { path: path() }.into(),
                "d/x: not a recording: expected a native set folder (with setting.json), a folder \
                 of sets, a CSV inside a set, or an MIT Push Dataset .json/.h5 file",
            ),
            (
                LoadError::Cancelled { path: path() },
                "d/x: opening cancelled",
            ),
            (
                LoadError::NothingFound { path: path() },
                "d/x: no recordings found (no setting.json and no MIT Push Dataset files inside)",
            ),
        ];
        for (error, message) in said {
            assert_eq!(error.to_string(), message);
            assert_eq!(error.path(), path());
        }
        let problem =
            crate::json_problem::from_file_bytes::<serde_json::Value>(b"{").expect_err("not JSON");
        let json = LoadError::from(NativeError::SettingJson {
            path: path(),
            problem: problem.clone(),
        });
        assert_eq!(
            json.to_string(),
            format!("d/x: not a valid setting.json: {problem}")
        );
    }

    #[test]
    fn a_bag_read_cancelled_is_the_load_cancelled() {
        let cancelled = LoadError::from(BagError::Problem {
            path: path(),
            problem: BagProblem::Cancelled,
        });
        assert!(
            matches!(cancelled, LoadError::Cancelled { .. }),
            "{cancelled}"
        );
        assert_eq!(cancelled.to_string(), "d/x: opening cancelled");
    }
}
