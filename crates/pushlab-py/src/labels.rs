//! `pushlab.Labels`: a folder's labels file (`pushlab-labels.json`) opened as the core's
//! `LabelDocument`, the one the app's labels panel edits: every edit is a core `Command` with the
//! core's checks (known label, right kind, exclusive groups, valid metadata), and `save` is the
//! document's atomic save, which refuses to overwrite a file another program changed meanwhile.

use std::path::PathBuf;

use numpy::PyArray1;
use pushlab_core::labels::pipeline::key_names_a_recording_in;
use pushlab_core::labels::{
    Command, LabelDef, LabelDocument, LabelKind, MetaField, RecordingLabels, Split,
};
use pushlab_core::recording::PushSide;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{column, from_python, to_python};
use crate::error::error;
use crate::recording::Recording;

/// A recording set's labels file, opened for editing. Opening a folder without one starts from the
/// default schema; nothing is written until `save()`.
#[pyclass(module = "pushlab", name = "Labels")]
pub struct Labels {
    document: LabelDocument,
}

/// A recording named by its file name (`push_003.csv`) or given as a `Recording`.
fn recording_key(recording: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(r) = recording.cast::<Recording>() {
        return Ok(r.get().key());
    }
    recording.extract::<String>().map_err(|_| {
        PyValueError::new_err(
            "expected a Recording or a recording's file name (e.g. \"push_003.csv\")",
        )
    })
}

/// The recording's frame count when it is given as a `Recording`; a file name alone does not say.
fn known_frames(recording: &Bound<'_, PyAny>) -> Option<usize> {
    recording
        .cast::<Recording>()
        .ok()
        .map(|r| r.get().frame_count())
}

/// Frames `start..end` (end exclusive) of a paint or an erase; a reversed range is a mistake, not
/// nothing to do, and so is a range past the end of a recording whose length is known.
fn frame_range(
    recording: &Bound<'_, PyAny>,
    start: usize,
    end: usize,
) -> PyResult<std::ops::Range<usize>> {
    if start > end {
        return Err(PyValueError::new_err(format!(
            "frames {start}..{end}: start is after end (frames start..end, end exclusive)"
        )));
    }
    if let Some(count) = known_frames(recording)
        && end > count
    {
        return Err(PyValueError::new_err(format!(
            "frames {start}..{end}: {} has {count} frames, 0..{count} (end exclusive)",
            recording_key(recording)?
        )));
    }
    Ok(start..end)
}

/// An event's frame, refused past the end of a recording whose length is known.
fn event_frame(recording: &Bound<'_, PyAny>, frame: usize) -> PyResult<usize> {
    if let Some(count) = known_frames(recording)
        && frame >= count
    {
        return Err(PyValueError::new_err(format!(
            "frame {frame}: {} has {count} frames, 0 to {}",
            recording_key(recording)?,
            count.saturating_sub(1)
        )));
    }
    Ok(frame)
}

impl Labels {
    /// The key of a recording given as a `Recording`, or by a name that is in the folder or
    /// already labelled: a name that is neither is a typo, whose labels no recording would show.
    fn key(&self, recording: &Bound<'_, PyAny>) -> PyResult<String> {
        let key = recording_key(recording)?;
        if recording.cast::<Recording>().is_ok() || self.document.recording(&key).is_some() {
            return Ok(key);
        }
        let folder = (self.document.path().parent())
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(std::path::Path::new("."));
        if key_names_a_recording_in(folder, &key) {
            return Ok(key);
        }
        Err(PyValueError::new_err(format!(
            "{key:?}: no recording of that name in {} and none labelled so (name a file there, \
             e.g. \"push_003.csv\", or pass the Recording)",
            folder.display()
        )))
    }

    fn labels_of(&self, key: &str) -> RecordingLabels {
        self.document.recording(key).cloned().unwrap_or_default()
    }

    fn apply(&mut self, command: Command) -> PyResult<bool> {
        self.document.apply(command).map_err(error)
    }
}

#[pymethods]
impl Labels {
    /// Opens the labels file of the set folder `path` (or the labels file itself).
    #[new]
    fn new(path: PathBuf) -> PyResult<Self> {
        // A labels file not written yet is fine (a new one, saved into its folder); a folder that
        // is not there is a mistyped path, which would only fail at `save()`.
        let new_file_in_a_folder = path.extension().is_some_and(|e| e == "json")
            && path
                .parent()
                .is_some_and(|p| p.as_os_str().is_empty() || p.is_dir());
        if !path.exists() && !new_file_in_a_folder {
            return Err(error(format!(
                "{}: no such set folder (or labels file in an existing folder)",
                path.display()
            )));
        }
        let document = if path.is_dir() {
            LabelDocument::open_set_folder(&path)
        } else {
            LabelDocument::open(&path)
        };
        Ok(Self {
            document: document.map_err(error)?,
        })
    }

