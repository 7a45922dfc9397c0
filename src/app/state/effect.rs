//! What a sub-state's command asks of the rest of the app. A sub-state applies its own commands
//! and returns these instead of reaching into its siblings; [`AppState`](super::AppState) carries
//! them out in order, so that every write to the status line, the session's problems or the labels
//! has one place, and each sub-state can be tested alone.

use std::path::PathBuf;

use pushlab_core::recording::bag::BagChoice;
use pushlab_core::recording::dataset::DatasetChoice;

use super::labels::labeling::LabelAction;
use super::labels::proposals::Asked;
use super::recordings::session::{LoadProblem, RecordingId};

/// One thing asked of the whole state.
#[derive(Debug)]
pub enum Effect {
    /// A line for the status bar (what just happened, or what went wrong).
    Status(String),
    /// Show this recording (a fresh online run on it).
    Select(RecordingId),
    /// Open a bag with a choice of topics; the bag's earlier problems are tried again.
    OpenBag {
        bag: PathBuf,
        choice: Box<BagChoice>,
    },
    /// Open a dataset with a choice of features; its earlier problems are tried again.
    OpenDataset {
        dataset: PathBuf,
        choice: Box<DatasetChoice>,
    },
    /// A problem for the browser's list of files that did not open.
    Problem(LoadProblem),
    /// An edit of the selected recording's labels at the frame shown.
    Label(LabelAction),
}

impl Effect {
    /// What a proposals action asked, in order: the status line first, then the labels edit, whose
    /// own message (a refusal, a rescue) replaces it.
    pub fn asked_by_proposals(asked: Asked) -> Vec<Effect> {
        let mut effects = vec![Effect::Status(asked.status)];
        effects.extend(asked.edit.map(Effect::Label));
        effects
    }
}
