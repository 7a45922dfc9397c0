//! `pushlab.load` and `pushlab.Recording`: whatever the core's loader opens (native sets, MIT Push
//! Dataset files, bags and datasets with a remembered choice), each push with its folder's labels.

use std::path::PathBuf;

use numpy::{PyArray1, PyArray2};
use pushlab_core::experiment::{self, UsedRecording};
use pushlab_core::labels::pipeline::key_of;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{column, rows, to_python};
use crate::error::error;

/// One push: its frames as numpy arrays, its setting, and its labels when its folder has a labels
/// file that mentions it.
#[pyclass(module = "pushlab", name = "Recording", frozen)]
pub struct Recording {
    pub(crate) used: UsedRecording,
}

impl Recording {
    pub(crate) fn new(used: UsedRecording) -> Self {
        Self { used }
    }

    /// The key of this recording in its folder's labels file (its file name).
    pub(crate) fn key(&self) -> String {
        key_of(&self.used.recording.source).unwrap_or_default()
    }

    pub(crate) fn frame_count(&self) -> usize {
        self.used.recording.trajectory.len()
    }
}

#[pymethods]
impl Recording {
    /// A short name: the file stem (`offline_000`, `motion_surface=abs_shape=rect1_a=0_v=10_i=0.000_s=0.000_t=0.000`).
    #[getter]
    fn name(&self) -> &str {
        &self.used.recording.name
    }

    /// The file it was read from.
    #[getter]
    fn source(&self) -> PathBuf {
        self.used.recording.source.clone()
    }

    /// Seconds of each frame, shape (N,).
    #[getter]
    fn times<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let frames = &self.used.recording.trajectory.frames;
        column(py, frames.iter().map(|f| f.time).collect())
    }

    /// The pusher's centre in the world frame, metres, shape (N, 2).
    #[getter]
    fn robot<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let frames = &self.used.recording.trajectory.frames;
        let xy: Vec<[f64; 2]> = frames.iter().map(|f| [f.robot.x, f.robot.y]).collect();
        rows(py, &xy)
    }

    /// The object's geometric centre and yaw in the world frame (x, y metres; yaw radians,
    /// unwrapped), shape (N, 3).
    #[getter]
    fn object<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let frames = &self.used.recording.trajectory.frames;
        let pose: Vec<[f64; 3]> = frames
            .iter()
            .map(|f| {
                let o = &f.object;
                [o.position.x, o.position.y, o.yaw]
            })
            .collect();
        rows(py, &pose)
    }

    /// The setting (`setting.json`'s fields: name, object, pusher_radius, com_offset, h, …) as a
    /// dict.
    #[getter]
    fn setting<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &*self.used.recording.setting)
    }

    /// Per-frame masks of the range labels painted on this recording, `{label: bool array (N,)}`;
    /// `None` when its folder's labels file says nothing of it (or there is none).
    #[getter]
    fn labels<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(labels) = &self.used.labels else {
            return Ok(None);
        };
        let masks = PyDict::new(py);
        for label in labels.range_labels() {
            masks.set_item(label, column(py, labels.mask(label, self.frame_count())))?;
        }
        Ok(Some(masks))
    }

    /// Point events as `(label, frame)` pairs, in frame order.
    #[getter]
    fn events(&self) -> Vec<(String, usize)> {
        self.used
            .labels
            .iter()
            .flat_map(|l| &l.events)
            .map(|e| (e.label.clone(), e.frame))
            .collect()
    }

    /// The labelled metadata (object, material, com_offset, push_side, split, notes) as a dict; empty
    /// when none is labelled.
    #[getter]
    fn meta<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let meta = self
            .used
            .labels
            .as_ref()
            .map(|l| l.meta.clone())
            .unwrap_or_default();
        to_python(py, &meta)
    }

    /// True at frames covered by a label that is left out of training and evaluation (bad tracking),
    /// shape (N,). Online learning holds θ over samples touching them.
    #[getter]
    fn skip<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        let mut skip = self.used.skip.clone();
        skip.resize(self.frame_count(), false);
        column(py, skip)
    }

    /// Recoverable defects found while loading, each a sentence: rows dropped, gaps interpolated
    /// across, a file cut short (the frames are not all the recording had).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.used.recording.warnings.clone()
    }

    /// What loading did that loses nothing, each a sentence: an angle unwrapped, streams put on one
    /// clock, a log time for a missing stamp.
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.used.recording.notes.clone()
    }

    fn __len__(&self) -> usize {
        self.frame_count()
    }

    fn __repr__(&self) -> String {
        format!(
            "<pushlab.Recording {} ({} frames, setting {:?}) from {}>",
            self.used.recording.name,
            self.frame_count(),
            self.used.recording.setting.name,
            self.used.recording.source.display()
        )
    }
}

/// Loads every recording at `paths` (a path or a list of paths): native set folders, CSV files
/// inside a set, MIT Push Dataset `.json`/`.h5` files, ROS 2 bags and Push-T datasets with a
/// remembered choice, or folders of them (searched recursively) — the core's one loader, as
/// `pushlab validate` and the app use it. Each recording comes with its folder's labels.
///
/// Raises `PushlabError` naming every file that could not be read (and why), including a broken
/// labels file.
#[pyfunction]
pub fn load(py: Python<'_>, paths: &Bound<'_, PyAny>) -> PyResult<Vec<Recording>> {
    let paths: Vec<PathBuf> = match paths.extract::<PathBuf>() {
        Ok(path) => vec![path],
        Err(_) => paths.extract()?,
    };
    let loaded = py.detach(|| experiment::load_all(&paths));
    match loaded {
        Ok(used) => Ok(used.into_iter().map(Recording::new).collect()),
        Err(problems) => {
            let lines: Vec<String> = problems.iter().map(|p| p.message()).collect();
            Err(error(lines.join("\n")))
        }
    }
}
