//! Labeling in the app: one editable [`LabelDocument`] per labels file (one per recording folder),
//! the label chosen for in/out painting, the in point, the paint stroke of a held hotkey, and autosave.
//!
//! Every edit goes through a document's `apply`, so undo covers it by construction. A labels file
//! that exists but cannot be read is never overwritten: its recordings stay read-only, with the
//! reason shown, until the file is fixed and the folder opened again. A folder that cannot be
//! written (a dataset checkout, a read-only share) still opens and can be labelled: the labels stay
//! in memory, and the status says where they go instead — the app's own folder for unsaved labels,
//! on Ctrl+S and when the app closes.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use pushlab_core::labels::LabelFileError;
use pushlab_core::labels::pipeline::{frames_to_skip, key_of, labels_file_beside};
use pushlab_core::labels::{
    self, Autosave, LabelDocument, LabelKind, LabelSchema, RecordingLabels, SaveState,
};
use pushlab_core::recording::Recording;

use crate::app::platform;

/// Where the labels of one recording live: its labels file and its key in that file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LabelTarget {
    /// The labels file beside the recording (`pushlab-labels.json`).
    pub document: PathBuf,
    /// The recording's key in that file (its file name).
    pub recording: String,
    /// Number of frames of the recording; edits are clamped to it.
    pub frames: usize,
}

impl LabelTarget {
    /// The target of a loaded recording.
    pub fn of(recording: &Recording) -> Option<Self> {
        Some(Self {
            document: labels_file_beside(&recording.source),
            recording: key_of(&recording.source)?,
            frames: recording.trajectory.len(),
        })
    }
}

/// Everything the labeling UI can ask for. Frame-based actions act at the frame shown.
#[derive(Clone, Debug, PartialEq)]
pub enum LabelAction {
    /// A label's hotkey went down: a range label starts a paint stroke at this frame (one undo step
    /// until [`LabelAction::EndStroke`]); an event label toggles its event at this frame.
    Hotkey(String),
    /// The erase key went down: erases every range label at this frame and wherever the frame moves
    /// until [`LabelAction::EndStroke`].
    StartErase,
    /// The held key was released.
    EndStroke,
    /// Chooses the range label that in/out painting uses.
    SetActive(String),
    /// Marks the in point at this frame.
    SetInPoint,
    /// Forgets the in point.
    ClearInPoint,
    /// Paints the active label from the in point to this frame, both included, and clears the in point.
    PaintFromInPoint,
    /// Any edit of the selected recording's labels file (metadata form, delete buttons, revert).
    Edit(labels::Command),
    /// Several edits as one undo step named `description` (accepting label proposals).
    EditAll {
        description: String,
        commands: Vec<labels::Command>,
    },
    /// Starts one undo step for many edits (dragging the COM label).
    BeginGroup(String),
    /// Ends it.
    EndGroup,
    /// The metadata text box lost focus: the next typing is a new undo step.
    Seal,
    Undo,
    Redo,
    /// Saves every labels file with unsaved edits now.
    SaveAll,
    /// The selected recording's labels file was changed by another program: write ours over it.
    Overwrite,
    /// The selected recording's labels file was changed by another program: take theirs, dropping
    /// our unsaved edits.
    Reload,
}

/// A paint or erase stroke in progress: a hotkey is held while frames go by.
#[derive(Clone, Debug, PartialEq)]
struct Stroke {
    target: LabelTarget,
    /// The label painted, `None` when erasing.
    label: Option<String>,
    /// The last frame painted.
    last: usize,
    /// The schema hotkey held, so the keyboard handler knows which key ends the stroke.
    hotkey: String,
}

/// The key that erases while held. It wins over a label given the same hotkey (the cheat-sheet marks
/// such a label as taken).
pub const ERASE_HOTKEY: &str = "Delete";

