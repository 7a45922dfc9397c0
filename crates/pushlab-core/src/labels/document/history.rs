//! The undo history's steps: the touched recordings (or schema) before and after an edit.

use super::super::RecordingLabels;
use super::super::schema::LabelSchema;

/// What an undo step restores.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Change {
    /// A recording's labels; `None` means the recording had no labels at all. Boxed so that the
    /// steps of schema edits stay small.
    Recording {
        name: String,
        before: Option<Box<RecordingLabels>>,
        after: Option<Box<RecordingLabels>>,
    },
    Schema {
        before: LabelSchema,
        after: LabelSchema,
    },
}

impl Change {
    pub(super) fn same_target(&self, other: &Change) -> bool {
        match (self, other) {
            (Change::Recording { name: a, .. }, Change::Recording { name: b, .. }) => a == b,
            (Change::Schema { .. }, Change::Schema { .. }) => true,
            _ => false,
        }
    }

    pub(super) fn is_noop(&self) -> bool {
        match self {
            Change::Recording { before, after, .. } => before == after,
            Change::Schema { before, after } => before == after,
        }
    }

    /// Takes `later`'s "after" as this change's "after" (same target).
    pub(super) fn absorb(&mut self, later: Change) {
        match (self, later) {
            (Change::Recording { after, .. }, Change::Recording { after: new, .. }) => *after = new,
            (Change::Schema { after, .. }, Change::Schema { after: new, .. }) => *after = new,
            _ => {}
        }
    }
}

#[derive(Clone, Debug)]
pub(super) struct Step {
    pub(super) description: String,
    pub(super) changes: Vec<Change>,
    pub(super) state_before: u64,
    pub(super) state_after: u64,
}
