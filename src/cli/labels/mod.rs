//! `pushlab labels`: set splits, inspect and export a recording set's labels file without the app,
//! propose labels from physics ([`propose`]) and compare two labels files ([`compare`]).
//!
//! Every change goes through the same [`LabelDocument`] commands as the app, so the file written here
//! is exactly what the app would write, and it is saved atomically.

mod compare;
mod propose;

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use clap::Subcommand;
use pushlab_core::labels::export::{self, FrameTimes};
use pushlab_core::labels::file::{self, LABELS_FILE_NAME};
use pushlab_core::labels::pipeline::key_of;
use pushlab_core::labels::{Command, LabelDocument, LabelKind, LabelSet, MetaField, Split};
use pushlab_core::pattern::wildcard_match;
use pushlab_core::recording::native::{SETTING_FILE, parse_setting};
use pushlab_core::recording::{ObjectShape, load_paths};

/// The `labels` subcommands.
#[derive(Debug, Subcommand)]
pub enum LabelsCommand {
    /// Set the offline / online / held-out split of recordings in set folders' labels files
    /// (`pushlab-labels.json`, created if missing). Other labels and recordings are kept.
    ///
    /// A folder without `setting.json` whose subfolders are sets (like `sample-data`) stands for
    /// those subfolders.
    InitSplits {
        /// Recording set folders, or folders of sets.
        #[arg(required = true)]
        folders: Vec<PathBuf>,
        /// Recordings for offline training: file names in each folder; `*` and `?` match any text
        /// and any one character.
        #[arg(long, num_args = 1.., value_name = "FILE")]
        offline: Vec<String>,
        /// Recordings for online learning, as for `--offline`.
        #[arg(long, num_args = 1.., value_name = "FILE")]
        online: Vec<String>,
        /// Recordings held out from both, as for `--offline`.
        #[arg(long = "held-out", num_args = 1.., value_name = "FILE")]
        held_out: Vec<String>,
        /// Take each recording's split from the `split` of its entry in `setting.json` (as written
        /// by `pushlab simulate`), and fill the object, material, pushing side and COM label from
        /// the setting where they are not labelled yet.
        #[arg(long)]
        from_setting: bool,
    },
    /// Print the labels of a set folder: its schema, and per recording the split and labels.
    Show {
        /// The recording set folder.
        folder: PathBuf,
    },
    /// Export the labels of a set folder, one row per segment or event with frame numbers and the
    /// recordings' frame times.
    Export {
        /// The recording set folder.
        folder: PathBuf,
        /// Write CSV here.
        #[arg(long, value_name = "FILE")]
        csv: Option<PathBuf>,
        /// Write JSON here.
        #[arg(long, value_name = "FILE")]
        json: Option<PathBuf>,
    },
    /// Propose contact / no contact, sticking / slipping and bad tracking from the recordings' own
    /// physics, into a new labels file (the set's own labels and recordings are never written).
    Propose(propose::ProposeArgs),
    /// Per label, frame precision, recall and F1 of OTHER against TRUTH (two labels files).
    Compare(compare::CompareArgs),
}

/// Runs one `labels` subcommand; the messages it prints go to stdout.
pub fn run(command: LabelsCommand) -> anyhow::Result<()> {
    match command {
        LabelsCommand::InitSplits {
            folders,
            offline,
            online,
            held_out,
            from_setting,
        } => {
            let patterns = [
                (Split::Offline, offline),
                (Split::Online, online),
                (Split::HeldOut, held_out),
            ];
            if !from_setting && patterns.iter().all(|(_, p)| p.is_empty()) {
                bail!(
                    "nothing to set: give --from-setting, or --offline, --online and/or --held-out FILE…"
                );
            }
            for folder in set_folders(&folders)? {
                print!("{}", init_splits(&folder, &patterns, from_setting)?);
            }
            Ok(())
        }
        LabelsCommand::Show { folder } => {
            let path = file::path_in(&folder);
            let set = file::read(&path)?;
            print!("{}", summary(&path, &set));
            Ok(())
        }
        LabelsCommand::Export { folder, csv, json } => {
            if csv.is_none() && json.is_none() {
                bail!("nothing to export: give --csv FILE and/or --json FILE");
            }
            let set = file::read(&file::path_in(&folder))?;
            let times = frame_times(&folder)?;
            if let Some(path) = csv {
                export::write(&path, &export::to_csv(&set, &times)?)?;
                println!("wrote {}", path.display());
            }
            if let Some(path) = json {
                export::write(&path, &export::to_json(&set, &times)?)?;
                println!("wrote {}", path.display());
            }
            Ok(())
        }
        LabelsCommand::Propose(args) => propose::run(&args),
        LabelsCommand::Compare(args) => compare::run(&args),
    }
}

