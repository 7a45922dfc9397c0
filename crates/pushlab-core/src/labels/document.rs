//! The open labels file as an editable document: every edit is a [`Command`], every applied command
//! can be undone and redone, and a recording can be reverted to how it was when the file was opened.
//!
//! This is what the app's labels panel holds. The panel only reads the document and sends commands;
//! it never changes labels directly, so undo covers every edit by construction.
//!
//! Undo steps store the touched recordings (and schema) before and after, not inverse operations:
//! recordings are small, and restoring a snapshot cannot drift from what the edit did. Three things
//! shape the steps the way a person expects:
//! - typing into one metadata text field becomes one step (consecutive edits of the same field of
//!   the same recording coalesce until [`LabelDocument::seal`] or any other edit);
//! - [`LabelDocument::begin_group`] … [`LabelDocument::end_group`] makes one step of many commands,
//!   e.g. painting while a hotkey is held during playback;
//! - a command that changes nothing makes no step.
//!
//! Whether the document differs from the file is tracked by state ids, so undoing back to the saved
//! state shows "saved" again.

use std::ops::Range;
use std::path::{Path, PathBuf};

use super::file::{self, LabelFileError};
use super::metadata::MetaField;
use super::schema::{LabelDef, LabelKind, LabelSchema, Rgb};
use super::segments::{self, Event};
use super::{LabelSet, RecordingLabels, check_label};

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

/// What the "saved" indicator shows.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SaveState {
    /// The file on disk holds exactly what is shown.
    Saved,
    /// There are edits not yet on disk.
    Unsaved,
    /// The last save failed with this message; edits are kept in memory.
    Failed(String),
}

/// What an undo step restores.
#[derive(Clone, Debug, PartialEq)]
enum Change {
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
    fn same_target(&self, other: &Change) -> bool {
        match (self, other) {
            (Change::Recording { name: a, .. }, Change::Recording { name: b, .. }) => a == b,
            (Change::Schema { .. }, Change::Schema { .. }) => true,
            _ => false,
        }
    }

    fn is_noop(&self) -> bool {
        match self {
            Change::Recording { before, after, .. } => before == after,
            Change::Schema { before, after } => before == after,
        }
    }

    /// Takes `later`'s "after" as this change's "after" (same target).
    fn absorb(&mut self, later: Change) {
        match (self, later) {
            (Change::Recording { after, .. }, Change::Recording { after: new, .. }) => *after = new,
            (Change::Schema { after, .. }, Change::Schema { after: new, .. }) => *after = new,
            _ => {}
        }
    }
}

#[derive(Clone, Debug)]
struct Step {
    description: String,
    changes: Vec<Change>,
    state_before: u64,
    state_after: u64,
}

/// A labels file opened for editing.
#[derive(Clone, Debug)]
pub struct LabelDocument {
    path: PathBuf,
    set: LabelSet,
    /// The content when the file was opened: what "revert" restores.
    opened: LabelSet,
    undo: Vec<Step>,
    redo: Vec<Step>,
    /// Id of the current content; equal ids mean equal content.
    state: u64,
    next_state: u64,
    /// Id of the content on disk, if it is still reachable by undo/redo.
    saved_state: Option<u64>,
    /// An explicit group is open: commands add to the top undo step.
    group_open: bool,
    /// The top undo step is a text edit of this (recording, field) and may absorb the next one.
    coalescing: Option<(String, &'static str)>,
    last_save_error: Option<String>,
    /// The file's text when it was read or last written (`Some(None)`: there was no file); `None`
    /// when unknown (a document made with [`LabelDocument::new`]). A save first checks that the
    /// file still holds this, so that labels another program wrote meanwhile are never overwritten.
    on_disk: Option<Option<String>>,
    /// The last save found the file changed by another program.
    conflict: bool,
}

/// At most this many undo steps are kept; the oldest are dropped first.
pub const UNDO_LIMIT: usize = 1000;

impl LabelDocument {
    /// Opens the labels file at `path`, or an empty document with the default schema if there is
    /// no file yet. An unedited document counts as saved either way: opening a folder and closing
    /// it writes nothing into it; the file is created by the first save after an edit.
    pub fn open(path: &Path) -> Result<Self, LabelFileError> {
        let text = file::current_text(path)?;
        let set = match &text {
            Some(text) => file::parse(text, path)?,
            None => LabelSet::default(),
        };
        let mut doc = Self::new(path, set);
        doc.on_disk = Some(text);
        Ok(doc)
    }

    /// Drops the document and reads the file again: what "reload" does after another program
    /// changed it. Unsaved edits and the undo history are gone.
    pub fn reload(&mut self) -> Result<(), LabelFileError> {
        *self = Self::open(&self.path)?;
        Ok(())
    }

