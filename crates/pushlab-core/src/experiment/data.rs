//! The recordings an experiment uses: loaded from whatever paths the user gave, optionally narrowed
//! to one split, with frames labelled "bad tracking" left out of the samples.
//!
//! A recording's split comes from the labels file of its folder (`pushlab-labels.json`) or, where that
//! file does not give one, from the `split` of its entry in `setting.json` (written by
//! `pushlab simulate`), so that simulated sets can be split before anyone has labelled them
//! ([`split_of`], the one rule the CLI and the app share).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::geometry::OutlineError;
use crate::labels::pipeline::{frames_to_skip, key_of, labels_file_beside};
use crate::labels::{LabelSet, RecordingLabels, Split, file as labels_file};
use crate::model::{ContactGeometry, Sample, samples_kept};
use crate::recording::{LoadError, Recording, Setting, load_paths};

/// One recording an experiment uses, with what the models need of it.
#[derive(Clone, Debug)]
pub struct UsedRecording {
    pub recording: Recording,
    /// Its labels, when its folder has a readable labels file that mentions it.
    pub labels: Option<RecordingLabels>,
    /// One flag per frame: `true` where a label marked "skip in training" (bad tracking) covers it.
    pub skip: Vec<bool>,
    /// The object's outline and the pusher as the contact-frame model uses them; `Err` when the
    /// setting's outline is unusable.
    pub geometry: Result<Arc<ContactGeometry>, OutlineError>,
}

impl UsedRecording {
    /// A recording with its skip mask (from labels the caller holds, e.g. the app's open documents).
    pub fn new(recording: Recording, labels: Option<RecordingLabels>, skip: Vec<bool>) -> Self {
        let geometry = geometry_of(&recording.setting);
        Self {
            recording,
            labels,
            skip,
            geometry,
        }
    }

    /// A recording with what its folder's labels file (`labels`, when there is one) says of it: its
    /// labels and the frames labelled bad tracking. The one rule by which `pushlab train`, `eval`, the
    /// suite and the Python package attach labels to a loaded recording.
    pub fn labelled_with(
        recording: Recording,
        labels: Option<&LabelSet>,
        geometry: Result<Arc<ContactGeometry>, OutlineError>,
    ) -> Self {
        let key = key_of(&recording.source).unwrap_or_default();
        let (labels, skip) = match labels {
            Some(set) => (
                set.recording(&key).cloned(),
                frames_to_skip(set, &key, recording.trajectory.len()),
            ),
            None => (None, Vec::new()),
        };
        Self {
            recording,
            labels,
            skip,
            geometry,
        }
    }

    /// The samples for `horizon`, without those whose start or end frame is skipped (a sample is made
    /// from exactly those two frames).
    pub fn samples(&self, horizon: usize) -> Vec<Sample> {
        samples_kept(&self.recording.trajectory, horizon, &self.skip)
    }

    /// Whether it gives a sample at `horizon`: recordings that do not are left out of training and
    /// evaluation (too short, or every sample on frames labelled bad tracking).
    pub fn has_samples(&self, horizon: usize) -> bool {
        !self.samples(horizon).is_empty()
    }

    /// Number of frames labelled bad tracking.
    pub fn skipped_frames(&self) -> usize {
        self.skip.iter().filter(|&&s| s).count()
    }

    /// The path shown to the user and written to reports.
    pub fn source(&self) -> String {
        self.recording.source.display().to_string()
    }

    /// Whether `other` pushes the same physical object ([`Recording::same_object_as`]).
    pub fn same_object_as(&self, other: &UsedRecording) -> bool {
        self.recording.same_object_as(&other.recording)
    }
}

/// The contact-frame geometry of a setting's object and pusher.
pub fn geometry_of(setting: &Setting) -> Result<Arc<ContactGeometry>, OutlineError> {
    let outline = setting.object.outline()?;
    Ok(Arc::new(ContactGeometry::new(
        &outline,
        setting.pusher_radius,
    )))
}

