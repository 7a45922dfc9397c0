//! The recordings an experiment uses: loaded from whatever paths the user gave, optionally narrowed
//! to one split, with frames labelled "bad tracking" left out of the samples.
//!
//! A recording's split comes from the labels file of its folder (`pushlab-labels.json`) or, where that
//! file does not give one, from the `split` of its entry in `setting.json` (written by
//! `pushlab simulate`), so that simulated sets can be split before anyone has labelled them.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use pushlab_core::labels::pipeline::{
    frames_to_skip, key_of, labels_file_beside, sample_is_skipped,
};
use pushlab_core::labels::{LabelSet, RecordingLabels, Split, file as labels_file};
use pushlab_core::model::{OnlineParams, Sample, samples_from_trajectory};
use pushlab_core::recording::{ObjectShape, Recording, load_paths};

/// One recording an experiment uses.
#[derive(Clone, Debug)]
pub struct Used {
    pub recording: Recording,
    /// Its labels, when its folder has a readable labels file that mentions it.
    pub labels: Option<RecordingLabels>,
    /// One flag per frame: `true` where a label marked "skip in training" (bad tracking) covers it.
    pub skip: Vec<bool>,
}

impl Used {
    /// The samples for `horizon`, without those whose start or end frame is skipped (a sample is made
    /// from exactly those two frames).
    pub fn samples(&self, horizon: usize) -> Vec<Sample> {
        samples_from_trajectory(&self.recording.trajectory, horizon)
            .into_iter()
            .filter(|s| !sample_is_skipped(&self.skip, s.frame, horizon))
            .collect()
    }

    /// Number of frames labelled bad tracking.
    pub fn skipped_frames(&self) -> usize {
        self.skip.iter().filter(|&&s| s).count()
    }

    /// The path shown to the user and written to reports.
    pub fn source(&self) -> String {
        self.recording.source.display().to_string()
    }
}

/// A file or recording left out, and why.
#[derive(Clone, Debug, serde::Serialize)]
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
#[derive(Debug, Default)]
pub struct Loaded {
    pub used: Vec<Used>,
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
    pub fn drop_short(&mut self, horizon: usize) {
        let (kept, short): (Vec<Used>, Vec<Used>) = std::mem::take(&mut self.used)
            .into_iter()
            .partition(|u| !u.samples(horizon).is_empty());
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
        if unreadable > 0 {
            parts.push(format!("{unreadable} skipped"));
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
                    // Without a split selection the labels only remove bad-tracking frames; say
                    // once per file that they are not used (done in `LabelCache`).
                    None
                }
            };
            let key = key_of(&recording.source).unwrap_or_default();
            if let Some(wanted) = split {
                match split_of(&recording, label_set.as_deref(), &key) {
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
            let frame_count = recording.trajectory.len();
            let (labels, skip) = match &label_set {
                Some(set) => (
                    set.recording(&key).cloned(),
                    frames_to_skip(set, &key, frame_count),
                ),
                None => (None, Vec::new()),
            };
            loaded.used.push(Used {
                recording,
                labels,
                skip,
            });
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

/// The split of a recording: its labels first, then `setting.json`.
fn split_of(recording: &Recording, labels: Option<&LabelSet>, key: &str) -> Option<Split> {
    labels.and_then(|l| l.split_of(key)).or_else(|| {
        recording
            .entry
            .as_ref()
            .and_then(|e| e.extra.get("split"))
            .and_then(|v| v.as_str())
            .and_then(Split::from_name)
    })
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
        let found = if path.is_file() {
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

/// The file a load error is about (its message starts with the path).
fn error_path(error: &pushlab_core::recording::LoadError) -> String {
    let text = error.to_string();
    match text.split_once(": ") {
        Some((path, _)) => path.split(" line ").next().unwrap_or(path).to_owned(),
        None => text,
    }
}

/// `θ_online(0)` for recordings that share one object outline: COM at the centre and `h` of a uniform
/// pressure over the footprint. `None` when the outlines differ or one is unusable.
pub fn theta0_for(used: &[Used]) -> Option<OnlineParams> {
    let first: &ObjectShape = &used.first()?.recording.setting.object;
    if used.iter().any(|u| &u.recording.setting.object != first) {
        return None;
    }
    first.outline().ok().map(|o| OnlineParams::for_outline(&o))
}

/// Prints the recordings used, one line per folder, and what was left out.
pub fn print_summary(role: &str, loaded: &Loaded, horizon: usize) {
    let samples: usize = loaded.used.iter().map(|u| u.samples(horizon).len()).sum();
    let bad: usize = loaded.used.iter().map(Used::skipped_frames).sum();
    println!(
        "{role}: {} recording(s), {samples} sample(s) at horizon {horizon}",
        loaded.used.len()
    );
    let mut by_folder: Vec<(String, Vec<String>)> = Vec::new();
    for u in &loaded.used {
        let folder = u
            .recording
            .source
            .parent()
            .map(|p| p.display().to_string())
            .unwrap_or_default();
        let name = u
            .recording
            .source
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| u.recording.name.clone());
        match by_folder.last_mut() {
            Some((f, names)) if *f == folder => names.push(name),
            _ => by_folder.push((folder, vec![name])),
        }
    }
    for (folder, names) in by_folder {
        println!("  {folder}/ ({}): {}", names.len(), names.join(" "));
    }
    if loaded.other_split > 0 {
        println!(
            "  ({} recording(s) with another split left out)",
            loaded.other_split
        );
    }
    if bad > 0 {
        println!("  ({bad} frame(s) labelled bad tracking left out)");
    }
    for s in &loaded.skipped {
        println!("  skipped: {}", s.message());
    }
}
