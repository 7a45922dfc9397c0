//! The one entry point the app and the CLI use to open recordings, whatever the user points at.

use std::collections::{BTreeMap, HashSet};
use std::path::{Path, PathBuf};

use super::RecordingSet;
use super::bag::{self, BagChoice};
use super::bag::{BagError, BagProblem};
use super::dataset::{self, DatasetChoice};
use super::error::LoadError;
use super::mit_push::{self, MitError, MitPush};
use super::native::{self, SETTING_FILE};
use super::progress::{LoadProgress, Progress};
use crate::files;

/// Deepest folder nesting searched below a path given by the user; deeper folders are not searched.
const MAX_DEPTH: usize = 16;

/// Everything that loaded and everything that did not.
///
/// Loading never stops at the first problem: a user opening a folder of fifty recordings with one
/// broken file wants the forty-nine and a precise message about the fiftieth.
#[derive(Debug, Default)]
pub struct LoadReport {
    /// The sets that loaded, each with at least one recording.
    pub sets: Vec<RecordingSet>,
    /// One error per file (or set) that could not be loaded.
    pub errors: Vec<LoadError>,
}

impl LoadReport {
    /// Number of recordings loaded across all sets.
    pub fn recording_count(&self) -> usize {
        self.sets.iter().map(|s| s.recordings.len()).sum()
    }
}

/// One thing to load, as planning finds it.
enum Item {
    /// A native set folder, or one CSV of it.
    Set {
        dir: PathBuf,
        only: Option<PathBuf>,
    },
    Mit(PathBuf),
    Bag(PathBuf),
    /// A Push-T dataset: a zarr replay buffer or a LeRobot dataset folder.
    Dataset(PathBuf),
}

/// Loads recordings from the given paths.
///
/// Each path may be
/// - a native set folder (with `setting.json`),
/// - a folder of sets and/or MIT files, searched recursively (symbolic links to folders are not
///   followed): every set folder and every MIT Push Dataset file (`motion_*.json`/`.h5`) inside,
/// - a single CSV inside a set, or that set's `setting.json`,
/// - an MIT Push Dataset `.json` or `.h5` file.
///
/// A ROS 2 bag (an `.mcap` file or a rosbag2 folder) opens with the choice of topics and setting
/// remembered beside it; without one it is reported with its topics (which are the pusher and the
/// object is the user's to say: in the app's dialog, or with `pushlab import`).
///
/// MIT files are grouped into one set per folder, surface and shape, since those share an object
/// outline and a material; the set's trajectories list the files. Input files are only ever read.
/// A path reached twice (e.g. a folder and a file inside it) is loaded once.
pub fn load_paths(paths: &[PathBuf]) -> LoadReport {
    load_paths_choosing(paths, &[])
}

/// What the user chose for a source that needs a choice to open: a bag's topics and object, a
/// dataset's pusher and object features and scale.
#[derive(Clone, Debug, PartialEq)]
pub enum SourceChoice {
    /// Boxed: a bag's choice may carry a whole setting.
    Bag(Box<BagChoice>),
    Dataset(DatasetChoice),
}

/// [`load_paths`], opening the bags and datasets listed in `choices` as their choice says (whether
/// or not one is remembered beside them): how the app tries a choice before remembering it.
pub fn load_paths_choosing(paths: &[PathBuf], choices: &[(PathBuf, SourceChoice)]) -> LoadReport {
    load_paths_with(paths, choices, &LoadProgress::default())
}

/// [`load_paths_choosing`], telling `progress` the bytes loaded of the total found first, and
/// stopping (with a [`LoadError::Cancelled`]) at the next file or bag chunk once it is cancelled.
pub fn load_paths_with(
    paths: &[PathBuf],
    choices: &[(PathBuf, SourceChoice)],
    progress: &LoadProgress,
) -> LoadReport {
    crate::slices::finish(load_paths_in_slices(paths, choices, progress))
}