    /// Whether the last save was refused because another program changed the file (then
    /// [`Self::overwrite`] or [`Self::reload`] resolves it).
    pub fn has_conflict(&self) -> bool {
        self.conflict
    }

    /// Opens the labels file of the recording set in `folder` (`folder/pushlab-labels.json`).
    pub fn open_set_folder(folder: &Path) -> Result<Self, LabelFileError> {
        Self::open(&file::path_in(folder))
    }

    /// A document over `set` that will be saved to `path`; `set` counts as what is on disk.
    pub fn new(path: &Path, set: LabelSet) -> Self {
        Self {
            path: path.to_owned(),
            opened: set.clone(),
            set,
            undo: Vec::new(),
            redo: Vec::new(),
            state: 0,
            next_state: 1,
            saved_state: Some(0),
            group_open: false,
            coalescing: None,
            last_save_error: None,
            on_disk: None,
            conflict: false,
        }
    }

    /// The file the document saves to.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The current labels.
    pub fn set(&self) -> &LabelSet {
        &self.set
    }

    /// The current schema.
    pub fn schema(&self) -> &LabelSchema {
        &self.set.schema
    }

    /// The current labels of `recording`, `None` if it has none.
    pub fn recording(&self, recording: &str) -> Option<&RecordingLabels> {
        self.set.recordings.get(recording)
    }

    /// Applies `command`. Returns whether anything changed; a refused command changes nothing.
    pub fn apply(&mut self, command: Command) -> Result<bool, EditError> {
        let description = command.describe();
        let coalesce_key = match &command {
            Command::SetMeta { recording, field } if field.is_text() => {
                Some((recording.clone(), field.name()))
            }
            _ => None,
        };
        let changes = self.changes_for(command)?;
        let changes: Vec<Change> = changes.into_iter().filter(|c| !c.is_noop()).collect();
        if changes.is_empty() {
            return Ok(false);
        }
        for change in &changes {
            self.restore(change, false);
        }
        self.redo.clear();
        let merge_into_top = self.group_open
            || (coalesce_key.is_some() && coalesce_key == self.coalescing && !self.undo.is_empty());
        let state = self.fresh_state();
        if merge_into_top && let Some(top) = self.undo.last_mut() {
            for change in changes {
                match top.changes.iter_mut().find(|c| c.same_target(&change)) {
                    Some(existing) => existing.absorb(change),
                    None => top.changes.push(change),
                }
            }
            top.changes.retain(|c| !c.is_noop());
            top.state_after = state;
            self.state = state;
            if top.changes.is_empty() && !self.group_open {
                // Typed back to where the step began: the step is gone and so is its state.
                self.state = top.state_before;
                self.undo.pop();
                self.coalescing = None;
                return Ok(true);
            }
        } else {
            self.undo.push(Step {
                description,
                changes,
                state_before: self.state,
                state_after: state,
            });
            if self.undo.len() > UNDO_LIMIT {
                self.undo.remove(0);
            }
            self.state = state;
        }
        self.coalescing = if self.group_open { None } else { coalesce_key };
        Ok(true)
    }

    /// Starts one undo step for many commands (a paint stroke while a hotkey is held). Commands
    /// applied until [`Self::end_group`] are undone together. `description` names the step.
    pub fn begin_group(&mut self, description: &str) {
        self.end_group();
        self.undo.push(Step {
            description: description.to_owned(),
            changes: Vec::new(),
            state_before: self.state,
            state_after: self.state,
        });
        self.group_open = true;
        self.coalescing = None;
    }

    /// Closes the group started by [`Self::begin_group`]; an empty group leaves no step.
    pub fn end_group(&mut self) {
        if !self.group_open {
            return;
        }
        self.group_open = false;
        if let Some(top) = self.undo.last()
            && top.changes.is_empty()
        {
            self.state = top.state_before;
            self.undo.pop();
        }
    }

    /// Ends the current text-typing step, so the next edit of the same field is a new undo step
    /// (call when a text box loses focus).
    pub fn seal(&mut self) {
        self.coalescing = None;
    }

    /// Undoes the last step. Returns its description, or `None` if there is nothing to undo.
    pub fn undo(&mut self) -> Option<String> {
        self.end_group();
        self.coalescing = None;
        let step = self.undo.pop()?;
        for change in step.changes.iter().rev() {
            self.restore(change, true);
        }
        self.state = step.state_before;
        let description = step.description.clone();
        self.redo.push(step);
        Some(description)
    }