/// The labeling state of the app.
#[derive(Default)]
pub struct Labeling {
    documents: BTreeMap<PathBuf, LabelDocument>,
    autosaves: BTreeMap<PathBuf, Autosave>,
    /// Labels files that exist but could not be read, with the reason. Their recordings are
    /// read-only so that the file is never overwritten.
    pub unreadable: BTreeMap<PathBuf, String>,
    /// The range label used by in/out painting.
    pub active: Option<String>,
    /// In point on the selected recording.
    pub in_point: Option<usize>,
    stroke: Option<Stroke>,
    /// A mouse drag (the COM label) is one undo step in progress; strokes wait until it ends, since
    /// a document has one open group at a time.
    dragging: bool,
    /// Where labels go whose own folder cannot be written (in the app's data folder, never in a
    /// user's data); `None`: nowhere but beside the labels file.
    pub rescue_dir: Option<PathBuf>,
}

impl Labeling {
    /// Opens the labels file of every recording folder not seen yet. A folder opened again keeps
    /// its document, with its unsaved edits and undo history.
    pub fn sync<'a>(&mut self, recordings: impl IntoIterator<Item = &'a Recording>) {
        for recording in recordings {
            let path = labels_file_beside(&recording.source);
            if self.documents.contains_key(&path) || self.unreadable.contains_key(&path) {
                continue;
            }
            match LabelDocument::open(&path) {
                Ok(document) => {
                    self.autosaves.insert(path.clone(), Autosave::default());
                    self.documents.insert(path, document);
                }
                Err(e) => {
                    self.unreadable.insert(path, e.to_string());
                }
            }
        }
    }

    /// The document at `path`, if it is open.
    pub fn document(&self, path: &Path) -> Option<&LabelDocument> {
        self.documents.get(path)
    }

    /// What changes whenever a labels file is opened or any open one is edited, undone or redone:
    /// each open file's content id, in the files' order (a file is opened once and never closed,
    /// so one more id is one more file). What views computed from the labels (the browser's rows)
    /// are kept by.
    pub fn contents_key(&self) -> Vec<u64> {
        self.documents
            .values()
            .map(LabelDocument::state_id)
            .collect()
    }

    /// One flag per frame of a target: labelled "skip in training" (bad tracking). All false when
    /// its labels file is not open.
    pub fn frames_to_skip(&self, target: &LabelTarget) -> Vec<bool> {
        self.document(&target.document)
            .map(|d| frames_to_skip(d.set(), &target.recording, target.frames))
            .unwrap_or_default()
    }

    /// The labels of a target, `None` when it has none (or its file is unreadable).
    pub fn labels_of(&self, target: &LabelTarget) -> Option<&RecordingLabels> {
        self.document(&target.document)?
            .recording(&target.recording)
    }

    /// The schema that applies to a target (the default schema while its file is unreadable).
    pub fn schema_of(&self, target: &LabelTarget) -> Option<&LabelSchema> {
        self.document(&target.document).map(LabelDocument::schema)
    }

    /// Why a target cannot be labelled, if it cannot.
    pub fn read_only_reason(&self, target: &LabelTarget) -> Option<&str> {
        self.unreadable.get(&target.document).map(String::as_str)
    }

    /// The hotkey held for the current stroke, so the keyboard handler can end it on release.
    pub fn stroke_hotkey(&self) -> Option<&str> {
        self.stroke.as_ref().map(|s| s.hotkey.as_str())
    }

    /// What the "saved" indicator shows for the labels file of `target`.
    pub fn save_state(&self, target: &LabelTarget) -> Option<SaveState> {
        self.document(&target.document)
            .map(LabelDocument::save_state)
    }

    /// Whether any labels file has edits not yet on disk (the app then keeps waking up to autosave).
    pub fn any_unsaved(&self) -> bool {
        self.documents.values().any(LabelDocument::is_dirty)
    }

    /// Applies an action at `frame` of `target`. Returns a message for the status bar when there is
    /// something to tell (what undo undid, why an edit was refused).
    pub fn apply(
        &mut self,
        target: Option<&LabelTarget>,
        frame: usize,
        action: LabelAction,
    ) -> Option<String> {
        match action {
            LabelAction::SaveAll => return self.save_all(),
            LabelAction::SetActive(label) => {
                self.active = Some(label);
                return None;
            }
            LabelAction::EndStroke => {
                self.end_stroke();
                return None;
            }
            _ => {}
        }
        let target = target?;
        if let Some(reason) = self.read_only_reason(target) {
            return Some(format!("labels are read-only here: {reason}"));
        }
        let frame = frame.min(target.frames.saturating_sub(1));
        let recording = target.recording.clone();
        match action {
            LabelAction::Hotkey(_)
            | LabelAction::StartErase
            | LabelAction::EditAll { .. }
            | LabelAction::Undo
            | LabelAction::Redo
                if self.dragging =>
            {
                return Some("finish the drag first".into());
            }
            // A stroke in progress is its own undo step: it ends first.
            LabelAction::EditAll { .. } => self.end_stroke(),
            LabelAction::BeginGroup(_) => {
                // One undo step for the drag: a stroke in progress ends first.
                self.end_stroke();
                self.dragging = true;
            }
            LabelAction::EndGroup | LabelAction::Reload => {
                self.dragging = false;
            }
            _ => {}
        }
        match action {
            LabelAction::Hotkey(label) => {
                let schema = self.schema_of(target)?;
                let definition = schema.get(&label)?;
                let hotkey = definition.hotkey.clone().unwrap_or_default();
                if definition.kind == LabelKind::Range {
                    self.active = Some(label.clone());
                    self.start_stroke(target, Some(label), frame, hotkey);
                    return None;
                }
                let present = self.labels_of(target).is_some_and(|r| {
                    r.events
                        .iter()
                        .any(|e| e.frame == frame && e.label == label)
                });
                let command = if present {
                    labels::Command::RemoveEvent {
                        recording,
                        label,
                        frame,
                    }
                } else {
                    labels::Command::AddEvent {
                        recording,
                        label,
                        frame,
                    }
                };
                return edit(self.documents.get_mut(&target.document)?, command);
            }
            LabelAction::StartErase => {
                self.start_stroke(target, None, frame, ERASE_HOTKEY.to_owned());
                return None;
            }
            _ => {}
        }
        let document = self.documents.get_mut(&target.document)?;
        match action {
            LabelAction::SetInPoint => {
                self.in_point = Some(frame);
                None
            }
            LabelAction::ClearInPoint => {
                self.in_point = None;
                None
            }
            LabelAction::PaintFromInPoint => {
                let Some(label) = self.active.clone() else {
                    return Some(
                        "choose a range label first (its hotkey or the Labels tab)".into(),
                    );
                };
                let Some(start) = self.in_point.take() else {
                    return Some("set an in point first (I)".into());
                };
                let frames = start.min(frame)..start.max(frame) + 1;
                edit(
                    document,
                    labels::Command::Paint {
                        recording,
                        label,
                        frames,
                    },
                )
            }
            LabelAction::Edit(command) => edit(document, command),
            LabelAction::EditAll {
                description,
                commands,
            } => {
                document.begin_group(&description);
                let refused: Vec<String> = commands
                    .into_iter()
                    .filter_map(|c| edit(document, c))
                    .collect();
                document.end_group();
                refused.into_iter().next()
            }
            LabelAction::BeginGroup(description) => {
                document.begin_group(&description);
                None
            }
            LabelAction::EndGroup => {
                document.end_group();
                None
            }
            LabelAction::Seal => {
                document.seal();
                None
            }
            LabelAction::Overwrite => Some(match document.overwrite() {
                Ok(()) => format!("labels written over {}", target.document.display()),
                Err(e) => e.to_string(),
            }),
            LabelAction::Reload => {
                self.stroke = None;
                let message = match document.reload() {
                    Ok(()) => format!("labels reloaded from {}", target.document.display()),
                    Err(e) => e.to_string(),
                };
                // The reloaded document counts its edits afresh.
                self.autosaves
                    .insert(target.document.clone(), Autosave::default());
                Some(message)
            }
            LabelAction::Undo => {
                self.stroke = None;
                Some(match document.undo() {
                    Some(description) => format!("undid: {description}"),
                    None => "nothing to undo".to_owned(),
                })
            }
            LabelAction::Redo => {
                self.stroke = None;
                Some(match document.redo() {
                    Some(description) => format!("redid: {description}"),
                    None => "nothing to redo".to_owned(),
                })
            }
            LabelAction::Hotkey(_)
            | LabelAction::StartErase
            | LabelAction::SaveAll
            | LabelAction::SetActive(_)
            | LabelAction::EndStroke => None,
        }
    }

    /// Extends the stroke in progress to `frame` (called whenever the shown frame moves), painting
    /// every frame between.
    pub fn stroke_to(&mut self, frame: usize) {
        self.move_stroke(frame, true);
    }

    /// Moves the stroke in progress to `frame` without painting the frames between (a seek, a jump,
    /// a loop starting over): only `frame` itself is painted.
    pub fn stroke_jump(&mut self, frame: usize) {
        self.move_stroke(frame, false);
    }

    /// Paints the stroke's label (or erases) at `frame` and, when `passing`, at every frame since
    /// the last one painted.
    fn move_stroke(&mut self, frame: usize, passing: bool) {
        let Some(stroke) = &mut self.stroke else {
            return;
        };
        let frame = frame.min(stroke.target.frames.saturating_sub(1));
        let from = if passing { stroke.last } else { frame };
        stroke.last = frame;
        let command = stroke_command(stroke, from.min(frame)..from.max(frame) + 1);
        if let Some(document) = self.documents.get_mut(&stroke.target.document) {
            // The label exists (the stroke started with it), and painting a frame twice changes
            // nothing: there is nothing to report per frame.
            let _ = document.apply(command);
        }
    }

    /// Ends a stroke (the key was released, another recording was selected).
    pub fn end_stroke(&mut self) {
        if let Some(stroke) = self.stroke.take()
            && let Some(document) = self.documents.get_mut(&stroke.target.document)
        {
            document.end_group();
        }
    }

    /// Saves every document whose autosave is due at `now_s` (seconds on any steady clock). Returns
    /// a message when a save failed: for a folder that cannot be written, where the labels can go.
    pub fn autosave(&mut self, now_s: f64) -> Option<String> {
        let mut failure = None;
        for (path, document) in &mut self.documents {
            let autosave = self.autosaves.entry(path.clone()).or_default();
            if let Some(Err(e)) = autosave.poll(document, now_s) {
                failure = Some(match &e {
                    LabelFileError::Write { source, .. } => {
                        unwritable_message(path, source, self.rescue_dir.as_deref())
                    }
                    _ => format!("labels not saved: {e}"),
                });
            }
        }
        failure
    }

    /// Saves every document with unsaved edits; the message says what happened. Labels whose
    /// folder cannot be written go to the app's folder for unsaved labels, and the message says where.
    pub fn save_all(&mut self) -> Option<String> {
        let mut saved = 0;
        let mut errors = Vec::new();
        for document in self.documents.values_mut() {
            match document.save_if_dirty() {
                Ok(true) => saved += 1,
                Ok(false) => {}
                Err(LabelFileError::Write { source, .. }) => {
                    errors.push(match self.rescue_dir.as_deref() {
                        Some(dir) => match rescue(document, dir) {
                            Ok(to) => format!(
                                "{} cannot be written ({source}), so its labels were saved to {}",
                                folder_of(document.path()).display(),
                                to.display()
                            ),
                            Err(e) => format!("{e}"),
                        },
                        None => unwritable_message(document.path(), &source, None),
                    });
                }
                Err(e) => errors.push(e.to_string()),
            }
        }
        Some(if errors.is_empty() {
            match saved {
                0 => "labels: nothing to save".to_owned(),
                1 => "labels saved".to_owned(),
                n => format!("labels saved ({n} files)"),
            }
        } else {
            format!("labels not saved in place: {}", errors.join("; "))
        })
    }

    /// Saves what can be saved when the app closes. Edits that cannot go to their labels file (it
    /// was changed by another program, or the disk refused) are written beside it to
    /// `pushlab-labels.unsaved-<seconds since 1970>.json`, or, when that folder cannot be written
    /// either, to the app's folder for unsaved labels, so closing never loses them. Returns one line
    /// per file for the terminal.
    pub fn save_on_exit(&mut self) -> Vec<String> {
        let mut lines = Vec::new();
        for document in self.documents.values_mut() {
            if let Err(e) = document.save_if_dirty() {
                let stamp = platform::SystemTime::now()
                    .duration_since(platform::UNIX_EPOCH)
                    .map_or(0, |d| d.as_secs());
                let beside = document
                    .path()
                    .with_file_name(format!("pushlab-labels.unsaved-{stamp}.json"));
                let rescued = pushlab_core::labels::file::write(&beside, document.set())
                    .map(|()| beside)
                    .or_else(|beside_error| match self.rescue_dir.as_deref() {
                        Some(dir) => rescue(document, dir),
                        None => Err(beside_error),
                    });
                lines.push(match rescued {
                    Ok(to) => format!("{e}\nyour unsaved labels were written to {}", to.display()),
                    Err(rescue_error) => {
                        format!("{e}\nand they could not be rescued: {rescue_error}")
                    }
                });
            }
        }
        lines
    }

    fn start_stroke(
        &mut self,
        target: &LabelTarget,
        label: Option<String>,
        frame: usize,
        hotkey: String,
    ) {
        self.end_stroke();
        let Some(document) = self.documents.get_mut(&target.document) else {
            return;
        };
        let description = match &label {
            Some(label) => format!("paint {label:?} on {}", target.recording),
            None => format!("erase labels on {}", target.recording),
        };
        document.begin_group(&description);
        self.stroke = Some(Stroke {
            target: target.clone(),
            label,
            last: frame,
            hotkey,
        });
        self.stroke_jump(frame);
    }
}

