//! What is open: the recording sets, the load errors, and which recording is selected.
//!
//! Loading runs on worker threads (`start_loading` + `poll_loading`; in a page, a file a frame, round
//! the queue: `platform`), one per open, side by side, so that the window keeps drawing and opening a second folder never waits for a large first one;
//! each load reports its bytes (the status bar's progress bar) and stops at its next file or chunk
//! when cancelled. Tests and the command line can load synchronously with `open_blocking`.

use crate::app::platform::{self, Duration, Instant};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::mpsc::{Receiver, TryRecvError, channel};

use pushlab_core::recording::bag::BagListing;
use pushlab_core::recording::dataset;
use pushlab_core::recording::{
    BagError, BagProblem, DatasetError, DatasetProblem, LoadError, LoadReport, Recording,
    RecordingSet, SourceChoice, load_paths, load_paths_in_slices,
};
use pushlab_core::recording::{LoadProgress, ProgressSnapshot};

/// Where a recording sits in the session: set index and recording index within the set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct RecordingId {
    pub set: usize,
    pub recording: usize,
}

/// A load error as the user sees it: the file and the reason.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadProblem {
    /// The file or folder the problem is about.
    pub path: PathBuf,
    /// The full message, naming the file and what was expected.
    pub message: String,
    /// A bag that opens once its topics are chosen (again): the browser offers to.
    pub bag_to_choose: bool,
    /// A dataset that may open with its features chosen (again): the browser offers to.
    pub dataset_to_choose: bool,
}

impl LoadProblem {
    fn of(error: &LoadError) -> Self {
        Self {
            path: error.path().to_path_buf(),
            message: error.to_string(),
            bag_to_choose: matches!(
                error,
                LoadError::Bag(BagError::Problem {
                    problem: BagProblem::ChoiceFailed { .. },
                    ..
                })
            ),
            dataset_to_choose: matches!(error, LoadError::Dataset(DatasetError::Problem { path, .. }) if dataset::is_dataset(path)),
        }
    }
}

/// A load running on a worker thread.
struct LoadJob {
    paths: Vec<PathBuf>,
    receiver: Receiver<(LoadReport, Duration)>,
    progress: Arc<LoadProgress>,
    started: Instant,
}

/// The loads under way, as the status bar shows them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Loading {
    /// Paths being opened, over every load.
    pub paths: usize,
    /// Bytes and files read of those planned, over every load.
    pub progress: ProgressSnapshot,
    /// Since the oldest load started.
    pub elapsed: Duration,
}

/// The open recordings and the selection.
#[derive(Default)]
pub struct Session {
    /// Every set opened so far, in opening order.
    pub sets: Vec<RecordingSet>,
    /// Problems of every load so far, newest last. Never cleared by a later load, so a user who opens
    /// many folders still sees what was skipped.
    pub problems: Vec<LoadProblem>,
    /// The recording shown in the scene and plots.
    pub selected: Option<RecordingId>,
    /// How long the last load took on its worker thread (for the status bar and the guide's
    /// figure).
    pub last_load_time: Option<Duration>,
    /// Bags opened without a choice of topics, with their topics: the app asks (see `bag_import`).
    pub bags_to_choose: Vec<(PathBuf, BagListing)>,
    /// Datasets whose pusher and object features are not chosen and cannot be guessed: the app
    /// asks (see `dataset_import`).
    pub datasets_to_choose: Vec<PathBuf>,
    jobs: Vec<LoadJob>,
}

impl Session {
    /// Loads paths on this thread and merges them in, the first recording opened shown. Returns
    /// whether the selection changed.
    pub fn open_blocking(&mut self, paths: &[PathBuf]) -> bool {
        let started = Instant::now();
        let report = load_paths(paths);
        self.merge(report, started.elapsed())
    }

    /// Starts loading paths on a worker thread, beside any load already running (loading only
    /// reads files); returns at once.
    pub fn start_loading(&mut self, paths: Vec<PathBuf>) {
        self.start_loading_choosing(paths, Vec::new());
    }

    /// [`Self::start_loading`], opening the bags and datasets in `choices` with the choice given
    /// for each.
    pub fn start_loading_choosing(
        &mut self,
        paths: Vec<PathBuf>,
        choices: Vec<(PathBuf, SourceChoice)>,
    ) {
        if paths.is_empty() {
            return;
        }
        let (sender, receiver) = channel();
        let progress = Arc::new(LoadProgress::default());
        let (worker_paths, worker_progress) = (paths.clone(), Arc::clone(&progress));
        // In slices: a page reads a file a frame, its bar moving (`platform`).
        platform::spawn_in_slices(move || async move {
            let started = Instant::now();
            let report = load_paths_in_slices(&worker_paths, &choices, &worker_progress).await;
            // The receiver is gone only if the app closed or the load was cancelled.
            let _ = sender.send((report, started.elapsed()));
        });
        self.jobs.push(LoadJob {
            paths,
            receiver,
            progress,
            started: Instant::now(),
        });
    }