    /// Redoes the last undone step. Returns its description, or `None` if there is nothing to redo.
    pub fn redo(&mut self) -> Option<String> {
        self.end_group();
        self.coalescing = None;
        let step = self.redo.pop()?;
        for change in &step.changes {
            self.restore(change, false);
        }
        self.state = step.state_after;
        let description = step.description.clone();
        self.undo.push(step);
        Some(description)
    }

    /// What undo would undo, for the menu.
    pub fn undo_description(&self) -> Option<&str> {
        self.undo.last().map(|s| s.description.as_str())
    }

    /// What redo would redo, for the menu.
    pub fn redo_description(&self) -> Option<&str> {
        self.redo.last().map(|s| s.description.as_str())
    }

    /// Whether there are edits not yet on disk.
    pub fn is_dirty(&self) -> bool {
        self.saved_state != Some(self.state)
    }

    /// An id of the current content, changing with every edit, undo and redo; the app's autosave
    /// uses it to notice edits.
    pub fn state_id(&self) -> u64 {
        self.state
    }

    /// What the "saved" indicator should show.
    pub fn save_state(&self) -> SaveState {
        match (&self.last_save_error, self.is_dirty()) {
            (Some(message), true) => SaveState::Failed(message.clone()),
            (_, true) => SaveState::Unsaved,
            (_, false) => SaveState::Saved,
        }
    }

    /// Writes the labels to the document's file, atomically. On failure the edits stay in memory,
    /// the file on disk is unchanged, and [`Self::save_state`] reports the error. A file that another
    /// program changed since it was read or last saved is not overwritten
    /// ([`LabelFileError::ChangedOnDisk`]).
    pub fn save(&mut self) -> Result<(), LabelFileError> {
        if let Some(expected) = &self.on_disk {
            let refused = match file::current_text(&self.path) {
                Ok(current) if current == *expected => None,
                Ok(_) => {
                    self.conflict = true;
                    Some(LabelFileError::ChangedOnDisk {
                        path: self.path.clone(),
                    })
                }
                Err(e) => Some(e),
            };
            if let Some(e) = refused {
                self.last_save_error = Some(e.to_string());
                return Err(e);
            }
        }
        self.overwrite()
    }

    /// Writes the labels to the file even if another program changed it meanwhile.
    pub fn overwrite(&mut self) -> Result<(), LabelFileError> {
        match file::write(&self.path, &self.set) {
            Ok(()) => {
                self.saved_state = Some(self.state);
                self.last_save_error = None;
                self.conflict = false;
                self.on_disk = Some(Some(file::to_json(&self.set)));
                Ok(())
            }
            Err(e) => {
                self.last_save_error = Some(e.to_string());
                Err(e)
            }
        }
    }

    /// Saves if there are unsaved edits; returns whether it wrote.
    pub fn save_if_dirty(&mut self) -> Result<bool, LabelFileError> {
        if self.is_dirty() {
            self.save().map(|()| true)
        } else {
            Ok(false)
        }
    }

    fn fresh_state(&mut self) -> u64 {
        let id = self.next_state;
        self.next_state += 1;
        id
    }

    /// Writes one side of a change into the current set.
    fn restore(&mut self, change: &Change, to_before: bool) {
        match change {
            Change::Recording {
                name,
                before,
                after,
            } => match if to_before { before } else { after } {
                Some(labels) => {
                    self.set.recordings.insert(name.clone(), (**labels).clone());
                }
                None => {
                    self.set.recordings.remove(name);
                }
            },
            Change::Schema { before, after } => {
                self.set.schema = if to_before { before } else { after }.clone();
            }
        }
    }

    /// A change of one recording made by `edit` on a copy of its labels.
    fn edit_recording(&self, recording: &str, edit: impl FnOnce(&mut RecordingLabels)) -> Change {
        let before = self.set.recordings.get(recording).cloned();
        let mut labels = before.clone().unwrap_or_default();
        edit(&mut labels);
        Change::Recording {
            name: recording.to_owned(),
            before: before.map(Box::new),
            after: (!labels.is_empty()).then(|| Box::new(labels)),
        }
    }

