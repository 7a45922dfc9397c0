//! Recordings: what pushlab loads and what it knows about each push.
//!
//! A [`Recording`] is one push with the [`Setting`] it was recorded in. Native recording sets (a folder
//! with `setting.json` and one CSV per push) and MIT Push Dataset files both load into it.

mod setting;

use std::path::PathBuf;
use std::sync::Arc;

pub use setting::{ObjectShape, PushSide, Setting, TrajectoryEntry};

use crate::trajectory::Trajectory;

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
    /// The frames.
    pub trajectory: Trajectory,
    /// Recoverable defects found while loading, each a sentence with numbers.
    pub warnings: Vec<String>,
}
