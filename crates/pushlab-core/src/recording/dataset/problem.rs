//! What can be wrong with a Push-T dataset (a zarr replay buffer or a LeRobot dataset), beside the
//! readers that find it. The error that carries it ([`super::DatasetError::Problem`]) names
//! the file: the array's `.zarray` or chunk, the parquet file, `meta/info.json`.

use crate::json_problem::JsonProblem;

/// What is wrong with a dataset, or with the features asked of it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DatasetProblem {
    /// A metadata file (`.zarray`, `meta/info.json`, a remembered choice) is not the JSON expected.
    #[error("{0}")]
    Json(JsonProblem),
    /// A metadata field with a value pushlab cannot use.
    #[error("field `{field}`: {why}")]
    Field { field: String, why: String },
    /// A compressed chunk or page that cannot be decoded.
    #[error("{0}")]
    Codec(String),
    /// A parquet file that cannot be read.
    #[error("not a readable parquet file: {0}")]
    Parquet(String),
    /// A chunk whose decoded size is not the chunk's.
    #[error("chunk `{chunk}` holds {bytes} bytes, expected {expected}")]
    ChunkSize {
        chunk: String,
        bytes: usize,
        expected: usize,
    },
    /// A chunk file of an array that is not there. Zarr lets an absent chunk mean "all fill value",
    /// but no recording is made of fill values: reading it as zeros would put the pusher and the
    /// object at the origin for the chunk's frames, so it is refused naming the file.
    #[error(
        "chunk file missing: rows {start}..{end} of the array would read as its fill value, which \
         no recording holds; restore the file (or leave the dataset's other files and re-export it)"
    )]
    MissingChunk { start: usize, end: usize },
    /// A column of a LeRobot parquet file that is not what `meta/info.json` says its feature is.
    #[error("column `{column}` row {row} (counting from 0): {found}, expected {expected}")]
    Column {
        column: String,
        row: usize,
        found: String,
        expected: String,
    },
    /// A column a parquet file should have and does not: a feature `meta/info.json` lists, or
    /// one every LeRobot file of its kind has; `wanted_by` says which.
    #[error("no column `{name}`, which {wanted_by}; the file's columns: {columns}")]
    MissingColumn {
        name: String,
        wanted_by: String,
        columns: String,
    },
    /// A feature asked for (or one every such dataset has) that is not there.
    #[error("no feature `{name}`; the dataset's features: {available}")]
    MissingFeature { name: String, available: String },
    /// A feature with too few values per frame for what it was asked to be.
    #[error("feature `{name}` has {width} value(s) per frame, {expected}")]
    FeatureWidth {
        name: String,
        width: usize,
        expected: String,
    },
    /// A value that is not a finite number where a position or angle is read.
    #[error("feature `{name}` row {row} (counting from 0) is {value}, expected a finite number")]
    NotFinite {
        name: String,
        row: usize,
        value: f64,
    },
    /// Frame times (a LeRobot `timestamp` column) that do not go forward within an episode.
    #[error(
        "frame times: row {row} (counting from 0) is at {} s, expected a finite time after row {}'s {} s",
        seconds(*time),
        row - 1,
        seconds(*previous)
    )]
    TimeNotIncreasing {
        row: usize,
        time: f64,
        previous: f64,
    },
    /// `meta/episode_ends` (or the episode index column) that does not cut the frames into episodes.
    #[error("{0}")]
    Episodes(String),
    /// No episode is left to import (an `--episodes` range past the end, or an empty dataset).
    #[error("no episodes in {asked}; the dataset has {count} (0..{count})")]
    NoEpisodes { asked: String, count: usize },
    /// A dataset whose pusher and object features are not chosen, nor pre-selected.
    #[error(
        "which features are the pusher and the object is not chosen and cannot be guessed; the \
         dataset's features: {features}; choose them in the app's dataset form, or import with \
         pushlab import DATASET --pusher-feature FEATURE[:COLUMN] --object-feature \
         pose:FEATURE[:COLUMN] or keypoints:FEATURE --out SET"
    )]
    NeedsChoice { features: String },
    /// The load it was read for was cancelled.
    #[error("opening cancelled")]
    Cancelled,
}

/// Seconds as a person reads them: fixed point to the microsecond, or in scientific notation when
/// that would show only zeros.
fn seconds(value: f64) -> String {
    if value == 0.0 || !value.is_finite() || value.abs() >= 1e-6 {
        let text = format!("{value:.6}");
        let text = text.trim_end_matches('0');
        text.strip_suffix('.').unwrap_or(text).to_owned()
    } else {
        format!("{value:.3e}")
    }
}