    fn changes_for(&self, command: Command) -> Result<Vec<Change>, EditError> {
        let schema = &self.set.schema;
        let range_label =
            |label: &str| check_label(schema, label, LabelKind::Range).map_err(EditError::Label);
        let event_label =
            |label: &str| check_label(schema, label, LabelKind::Event).map_err(EditError::Label);
        Ok(match command {
            Command::Paint {
                recording,
                label,
                frames,
            } => {
                range_label(&label)?;
                vec![self.edit_recording(&recording, |r| {
                    segments::paint(&mut r.segments, schema, &label, frames);
                })]
            }
            Command::Erase {
                recording,
                label,
                frames,
            } => {
                if let Some(label) = &label {
                    range_label(label)?;
                }
                vec![self.edit_recording(&recording, |r| {
                    segments::erase(&mut r.segments, label.as_deref(), frames);
                })]
            }
            Command::AddEvent {
                recording,
                label,
                frame,
            } => {
                event_label(&label)?;
                vec![self.edit_recording(&recording, |r| {
                    r.events.push(Event { label, frame });
                    segments::sort_events(&mut r.events);
                })]
            }
            Command::RemoveEvent {
                recording,
                label,
                frame,
            } => vec![self.edit_recording(&recording, |r| {
                r.events.retain(|e| !(e.label == label && e.frame == frame));
            })],
            Command::MoveEvent {
                recording,
                label,
                from,
                to,
            } => vec![self.edit_recording(&recording, |r| {
                let had = r.events.len();
                r.events.retain(|e| !(e.label == label && e.frame == from));
                if r.events.len() < had {
                    r.events.push(Event { label, frame: to });
                    segments::sort_events(&mut r.events);
                }
            })],
            Command::SetMeta { recording, field } => {
                let name = field.name();
                let change = self.edit_recording(&recording, |r| field.apply(&mut r.meta));
                if let Change::Recording {
                    after: Some(after), ..
                } = &change
                {
                    after
                        .meta
                        .validate()
                        .map_err(|(_, message)| EditError::Meta {
                            field: name.into(),
                            message,
                        })?;
                }
                vec![change]
            }
            Command::ClearRecording { recording } => {
                vec![self.edit_recording(&recording, |r| *r = RecordingLabels::default())]
            }
            Command::RevertRecording { recording } => {
                let original = self.opened.recordings.get(&recording).cloned();
                vec![self.edit_recording(&recording, |r| *r = original.unwrap_or_default())]
            }
            Command::RevertAll => {
                let mut names: Vec<&String> = self.set.recordings.keys().collect();
                names.extend(self.opened.recordings.keys());
                names.sort();
                names.dedup();
                let mut changes = vec![Change::Schema {
                    before: schema.clone(),
                    after: self.opened.schema.clone(),
                }];
                for name in names {
                    let original = self.opened.recordings.get(name).cloned();
                    changes.push(self.edit_recording(name, |r| *r = original.unwrap_or_default()));
                }
                changes
            }
            Command::AddLabel(def) => {
                let mut after = schema.clone();
                after.labels.push(def);
                self.schema_change(after)?
            }
            Command::RemoveLabel { name, with_uses } => {
                if schema.get(&name).is_none() {
                    return Err(EditError::Label(format!("unknown label {name:?}")));
                }
                let (uses, recordings) = self.uses_of(&name);
                if uses > 0 && !with_uses {
                    return Err(EditError::LabelInUse {
                        label: name,
                        uses,
                        recordings: summarise(&recordings),
                    });
                }
                let mut after = schema.clone();
                after.labels.retain(|l| l.name != name);
                let mut changes = self.schema_change(after)?;
                for recording in recordings {
                    changes.push(self.edit_recording(&recording, |r| {
                        r.segments.retain(|s| s.label != name);
                        r.events.retain(|e| e.label != name);
                    }));
                }
                changes
            }
            Command::SetLabelAppearance {
                name,
                colour,
                hotkey,
            } => {
                let mut after = schema.clone();
                let def = after
                    .labels
                    .iter_mut()
                    .find(|l| l.name == name)
                    .ok_or_else(|| EditError::Label(format!("unknown label {name:?}")))?;
                def.colour = colour;
                def.hotkey = hotkey;
                self.schema_change(after)?
            }
            Command::RenameLabel { from, to } => {
                let mut after = schema.clone();
                let def = after
                    .labels
                    .iter_mut()
                    .find(|l| l.name == from)
                    .ok_or_else(|| EditError::Label(format!("unknown label {from:?}")))?;
                def.name.clone_from(&to);
                let mut changes = self.schema_change(after)?;
                for recording in self.uses_of(&from).1 {
                    changes.push(self.edit_recording(&recording, |r| {
                        for s in r.segments.iter_mut().filter(|s| s.label == from) {
                            s.label.clone_from(&to);
                        }
                        for e in r.events.iter_mut().filter(|e| e.label == from) {
                            e.label.clone_from(&to);
                        }
                        segments::sort(&mut r.segments);
                        segments::sort_events(&mut r.events);
                    }));
                }
                changes
            }
        })
    }

    fn schema_change(&self, after: LabelSchema) -> Result<Vec<Change>, EditError> {
        after
            .validate()
            .map_err(|(field, message)| EditError::Schema { field, message })?;
        Ok(vec![Change::Schema {
            before: self.set.schema.clone(),
            after,
        }])
    }