    /// The labels file this saves to.
    #[getter]
    fn path(&self) -> PathBuf {
        self.document.path().to_path_buf()
    }

    /// The schema: one dict per label (name, colour, hotkey, kind, group, skip_in_training).
    #[getter]
    fn schema<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.document.schema().labels)
    }

    /// Names of the recordings that carry any label or metadata, sorted.
    #[getter]
    fn recordings(&self) -> Vec<String> {
        self.document.set().recordings.keys().cloned().collect()
    }

    /// Whether there are edits not yet saved.
    #[getter]
    fn dirty(&self) -> bool {
        self.document.is_dirty()
    }

    /// The range segments of a recording as `(label, start, end)` (end exclusive), sorted by start.
    fn segments(&self, recording: &Bound<'_, PyAny>) -> PyResult<Vec<(String, usize, usize)>> {
        let labels = self.labels_of(&self.key(recording)?);
        Ok(labels
            .segments
            .iter()
            .map(|s| (s.label.clone(), s.start, s.end))
            .collect())
    }

    /// The point events of a recording as `(label, frame)`, in frame order.
    fn events(&self, recording: &Bound<'_, PyAny>) -> PyResult<Vec<(String, usize)>> {
        let labels = self.labels_of(&self.key(recording)?);
        Ok(labels
            .events
            .iter()
            .map(|e| (e.label.clone(), e.frame))
            .collect())
    }

    /// A recording's metadata as a dict (only the fields set).
    fn meta<'py>(
        &self,
        py: Python<'py>,
        recording: &Bound<'_, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.labels_of(&self.key(recording)?).meta)
    }

    /// The per-frame mask of one range label: True where it covers a frame, shape (frames,). With a
    /// `Recording`, `frames` defaults to its length.
    #[pyo3(signature = (recording, label, frames=None))]
    fn mask<'py>(
        &self,
        py: Python<'py>,
        recording: &Bound<'_, PyAny>,
        label: &str,
        frames: Option<usize>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let frames = frame_count(recording, frames)?;
        if self
            .document
            .schema()
            .get(label)
            .is_none_or(|l| l.kind != LabelKind::Range)
        {
            return Err(error(format!(
                "{label:?} is not a range label of the schema"
            )));
        }
        Ok(column(
            py,
            self.labels_of(&self.key(recording)?).mask(label, frames),
        ))
    }

    /// Per-frame masks of every range label of the schema, `{label: bool array (frames,)}`.
    #[pyo3(signature = (recording, frames=None))]
    fn masks<'py>(
        &self,
        py: Python<'py>,
        recording: &Bound<'_, PyAny>,
        frames: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let frames = frame_count(recording, frames)?;
        let labels = self.labels_of(&self.key(recording)?);
        let masks = PyDict::new(py);
        for def in self
            .document
            .schema()
            .labels
            .iter()
            .filter(|l| l.kind == LabelKind::Range)
        {
            masks.set_item(&def.name, column(py, labels.mask(&def.name, frames)))?;
        }
        Ok(masks)
    }

    /// Paints a range label over frames `start..end` (end exclusive), cutting the labels of its
    /// exclusive group there. Returns whether anything changed.
    fn paint(
        &mut self,
        recording: &Bound<'_, PyAny>,
        label: String,
        start: usize,
        end: usize,
    ) -> PyResult<bool> {
        let frames = frame_range(recording, start, end)?;
        let recording = self.key(recording)?;
        self.apply(Command::Paint {
            recording,
            label,
            frames,
        })
    }

    /// Removes one range label (every label with `label=None`) from frames `start..end`.
    #[pyo3(signature = (recording, start, end, label=None))]
    fn erase(
        &mut self,
        recording: &Bound<'_, PyAny>,
        start: usize,
        end: usize,
        label: Option<String>,
    ) -> PyResult<bool> {
        let frames = frame_range(recording, start, end)?;
        let recording = self.key(recording)?;
        self.apply(Command::Erase {
            recording,
            label,
            frames,
        })
    }

    /// Places a point event at a frame.
    fn add_event(
        &mut self,
        recording: &Bound<'_, PyAny>,
        label: String,
        frame: usize,
    ) -> PyResult<bool> {
        let frame = event_frame(recording, frame)?;
        let recording = self.key(recording)?;
        self.apply(Command::AddEvent {
            recording,
            label,
            frame,
        })
    }

    /// Removes a point event.
    fn remove_event(
        &mut self,
        recording: &Bound<'_, PyAny>,
        label: String,
        frame: usize,
    ) -> PyResult<bool> {
        let recording = self.key(recording)?;
        self.apply(Command::RemoveEvent {
            recording,
            label,
            frame,
        })
    }

    /// Sets one metadata field: `object`, `material`, `notes` (text), `com_offset` ((x, y) metres,
    /// object frame, or None), `push_side` ("front", "left", "back", "right" or None), `split`
    /// ("offline", "online", "held-out" or None).
    fn set_meta(
        &mut self,
        recording: &Bound<'_, PyAny>,
        field: &str,
        value: &Bound<'_, PyAny>,
    ) -> PyResult<bool> {
        let recording = self.key(recording)?;
        let text = || value.extract::<String>();
        let field = match field {
            "object" => MetaField::Object(text()?),
            "material" => MetaField::Material(text()?),
            "notes" => MetaField::Notes(text()?),
            "com_offset" => MetaField::ComOffset(value.extract()?),
            "push_side" => MetaField::PushSide(match value.extract::<Option<String>>()? {
                Some(name) => Some(name.parse::<PushSide>().map_err(error)?),
                None => None,
            }),
            "split" => MetaField::Split(match value.extract::<Option<String>>()? {
                Some(name) => Some(Split::from_name(&name).ok_or_else(|| {
                    error(format!(
                        "split: {name:?} is not a split, expected offline, online or held-out"
                    ))
                })?),
                None => None,
            }),
            other => {
                return Err(error(format!(
                    "{other:?} is not a metadata field, expected object, material, com_offset, push_side, split or notes"
                )));
            }
        };
        self.apply(Command::SetMeta { recording, field })
    }

    /// Removes every label and metadata field of a recording.
    fn clear(&mut self, recording: &Bound<'_, PyAny>) -> PyResult<bool> {
        let recording = self.key(recording)?;
        self.apply(Command::ClearRecording { recording })
    }

    /// Adds a label to the schema: `kind` "range" or "event", `colour` "#rrggbb", an exclusive
    /// `group`, a `hotkey` for the app, and whether its frames are left out of training.
    #[pyo3(signature = (name, *, kind="range", colour="#808080", group=None, hotkey=None, skip_in_training=false))]
    #[allow(clippy::too_many_arguments)] // Python's keyword arguments, one per field of a label
    fn add_label(
        &mut self,
        py: Python<'_>,
        name: &str,
        kind: &str,
        colour: &str,
        group: Option<&str>,
        hotkey: Option<&str>,
        skip_in_training: bool,
    ) -> PyResult<bool> {
        let spec = PyDict::new(py);
        spec.set_item("name", name)?;
        spec.set_item("kind", kind)?;
        spec.set_item("colour", colour)?;
        spec.set_item("group", group)?;
        spec.set_item("hotkey", hotkey)?;
        spec.set_item("skip_in_training", skip_in_training)?;
        let def: LabelDef = from_python(spec.as_any(), &format!("label {name:?}"))?;
        self.apply(Command::AddLabel(def))
    }

    /// Removes a label from the schema; refused while it is used unless `with_uses`.
    #[pyo3(signature = (name, *, with_uses=false))]
    fn remove_label(&mut self, name: String, with_uses: bool) -> PyResult<bool> {
        self.apply(Command::RemoveLabel { name, with_uses })
    }

    /// Renames a label everywhere it is used.
    fn rename_label(&mut self, old: String, new: String) -> PyResult<bool> {
        self.apply(Command::RenameLabel { from: old, to: new })
    }

    /// Writes the labels file atomically. Refuses (PushlabError) when another program changed the
    /// file since it was opened or last saved; `overwrite=True` writes anyway.
    #[pyo3(signature = (*, overwrite=false))]
    fn save(&mut self, overwrite: bool) -> PyResult<()> {
        let saved = if overwrite {
            self.document.overwrite()
        } else {
            self.document.save()
        };
        saved.map_err(error)
    }

    /// Reads the file again, dropping unsaved edits.
    fn reload(&mut self) -> PyResult<()> {
        self.document.reload().map_err(error)
    }

    fn __repr__(&self) -> String {
        format!(
            "<pushlab.Labels {} ({} recordings labelled{})>",
            self.document.path().display(),
            self.document.set().recordings.len(),
            if self.document.is_dirty() {
                ", unsaved edits"
            } else {
                ""
            }
        )
    }
}

/// The frame count given, or the recording's length.
fn frame_count(recording: &Bound<'_, PyAny>, frames: Option<usize>) -> PyResult<usize> {
    if let Some(frames) = frames {
        return Ok(frames);
    }
    known_frames(recording).ok_or_else(|| {
        PyValueError::new_err(
            "frames: give the recording's frame count, or pass the Recording itself",
        )
    })
}
