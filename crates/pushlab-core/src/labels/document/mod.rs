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

use std::path::{Path, PathBuf};

use super::file::{self, LabelFileError};
use super::schema::{LabelKind, LabelSchema};
use super::segments::{self, Event};
use super::{LabelSet, RecordingLabels, check_label};

mod autosave;
mod command;
mod history;

pub use self::autosave::Autosave;
pub use self::command::{Command, EditError};
use self::history::{Change, Step};

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

#[cfg(test)]
mod tests;