/// The split of a recording: its labels first, then the `split` of its entry in `setting.json`.
pub fn split_of(recording: &Recording, labels: Option<&LabelSet>) -> Option<Split> {
    let key = key_of(&recording.source).unwrap_or_default();
    labels.and_then(|l| l.split_of(&key)).or_else(|| {
        recording
            .entry
            .as_ref()
            .and_then(|e| e.extra.get("split"))
            .and_then(|v| v.as_str())
            .and_then(Split::from_name)
    })
}

/// A file or recording left out, and why.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Skipped {
    pub path: String,
    pub reason: String,
}

impl Skipped {
    /// One line naming the file and the reason.
    pub fn message(&self) -> String {
        if self.reason.starts_with(&self.path) {
            self.reason.clone()
        } else {
            format!("{}: {}", self.path, self.reason)
        }
    }
}

/// What loading one role's paths (`--offline`, `--online`, `--data`) gave.
#[derive(Clone, Debug, Default)]
pub struct Loaded {
    pub used: Vec<UsedRecording>,
    /// Unreadable files and recordings that could not be used, each with its reason.
    pub skipped: Vec<Skipped>,
    /// Recordings that loaded but carry another split (only with a split selection).
    pub other_split: usize,
    /// Recordings that loaded but give no sample at the horizon (also listed in `skipped`).
    pub too_short: usize,
}

impl Loaded {
    /// Moves the recordings that give no sample at `horizon` (too short, or every sample on
    /// bad-tracking frames) to `skipped`, so that no trajectory reports a loss over zero samples.
    fn drop_short(&mut self, horizon: usize) {
        let (kept, short): (Vec<UsedRecording>, Vec<UsedRecording>) =
            std::mem::take(&mut self.used)
                .into_iter()
                .partition(|u| u.has_samples(horizon));
        self.used = kept;
        self.too_short = short.len();
        for u in short {
            self.skipped.push(Skipped {
                path: u.source(),
                reason: format!(
                    "no sample at horizon {horizon}: {} frame(s), {} of them labelled bad tracking",
                    u.recording.trajectory.len(),
                    u.skipped_frames()
                ),
            });
        }
    }

    /// Why nothing is left, for the error message when `used` is empty.
    pub fn why_nothing(&self, horizon: usize) -> String {
        let mut parts = Vec::new();
        let unreadable = self.skipped.len() - self.too_short;
        // The unreadable come first (`drop_short` adds the short ones after them): the first is
        // named, so that a wrong path says which path it was.
        if let Some(first) = self.skipped.first().filter(|_| unreadable > 0) {
            let more = match unreadable {
                1 => String::new(),
                n => format!("; {} more", n - 1),
            };
            parts.push(format!("{unreadable} skipped: {}{more}", first.message()));
        }
        if self.too_short > 0 {
            parts.push(format!(
                "{} without a sample at horizon {horizon} (shorter than {} frames)",
                self.too_short,
                horizon + 1
            ));
        }
        if self.other_split > 0 {
            parts.push(format!("{} with another split", self.other_split));
        }
        if parts.is_empty() {
            "no recording found".into()
        } else {
            format!("no recording could be used ({})", parts.join(", "))
        }
    }

    /// The samples of every recording used, one list per recording.
    pub fn samples(&self, horizon: usize) -> Vec<Vec<Sample>> {
        self.used.iter().map(|u| u.samples(horizon)).collect()
    }
}

