//! The sample data's labels files: every set has one, it loads, and its splits are the ones the
//! simulator wrote into `setting.json` (27 offline and 9 online pushes per set, see sample-data/README.md).

use std::path::{Path, PathBuf};

use pushlab_core::experiment;
use pushlab_core::labels::file;
use pushlab_core::labels::{LabelSchema, Split};
use pushlab_core::recording::native::{SETTING_FILE, parse_setting};

fn sample_sets() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../sample-data");
    let mut sets: Vec<PathBuf> = std::fs::read_dir(&root)
        .expect("sample-data is part of the repository")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.join(SETTING_FILE).is_file())
        .collect();
    sets.sort();
    sets
}

#[test]
fn every_sample_set_has_labels_with_the_settings_splits() {
    let sets = sample_sets();
    assert_eq!(sets.len(), 9, "{sets:?}");
    for dir in sets {
        let labels = file::read(&file::path_in(&dir)).expect("labels file loads");
        assert_eq!(labels.schema, LabelSchema::default());
        let setting_path = dir.join(SETTING_FILE);
        let bytes = std::fs::read(&setting_path).expect("setting.json readable");
        let setting = parse_setting(&bytes, &setting_path).expect("setting.json parses");
        for entry in &setting.trajectories {
            let written = entry.extra.get("split").and_then(|v| v.as_str());
            let split = labels.split_of(&entry.file).map(Split::name);
            assert_eq!(split, written, "{}: {}", dir.display(), entry.file);
            let meta = &labels.recording(&entry.file).expect("labelled").meta;
            assert_eq!(meta.com_offset, setting.com_offset, "{}", entry.file);
            assert_eq!(meta.push_side, setting.push_side, "{}", entry.file);
        }
        // The experiment pipeline selects the same splits from the labels file.
        let dirs = std::slice::from_ref(&dir);
        let offline = experiment::load(dirs, Some(Split::Offline), 10);
        let online = experiment::load(dirs, Some(Split::Online), 10);
        assert_eq!(
            (offline.used.len(), online.used.len()),
            (27, 9),
            "{}",
            dir.display()
        );
        assert!(
            offline
                .used
                .iter()
                .all(|u| u.recording.name.starts_with("offline_"))
        );
        assert!(offline.skipped.is_empty() && online.skipped.is_empty());
    }
}