    /// How often `label` is used, and in which recordings.
    fn uses_of(&self, label: &str) -> (usize, Vec<String>) {
        let mut uses = 0;
        let mut recordings = Vec::new();
        for (name, r) in &self.set.recordings {
            let n = r.segments.iter().filter(|s| s.label == label).count()
                + r.events.iter().filter(|e| e.label == label).count();
            if n > 0 {
                uses += n;
                recordings.push(name.clone());
            }
        }
        (uses, recordings)
    }
}

/// "a.csv, b.csv and 3 more".
fn summarise(names: &[String]) -> String {
    match names.len() {
        0..=3 => names.join(", "),
        n => format!("{} and {} more", names[..3].join(", "), n - 3),
    }
}

/// When to save without being asked: shortly after the last edit, but at least every `max_delay_s`
/// while edits keep coming (painting during playback), and after a failure only every `retry_s`.
/// Time is passed in, never read from the clock, so this is testable.
#[derive(Clone, Debug)]
pub struct Autosave {
    /// Quiet time after the last edit before saving, seconds.
    pub delay_s: f64,
    /// Longest time edits stay unsaved while editing continues, seconds.
    pub max_delay_s: f64,
    /// Wait after a failed save before trying again, seconds.
    pub retry_s: f64,
    /// (state id, time it was first seen) of the latest edit.
    last_edit: Option<(u64, f64)>,
    /// When unsaved edits were first seen.
    dirty_since: Option<f64>,
    last_failure: Option<f64>,
}

impl Default for Autosave {
    fn default() -> Self {
        Self {
            delay_s: 0.5,
            max_delay_s: 5.0,
            retry_s: 5.0,
            last_edit: None,
            dirty_since: None,
            last_failure: None,
        }
    }
}

impl Autosave {
    /// Call once per app update with the current time in seconds. Saves when due and returns the
    /// outcome; `None` when nothing was due.
    pub fn poll(
        &mut self,
        doc: &mut LabelDocument,
        now_s: f64,
    ) -> Option<Result<(), LabelFileError>> {
        if !doc.is_dirty() {
            self.last_edit = None;
            self.dirty_since = None;
            self.last_failure = None;
            return None;
        }
        let state = doc.state_id();
        let edited_at = match self.last_edit {
            Some((s, t)) if s == state => t,
            _ => {
                self.last_edit = Some((state, now_s));
                now_s
            }
        };
        let dirty_since = *self.dirty_since.get_or_insert(now_s);
        if self.last_failure.is_some_and(|t| now_s - t < self.retry_s) {
            return None;
        }
        let due = now_s - edited_at >= self.delay_s || now_s - dirty_since >= self.max_delay_s;
        if !due {
            return None;
        }
        let result = doc.save();
        match &result {
            Ok(()) => {
                self.dirty_since = None;
                self.last_failure = None;
            }
            Err(_) => self.last_failure = Some(now_s),
        }
        Some(result)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::super::Segment;
    use super::super::metadata::Split;
    use super::super::schema::names::*;
    use super::*;

    const REC: &str = "push_000.csv";

    fn doc() -> LabelDocument {
        LabelDocument::new(
            Path::new("/nonexistent/pushlab-labels.json"),
            LabelSet::default(),
        )
    }

    fn paint(label: &str, frames: Range<usize>) -> Command {
        Command::Paint {
            recording: REC.into(),
            label: label.into(),
            frames,
        }
    }

    fn segs(doc: &LabelDocument) -> Vec<Segment> {
        doc.recording(REC)
            .map(|r| r.segments.clone())
            .unwrap_or_default()
    }

    fn s(label: &str, frames: Range<usize>) -> Segment {
        Segment::new(label, frames)
    }

    #[test]
    fn undo_and_redo_walk_through_paint_steps() {
        let mut d = doc();
        assert!(d.apply(paint(STICKING, 0..100)).unwrap());
        assert!(d.apply(paint(SLIPPING, 40..60)).unwrap());
        assert_eq!(
            segs(&d),
            vec![
                s(STICKING, 0..40),
                s(SLIPPING, 40..60),
                s(STICKING, 60..100)
            ]
        );
        assert_eq!(
            d.undo().unwrap(),
            "paint \"slipping\" over frames 40–59 of push_000.csv"
        );
        assert_eq!(segs(&d), vec![s(STICKING, 0..100)]);
        assert_eq!(
            d.undo().unwrap(),
            "paint \"sticking\" over frames 0–99 of push_000.csv"
        );
        assert_eq!(
            d.recording(REC),
            None,
            "an unlabelled recording is absent again"
        );
        assert_eq!(d.undo(), None);
        assert!(d.redo().is_some());
        assert!(d.redo().is_some());
        assert_eq!(d.redo(), None);
        assert_eq!(
            segs(&d),
            vec![
                s(STICKING, 0..40),
                s(SLIPPING, 40..60),
                s(STICKING, 60..100)
            ]
        );
        // A new edit after an undo drops the redo branch.
        d.undo();
        d.apply(paint(BAD_TRACKING, 5..6)).unwrap();
        assert_eq!(d.redo_description(), None);
        assert_eq!(segs(&d), vec![s(STICKING, 0..100), s(BAD_TRACKING, 5..6)]);
    }

    #[test]
    fn refused_and_empty_commands_make_no_step() {
        let mut d = doc();
        let err = d.apply(paint("sliding", 0..10)).unwrap_err();
        assert!(
            err.to_string().starts_with("unknown label \"sliding\""),
            "{err}"
        );
        let err = d.apply(paint(CONTACT_MADE, 0..10)).unwrap_err();
        assert_eq!(
            err.to_string(),
            "\"contact made\" is a point event, expected a range label here"
        );
        assert!(!d.apply(paint(STICKING, 5..5)).unwrap());
        d.apply(paint(STICKING, 0..10)).unwrap();
        assert!(
            !d.apply(paint(STICKING, 2..8)).unwrap(),
            "painting over itself changes nothing"
        );
        d.undo();
        assert_eq!(d.undo(), None);
    }

    #[test]
    fn revert_restores_the_opened_state_and_is_undoable() {
        let mut set = LabelSet::default();
        set.recordings.insert(
            REC.into(),
            RecordingLabels {
                segments: vec![s(CONTACT, 0..50)],
                ..Default::default()
            },
        );
        let mut d = LabelDocument::new(Path::new("/x/l.json"), set);
        d.apply(paint(NO_CONTACT, 20..50)).unwrap();
        d.apply(Command::SetMeta {
            recording: REC.into(),
            field: MetaField::Split(Some(Split::Online)),
        })
        .unwrap();
        d.apply(Command::SetMeta {
            recording: "other.csv".into(),
            field: MetaField::Split(Some(Split::Offline)),
        })
        .unwrap();
        assert!(
            d.apply(Command::RevertRecording {
                recording: REC.into()
            })
            .unwrap()
        );
        assert_eq!(segs(&d), vec![s(CONTACT, 0..50)]);
        assert_eq!(d.recording(REC).unwrap().meta.split, None);
        assert_eq!(
            d.set().split_of("other.csv"),
            Some(Split::Offline),
            "other recordings kept"
        );
        d.undo();
        assert_eq!(segs(&d), vec![s(CONTACT, 0..20), s(NO_CONTACT, 20..50)]);
        assert_eq!(d.recording(REC).unwrap().meta.split, Some(Split::Online));
        // Reverting an unchanged recording is a no-op, and reverting one that did not exist at
        // opening removes it.
        d.redo();
        assert!(
            !d.apply(Command::RevertRecording {
                recording: REC.into()
            })
            .unwrap()
        );
        d.apply(Command::RevertRecording {
            recording: "other.csv".into(),
        })
        .unwrap();
        assert_eq!(d.recording("other.csv"), None);
        d.apply(paint(STICKING, 0..3)).unwrap();
        d.apply(Command::RevertAll).unwrap();
        assert_eq!(d.set(), &d.opened.clone());
    }

    #[test]
    fn typing_in_a_text_field_is_one_step_until_sealed() {
        let mut d = doc();
        for text in ["b", "bo", "box"] {
            d.apply(Command::SetMeta {
                recording: REC.into(),
                field: MetaField::Object(text.into()),
            })
            .unwrap();
        }
        d.seal();
        d.apply(Command::SetMeta {
            recording: REC.into(),
            field: MetaField::Object("box 2".into()),
        })
        .unwrap();
        d.undo();
        assert_eq!(d.recording(REC).unwrap().meta.object, "box");
        d.undo();
        assert_eq!(d.recording(REC), None);
        assert_eq!(d.undo(), None);
        assert!(!d.is_dirty());
    }

    #[test]
    fn typing_back_to_the_start_leaves_no_step() {
        let mut d = doc();
        let notes = |t: &str| Command::SetMeta {
            recording: REC.into(),
            field: MetaField::Notes(t.into()),
        };
        d.apply(notes("x")).unwrap();
        d.apply(notes("")).unwrap();
        assert_eq!(d.undo_description(), None);
        assert!(!d.is_dirty());
    }

    #[test]
    fn a_group_is_one_undo_step() {
        let mut d = doc();
        d.apply(paint(CONTACT, 0..5)).unwrap();
        d.begin_group("paint \"sticking\" while playing");
        for end in 11..=20 {
            d.apply(paint(STICKING, 10..end)).unwrap();
        }
        d.apply(Command::AddEvent {
            recording: REC.into(),
            label: CONTACT_MADE.into(),
            frame: 10,
        })
        .unwrap();
        d.end_group();
        assert_eq!(
            d.undo_description(),
            Some("paint \"sticking\" while playing")
        );
        d.undo();
        assert_eq!(segs(&d), vec![s(CONTACT, 0..5)]);
        assert!(d.recording(REC).unwrap().events.is_empty());
        d.redo();
        assert_eq!(segs(&d), vec![s(CONTACT, 0..5), s(STICKING, 10..20)]);
        // An empty group leaves nothing.
        d.begin_group("nothing");
        d.end_group();
        assert_eq!(
            d.undo_description(),
            Some("paint \"sticking\" while playing")
        );
    }

    #[test]
    fn events_are_added_moved_and_removed() {
        let mut d = doc();
        let add = |frame| Command::AddEvent {
            recording: REC.into(),
            label: CONTACT_LOST.into(),
            frame,
        };
        d.apply(add(30)).unwrap();
        assert!(!d.apply(add(30)).unwrap(), "same event twice is one event");
        d.apply(add(10)).unwrap();
        d.apply(Command::MoveEvent {
            recording: REC.into(),
            label: CONTACT_LOST.into(),
            from: 30,
            to: 5,
        })
        .unwrap();
        let frames: Vec<usize> = d
            .recording(REC)
            .unwrap()
            .events
            .iter()
            .map(|e| e.frame)
            .collect();
        assert_eq!(frames, vec![5, 10]);
        d.apply(Command::RemoveEvent {
            recording: REC.into(),
            label: CONTACT_LOST.into(),
            frame: 10,
        })
        .unwrap();
        assert_eq!(d.recording(REC).unwrap().events.len(), 1);
        let err = d.apply(add(1).clone()).map(|_| ());
        assert!(err.is_ok());
        let err = d
            .apply(Command::AddEvent {
                recording: REC.into(),
                label: STICKING.into(),
                frame: 1,
            })
            .unwrap_err();
        assert!(err.to_string().contains("is a range label"), "{err}");
    }

    #[test]
    fn dirty_state_follows_undo_to_the_saved_point() {
        let dir = std::env::temp_dir().join(format!("pushlab-labels-doc-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let mut d = LabelDocument::open_set_folder(&dir).unwrap();
        // Without a file and without edits there is nothing to save: opening writes nothing.
        assert_eq!(d.save_state(), SaveState::Saved);
        assert!(!d.save_if_dirty().unwrap());
        assert!(!file::path_in(&dir).exists(), "nothing was written");
        d.save().unwrap();
        assert_eq!(d.save_state(), SaveState::Saved);
        d.apply(paint(STICKING, 0..10)).unwrap();
        assert_eq!(d.save_state(), SaveState::Unsaved);
        d.save().unwrap();
        d.apply(paint(SLIPPING, 5..10)).unwrap();
        assert!(d.is_dirty());
        d.undo();
        assert!(!d.is_dirty(), "undo back to what is on disk");
        d.undo();
        assert!(d.is_dirty());
        d.redo();
        assert!(!d.is_dirty());
        // Reopening shows what was saved, and that is the new revert point.
        let reopened = LabelDocument::open_set_folder(&dir).unwrap();
        assert_eq!(reopened.set(), d.set());
        assert_eq!(reopened.save_state(), SaveState::Saved);
    }

    #[test]
    fn failed_save_is_reported_and_edits_are_kept() {
        let mut d = doc();
        d.apply(paint(STICKING, 0..10)).unwrap();
        let err = d.save().unwrap_err().to_string();
        assert!(err.contains("/nonexistent/pushlab-labels.json"), "{err}");
        assert_eq!(d.save_state(), SaveState::Failed(err));
        assert_eq!(segs(&d), vec![s(STICKING, 0..10)]);
    }

    #[test]
    fn schema_edits_are_checked_and_undoable() {
        let mut d = doc();
        d.apply(paint(SLIPPING, 0..10)).unwrap();
        let err = d
            .apply(Command::RemoveLabel {
                name: SLIPPING.into(),
                with_uses: false,
            })
            .unwrap_err();
        assert_eq!(
            err.to_string(),
            "label \"slipping\" is used 1 times (in push_000.csv); erase it first or remove it with its uses"
        );
        d.apply(Command::RenameLabel {
            from: SLIPPING.into(),
            to: "sliding".into(),
        })
        .unwrap();
        assert_eq!(segs(&d), vec![s("sliding", 0..10)]);
        assert!(
            d.schema().excludes("sliding", STICKING),
            "the group travels with the name"
        );
        let err = d
            .apply(Command::SetLabelAppearance {
                name: "sliding".into(),
                colour: Rgb::new(1, 2, 3),
                hotkey: Some("1".into()),
            })
            .unwrap_err();
        assert!(
            err.to_string()
                .contains("hotkey \"1\" is used by two labels"),
            "{err}"
        );
        d.apply(Command::RemoveLabel {
            name: "sliding".into(),
            with_uses: true,
        })
        .unwrap();
        assert_eq!(d.recording(REC), None);
        assert!(d.schema().get("sliding").is_none());
        d.undo();
        d.undo();
        assert_eq!(segs(&d), vec![s(SLIPPING, 0..10)]);
        assert_eq!(d.schema(), &LabelSchema::default());
        d.apply(Command::AddLabel(LabelDef::range(
            "pusher occluded",
            Rgb::new(9, 9, 9),
        )))
        .unwrap();
        assert!(d.schema().get("pusher occluded").is_some());
    }

    #[test]
    fn non_finite_com_is_refused() {
        let mut d = doc();
        let err = d
            .apply(Command::SetMeta {
                recording: REC.into(),
                field: MetaField::ComOffset(Some([0.0, f64::INFINITY])),
            })
            .unwrap_err();
        assert!(
            err.to_string()
                .starts_with("com_offset: expected two finite numbers"),
            "{err}"
        );
        assert_eq!(d.recording(REC), None);
    }

    #[test]
    fn autosave_waits_for_a_pause_but_not_forever() {
        let dir = std::env::temp_dir().join(format!("pushlab-labels-auto-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let mut d = LabelDocument::open_set_folder(&dir).unwrap();
        d.save().unwrap();
        let mut auto = Autosave::default();
        assert!(auto.poll(&mut d, 0.0).is_none());
        d.apply(paint(STICKING, 0..1)).unwrap();
        assert!(auto.poll(&mut d, 0.1).is_none(), "too soon after the edit");
        assert!(auto.poll(&mut d, 0.7).unwrap().is_ok());
        assert!(!d.is_dirty());
        assert_eq!(file::read(d.path()).unwrap(), d.set().clone());
        // Painting every 0.1 s during playback: saved once max_delay has passed.
        let mut saved_at = None;
        for i in 0..80 {
            let t = 1.0 + 0.1 * f64::from(i);
            d.apply(paint(STICKING, 0..2 + i as usize)).unwrap();
            if auto.poll(&mut d, t).is_some() {
                saved_at = Some(t);
                break;
            }
        }
        let saved_at = saved_at.unwrap();
        assert!((5.9..6.2).contains(&saved_at), "saved at {saved_at}");
    }

    #[test]
    fn a_file_changed_by_another_program_is_not_overwritten_until_asked() {
        let dir = std::env::temp_dir().join(format!("pushlab-doc-conflict-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let path = super::super::file::path_in(&dir);
        let mut d = LabelDocument::open(&path).unwrap();
        d.apply(paint(STICKING, 0..10)).unwrap();
        d.save().unwrap();

        // Another program (`pushlab labels init-splits`, a text editor) writes the file.
        let mut theirs = d.set().clone();
        theirs.recordings.get_mut(REC).unwrap().meta.notes = "written elsewhere".into();
        super::super::file::write(&path, &theirs).unwrap();
        let on_disk = std::fs::read_to_string(&path).unwrap();

        d.apply(paint(SLIPPING, 20..30)).unwrap();
        let err = d.save().unwrap_err();
        assert!(matches!(err, LabelFileError::ChangedOnDisk { .. }), "{err}");
        assert!(err.to_string().contains("changed by another program"));
        assert!(d.has_conflict());
        assert!(matches!(d.save_state(), SaveState::Failed(_)));
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            on_disk,
            "their file is kept"
        );
        assert_eq!(segs(&d).len(), 2, "our edits are kept");

        // Reload takes their version; a later edit saves normally on top of it.
        let mut reloaded = d.clone();
        reloaded.reload().unwrap();
        assert_eq!(reloaded.set(), &theirs);
        assert!(!reloaded.has_conflict());
        reloaded.apply(paint(CONTACT, 40..50)).unwrap();
        reloaded.save().unwrap();

        // Or overwrite with ours (on the original document, whose file changed again meanwhile).
        d.overwrite().unwrap();
        assert!(!d.has_conflict());
        assert_eq!(d.save_state(), SaveState::Saved);
        assert_eq!(&super::super::file::read(&path).unwrap(), d.set());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