/// [`load_paths_with`] in slices (`crate::slices`): it pauses after each file, set or bag.
pub async fn load_paths_in_slices(
    paths: &[PathBuf],
    choices: &[(PathBuf, SourceChoice)],
    progress: &LoadProgress,
) -> LoadReport {
    let mut loader = Loader {
        choices: choices.to_vec(),
        ..Loader::default()
    };
    for path in paths {
        loader.add_path(path);
    }
    let sizes: Vec<u64> = loader.items.iter().map(Item::bytes).collect();
    progress.plan(sizes.len(), sizes.iter().sum());
    for (item, bytes) in std::mem::take(&mut loader.items).into_iter().zip(sizes) {
        if progress.is_cancelled() {
            loader.report.errors.push(LoadError::Cancelled {
                path: item.path().to_path_buf(),
            });
            break;
        }
        let counted = Counted::new(progress);
        loader.load(item, &counted);
        progress.file_done(counted.reported(), bytes);
        crate::slices::pause().await;
    }
    loader.finish()
}

impl Item {
    fn path(&self) -> &Path {
        match self {
            Item::Set { dir, only } => only.as_deref().unwrap_or(dir),
            Item::Mit(path) | Item::Bag(path) | Item::Dataset(path) => path,
        }
    }

    /// Bytes it will read, for the progress bar: the set's CSV files, the MIT file, the bag's files.
    fn bytes(&self) -> u64 {
        let size = |p: &Path| files::metadata(p).map_or(0, |m| m.len);
        match self {
            Item::Set {
                only: Some(file), ..
            }
            | Item::Mit(file) => size(file),
            Item::Set { dir, only: None } => files::read_dir(dir).map_or(0, |entries| {
                entries
                    .into_iter()
                    .map(|e| e.path)
                    .filter(|p| extension(p).as_deref() == Some("csv"))
                    .map(|p| size(&p))
                    .sum()
            }),
            Item::Bag(path) => {
                bag::bag_files(path).map_or(0, |files| files.iter().map(|f| size(f)).sum())
            }
            Item::Dataset(path) => dataset::bytes(path),
        }
    }
}

/// A load's progress for one file: what it reported, so that the rest is counted when it is done.
struct Counted<'a> {
    inner: &'a LoadProgress,
    reported: std::sync::atomic::AtomicU64,
}

impl<'a> Counted<'a> {
    fn new(inner: &'a LoadProgress) -> Self {
        Self {
            inner,
            reported: std::sync::atomic::AtomicU64::new(0),
        }
    }

    fn reported(&self) -> u64 {
        self.reported.load(std::sync::atomic::Ordering::Relaxed)
    }
}

impl Progress for Counted<'_> {
    fn advance(&self, bytes: u64) {
        self.reported
            .fetch_add(bytes, std::sync::atomic::Ordering::Relaxed);
        self.inner.advance(bytes);
    }

    fn is_cancelled(&self) -> bool {
        self.inner.is_cancelled()
    }
}

#[derive(Default)]
struct Loader {
    report: LoadReport,
    /// What planning found to load, in order.
    items: Vec<Item>,
    /// Set folders already loaded whole, and single files already loaded.
    seen: HashSet<PathBuf>,
    /// MIT pushes by (folder, surface, shape), in file-name order.
    mit: BTreeMap<(PathBuf, String, String), Vec<(PathBuf, MitPush)>>,
    /// Bags and datasets to open with a choice given by the caller.
    choices: Vec<(PathBuf, SourceChoice)>,
}

impl Loader {
    fn add_path(&mut self, path: &Path) {
        let meta = match files::metadata(path) {
            Ok(m) => m,
            Err(e) => return self.report.errors.push(LoadError::io(path, e)),
        };
        if meta.is_dir {
            if files::is_file(&path.join(SETTING_FILE)) {
                self.add_set(path, None);
                self.add_bags_in(path);
            } else if dataset::is_dataset(path) {
                self.add_dataset(path);
            } else if bag::is_bag(path) {
                self.add_bag(path);
            } else if !self.scan(path, 0) {
                self.report.errors.push(LoadError::NothingFound {
                    path: path.to_path_buf(),
                });
            }
            return;
        }
        let dir = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let file_name = path.file_name().map(|n| n.to_string_lossy().into_owned());
        match extension(path).as_deref() {
            _ if file_name.as_deref() == Some(SETTING_FILE) => self.add_set(dir, None),
            Some("csv") => {
                if files::is_file(&dir.join(SETTING_FILE)) {
                    self.add_set(dir, Some(path));
                } else {
                    self.report.errors.push(LoadError::NoSetting {
                        path: path.to_path_buf(),
                    });
                }
            }
            Some("json" | "h5") => self.add_mit(path),
            Some("mcap") => self.add_bag(path),
            _ => self.report.errors.push(LoadError::NotRecognised {
                path: path.to_path_buf(),
            }),
        }
    }