/// The set folders meant by the folders given: each folder itself, or, for a folder without
/// `setting.json` that has set subfolders, those subfolders (sorted).
fn set_folders(folders: &[PathBuf]) -> anyhow::Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for folder in folders {
        if !folder.is_dir() {
            bail!("{} is not a folder", folder.display());
        }
        if folder.join(SETTING_FILE).is_file() {
            out.push(folder.clone());
            continue;
        }
        let mut sets: Vec<PathBuf> = fs::read_dir(folder)
            .with_context(|| format!("cannot list {}", folder.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.join(SETTING_FILE).is_file())
            .collect();
        sets.sort();
        if sets.is_empty() {
            out.push(folder.clone());
        } else {
            out.extend(sets);
        }
    }
    Ok(out)
}

/// Sets the splits of one set folder (from patterns and/or `setting.json`) and saves; returns what
/// was done, one line per split.
fn init_splits(
    folder: &Path,
    patterns: &[(Split, Vec<String>)],
    from_setting: bool,
) -> anyhow::Result<String> {
    let files = recording_files(folder)?;
    // (recording, split, where the split came from), in the order chosen.
    let mut chosen: Vec<(String, Split, String)> = Vec::new();
    let mut choose = |name: &str, split: Split, source: String| -> anyhow::Result<()> {
        match chosen.iter().find(|(n, _, _)| n == name) {
            Some((_, other, other_source)) if *other != split => bail!(
                "{}: {name} is named for both {other_source} and {source}",
                folder.display()
            ),
            Some(_) => Ok(()),
            None => {
                chosen.push((name.to_owned(), split, source));
                Ok(())
            }
        }
    };
    let mut doc = LabelDocument::open_set_folder(folder)?;
    if from_setting {
        let path = folder.join(SETTING_FILE);
        let bytes = fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
        let setting = parse_setting(&bytes, &path)?;
        for entry in &setting.trajectories {
            if let Some(value) = entry.extra.get("split") {
                let split = value.as_str().and_then(Split::from_name).with_context(|| {
                    format!(
                        "{}: trajectory {}: split {value} is not offline, online or held-out",
                        path.display(),
                        entry.file
                    )
                })?;
                choose(
                    &entry.file,
                    split,
                    format!("{SETTING_FILE} ({})", split.name()),
                )?;
            }
            let meta = doc
                .recording(&entry.file)
                .map(|r| r.meta.clone())
                .unwrap_or_default();
            let mut fields = Vec::new();
            if meta.object.is_empty() {
                fields.push(MetaField::Object(describe(&setting.object)));
            }
            if let Some(material) = &setting.material
                && meta.material.is_empty()
            {
                fields.push(MetaField::Material(material.clone()));
            }
            if setting.push_side.is_some() && meta.push_side.is_none() {
                fields.push(MetaField::PushSide(setting.push_side));
            }
            if setting.com_offset.is_some() && meta.com_offset.is_none() {
                fields.push(MetaField::ComOffset(setting.com_offset));
            }
            for field in fields {
                doc.apply(Command::SetMeta {
                    recording: entry.file.clone(),
                    field,
                })?;
            }
        }
    }
    for (split, split_patterns) in patterns {
        for pattern in split_patterns {
            let matches: Vec<&String> = files
                .iter()
                .filter(|f| wildcard_match(pattern, f))
                .collect();
            if matches.is_empty() {
                bail!(
                    "--{} {pattern:?} matches no recording in {}",
                    split.name(),
                    folder.display()
                );
            }
            for name in matches {
                choose(name, *split, format!("--{}", split.name()))?;
            }
        }
    }
    for (name, split, _) in &chosen {
        doc.apply(Command::SetMeta {
            recording: name.clone(),
            field: MetaField::Split(Some(*split)),
        })?;
    }
    doc.save()?;
    let mut report = String::new();
    for split in Split::ALL {
        let count = chosen.iter().filter(|(_, s, _)| *s == split).count();
        if count > 0 {
            let _ = write!(report, "{} {split}, ", count, split = split.name());
        }
    }
    let _ = writeln!(report, "wrote {}", doc.path().display());
    Ok(report)
}