    /// Cancels every load under way: each stops at its next file or chunk and what it read is not
    /// added (loading only reads files, so nothing is left half-done). Returns whether one was
    /// running.
    pub fn cancel_loading(&mut self) -> bool {
        for job in &self.jobs {
            job.progress.cancel();
        }
        !std::mem::take(&mut self.jobs).is_empty()
    }

    /// The loads under way, if any.
    pub fn loading(&self) -> Option<Loading> {
        if self.jobs.is_empty() {
            return None;
        }
        Some(Loading {
            paths: self.jobs.iter().map(|j| j.paths.len()).sum(),
            progress: (self.jobs.iter())
                .map(|j| j.progress.snapshot())
                .fold(ProgressSnapshot::default(), ProgressSnapshot::plus),
            elapsed: (self.jobs.iter())
                .map(|j| j.started.elapsed())
                .max()
                .unwrap_or_default(),
        })
    }

    /// Merges the background loads that finished, in the order they finish. Returns whether a new
    /// recording got selected.
    pub fn poll_loading(&mut self) -> bool {
        let mut selected = false;
        for job in std::mem::take(&mut self.jobs) {
            match job.receiver.try_recv() {
                Ok((report, elapsed)) => selected |= self.merge(report, elapsed),
                Err(TryRecvError::Empty) => self.jobs.push(job),
                Err(TryRecvError::Disconnected) => {
                    for path in job.paths {
                        self.problems.push(LoadProblem {
                            message: format!("{}: loading stopped unexpectedly", path.display()),
                            path,
                            bag_to_choose: false,
                            dataset_to_choose: false,
                        });
                    }
                }
            }
        }
        selected
    }

    /// Adds the sets of a report (a set folder opened again replaces its older copy) and its errors.
    fn merge(&mut self, report: LoadReport, elapsed: Duration) -> bool {
        self.last_load_time = Some(elapsed);
        for error in report.errors {
            match error {
                LoadError::Bag(BagError::Problem {
                    path,
                    problem: BagProblem::NeedsImport { listing },
                }) => self.bags_to_choose.push((path, listing)),
                LoadError::Dataset(DatasetError::Problem {
                    path,
                    problem: DatasetProblem::NeedsChoice { .. },
                }) => self.datasets_to_choose.push(path),
                error => self.problems.push(LoadProblem::of(&error)),
            }
        }
        let mut opened = Vec::new();
        for set in report.sets {
            if set.recordings.is_empty() {
                continue;
            }
            // A folder may hold several sets (the MIT files of each shape and surface): a set is its
            // folder and its setting's name, and opening it again replaces it.
            let same = |s: &RecordingSet| s.dir == set.dir && s.setting.name == set.setting.name;
            let index = match self.sets.iter().position(same) {
                Some(i) => {
                    self.sets[i] = joined(&self.sets[i], set);
                    i
                }
                None => {
                    self.sets.push(set);
                    self.sets.len() - 1
                }
            };
            opened.push(index);
        }
        // A replaced set may have fewer recordings than before.
        if let Some(id) = self.selected
            && self.get(id).is_none()
        {
            self.selected = None;
        }
        // What was just opened is shown: its first recording, unless the one shown is in a set
        // opened again (it stays).
        let shown_reopened = self.selected.is_some_and(|id| opened.contains(&id.set));
        match opened.first() {
            Some(&set) if !shown_reopened => {
                self.selected = Some(RecordingId { set, recording: 0 });
                true
            }
            _ => false,
        }
    }

    /// A recording by id.
    pub fn get(&self, id: RecordingId) -> Option<&Recording> {
        self.sets.get(id.set)?.recordings.get(id.recording)
    }

    /// The selected recording.
    pub fn selected_recording(&self) -> Option<&Recording> {
        self.get(self.selected?)
    }

    /// The folder or file the selected recording's set was read from.
    pub fn selected_set_dir(&self) -> Option<&Path> {
        Some(&self.sets.get(self.selected?.set)?.dir)
    }

    /// Every recording with its id, in browser order.
    pub fn recordings(&self) -> impl Iterator<Item = (RecordingId, &Recording)> {
        self.sets.iter().enumerate().flat_map(|(set, s)| {
            s.recordings
                .iter()
                .enumerate()
                .map(move |(recording, r)| (RecordingId { set, recording }, r))
        })
    }

    /// Number of recordings open.
    pub fn recording_count(&self) -> usize {
        self.sets.iter().map(|s| s.recordings.len()).sum()
    }
}

