//! A dataset's numbers as pushlab reads them, whatever the format: named features with a fixed
//! number of values per frame, the frames of every episode one after the other, and each episode's
//! rows. The zarr and LeRobot readers fill it; choosing the pusher and the object and turning them
//! into recordings works on it alone.

use std::ops::Range;
use std::path::PathBuf;

/// Which layout a dataset was read from.
#[derive(Clone, Debug, PartialEq)]
pub enum DatasetFormat {
    /// A zarr v2 replay buffer as Diffusion Policy writes it.
    ReplayBuffer,
    /// A LeRobot dataset; its `codebase_version` (`v2.1`, `v3.0`).
    LeRobot(String),
}

impl std::fmt::Display for DatasetFormat {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DatasetFormat::ReplayBuffer => write!(f, "zarr replay buffer"),
            DatasetFormat::LeRobot(version) => write!(f, "LeRobot dataset {version}"),
        }
    }
}

/// One numeric feature: `width` values per frame, frame after frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Feature {
    pub name: String,
    pub width: usize,
    pub values: Vec<f64>,
}

impl Feature {
    /// The values of frame `row`.
    pub fn row(&self, row: usize) -> &[f64] {
        &self.values[row * self.width..(row + 1) * self.width]
    }
}

/// Everything read from a dataset.
#[derive(Clone, Debug, PartialEq)]
pub struct DatasetTable {
    pub format: DatasetFormat,
    /// The numeric features, by name.
    pub features: Vec<Feature>,
    /// Each episode's rows, in order, covering every frame.
    pub episodes: Vec<Range<usize>>,
    /// Frames per second.
    pub fps: f64,
    /// Each frame's time within its episode, seconds, where the dataset records it (LeRobot's
    /// `timestamp`); else frame number / fps.
    pub times: Option<Vec<f64>>,
    /// Image and video features, each episode's cameras (read when shown): (name, what they are).
    pub cameras: Vec<(String, String)>,
    /// A LeRobot dataset's video features (dtype `video`), each one of `cameras` too: where their
    /// MP4 files are, so that a camera can be attached to each episode. Empty for a replay buffer.
    pub videos: Vec<VideoFeature>,
    /// A LeRobot dataset's image features (dtype `image`: a PNG or JPEG in each row of the parquet
    /// files, as `lerobot/pusht_image` keeps them), each one of `cameras` too. Empty for a replay
    /// buffer, whose images are arrays of its own.
    pub images: Vec<ImageFeature>,
    /// What reading did that loses nothing but a user should know (metadata that disagrees with
    /// the files, which are read): said by `validate` and kept in every episode's notes.
    pub notes: Vec<String>,
}

/// A LeRobot video feature: its frames are in MP4 files beside the parquet, one per episode (v2) or
/// several episodes per file (v3.0, each episode's span in `meta/episodes`).
#[derive(Clone, Debug, PartialEq)]
pub struct VideoFeature {
    /// The feature's name, `observation.image`; `{video_key}` in the template.
    pub name: String,
    /// `meta/info.json`'s `video_path` as written, relative to the dataset's folder: v2
    /// `videos/chunk-{episode_chunk:03d}/{video_key}/episode_{episode_index:06d}.mp4`, v3.0
    /// `videos/{video_key}/chunk-{chunk_index:03d}/file-{file_index:03d}.mp4`.
    pub path_template: String,
    /// Width and height of its frames, pixels (`info.json`'s shape).
    pub size_px: (u32, u32),
    /// Where each episode's frames are, in the order of the table's episodes.
    pub episodes: Vec<VideoSpan>,
}

/// Where one episode's frames of a video feature are: its file, and the time in the file of the
/// episode's time 0 (`from_timestamp`; 0 where each episode has its own file).
#[derive(Clone, Debug, PartialEq)]
pub struct VideoSpan {
    pub file: PathBuf,
    pub from_s: f64,
}

/// A LeRobot image feature: each frame's picture is a cell of its column in the parquet files.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageFeature {
    /// The feature's name, `observation.image`: its column.
    pub name: String,
    /// Where each episode's rows are, in the order of the table's episodes.
    pub episodes: Vec<RowSpan>,
}

/// Where one episode's rows are: its parquet file and the row of its first frame in that file (0
/// where each episode has its own file).
#[derive(Clone, Debug, PartialEq)]
pub struct RowSpan {
    pub file: PathBuf,
    pub first_row: usize,
}

impl DatasetTable {
    /// The feature called `name`.
    pub fn feature(&self, name: &str) -> Option<&Feature> {
        self.features.iter().find(|f| f.name == name)
    }

    /// The features' names and widths, for messages: `state (5), action (2)`.
    pub fn feature_list(&self) -> String {
        let list: Vec<String> = (self.features.iter())
            .map(|f| format!("{} ({})", f.name, f.width))
            .collect();
        list.join(", ")
    }

    /// The time of frame `row` of an episode starting at row `first`.
    pub fn time(&self, row: usize, first: usize) -> f64 {
        match &self.times {
            Some(times) => times[row] - times[first],
            None => (row - first) as f64 / self.fps,
        }
    }
}