/// A short name for an object's footprint, for the `object` field.
fn describe(shape: &ObjectShape) -> String {
    match shape {
        ObjectShape::Box { width, length } => format!("box {width} m × {length} m"),
        ObjectShape::Polygon { vertices } => format!("polygon with {} vertices", vertices.len()),
        ObjectShape::Preset(p) => format!("preset {} at {} m per unit", p.preset, p.metres_per_px),
    }
}

/// The names of the files in `folder` that may be recordings: everything but hidden files, the
/// labels file and `setting.json`, sorted.
fn recording_files(folder: &Path) -> anyhow::Result<Vec<String>> {
    let entries =
        fs::read_dir(folder).with_context(|| format!("cannot list {}", folder.display()))?;
    let mut names = Vec::new();
    for entry in entries {
        let entry = entry.with_context(|| format!("cannot list {}", folder.display()))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if entry.path().is_file()
            && !name.starts_with('.')
            && name != LABELS_FILE_NAME
            && name != SETTING_FILE
        {
            names.push(name);
        }
    }
    names.sort();
    Ok(names)
}

/// A readable summary of a labels file.
fn summary(path: &Path, set: &LabelSet) -> String {
    let mut out = format!("{}\nlabels:\n", path.display());
    for label in &set.schema.labels {
        let kind = match label.kind {
            LabelKind::Range => "range",
            LabelKind::Event => "event",
        };
        let _ = write!(out, "  {:<14} {kind:<5} {}", label.name, label.colour);
        if let Some(key) = &label.hotkey {
            let _ = write!(out, "  key {key}");
        }
        if let Some(group) = &label.group {
            let _ = write!(out, "  group {group:?}");
        }
        if label.skip_in_training {
            let _ = write!(out, "  skipped in training");
        }
        out.push('\n');
    }
    out.push_str("recordings:\n");
    for (name, rec) in &set.recordings {
        let split = rec.meta.split.map_or("-", Split::name);
        let _ = writeln!(
            out,
            "  {name:<24} {split:<9} {} segments, {} events",
            rec.segments.len(),
            rec.events.len()
        );
    }
    out
}

/// Frame times of every recording in `folder`, by file name, from the recording loader.
struct LoadedTimes(std::collections::BTreeMap<String, Vec<f64>>);

impl FrameTimes for LoadedTimes {
    fn frame_times(&self, recording: &str) -> Option<&[f64]> {
        self.0.frame_times(recording)
    }
}

