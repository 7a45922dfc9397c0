//! Recordings: what pushlab loads and what it knows about each push.
//!
//! A [`Recording`] is one push with the [`Setting`] it was recorded in. Native recording sets (a folder
//! with `setting.json` and one CSV per push) and MIT Push Dataset files both load into it, grouped
//! into [`RecordingSet`]s. [`load_paths`] is the one entry point for opening whatever a user points at;
//! [`write_set`] writes a native set.

pub mod bag;
pub mod camera;
pub mod dataset;
mod describe;
mod error;
mod load;
pub mod mit_push;
pub mod native;
mod progress;
mod read;
pub mod resample;
mod setting;

use std::path::PathBuf;
use std::sync::Arc;

pub use bag::{BagError, BagProblem};
pub use dataset::{DatasetError, DatasetProblem};
pub use describe::PushParameters;
pub use error::LoadError;
pub use load::{
    LoadReport, SourceChoice, is_recording_file, load_paths, load_paths_choosing,
    load_paths_in_slices, load_paths_with,
};
pub use mit_push::{MitError, MitProblem};
pub use native::{CsvProblem, NativeError, WriteError};
pub use native::{read_set, write_set};
pub use progress::{LoadProgress, NoProgress, Progress, ProgressSnapshot};
pub use read::{MEMORY_PER_FILE_BYTE, ReadError, available_memory};
pub use resample::SpanProblem;
pub use setting::{
    BoxSize, BoxSizeError, ObjectShape, PushSide, Setting, ShapePreset, TrajectoryEntry,
    UnknownSide,
};

use self::camera::CameraStream;
use crate::trajectory::Trajectory;

/// What is said of a path that is none of the things pushlab opens, after the path.
const NOT_A_RECORDING: &str = "not a recording: expected a native set folder (with setting.json), a \
     folder of sets, a CSV inside a set, or an MIT Push Dataset .json/.h5 file";

/// One loaded push.
#[derive(Clone, Debug)]
pub struct Recording {
    /// The file it was read from, for messages and the browser.
    pub source: PathBuf,
    /// A short human name (the file stem).
    pub name: String,
    /// The setting it belongs to; shared by every push of a set.
    pub setting: Arc<Setting>,
    /// What `setting.json` lists about this push (contact offset, push angle), when listed.
    pub entry: Option<TrajectoryEntry>,
    /// The frames. Shared, so that an online run, a training job or an evaluation on another thread
    /// reads a long recording without copying it.
    pub trajectory: Arc<Trajectory>,
    /// Recoverable defects found while loading, each a sentence with numbers: rows dropped, gaps
    /// interpolated across, a file cut short — the frames are not all the recording had. Flagged
    /// wherever the recording is listed.
    pub warnings: Vec<String>,
    /// What loading did that loses nothing, each a sentence with numbers: an angle unwrapped,
    /// streams put on one clock, a log time for a missing stamp, a stream pushlab does not use
    /// found frozen. Said where asked for, not flagged: a note on most of a dataset's files would
    /// hide the warnings among them.
    pub notes: Vec<String>,
    /// What its cameras saw: one stream of frames per camera, read when shown.
    pub cameras: Vec<Arc<CameraStream>>,
}

impl Recording {
    /// Whether `other` pushes the same physical object: read from the same folder, with the same
    /// footprint, material and pusher. What lets online learning go on from one push to the next
    /// (`learn::OnlineRun::continuing`): a folder of pushes of one object (the MIT files of one
    /// shape on one surface, a simulated set) is one object, however the pushes differ.
    pub fn same_object_as(&self, other: &Recording) -> bool {
        self.source.parent() == other.source.parent()
            && self.setting.object == other.setting.object
            && self.setting.material == other.setting.material
            && self.setting.pusher_radius == other.setting.pusher_radius
    }
}

/// Pushes that share one setting: a native set folder, or the MIT files of one surface and shape in
/// one folder.
#[derive(Clone, Debug)]
pub struct RecordingSet {
    /// The folder the set was read from.
    pub dir: PathBuf,
    /// The setting every recording of the set shares.
    pub setting: Arc<Setting>,
    /// The recordings that loaded, in the order `setting.json` lists them.
    pub recordings: Vec<Recording>,
}
