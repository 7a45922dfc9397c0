//! A bag's pushes as a recording set: how they are named and what their entries say. One rule for
//! `pushlab import` (which writes the set) and for opening a bag with a remembered choice (which
//! keeps it in memory), so that a push is called the same in both.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::choice::BagChoice;
use super::error::BagError;
use super::spec::TopicSpec;
use super::split::{BagImport, import_with_cameras};
use crate::recording::progress::{NoProgress, Progress};
use crate::recording::setting::{Setting, TrajectoryEntry};
use crate::recording::{Recording, RecordingSet};

/// The bag's name as a file stem: letters, digits, `-` and `_` kept, anything else `_`.
fn stem_of(bag: &Path) -> String {
    let name = bag
        .file_stem()
        .map_or_else(|| "push".to_owned(), |s| s.to_string_lossy().into_owned());
    name.chars()
        .map(|c| {
            if c.is_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The setting of an imported bag: `setting` with one entry per push (`STEM.csv`, or `STEM_001.csv`
/// … when the bag was split), each keeping the bag, the topics, the Unix time of its first frame
/// and the import's warnings, and the grid's rate.
pub fn setting_for(
    bag: &Path,
    import: &BagImport,
    pusher: &TopicSpec,
    object: &TopicSpec,
    mut setting: Setting,
) -> Setting {
    let stem = stem_of(bag);
    let many = import.pushes.len() > 1;
    setting.trajectories = import
        .pushes
        .iter()
        .enumerate()
        .map(|(i, push)| {
            let mut extra = serde_json::Map::new();
            extra.insert("bag".into(), bag.display().to_string().into());
            extra.insert("bag_pusher".into(), pusher.to_string().into());
            extra.insert("bag_object".into(), object.to_string().into());
            extra.insert("start_unix_s".into(), push.start_unix_s.into());
            if !push.warnings.is_empty() {
                extra.insert("import_warnings".into(), push.warnings.clone().into());
            }
            if !push.notes.is_empty() {
                extra.insert("import_notes".into(), push.notes.clone().into());
            }
            TrajectoryEntry {
                file: if many {
                    format!("{stem}_{:03}.csv", i + 1)
                } else {
                    format!("{stem}.csv")
                },
                contact_offset: None,
                push_angle_deg: None,
                extra,
            }
        })
        .collect();
    setting.sample_rate_hz = Some(import.rate_hz);
    setting
}

/// Where a push of a bag says it comes from: the bag, or `BAG#002` for the second of several
/// pushes (a distinct name per push, for labels and messages).
fn source_of(bag: &Path, index: usize, many: bool) -> PathBuf {
    if many {
        PathBuf::from(format!("{}#{:03}", bag.display(), index + 1))
    } else {
        bag.to_path_buf()
    }
}

/// Imports a bag as `choice` says and returns its pushes as a set, in memory (nothing is written).
/// The set's folder is the bag's.
pub fn open(bag: &Path, choice: &BagChoice) -> Result<RecordingSet, BagError> {
    open_with(bag, choice, &NoProgress)
}

/// [`open`], telling `progress` the bytes read and stopping when it is cancelled.
pub fn open_with(
    bag: &Path,
    choice: &BagChoice,
    progress: &dyn Progress,
) -> Result<RecordingSet, BagError> {
    let base = choice.setting.resolve()?;
    let import = import_with_cameras(
        bag,
        &choice.pusher,
        &choice.object,
        &choice.cameras,
        choice.options,
        progress,
    )?;
    let setting = Arc::new(setting_for(
        bag,
        &import,
        &choice.pusher,
        &choice.object,
        base,
    ));
    let many = import.pushes.len() > 1;
    let recordings = import
        .pushes
        .into_iter()
        .zip(&setting.trajectories)
        .enumerate()
        .map(|(i, (push, entry))| Recording {
            source: source_of(bag, i, many),
            name: entry.file.trim_end_matches(".csv").to_owned(),
            setting: Arc::clone(&setting),
            entry: Some(entry.clone()),
            trajectory: Arc::new(push.trajectory),
            warnings: push.warnings,
            notes: push.notes,
            cameras: push.cameras,
        })
        .collect();
    Ok(RecordingSet {
        dir: bag.to_path_buf(),
        setting,
        recordings,
    })
}