    /// Searches `dir` for sets and MIT files; returns whether anything recognisable was found.
    fn scan(&mut self, dir: &Path, depth: usize) -> bool {
        let entries = match files::read_dir(dir) {
            Ok(entries) => entries,
            Err(e) => {
                self.report.errors.push(LoadError::io(dir, e));
                return true; // reported: not "nothing found"
            }
        };
        let mut paths: Vec<(PathBuf, bool)> =
            entries.into_iter().map(|e| (e.path, e.is_dir)).collect();
        paths.sort();
        let mut found = false;
        for (path, is_dir) in paths {
            if is_dir {
                if files::is_file(&path.join(SETTING_FILE)) {
                    self.add_set(&path, None);
                    self.add_bags_in(&path);
                    found = true;
                } else if dataset::is_dataset(&path) {
                    self.add_dataset(&path);
                    found = true;
                } else if bag::is_bag(&path) {
                    self.add_bag(&path);
                    found = true;
                } else if depth < MAX_DEPTH {
                    found |= self.scan(&path, depth + 1);
                }
            } else if is_mit_file(&path) && files::is_file(&path) {
                self.add_mit(&path);
                found = true;
            } else if extension(&path).as_deref() == Some("mcap")
                && !files::is_file(&dir.join("metadata.yaml"))
            {
                self.add_bag(&path);
                found = true;
            }
        }
        found
    }

    /// Plans a bag (once).
    fn add_bag(&mut self, path: &Path) {
        if self.seen.insert(canonical(path)) {
            self.items.push(Item::Bag(path.to_path_buf()));
        }
    }

    /// Plans a dataset (once).
    fn add_dataset(&mut self, path: &Path) {
        if self.seen.insert(canonical(path)) {
            self.items.push(Item::Dataset(path.to_path_buf()));
        }
    }

    /// Loads what planning found.
    fn load(&mut self, item: Item, progress: &dyn Progress) {
        match item {
            Item::Set { dir, only } => self.load_set(&dir, only.as_deref()),
            Item::Mit(path) => self.load_mit(&path),
            Item::Bag(path) => self.load_bag(&path, progress),
            Item::Dataset(path) => {
                let key = canonical(&path);
                let given = self.choices.iter().find_map(|(p, c)| match c {
                    SourceChoice::Dataset(c) if canonical(p) == key => Some(c),
                    _ => None,
                });
                match dataset::open_with(&path, given, None, progress) {
                    Ok(set) => self.report.sets.push(set),
                    Err(e) => self.report.errors.push(e.into()),
                }
            }
        }
    }

    /// A ROS 2 bag opens with the choice given for it, or else the one remembered beside it
    /// ([`bag::choice`]). Without either it is reported with its topics: which are the pusher and
    /// the object, and what the object is, are the user's to say.
    fn load_bag(&mut self, path: &Path, progress: &dyn Progress) {
        let key = canonical(path);
        let given = self.choices.iter().find_map(|(p, c)| match c {
            SourceChoice::Bag(c) if canonical(p) == key => Some(c),
            _ => None,
        });
        let outcome = match given {
            Some(choice) => bag::open_with(path, choice, progress),
            None => match bag::choice::remembered(path) {
                Ok(Some(choice)) => bag::open_with(path, &choice, progress).map_err(|e| match e {
                    BagError::Problem {
                        problem: BagProblem::Cancelled,
                        ..
                    } => e,
                    e => BagError::problem(
                        path,
                        BagProblem::ChoiceFailed {
                            choice_file: bag::choice::choice_path(path),
                            why: e.to_string(),
                        },
                    ),
                }),
                Ok(None) => Err(match bag::topics(path) {
                    Ok(listing) => BagError::problem(path, BagProblem::NeedsImport { listing }),
                    Err(e) => e,
                }),
                Err(e) => Err(e),
            },
        };
        match outcome {
            Ok(set) => self.report.sets.push(set),
            Err(e) => self.report.errors.push(e.into()),
        }
    }