/// The folder a labels file is in.
fn folder_of(path: &Path) -> &Path {
    path.parent().unwrap_or(Path::new("."))
}

/// Where the labels of `document` go when its folder cannot be written: one file per folder in
/// `dir`, named after the folder (and a hash of its path, so that two folders of the same name
/// never share one).
pub fn rescue_path(document: &Path, dir: &Path) -> PathBuf {
    use std::hash::{Hash, Hasher};
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    document.hash(&mut hasher);
    let name = folder_of(document)
        .file_name()
        .map_or_else(|| "labels".into(), |n| n.to_string_lossy().into_owned());
    dir.join(format!("{name}-{:016x}.json", hasher.finish()))
}

/// Writes a document's labels to its [`rescue_path`] in `dir`.
fn rescue(document: &LabelDocument, dir: &Path) -> Result<PathBuf, LabelFileError> {
    let to = rescue_path(document.path(), dir);
    pushlab_core::files::create_dir_all(dir).map_err(|source| LabelFileError::Write {
        path: to.clone(),
        source,
    })?;
    pushlab_core::labels::file::write(&to, document.set())?;
    Ok(to)
}

/// The status when a folder cannot be written: the labels are in memory, and where they can go.
fn unwritable_message(
    document: &Path,
    error: &std::io::Error,
    rescue_dir: Option<&Path>,
) -> String {
    let folder = folder_of(document).display();
    match rescue_dir {
        Some(dir) => format!(
            "labels kept in memory: {folder} cannot be written ({error}); Ctrl+S (and closing pushlab) saves them to {}",
            rescue_path(document, dir).display()
        ),
        None => format!(
            "labels kept in memory: {folder} cannot be written ({error}); export them (Labels tab → Export labels as JSON…) or open a writable copy of the folder"
        ),
    }
}

/// Applies an edit; a refused edit becomes the status message.
fn edit(document: &mut LabelDocument, command: labels::Command) -> Option<String> {
    match document.apply(command) {
        Ok(_) => None,
        Err(e) => Some(e.to_string()),
    }
}

fn stroke_command(stroke: &Stroke, frames: std::ops::Range<usize>) -> labels::Command {
    let recording = stroke.target.recording.clone();
    match &stroke.label {
        Some(label) => labels::Command::Paint {
            recording,
            label: label.clone(),
            frames,
        },
        None => labels::Command::Erase {
            recording,
            label: None,
            frames,
        },
    }
}

#[cfg(test)]
pub(in crate::app::state) mod tests;
