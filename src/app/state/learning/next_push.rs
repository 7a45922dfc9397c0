//! The Steer tab's "next push that teaches the most": the other open pushes of the object shown,
//! ranked by how much each is expected to shrink the COM's uncertainty after what the run has
//! learned — pushlab-core's `experiment::suggest::rank`, the ranking `pushlab suggest` prints —
//! found off the UI thread (a candidate a slice in a page) with progress and cancel.
//!
//! The candidates are the object's other open recordings; with none open (one file, a live push),
//! the core's default grid of pushes laid out on the object (`experiment::suggest::PushGrid`, what
//! `pushlab suggest --grid` lays out).
//!
//! Why in the app: one push leaves the COM's depth along the pushed face unseen, and a researcher
//! choosing what to push next wants the push that shows it. The ranking belongs to the run and the
//! frame it was asked at (the posterior there): another model or recording makes it stale and it
//! is not shown; a later frame leaves it shown, with the frame it is for. The scene draws the best
//! few as arrows on the object.

use pushlab_core::experiment::suggest::{Criterion, PushGrid, Ranking, rank_in_slices};
use pushlab_core::recording::Recording;

use crate::app::state::job::{Job, progress_of, take_ended};
use crate::app::state::learning::online::{OnlineRun, RunIdentity};

/// How many suggestions the scene draws as arrows.
pub const ARROWS: usize = 3;

/// A change to the next-push ranking.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NextPushCommand {
    /// Rank the object's other open pushes now (replacing any ranking under way).
    Suggest,
    /// Stop the ranking under way.
    Cancel,
}

/// The grid of pushes the app ranks when no other push of the object is open: the core's default,
/// what `pushlab suggest --grid` lays out unless told otherwise.
pub fn grid() -> PushGrid {
    PushGrid::default()
}

/// What the ranking chooses among.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Candidates {
    /// The object's other open recordings.
    Open,
    /// A grid of pushes laid out on the object (no other recording of it is open); the grid
    /// points that cannot be pushed, each a sentence.
    Grid { left_out: Vec<String> },
}

/// A finished ranking and what it is for.
#[derive(Clone, Debug, PartialEq)]
pub struct NextPushResult {
    /// The ranking; each suggestion's `push` indexes the candidates it was given.
    pub ranking: Ranking,
    /// Where the candidates came from.
    pub candidates: Candidates,
    /// The frame the run had learned up to when it was ranked.
    pub frame: usize,
    run: RunIdentity,
}

/// The ranking's state: the last result and the ranking under way (with the run it is for).
#[derive(Default)]
pub struct NextPushState {
    result: Option<NextPushResult>,
    /// Why the last ranking failed (an object whose outline cannot be read), for the run it was for.
    problem: Option<(RunIdentity, String)>,
    job: Option<(RunIdentity, Job<Result<NextPushResult, String>>)>,
}

/// Pushes to rank and where they came from.
pub struct ToRank {
    pub pushes: Vec<Recording>,
    pub from: Candidates,
}

impl NextPushState {
    /// Applies a command; `Suggest` ranks `candidates` for `run`.
    pub fn apply(&mut self, command: NextPushCommand, run: Option<&OnlineRun>, candidates: ToRank) {
        // A ranking replaced or cancelled is dropped, which cancels it.
        self.job = None;
        if let (NextPushCommand::Suggest, Some(run)) = (command, run) {
            self.start(run, candidates);
        }
    }

    /// The last ranking, when it belongs to `run`.
    pub fn result_for(&self, run: &OnlineRun) -> Option<&NextPushResult> {
        self.result.as_ref().filter(|r| r.run == run.identity())
    }

    /// Why the last ranking for `run` failed, if it did.
    pub fn problem_for(&self, run: &OnlineRun) -> Option<&str> {
        let (for_run, problem) = self.problem.as_ref()?;
        (*for_run == run.identity()).then_some(problem.as_str())
    }

    /// The share done of the ranking under way for `run`, or `None` when none runs for it.
    pub fn progress_for(&self, run: &OnlineRun) -> Option<f32> {
        progress_of(&self.job, &run.identity())
    }

    /// Whether a ranking is under way.
    pub fn is_running(&self) -> bool {
        self.job.is_some()
    }

    /// Takes a finished ranking; returns whether one is still running.
    pub fn poll(&mut self) -> bool {
        match take_ended(&mut self.job) {
            None => self.job.is_some(),
            Some((for_run, ended)) => {
                match ended {
                    Some(Ok(result)) => {
                        self.result = Some(result);
                        self.problem = None;
                    }
                    Some(Err(problem)) => self.problem = Some((for_run, problem)),
                    None => {}
                }
                false
            }
        }
    }

    fn start(&mut self, run: &OnlineRun, candidates: ToRank) {
        let model = std::sync::Arc::clone(run.model());
        let horizon = run.horizon();
        let state = run.end_state();
        let frame = run.frontier();
        let identity = run.identity();
        let for_job = identity.clone();
        let ToRank { pushes, from } = candidates;
        let job = Job::spawn_in_slices(move |context| async move {
            let count = pushes.len().max(1);
            let done = std::cell::Cell::new(0usize);
            let cancelled = || {
                context.set_progress(done.get() as f32 / count as f32);
                done.set(done.get() + 1);
                context.is_cancelled()
            };
            let given: Vec<(usize, &Recording)> = pushes.iter().enumerate().collect();
            let ranked = rank_in_slices(
                model.as_ref(),
                horizon,
                &state,
                &given,
                Criterion::default(),
                &cancelled,
            )
            .await;
            match ranked {
                Ok(ranking) => Some(Ok(NextPushResult {
                    ranking: ranking?,
                    candidates: from,
                    frame,
                    run: for_job,
                })),
                Err(e) => Some(Err(format!("the object's outline: {e}"))),
            }
        });
        self.job = Some((identity, job));
    }
}