/// A set opened again (`fresh`) joined with what was open of it: each push opened again replaces
/// its older copy where it was; a push not opened again stays while its file does — files of a
/// set opened one at a time (`pushlab open a.csv b.csv`, two drops) add up, while a folder opened
/// again drops the pushes whose files are gone.
fn joined(open: &RecordingSet, mut fresh: RecordingSet) -> RecordingSet {
    let mut recordings = Vec::with_capacity(open.recordings.len().max(fresh.recordings.len()));
    for old in &open.recordings {
        match fresh.recordings.iter().position(|r| r.source == old.source) {
            Some(at) => recordings.push(fresh.recordings.remove(at)),
            None if old.source.is_file() => recordings.push(old.clone()),
            None => {}
        }
    }
    recordings.append(&mut fresh.recordings);
    fresh.recordings = recordings;
    fresh
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_data() -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("sample-data")
    }

    #[test]
    fn a_missing_path_is_reported_by_name_and_keeps_what_is_open() {
        let mut session = Session::default();
        if sample_data().is_dir() {
            assert!(session.open_blocking(&[sample_data()]));
        }
        let open_before = session.recording_count();
        let missing = PathBuf::from("/nonexistent/pushes-42");
        assert!(!session.open_blocking(std::slice::from_ref(&missing)));
        assert_eq!(session.recording_count(), open_before);
        assert_eq!(session.problems.len(), 1);
        assert_eq!(session.problems[0].path, missing);
        assert!(session.problems[0].message.contains("pushes-42"));
    }

    #[test]
    fn files_of_one_set_opened_apart_add_up_and_a_folder_opened_again_drops_deleted_files() {
        let set = sample_data().join("box1-paper-ur-front");
        let scratch = std::env::temp_dir().join(format!("pushlab-join-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&scratch);
        std::fs::create_dir_all(&scratch).expect("a scratch folder");
        for name in [
            "setting.json",
            "online_000.csv",
            "online_001.csv",
            "online_002.csv",
        ] {
            std::fs::copy(set.join(name), scratch.join(name)).expect("a copy of the sample set");
        }
        let names = |session: &Session| -> Vec<String> {
            (session.recordings())
                .map(|(_, r)| r.name.clone())
                .collect()
        };
        let mut session = Session::default();
        // Together, then one more later (a second drop): all three, in the order opened.
        session.open_blocking(&[
            scratch.join("online_001.csv"),
            scratch.join("online_000.csv"),
        ]);
        session.open_blocking(&[scratch.join("online_002.csv")]);
        assert_eq!(names(&session).len(), 3, "{:?}", names(&session));
        // Opening one again replaces its copy where it was.
        session.open_blocking(&[scratch.join("online_001.csv")]);
        assert_eq!(names(&session).len(), 3);
        // The folder opened again after a file was deleted: that push is gone, the rest stay.
        std::fs::remove_file(scratch.join("online_000.csv")).expect("the file deleted");
        session.open_blocking(std::slice::from_ref(&scratch));
        let mut left = names(&session);
        left.sort();
        assert_eq!(left, ["online_001", "online_002"]);
        let _ = std::fs::remove_dir_all(&scratch);
    }

    #[test]
    fn opening_the_same_folder_twice_does_not_duplicate_sets() {
        if !sample_data().is_dir() {
            eprintln!("skipped: no sample-data folder yet");
            return;
        }
        let mut session = Session::default();
        session.open_blocking(&[sample_data()]);
        let (sets, recordings) = (session.sets.len(), session.recording_count());
        assert!(recordings > 0);
        session.open_blocking(&[sample_data()]);
        assert_eq!(session.sets.len(), sets);
        assert_eq!(session.recording_count(), recordings);
        assert_eq!(
            session.selected,
            Some(RecordingId {
                set: 0,
                recording: 0
            })
        );
    }

    #[test]
    fn a_folder_of_mit_files_of_four_shapes_opens_as_four_sets_of_all_its_files() {
        let Some(dir) = crate::skip::shared(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")),
            "mit-push-abs-train",
        ) else {
            return;
        };
        let mut session = Session::default();
        session.open_blocking(std::slice::from_ref(&dir));
        // Every set shares the folder; before sets were told apart by name, each replaced the last.
        assert_eq!(session.sets.len(), 4);
        assert_eq!(session.recording_count(), 50);
        session.open_blocking(std::slice::from_ref(&dir));
        assert_eq!(session.recording_count(), 50, "opening again replaces");
    }

    #[test]
    fn a_second_open_starts_at_once_beside_the_first() {
        let mut session = Session::default();
        session.start_loading(vec![sample_data()]);
        session.start_loading(vec![PathBuf::from("/nonexistent/b")]);
        // Neither was waited for: both are under way until polled.
        assert_eq!(session.loading().map(|l| l.paths), Some(2));
        let deadline = Instant::now() + Duration::from_secs(60);
        while session.loading().is_some() && Instant::now() < deadline {
            session.poll_loading();
            std::thread::sleep(Duration::from_millis(5));
        }
        assert!(session.recording_count() > 0, "{:?}", session.problems);
        assert_eq!(session.problems.len(), 1, "{:?}", session.problems);
        assert!(session.problems[0].message.contains("/nonexistent/b"));
    }

    #[test]
    fn background_loading_arrives_through_poll() {
        let mut session = Session::default();
        session.start_loading(vec![PathBuf::from("/nonexistent/a")]);
        assert!(session.loading().is_some());
        let deadline = Instant::now() + Duration::from_secs(10);
        while session.loading().is_some() && Instant::now() < deadline {
            session.poll_loading();
            std::thread::sleep(Duration::from_millis(5));
        }
        assert!(session.loading().is_none());
        assert_eq!(session.problems.len(), 1);
    }
}
