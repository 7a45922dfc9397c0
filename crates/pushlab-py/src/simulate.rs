//! `pushlab.simulate`: recording sets from the core's quasi-static simulator, whose true COM offset
//! and `h` are in each recording's setting (what `pushlab simulate` writes).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use pushlab_core::experiment::{self, UsedRecording, geometry_of};
use pushlab_core::labels::file as labels_file;
use pushlab_core::recording::{Recording as CoreRecording, write_set};
use pushlab_core::sim::{
    GeneratedSet, SetSpec, TRUTH_LABELS_FILE, generate_set, read_sample_spec, truth_labels,
};
use pyo3::prelude::*;

use crate::convert::from_python;
use crate::error::error;
use crate::recording::Recording;

/// Simulates recording sets with a known COM offset and h.
///
/// `spec` is one set as a dict — the fields of a set in the simulator (name, object, com_offset,
/// pressure, pusher_friction, pusher_radius, push_side, sample_rate_hz, duration_s, speed, noise,
/// seed, pushes, …; see the guide's simulator page) — or the path of a sample-data spec file
/// (`pushlab simulate --spec`), which gives every setting it lists.
///
/// Without `out` the recordings stay in memory (their source is `NAME/FILE.csv`). With `out` each
/// set is written as a native set (one set: into `out`; a spec file: into `out/NAME`) and read back
/// through the loader, with the simulator's true contact and stick/slip as `truth-labels.json` when
/// `truth_labels` is set. A folder that already holds a set is never overwritten.
#[pyfunction]
#[pyo3(signature = (spec, *, out=None, truth_labels=false))]
pub fn simulate(
    py: Python<'_>,
    spec: &Bound<'_, PyAny>,
    out: Option<PathBuf>,
    truth_labels: bool,
) -> PyResult<Vec<Recording>> {
    let (specs, single) = match spec.extract::<PathBuf>() {
        Ok(path) => (py.detach(|| read_sample_spec(&path)).map_err(error)?, false),
        Err(_) => (vec![from_python::<SetSpec>(spec, "spec")?], true),
    };
    let mut recordings = Vec::new();
    for spec in &specs {
        let set = py
            .detach(|| generate_set(spec, &mut |_, _| {}))
            .map_err(|e| error(format!("simulating set '{}': {e}", spec.name)))?;
        match &out {
            Some(out) => {
                let dir = if single {
                    out.clone()
                } else {
                    out.join(&spec.name)
                };
                recordings.extend(write_and_load(py, &dir, &set, truth_labels)?);
            }
            None => recordings.extend(in_memory(&spec.name, set)),
        }
    }
    Ok(recordings)
}

/// Writes a generated set into `dir` and loads it back.
fn write_and_load(
    py: Python<'_>,
    dir: &Path,
    set: &GeneratedSet,
    truth: bool,
) -> PyResult<Vec<Recording>> {
    if dir.join("setting.json").exists() {
        return Err(error(format!(
            "{} already holds a recording set; simulate into another folder",
            dir.display()
        )));
    }
    write_set(dir, &set.setting, &set.trajectories).map_err(error)?;
    if truth {
        labels_file::write(&dir.join(TRUTH_LABELS_FILE), &truth_labels(set)).map_err(error)?;
    }
    let loaded = py.detach(|| experiment::load_all(&[dir.to_path_buf()]));
    let used = loaded.map_err(|problems| {
        let lines: Vec<String> = problems.iter().map(|p| p.message()).collect();
        error(lines.join("\n"))
    })?;
    Ok(used.into_iter().map(Recording::new).collect())
}

/// A generated set's recordings as the loader would give them, without files.
fn in_memory(name: &str, set: GeneratedSet) -> Vec<Recording> {
    let setting = Arc::new(set.setting);
    let geometry = geometry_of(&setting);
    setting
        .trajectories
        .iter()
        .zip(set.trajectories)
        .map(|(entry, trajectory)| {
            let source = Path::new(name).join(&entry.file);
            let recording = CoreRecording {
                name: source
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                source,
                setting: Arc::clone(&setting),
                entry: Some(entry.clone()),
                trajectory: Arc::new(trajectory),
                warnings: Vec::new(),
                notes: Vec::new(),
                cameras: Vec::new(),
            };
            Recording::new(UsedRecording::labelled_with(
                recording,
                None,
                geometry.clone(),
            ))
        })
        .collect()
}
