//! Push-T datasets: Diffusion Policy's zarr replay buffers and LeRobot datasets, read as recording
//! sets of the Push-T T, one recording per episode.
//!
//! The readers ([`replay`] over [`zarr`] and [`blosc`]; [`lerobot`], v2.x and v3.0, over parquet
//! through the parquet crate's record API) fill one
//! [`DatasetTable`] — named features over every frame, the episodes' rows, the frame rate; the
//! user's [`DatasetChoice`] (or Push-T's pre-selection, [`choice::suggest`]) says which features are
//! the pusher and the object; [`to_set`] turns the chosen episodes into recordings in pushlab's
//! conventions (metres, the T's area centroid; see `as_set`). Input files are only ever read.

mod as_set;
pub mod blosc;
mod cameras;
pub mod choice;
mod error;
pub mod lerobot;
mod problem;
pub mod replay;
mod table;
pub mod zarr;
mod zarr_frames;

use std::ops::Range;
use std::path::Path;

pub use self::as_set::{episode_indexes, setting_for, to_set};
pub use self::choice::{Columns, DatasetChoice, ObjectSource};
pub use self::error::DatasetError;
pub use self::problem::DatasetProblem;
pub use self::table::{
    DatasetFormat, DatasetTable, Feature, ImageFeature, RowSpan, VideoFeature, VideoSpan,
};
use crate::recording::RecordingSet;
use crate::recording::progress::Progress;

/// Whether `path` is a dataset pushlab reads: a zarr replay buffer or a LeRobot dataset (a
/// LeRobot version it does not read is recognised, and refused by [`read_table`] naming it).
pub fn is_dataset(path: &Path) -> bool {
    crate::files::is_dir(path) && (replay::is_replay_buffer(path) || lerobot::is_lerobot(path))
}

/// Bytes the reader will read, for the progress bar: a buffer's numeric arrays, a LeRobot
/// dataset's parquet files.
pub fn bytes(path: &Path) -> u64 {
    if replay::is_replay_buffer(path) {
        replay::bytes(path)
    } else {
        lerobot::bytes(path)
    }
}

/// Reads a dataset's features and episodes.
pub fn read_table(path: &Path, progress: &dyn Progress) -> Result<DatasetTable, DatasetError> {
    if replay::is_replay_buffer(path) {
        return replay::read(path, progress);
    }
    if lerobot::is_lerobot(path) {
        return lerobot::read(path, progress);
    }
    Err(DatasetError::NotRecognised {
        path: path.to_path_buf(),
    })
}

/// Opens a dataset with `choice` when given, else the choice remembered beside it, else Push-T's
/// pre-selection; without any of these it is an error listing its features.
pub fn open_with(
    path: &Path,
    choice: Option<&DatasetChoice>,
    range: Option<Range<usize>>,
    progress: &dyn Progress,
) -> Result<RecordingSet, DatasetError> {
    let table = read_table(path, progress)?;
    let choice = match choice {
        Some(choice) => choice.clone(),
        None => match choice::remembered(path)?.or_else(|| choice::suggest(&table)) {
            Some(choice) => choice,
            None => {
                return Err(DatasetError::Problem {
                    path: path.to_path_buf(),
                    problem: DatasetProblem::NeedsChoice {
                        features: table.feature_list(),
                    },
                });
            }
        },
    };
    to_set(path, &table, &choice, range)
}
