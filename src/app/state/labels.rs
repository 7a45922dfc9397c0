//! Labeling in the app: one editable [`LabelDocument`] per labels file (one per recording folder),
//! the label chosen for in/out painting, the in point, the paint stroke of a held hotkey, and autosave.
//!
//! Every edit goes through a document's `apply`, so undo covers it by construction. A labels file
//! that exists but cannot be read is never overwritten: its recordings stay read-only, with the
//! reason shown, until the file is fixed and the folder opened again.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use pushlab_core::labels::pipeline::{frames_to_skip, key_of, labels_file_beside};
use pushlab_core::labels::{
    self, Autosave, LabelDocument, LabelKind, LabelSchema, RecordingLabels, SaveState,
};
use pushlab_core::recording::Recording;

use super::session::Session;

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
}

impl Labeling {
    /// Opens the labels file of every recording folder not seen yet. A folder opened again keeps
    /// its document, with its unsaved edits and undo history.
    pub fn sync(&mut self, session: &Session) {
        for (_, recording) in session.recordings() {
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
            | LabelAction::Undo
            | LabelAction::Redo
                if self.dragging =>
            {
                return Some("finish the drag first".into());
            }
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
    /// a message when a save failed.
    pub fn autosave(&mut self, now_s: f64) -> Option<String> {
        let mut failure = None;
        for (path, document) in &mut self.documents {
            let autosave = self.autosaves.entry(path.clone()).or_default();
            if let Some(Err(e)) = autosave.poll(document, now_s) {
                failure = Some(format!("labels not saved: {e}"));
            }
        }
        failure
    }

    /// Saves every document with unsaved edits; the message says what happened.
    pub fn save_all(&mut self) -> Option<String> {
        let mut saved = 0;
        let mut errors = Vec::new();
        for document in self.documents.values_mut() {
            match document.save_if_dirty() {
                Ok(true) => saved += 1,
                Ok(false) => {}
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
            format!("labels not saved: {}", errors.join("; "))
        })
    }

    /// Saves what can be saved when the app closes. Edits that cannot go to their labels file (it
    /// was changed by another program, or the disk refused) are written beside it to
    /// `pushlab-labels.unsaved-<seconds since 1970>.json`, so closing never loses them. Returns one
    /// line per file for the terminal.
    pub fn save_on_exit(&mut self) -> Vec<String> {
        let mut lines = Vec::new();
        for document in self.documents.values_mut() {
            if let Err(e) = document.save_if_dirty() {
                let stamp = std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0, |d| d.as_secs());
                let rescue = document
                    .path()
                    .with_file_name(format!("pushlab-labels.unsaved-{stamp}.json"));
                lines.push(
                    match pushlab_core::labels::file::write(&rescue, document.set()) {
                        Ok(()) => format!(
                            "{e}\nyour unsaved labels were written to {}",
                            rescue.display()
                        ),
                        Err(rescue_error) => {
                            format!("{e}\nand they could not be rescued: {rescue_error}")
                        }
                    },
                );
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
mod tests {
    #![allow(clippy::unwrap_used)]

    use std::path::PathBuf;

    use pushlab_core::labels::{LABELS_FILE_NAME, Split};

    use super::*;
    use crate::app::state::models::Models;
    use crate::app::state::timeline::TimelineCommand;
    use crate::app::state::{AppState, Command, Persisted};

    /// A private copy of one sample-data set, so tests never write into the repository.
    fn copy_of_sample_set(test: &str) -> Option<PathBuf> {
        let source = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("sample-data")
            .join("box1-paper-center-front");
        if !source.is_dir() {
            eprintln!("skipped: {} is missing", source.display());
            return None;
        }
        let dir =
            std::env::temp_dir().join(format!("pushlab-labels-{test}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        for entry in std::fs::read_dir(&source).unwrap() {
            let entry = entry.unwrap();
            std::fs::copy(entry.path(), dir.join(entry.file_name())).unwrap();
        }
        Some(dir)
    }

    fn state_on(dir: &std::path::Path) -> AppState {
        let mut state = AppState::new(Persisted::default(), Models::default());
        state.open_blocking(&[dir.to_path_buf()]);
        assert!(state.recording().is_some(), "{:?}", state.session.problems);
        state
    }

    fn label(state: &mut AppState, action: LabelAction) {
        state.apply(Command::Label(action));
    }

    fn seek(state: &mut AppState, frame: usize) {
        state.apply(Command::Timeline(TimelineCommand::SeekTo(frame)));
    }

    /// Paints `label` over `first..=last` with the in and out points, as a user would.
    fn paint_frames(state: &mut AppState, label_name: &str, first: usize, last: usize) {
        seek(state, first);
        label(state, LabelAction::SetInPoint);
        seek(state, last);
        label(state, LabelAction::SetActive(label_name.into()));
        label(state, LabelAction::PaintFromInPoint);
    }

    /// Forgets what was learned and steps over the first `frames` frames with "Learn while
    /// playing" on (the default), so that each of them is learned from.
    fn learn_from_start(state: &mut AppState, frames: usize) {
        seek(state, 0);
        state.apply(Command::ResetTheta);
        for _ in 0..frames {
            state.apply(Command::Timeline(TimelineCommand::Step(1)));
        }
    }

    fn segments(state: &AppState) -> Vec<(String, std::ops::Range<usize>)> {
        let target = state.label_target().unwrap();
        state
            .labels
            .labels_of(&target)
            .map(|l| {
                l.segments
                    .iter()
                    .map(|s| (s.label.clone(), s.frames()))
                    .collect()
            })
            .unwrap_or_default()
    }

    #[test]
    fn a_held_hotkey_paints_every_frame_passed_as_one_undo_step() {
        let Some(dir) = copy_of_sample_set("stroke") else {
            return;
        };
        let mut state = state_on(&dir);
        seek(&mut state, 5);
        label(&mut state, LabelAction::Hotkey("contact".into()));
        for _ in 0..3 {
            state.apply(Command::Timeline(TimelineCommand::Step(1)));
        }
        // Stepping back inside the stroke keeps what was painted.
        state.apply(Command::Timeline(TimelineCommand::Step(-1)));
        label(&mut state, LabelAction::EndStroke);
        assert_eq!(segments(&state), vec![("contact".to_owned(), 5..9)]);
        assert_eq!(state.labels.active.as_deref(), Some("contact"));
        label(&mut state, LabelAction::Undo);
        assert_eq!(segments(&state), vec![]);
        assert!(
            state
                .status
                .as_deref()
                .unwrap()
                .contains("paint \"contact\"")
        );
        label(&mut state, LabelAction::Redo);
        assert_eq!(segments(&state), vec![("contact".to_owned(), 5..9)]);
    }

    #[test]
    fn painting_an_exclusive_label_cuts_the_other_and_erase_clears_frames() {
        let Some(dir) = copy_of_sample_set("exclusive") else {
            return;
        };
        let mut state = state_on(&dir);
        seek(&mut state, 10);
        label(&mut state, LabelAction::SetInPoint);
        seek(&mut state, 19);
        label(&mut state, LabelAction::SetActive("sticking".into()));
        label(&mut state, LabelAction::PaintFromInPoint);
        assert_eq!(segments(&state), vec![("sticking".to_owned(), 10..20)]);
        assert_eq!(state.labels.in_point, None);
        // Slipping over 15..=16 splits sticking in two.
        seek(&mut state, 15);
        label(&mut state, LabelAction::Hotkey("slipping".into()));
        seek(&mut state, 16);
        label(&mut state, LabelAction::EndStroke);
        assert_eq!(
            segments(&state),
            vec![
                ("sticking".to_owned(), 10..15),
                ("slipping".to_owned(), 15..17),
                ("sticking".to_owned(), 17..20)
            ]
        );
        // Delete held from 12 back to 11 erases both frames of every label.
        seek(&mut state, 12);
        label(&mut state, LabelAction::StartErase);
        state.apply(Command::Timeline(TimelineCommand::Step(-1)));
        label(&mut state, LabelAction::EndStroke);
        assert_eq!(
            segments(&state),
            vec![
                ("sticking".to_owned(), 10..11),
                ("sticking".to_owned(), 13..15),
                ("slipping".to_owned(), 15..17),
                ("sticking".to_owned(), 17..20)
            ]
        );
    }

    #[test]
    fn out_point_without_in_point_or_label_says_what_is_missing() {
        let Some(dir) = copy_of_sample_set("inout") else {
            return;
        };
        let mut state = state_on(&dir);
        label(&mut state, LabelAction::PaintFromInPoint);
        assert!(state.status.as_deref().unwrap().contains("range label"));
        label(&mut state, LabelAction::SetActive("contact".into()));
        label(&mut state, LabelAction::PaintFromInPoint);
        assert!(state.status.as_deref().unwrap().contains("in point"));
        assert_eq!(segments(&state), vec![]);
    }

    #[test]
    fn an_event_hotkey_toggles_its_event_and_label_keys_jump_between_boundaries() {
        let Some(dir) = copy_of_sample_set("events") else {
            return;
        };
        let mut state = state_on(&dir);
        seek(&mut state, 7);
        label(&mut state, LabelAction::Hotkey("contact made".into()));
        let target = state.label_target().unwrap();
        let events = |s: &AppState| {
            s.labels
                .labels_of(&target)
                .map(|l| l.events.iter().map(|e| e.frame).collect::<Vec<_>>())
                .unwrap_or_default()
        };
        assert_eq!(events(&state), vec![7]);
        paint_frames(&mut state, "contact", 20, 30);
        seek(&mut state, 0);
        let mut visited = Vec::new();
        for _ in 0..4 {
            state.apply(Command::JumpToLabel { forward: true });
            visited.push(state.frame());
        }
        assert_eq!(visited, vec![7, 20, 30, 30]);
        assert!(
            state
                .status
                .as_deref()
                .unwrap()
                .contains("no label after frame 30")
        );
        state.apply(Command::JumpToLabel { forward: false });
        assert_eq!(state.frame(), 20);
        seek(&mut state, 7);
        label(&mut state, LabelAction::Hotkey("contact made".into()));
        assert_eq!(events(&state), Vec::<usize>::new());
    }

    #[test]
    fn autosave_writes_the_file_after_a_quiet_half_second() {
        let Some(dir) = copy_of_sample_set("autosave") else {
            return;
        };
        let file = dir.join(LABELS_FILE_NAME);
        let before = std::fs::read_to_string(&file).unwrap();
        let mut state = state_on(&dir);
        let target = state.label_target().unwrap();
        label(&mut state, LabelAction::Hotkey("bad tracking".into()));
        label(&mut state, LabelAction::EndStroke);
        assert_eq!(state.labels.save_state(&target), Some(SaveState::Unsaved));
        state.autosave_labels(10.0);
        assert_eq!(
            std::fs::read_to_string(&file).unwrap(),
            before,
            "saved too early"
        );
        state.autosave_labels(10.6);
        assert_eq!(state.labels.save_state(&target), Some(SaveState::Saved));
        let saved = pushlab_core::labels::file::read(&file).unwrap();
        let labels = saved.recording(&target.recording).unwrap();
        assert_eq!(labels.segments.len(), 1);
        assert_eq!(labels.segments[0].label, "bad tracking");
        // What was there before is kept.
        assert_eq!(saved.split_of(&target.recording), Some(Split::Offline));
    }

    #[test]
    fn an_unreadable_labels_file_is_never_overwritten() {
        let Some(dir) = copy_of_sample_set("unreadable") else {
            return;
        };
        let file = dir.join(LABELS_FILE_NAME);
        std::fs::write(&file, "{ \"format\": \"pushlab-labels\", \"version\": 1, ").unwrap();
        let mut state = state_on(&dir);
        let target = state.label_target().unwrap();
        let reason = state.labels.read_only_reason(&target).unwrap().to_owned();
        assert!(reason.contains(LABELS_FILE_NAME), "{reason}");
        label(&mut state, LabelAction::Hotkey("contact".into()));
        assert!(state.status.as_deref().unwrap().contains("read-only"));
        label(&mut state, LabelAction::SaveAll);
        state.autosave_labels(100.0);
        assert_eq!(
            std::fs::read_to_string(&file).unwrap(),
            "{ \"format\": \"pushlab-labels\", \"version\": 1, "
        );
        // Fixed on disk and opened again: labeling works.
        std::fs::remove_file(&file).unwrap();
        state.open_blocking(std::slice::from_ref(&dir));
        assert_eq!(state.labels.read_only_reason(&target), None);
        label(&mut state, LabelAction::Hotkey("contact".into()));
        label(&mut state, LabelAction::EndStroke);
        assert_eq!(segments(&state).len(), 1);
    }

    #[test]
    fn training_chooses_the_offline_split_and_leaves_out_bad_tracking() {
        let Some(dir) = copy_of_sample_set("training") else {
            return;
        };
        let mut state = state_on(&dir);
        state.apply(Command::ChooseOfflineLabelled);
        let chosen: Vec<String> = state
            .training
            .chosen
            .iter()
            .map(|&id| state.session.get(id).unwrap().name.clone())
            .collect();
        assert_eq!(chosen.len(), 27, "{chosen:?}");
        assert!(chosen.iter().all(|n| n.starts_with("offline_")));
        assert!(state.status.as_deref().unwrap().contains("27"));
        // Relabel the first offline push as held out: it leaves the choice.
        let target = state.label_target().unwrap();
        label(
            &mut state,
            LabelAction::Edit(pushlab_core::labels::Command::SetMeta {
                recording: target.recording.clone(),
                field: pushlab_core::labels::MetaField::Split(Some(Split::HeldOut)),
            }),
        );
        state.apply(Command::ChooseOfflineLabelled);
        assert_eq!(state.training.chosen.len(), 26);

        // Bad tracking over frames 10..=14 of the selected push removes every sample touching them.
        let selected = state.session.selected.unwrap();
        state.training.chosen = [selected].into_iter().collect();
        state.training.config.horizon = 2;
        let samples = |state: &AppState| state.training_recordings()[0].samples(2);
        let all = samples(&state).len();
        paint_frames(&mut state, "bad tracking", 10, 14);
        let kept: Vec<usize> = samples(&state).iter().map(|s| s.frame).collect();
        // Samples start at 8..=14 touch a skipped frame (start or start + 2).
        assert_eq!(kept.len(), all - 7);
        assert!(kept.iter().all(|&f| !(8..=14).contains(&f)), "{kept:?}");
    }

    #[test]
    fn losses_by_label_average_online_and_fixed_over_the_same_learned_frames() {
        let Some(dir) = copy_of_sample_set("losses") else {
            return;
        };
        let mut state = state_on(&dir);
        paint_frames(&mut state, "sticking", 20, 29);
        learn_from_start(&mut state, 40);
        let rows = state.loss_by_label();
        assert_eq!(rows[0].label, "all");
        assert_eq!(rows[0].frames, 40);
        let sticking = rows.iter().find(|r| r.label == "sticking").unwrap();
        assert_eq!(sticking.frames, 10);
        let run = state.run.as_ref().unwrap();
        let mean = |f: &dyn Fn(usize) -> f64| (20..30).map(f).sum::<f64>() / 10.0;
        let online_pos = mean(&|k| f64::from(run.learned()[k].unwrap().pos));
        let fixed_rot = mean(&|k| f64::from(run.fixed()[k].rot));
        assert!((sticking.online_pos - online_pos).abs() < 1e-12);
        assert!((sticking.fixed_rot - fixed_rot).abs() < 1e-12);
        assert_ne!(sticking.online_pos, sticking.fixed_pos);
    }

    #[test]
    fn a_stroke_paints_while_playing() {
        let Some(dir) = copy_of_sample_set("playing") else {
            return;
        };
        let mut state = state_on(&dir);
        seek(&mut state, 3);
        label(&mut state, LabelAction::Hotkey("slipping".into()));
        state.apply(Command::Timeline(TimelineCommand::TogglePlay));
        // The sample data runs at 10 Hz: a second of playback passes ten frames.
        for _ in 0..20 {
            state.advance(0.05);
        }
        state.apply(Command::Timeline(TimelineCommand::TogglePlay));
        label(&mut state, LabelAction::EndStroke);
        let end = state.frame();
        assert!((12..=14).contains(&end), "stopped at {end}");
        assert_eq!(segments(&state), vec![("slipping".to_owned(), 3..end + 1)]);
        label(&mut state, LabelAction::Undo);
        assert_eq!(
            segments(&state),
            vec![],
            "the whole stroke is one undo step"
        );
    }

    #[test]
    fn online_learning_holds_theta_over_bad_tracking_and_says_why() {
        let Some(dir) = copy_of_sample_set("badtracking") else {
            return;
        };
        let mut state = state_on(&dir);
        paint_frames(&mut state, "bad tracking", 30, 34);
        learn_from_start(&mut state, 60);
        let skip = state.frames_to_skip();
        let run = state.run.as_ref().unwrap();
        let mut held = 0;
        for k in 0..60 {
            if run.is_skipped(k, &skip) {
                held += 1;
                assert!(run.learned()[k].is_none(), "learned from frame {k}");
                assert_eq!(run.checkpoints()[k + 1], run.checkpoints()[k]);
            } else {
                assert!(run.learned()[k].is_some(), "frame {k} not learned");
            }
        }
        // Frames 30..=34 and the samples ending on them (the model's horizon before).
        assert!(held >= 5, "{held} frames held");
        seek(&mut state, 32);
        state.apply(Command::LearnThisFrame);
        assert!(state.status.as_deref().unwrap().contains("bad tracking"));
    }

    #[test]
    fn labels_changed_by_another_program_are_kept_and_ours_are_rescued_on_exit() {
        let Some(dir) = copy_of_sample_set("conflict") else {
            return;
        };
        let file = dir.join(LABELS_FILE_NAME);
        let mut state = state_on(&dir);
        let target = state.label_target().unwrap();
        label(&mut state, LabelAction::Hotkey("contact".into()));
        label(&mut state, LabelAction::EndStroke);
        // `pushlab labels init-splits` or an editor rewrites the file meanwhile.
        let theirs = std::fs::read_to_string(&file)
            .unwrap()
            .replace("\"paper\"", "\"cardboard\"");
        std::fs::write(&file, &theirs).unwrap();
        state.autosave_labels(1.0);
        state.autosave_labels(2.0);
        assert!(
            state
                .status
                .as_deref()
                .unwrap()
                .contains("changed by another program")
        );
        assert_eq!(std::fs::read_to_string(&file).unwrap(), theirs);
        assert!(
            state
                .labels
                .document(&target.document)
                .unwrap()
                .has_conflict()
        );

        let lines = state.labels.save_on_exit();
        assert_eq!(lines.len(), 1);
        assert!(lines[0].contains("pushlab-labels.unsaved-"), "{}", lines[0]);
        assert_eq!(
            std::fs::read_to_string(&file).unwrap(),
            theirs,
            "theirs untouched"
        );
        let rescued = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .find(|p| p.to_string_lossy().contains("unsaved-"))
            .expect("a rescue file");
        let rescued = pushlab_core::labels::file::read(&rescued).unwrap();
        assert_eq!(
            rescued.recording(&target.recording).unwrap().segments.len(),
            1
        );

        // Reload takes their version.
        label(&mut state, LabelAction::Reload);
        let meta = &state.labels.labels_of(&target).unwrap().meta;
        assert_eq!(meta.material, "cardboard");
        assert!(segments(&state).is_empty());
        // Or, after another edit and conflict, overwrite with ours.
        std::fs::write(&file, theirs.replace("cardboard", "felt")).unwrap();
        label(&mut state, LabelAction::Hotkey("sticking".into()));
        label(&mut state, LabelAction::EndStroke);
        label(&mut state, LabelAction::SaveAll);
        assert!(
            state
                .status
                .as_deref()
                .unwrap()
                .contains("changed by another program")
        );
        label(&mut state, LabelAction::Overwrite);
        let on_disk = pushlab_core::labels::file::read(&file).unwrap();
        assert_eq!(
            on_disk.recording(&target.recording).unwrap().meta.material,
            "cardboard"
        );
        assert_eq!(
            on_disk.recording(&target.recording).unwrap().segments.len(),
            1
        );
    }

    #[test]
    fn a_stroke_paints_what_was_shown_not_what_a_seek_or_a_loop_jumped_over() {
        let Some(dir) = copy_of_sample_set("jumps") else {
            return;
        };
        let mut state = state_on(&dir);
        let last = state.timeline.last_frame();
        // A seek during a stroke paints where it lands, not the frames between.
        seek(&mut state, 10);
        label(&mut state, LabelAction::Hotkey("contact".into()));
        seek(&mut state, 50);
        state.apply(Command::Timeline(TimelineCommand::Step(1)));
        label(&mut state, LabelAction::EndStroke);
        assert_eq!(
            segments(&state),
            vec![
                ("contact".to_owned(), 10..11),
                ("contact".to_owned(), 50..52)
            ]
        );
        // Looping playback that wraps around paints the end and the start, not everything.
        state.apply(Command::Timeline(TimelineCommand::SetLoop(true)));
        seek(&mut state, last - 2);
        label(&mut state, LabelAction::Hotkey("slipping".into()));
        state.apply(Command::Timeline(TimelineCommand::TogglePlay));
        while state.frame() >= last - 2 || state.frame() < 2 {
            state.advance(0.05);
        }
        state.apply(Command::Timeline(TimelineCommand::TogglePlay));
        label(&mut state, LabelAction::EndStroke);
        let now = state.frame();
        let slipping: Vec<_> = segments(&state)
            .into_iter()
            .filter(|(l, _)| l == "slipping")
            .map(|(_, r)| r)
            .collect();
        assert_eq!(slipping, vec![0..now + 1, last - 2..last + 1]);
    }

    #[test]
    fn a_drag_ends_a_stroke_and_each_is_one_undo_step() {
        let Some(dir) = copy_of_sample_set("overlap") else {
            return;
        };
        let mut state = state_on(&dir);
        let target = state.label_target().unwrap();
        seek(&mut state, 5);
        label(&mut state, LabelAction::Hotkey("contact".into()));
        state.apply(Command::Timeline(TimelineCommand::Step(2)));
        // A drag of the COM label starts while the key is still down.
        label(
            &mut state,
            LabelAction::BeginGroup("move the COM label".into()),
        );
        assert_eq!(state.labels.stroke_hotkey(), None, "the stroke ended");
        for x in [0.01, 0.02] {
            label(
                &mut state,
                LabelAction::Edit(pushlab_core::labels::Command::SetMeta {
                    recording: target.recording.clone(),
                    field: pushlab_core::labels::MetaField::ComOffset(Some([x, 0.0])),
                }),
            );
        }
        label(&mut state, LabelAction::Hotkey("sticking".into()));
        assert!(state.status.as_deref().unwrap().contains("finish the drag"));
        label(&mut state, LabelAction::Undo);
        assert!(state.status.as_deref().unwrap().contains("finish the drag"));
        label(&mut state, LabelAction::EndGroup);
        label(&mut state, LabelAction::EndStroke);
        label(&mut state, LabelAction::Undo);
        assert!(
            state
                .status
                .as_deref()
                .unwrap()
                .contains("move the COM label")
        );
        label(&mut state, LabelAction::Undo);
        assert!(
            state
                .status
                .as_deref()
                .unwrap()
                .contains("paint \"contact\"")
        );
        assert!(segments(&state).is_empty());
    }

    #[test]
    fn a_new_model_keeps_the_stroke_the_in_point_and_playback() {
        let Some(dir) = copy_of_sample_set("restart") else {
            return;
        };
        let mut state = state_on(&dir);
        seek(&mut state, 4);
        label(&mut state, LabelAction::SetInPoint);
        label(&mut state, LabelAction::Hotkey("contact".into()));
        state.apply(Command::Timeline(TimelineCommand::TogglePlay));
        // What a finished training run or a loaded model does.
        state.restart_run_keeping_frame();
        assert_eq!(state.frame(), 4);
        assert!(state.timeline.playing);
        assert_eq!(state.labels.in_point, Some(4));
        assert_eq!(state.labels.stroke_hotkey(), Some("1"));
        state.apply(Command::Timeline(TimelineCommand::Step(2)));
        label(&mut state, LabelAction::EndStroke);
        assert_eq!(segments(&state), vec![("contact".to_owned(), 4..7)]);
    }
}
