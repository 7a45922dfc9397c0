//! The edits of a labels document, one command each, and why an edit is refused.

use std::ops::Range;

use super::super::metadata::MetaField;
use super::super::schema::{LabelDef, Rgb};

/// One edit of the labels. Recordings are named by file name, as in the labels file.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Paints a range label over `frames` (half-open), cutting labels of its exclusive group.
    Paint {
        recording: String,
        label: String,
        frames: Range<usize>,
    },
    /// Removes one range label (or all, with `None`) from `frames`.
    Erase {
        recording: String,
        label: Option<String>,
        frames: Range<usize>,
    },
    /// Places a point event.
    AddEvent {
        recording: String,
        label: String,
        frame: usize,
    },
    /// Removes a point event.
    RemoveEvent {
        recording: String,
        label: String,
        frame: usize,
    },
    /// Moves a point event to another frame (dragging it on the timeline).
    MoveEvent {
        recording: String,
        label: String,
        from: usize,
        to: usize,
    },
    /// Sets one metadata field.
    SetMeta { recording: String, field: MetaField },
    /// Removes every label and metadata field of a recording.
    ClearRecording { recording: String },
    /// Restores a recording to how it was when the file was opened.
    RevertRecording { recording: String },
    /// Restores everything (schema and all recordings) to how it was when the file was opened.
    RevertAll,
    /// Adds a label to the schema.
    AddLabel(LabelDef),
    /// Removes a label from the schema. Refused while it is used, unless `with_uses` is set, in
    /// which case its segments and events go too.
    RemoveLabel { name: String, with_uses: bool },
    /// Changes how a label looks and which key paints it.
    SetLabelAppearance {
        name: String,
        colour: Rgb,
        hotkey: Option<String>,
    },
    /// Renames a label everywhere it is used.
    RenameLabel { from: String, to: String },
}

impl Command {
    /// A short sentence for undo/redo menus and status messages.
    pub fn describe(&self) -> String {
        let frames = |r: &Range<usize>| {
            if r.end == r.start + 1 {
                format!("frame {}", r.start)
            } else {
                format!("frames {}–{}", r.start, r.end.saturating_sub(1))
            }
        };
        match self {
            Command::Paint {
                recording,
                label,
                frames: r,
            } => format!("paint {label:?} over {} of {recording}", frames(r)),
            Command::Erase {
                recording,
                label,
                frames: r,
            } => match label {
                Some(label) => format!("erase {label:?} from {} of {recording}", frames(r)),
                None => format!("erase all labels from {} of {recording}", frames(r)),
            },
            Command::AddEvent {
                recording,
                label,
                frame,
            } => format!("add {label:?} at frame {frame} of {recording}"),
            Command::RemoveEvent {
                recording,
                label,
                frame,
            } => format!("remove {label:?} at frame {frame} of {recording}"),
            Command::MoveEvent {
                recording,
                label,
                from,
                to,
            } => format!("move {label:?} from frame {from} to {to} of {recording}"),
            Command::SetMeta { recording, field } => {
                format!("set {} of {recording}", field.name())
            }
            Command::ClearRecording { recording } => format!("clear all labels of {recording}"),
            Command::RevertRecording { recording } => format!("revert {recording}"),
            Command::RevertAll => "revert all labels".into(),
            Command::AddLabel(def) => format!("add label {:?}", def.name),
            Command::RemoveLabel { name, .. } => format!("remove label {name:?}"),
            Command::SetLabelAppearance { name, .. } => format!("restyle label {name:?}"),
            Command::RenameLabel { from, to } => format!("rename label {from:?} to {to:?}"),
        }
    }
}

/// Why a command was refused. The document is unchanged when a command fails.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EditError {
    /// The label does not exist or is of the wrong kind for this command.
    #[error("{0}")]
    Label(String),
    /// Removing a label that is still used.
    #[error(
        "label {label:?} is used {uses} times (in {recordings}); erase it first or remove it with its uses"
    )]
    LabelInUse {
        label: String,
        uses: usize,
        recordings: String,
    },
    /// The schema would break a rule (duplicate name or hotkey …).
    #[error("schema {field}: {message}")]
    Schema { field: String, message: String },
    /// A metadata value is not acceptable.
    #[error("{field}: {message}")]
    Meta { field: String, message: String },
}