fn frame_times(folder: &Path) -> anyhow::Result<LoadedTimes> {
    let report = load_paths(&[folder.to_owned()]);
    for error in &report.errors {
        eprintln!("warning: {error}");
    }
    let mut times = std::collections::BTreeMap::new();
    for set in &report.sets {
        for recording in &set.recordings {
            if let Some(key) = key_of(&recording.source) {
                let t = recording.trajectory.frames.iter().map(|f| f.time).collect();
                times.insert(key, t);
            }
        }
    }
    Ok(LoadedTimes(times))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    fn folder(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("pushlab-cli-labels-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        for f in [
            "push_000.csv",
            "push_001.csv",
            "push_002.csv",
            "setting.json",
        ] {
            fs::write(dir.join(f), "x").unwrap();
        }
        dir
    }

    #[test]
    fn init_splits_writes_splits_and_keeps_other_labels() {
        let dir = folder("init");
        let mut doc = LabelDocument::open_set_folder(&dir).unwrap();
        doc.apply(Command::Paint {
            recording: "push_000.csv".into(),
            label: "sticking".into(),
            frames: 0..5,
        })
        .unwrap();
        doc.save().unwrap();
        let report = init_splits(
            &dir,
            &[
                (
                    Split::Offline,
                    vec!["push_000.csv".into(), "push_001.csv".into()],
                ),
                (Split::Online, vec!["push_002*".into()]),
            ],
            false,
        )
        .unwrap();
        assert!(
            report.starts_with("2 offline, 1 online, wrote "),
            "{report}"
        );
        let set = file::read(&file::path_in(&dir)).unwrap();
        assert_eq!(set.split_of("push_000.csv"), Some(Split::Offline));
        assert_eq!(set.split_of("push_002.csv"), Some(Split::Online));
        assert_eq!(set.recording("push_000.csv").unwrap().segments.len(), 1);
        assert_eq!(set.split_of("setting.json"), None);
    }

    #[test]
    fn init_splits_refuses_unmatched_and_conflicting_names() {
        let dir = folder("refuse");
        let err = init_splits(&dir, &[(Split::Online, vec!["push_9*".into()])], false).unwrap_err();
        assert!(
            err.to_string()
                .starts_with("--online \"push_9*\" matches no recording in "),
            "{err}"
        );
        let err = init_splits(
            &dir,
            &[
                (Split::Offline, vec!["*.csv".into()]),
                (Split::Online, vec!["push_001.csv".into()]),
            ],
            false,
        )
        .unwrap_err();
        assert!(
            err.to_string()
                .ends_with(": push_001.csv is named for both --offline and --online"),
            "{err}"
        );
        assert!(!file::path_in(&dir).exists(), "nothing written on error");
    }

    const SETTING: &str = r#"{"name": "t", "object": {"shape": "box", "width": 0.3, "length": 0.4},
        "pusher_radius": 0.01, "material": "paper", "com_offset": [0.05, -0.05], "push_side": "left",
        "trajectories": [{"file": "push_000.csv", "split": "offline"},
                         {"file": "push_001.csv", "split": "online"},
                         {"file": "push_002.csv"}]}"#;

    #[test]
    fn init_splits_from_setting_copies_splits_and_metadata_into_each_set() {
        let parent = folder("parent");
        // The parent is a folder of sets, not a set itself.
        fs::remove_file(parent.join(SETTING_FILE)).unwrap();
        for set in ["set_a", "set_b"] {
            let dir = parent.join(set);
            fs::create_dir_all(&dir).unwrap();
            for f in ["push_000.csv", "push_001.csv", "push_002.csv"] {
                fs::write(dir.join(f), "x").unwrap();
            }
            fs::write(dir.join(SETTING_FILE), SETTING).unwrap();
        }
        let sets = set_folders(std::slice::from_ref(&parent)).unwrap();
        assert_eq!(sets, vec![parent.join("set_a"), parent.join("set_b")]);
        // A label already made by hand is kept.
        let mut doc = LabelDocument::open_set_folder(&sets[1]).unwrap();
        doc.apply(Command::SetMeta {
            recording: "push_000.csv".into(),
            field: MetaField::Material("cardboard".into()),
        })
        .unwrap();
        doc.save().unwrap();
        for set in &sets {
            let report =
                init_splits(set, &[(Split::HeldOut, vec!["push_002.csv".into()])], true).unwrap();
            assert!(
                report.starts_with("1 offline, 1 online, 1 held-out, wrote "),
                "{report}"
            );
        }
        let a = file::read(&file::path_in(&sets[0])).unwrap();
        let meta = &a.recording("push_000.csv").unwrap().meta;
        assert_eq!(meta.split, Some(Split::Offline));
        assert_eq!(meta.material, "paper");
        assert_eq!(meta.object, "box 0.3 m × 0.4 m");
        assert_eq!(meta.com_offset, Some([0.05, -0.05]));
        assert_eq!(
            meta.push_side,
            Some(pushlab_core::recording::PushSide::Left)
        );
        assert_eq!(a.split_of("push_001.csv"), Some(Split::Online));
        assert_eq!(a.split_of("push_002.csv"), Some(Split::HeldOut));
        let b = file::read(&file::path_in(&sets[1])).unwrap();
        assert_eq!(
            b.recording("push_000.csv").unwrap().meta.material,
            "cardboard"
        );
        // The setting's split and a pattern may not disagree.
        let err = init_splits(
            &sets[0],
            &[(Split::Online, vec!["push_000.csv".into()])],
            true,
        )
        .unwrap_err();
        assert!(
            err.to_string()
                .ends_with("push_000.csv is named for both setting.json (offline) and --online"),
            "{err}"
        );
    }
}
