//! What is open: the recording sets, the load errors, and which recording is selected.
//!
//! Loading runs on a worker thread (`start_loading` + `poll_loading`) so that the window keeps
//! drawing; tests and the command line can load synchronously with `open_blocking`.

use std::path::PathBuf;
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::time::{Duration, Instant};

use pushlab_core::recording::bag::{BagChoice, TopicInfo};
use pushlab_core::recording::{
    BagProblem, LoadError, LoadReport, Recording, RecordingSet, load_paths, load_paths_choosing,
};

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
}

impl LoadProblem {
    fn of(error: &LoadError) -> Self {
        Self {
            path: error.path().to_path_buf(),
            message: error.to_string(),
            bag_to_choose: matches!(
                error,
                LoadError::Bag {
                    problem: BagProblem::ChoiceFailed { .. },
                    ..
                }
            ),
        }
    }
}

/// A load running on a worker thread.
struct LoadJob {
    paths: Vec<PathBuf>,
    receiver: Receiver<(LoadReport, Duration)>,
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
    pub bags_to_choose: Vec<(PathBuf, Vec<TopicInfo>)>,
    job: Option<LoadJob>,
}

impl Session {
    /// Loads paths on this thread and merges them in. Returns whether a new recording got selected.
    pub fn open_blocking(&mut self, paths: &[PathBuf]) -> bool {
        let started = Instant::now();
        let report = load_paths(paths);
        self.merge(report, started.elapsed())
    }

    /// Starts loading paths on a worker thread; a load already running keeps running and this one is
    /// queued behind it by simply loading in parallel (loading only reads files).
    pub fn start_loading(&mut self, paths: Vec<PathBuf>) {
        self.start_loading_choosing(paths, Vec::new());
    }

    /// [`Self::start_loading`], opening the bags in `choices` with the choice given for each.
    pub fn start_loading_choosing(
        &mut self,
        paths: Vec<PathBuf>,
        choices: Vec<(PathBuf, BagChoice)>,
    ) {
        if paths.is_empty() {
            return;
        }
        if let Some(job) = self.job.take() {
            // Finish the older job first so that its results are not lost.
            if let Ok((report, elapsed)) = job.receiver.recv() {
                self.merge(report, elapsed);
            }
        }
        let (sender, receiver) = channel();
        let worker_paths = paths.clone();
        std::thread::spawn(move || {
            let started = Instant::now();
            let report = load_paths_choosing(&worker_paths, &choices);
            // The receiver is gone only if the app closed; nothing to report then.
            let _ = sender.send((report, started.elapsed()));
        });
        self.job = Some(LoadJob { paths, receiver });
    }

    /// Stops waiting for the load under way: its results are dropped when the worker finishes
    /// (loading only reads files, so nothing is left half-done). Returns whether one was running.
    pub fn cancel_loading(&mut self) -> bool {
        self.job.take().is_some()
    }

    /// The paths being loaded right now, if any.
    pub fn loading(&self) -> Option<&[PathBuf]> {
        self.job.as_ref().map(|j| j.paths.as_slice())
    }

    /// Merges a finished background load. Returns whether a new recording got selected.
    pub fn poll_loading(&mut self) -> bool {
        let Some(job) = &self.job else {
            return false;
        };
        match job.receiver.try_recv() {
            Ok((report, elapsed)) => {
                self.job = None;
                self.merge(report, elapsed)
            }
            Err(TryRecvError::Empty) => false,
            Err(TryRecvError::Disconnected) => {
                let paths = self.job.take().map(|j| j.paths).unwrap_or_default();
                for path in paths {
                    self.problems.push(LoadProblem {
                        message: format!("{}: loading stopped unexpectedly", path.display()),
                        path,
                        bag_to_choose: false,
                    });
                }
                false
            }
        }
    }

    /// Adds the sets of a report (a set folder opened again replaces its older copy) and its errors.
    fn merge(&mut self, report: LoadReport, elapsed: Duration) -> bool {
        self.last_load_time = Some(elapsed);
        for error in report.errors {
            match error {
                LoadError::Bag {
                    path,
                    problem: BagProblem::NeedsImport { topics },
                } => self.bags_to_choose.push((path, topics)),
                error => self.problems.push(LoadProblem::of(&error)),
            }
        }
        let mut first_new = None;
        for set in report.sets {
            if set.recordings.is_empty() {
                continue;
            }
            // A folder may hold several sets (the MIT files of each shape and surface): a set is its
            // folder and its setting's name, and opening it again replaces it.
            let same = |s: &RecordingSet| s.dir == set.dir && s.setting.name == set.setting.name;
            let index = match self.sets.iter().position(same) {
                Some(i) => {
                    self.sets[i] = set;
                    i
                }
                None => {
                    self.sets.push(set);
                    self.sets.len() - 1
                }
            };
            first_new.get_or_insert(index);
        }
        // A replaced set may have fewer recordings than before.
        if let Some(id) = self.selected
            && self.get(id).is_none()
        {
            self.selected = None;
        }
        match (self.selected, first_new) {
            (None, Some(set)) => {
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
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/mit-push-abs-train");
        if !dir.is_dir() {
            eprintln!("skipped: {} is missing", dir.display());
            return;
        }
        let mut session = Session::default();
        session.open_blocking(std::slice::from_ref(&dir));
        // Every set shares the folder; before sets were told apart by name, each replaced the last.
        assert_eq!(session.sets.len(), 4);
        assert_eq!(session.recording_count(), 50);
        session.open_blocking(std::slice::from_ref(&dir));
        assert_eq!(session.recording_count(), 50, "opening again replaces");
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