    /// The bags directly inside a set folder: a `setting.json` beside a bag describes its object, so
    /// a folder holding both is opened with its bags.
    fn add_bags_in(&mut self, dir: &Path) {
        let Ok(entries) = files::read_dir(dir) else {
            return; // the set's own reading reports an unreadable folder
        };
        let mut bags: Vec<PathBuf> = entries
            .into_iter()
            .map(|e| e.path)
            .filter(|p| bag::is_bag(p))
            .collect();
        bags.sort();
        for path in bags {
            self.add_bag(&path);
        }
    }

    /// Plans a set (once; a CSV of a set planned whole is not planned again).
    fn add_set(&mut self, dir: &Path, only: Option<&Path>) {
        let whole = canonical(dir);
        if self.seen.contains(&whole) {
            return;
        }
        if let Some(file) = only {
            if !self.seen.insert(canonical(file)) {
                return;
            }
        } else {
            self.seen.insert(whole);
        }
        self.items.push(Item::Set {
            dir: dir.to_path_buf(),
            only: only.map(Path::to_path_buf),
        });
    }

    fn load_set(&mut self, dir: &Path, only: Option<&Path>) {
        match native::read_set_filtered(dir, only) {
            Ok((set, errors)) => {
                if !set.recordings.is_empty() {
                    self.report.sets.push(set);
                }
                self.report
                    .errors
                    .extend(errors.into_iter().map(LoadError::from));
            }
            Err(e) => self.report.errors.push(e.into()),
        }
    }

    /// Plans an MIT file (once).
    fn add_mit(&mut self, path: &Path) {
        if self.seen.insert(canonical(path)) {
            self.items.push(Item::Mit(path.to_path_buf()));
        }
    }

    fn load_mit(&mut self, path: &Path) {
        match mit_push::import_file(path) {
            Ok(push) => {
                let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
                let key = (dir, push.name.surface.clone(), push.name.shape.clone());
                self.mit
                    .entry(key)
                    .or_default()
                    .push((path.to_path_buf(), push));
            }
            Err(e) => self.report.errors.push(e.into()),
        }
    }

    fn finish(mut self) -> LoadReport {
        for ((dir, surface, shape), mut pushes) in std::mem::take(&mut self.mit) {
            pushes.sort_by(|a, b| a.0.cmp(&b.0));
            let first = pushes.first().map(|(p, _)| p.clone()).unwrap_or_default();
            match mit_push::recordings_for(&surface, &shape, pushes) {
                Ok((setting, recordings)) => self.report.sets.push(RecordingSet {
                    dir,
                    setting,
                    recordings,
                }),
                // Unreachable in practice: the shape was checked on import.
                Err(problem) => self.report.errors.push(LoadError::Mit(MitError::Problem {
                    path: first,
                    problem,
                })),
            }
        }
        self.report
    }
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
}

/// Whether the file at `path` is one the loader reads as a recording when it is named: a CSV of a
/// set, or an MIT Push Dataset `.json`/`.h5` — not one of pushlab's own JSON files beside them (the
/// set's `setting.json`, the labels, a bag's or dataset's remembered choice), whose names start
/// with `pushlab-` or hold `.pushlab-`.
pub fn is_recording_file(path: &Path) -> bool {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let pushlabs_own =
        name == SETTING_FILE || name.starts_with("pushlab-") || name.contains(".pushlab-");
    files::is_file(path)
        && match extension(path).as_deref() {
            Some("csv") => true,
            Some("json" | "h5") => !pushlabs_own,
            _ => false,
        }
}

/// Whether a file found while searching a folder is an MIT Push Dataset file (by name: other JSON
/// files, such as the dataset's `shapes.json`, are not recordings).
fn is_mit_file(path: &Path) -> bool {
    matches!(extension(path).as_deref(), Some("json" | "h5"))
        && path
            .file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("motion_"))
}

fn canonical(path: &Path) -> PathBuf {
    files::canonicalize(path).unwrap_or_else(|_| path.to_path_buf())
}