/// Loads `paths`; with `split`, keeps only the recordings labelled with it; leaves out those without
/// a sample at `horizon`.
pub fn load(paths: &[PathBuf], split: Option<Split>, horizon: usize) -> Loaded {
    let report = load_paths(paths);
    let mut loaded = Loaded::default();
    for error in &report.errors {
        loaded.skipped.push(Skipped {
            path: error_path(error),
            reason: error.to_string(),
        });
    }
    let mut labels = LabelCache::default();
    let mut geometries: HashMap<*const Setting, Result<Arc<ContactGeometry>, OutlineError>> =
        HashMap::new();
    for set in report.sets {
        for recording in set.recordings {
            let label_set = match labels.get(&recording.source) {
                Ok(set) => set,
                Err(reason) => {
                    if split.is_some() {
                        loaded.skipped.push(Skipped {
                            path: recording.source.display().to_string(),
                            reason: format!("its split is unknown: {reason}"),
                        });
                        continue;
                    }
                    // Without a split selection the labels only remove bad-tracking frames; the
                    // broken file is reported once below.
                    None
                }
            };
            if let Some(wanted) = split {
                match split_of(&recording, label_set.as_deref()) {
                    Some(s) if s == wanted => {}
                    Some(_) => {
                        loaded.other_split += 1;
                        continue;
                    }
                    None => {
                        loaded.skipped.push(Skipped {
                            path: recording.source.display().to_string(),
                            reason: format!(
                                "no split: neither its folder's labels file nor setting.json says whether it is {}",
                                wanted.name()
                            ),
                        });
                        continue;
                    }
                }
            }
            // One geometry per setting: the recordings of a set share it.
            let geometry = geometries
                .entry(Arc::as_ptr(&recording.setting))
                .or_insert_with(|| geometry_of(&recording.setting))
                .clone();
            loaded.used.push(UsedRecording::labelled_with(
                recording,
                label_set.as_deref(),
                geometry,
            ));
        }
    }
    for (path, reason) in labels.broken {
        loaded.skipped.push(Skipped {
            path: path.display().to_string(),
            reason: format!("labels not used: {reason}"),
        });
    }
    loaded.drop_short(horizon);
    loaded
}

/// Every recording `paths` hold, each with its folder's labels, or every file that could not be read:
/// what a script asks for (the Python package's `pushlab.load`), where a broken file is an error to
/// raise rather than a line in a summary. Short recordings are kept (a script may only look at them).
pub fn load_all(paths: &[PathBuf]) -> Result<Vec<UsedRecording>, Vec<Skipped>> {
    let report = load_paths(paths);
    let mut problems: Vec<Skipped> = report
        .errors
        .iter()
        .map(|error| Skipped {
            path: error_path(error),
            reason: error.to_string(),
        })
        .collect();
    let mut labels = LabelCache::default();
    let mut geometries: HashMap<*const Setting, Result<Arc<ContactGeometry>, OutlineError>> =
        HashMap::new();
    let mut used = Vec::new();
    for recording in report.sets.into_iter().flat_map(|set| set.recordings) {
        // A broken labels file is reported once, below.
        let label_set = labels.get(&recording.source).ok().flatten();
        let geometry = geometries
            .entry(Arc::as_ptr(&recording.setting))
            .or_insert_with(|| geometry_of(&recording.setting))
            .clone();
        used.push(UsedRecording::labelled_with(
            recording,
            label_set.as_deref(),
            geometry,
        ));
    }
    problems.extend(labels.broken.into_iter().map(|(path, reason)| Skipped {
        path: path.display().to_string(),
        reason,
    }));
    if problems.is_empty() {
        Ok(used)
    } else {
        Err(problems)
    }
}

/// Labels files read so far, by path; a missing file is `None`.
#[derive(Default)]
struct LabelCache {
    files: HashMap<PathBuf, Result<Option<Arc<LabelSet>>, String>>,
    /// Labels files that exist but could not be read, in the order found.
    broken: Vec<(PathBuf, String)>,
}

impl LabelCache {
    fn get(&mut self, recording: &Path) -> Result<Option<Arc<LabelSet>>, String> {
        let path = labels_file_beside(recording);
        if let Some(found) = self.files.get(&path) {
            return found.clone();
        }
        let found = if crate::files::is_file(&path) {
            labels_file::read(&path)
                .map(|set| Some(Arc::new(set)))
                .map_err(|e| e.to_string())
        } else {
            Ok(None)
        };
        if let Err(reason) = &found {
            self.broken.push((path.clone(), reason.clone()));
        }
        self.files.insert(path, found.clone());
        found
    }
}

/// The file a load error is about.
fn error_path(error: &LoadError) -> String {
    error.path().display().to_string()
}
