//! The Steer tab's "best θ for this push": the `θ_online` that fits the whole recording shown best,
//! held fixed over it — pushlab-core's `experiment::best_fit`, the one `pushlab eval --best-fit`
//! reports — found off the UI thread (a worker thread on the desktop, a slice of each frame in a page:
//! `platform`) with progress and cancel.
//!
//! Why in the app: an engineer watching online learning wants to know whether a COM far from the
//! truth is the learner's fault (it would do better with other steps) or the model's (no `θ` fits
//! the push better near the truth). The best fit answers that for the push shown, and "use it"
//! steers `θ` there to see how the model predicts with it. It is found over the samples online
//! learning takes (those on frames labelled bad tracking left out, as when it was asked for), and
//! belongs to the run's model and recording: another model or recording makes it stale, and it is
//! not shown. The UI thread only polls.

use std::sync::Arc;

use pushlab_core::experiment::{BEST_FIT_POLLS, BestFit, best_fit_in_slices};
use pushlab_core::model::samples_kept;

use crate::app::state::job::{Job, progress_of, take_ended};
use crate::app::state::learning::online::{OnlineRun, RunIdentity};

/// A change to the best-θ search.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BestFitCommand {
    /// Find the best θ for the recording shown (replacing any search under way).
    Find,
    /// Stop the search under way.
    Cancel,
}

/// A finished search: the best fit, or `None` when the recording had no sample to fit.
#[derive(Clone, Debug, PartialEq)]
pub struct BestFitResult {
    pub fit: Option<BestFit>,
    run: RunIdentity,
}

/// The search's state: the last result and the search under way (with the run it is for).
#[derive(Default)]
pub struct BestFitState {
    result: Option<BestFitResult>,
    job: Option<(RunIdentity, Job<Option<BestFit>>)>,
}

impl BestFitState {
    /// Applies a command; `Find` searches along `run` leaving out the samples `skip` marks.
    pub fn apply(&mut self, command: BestFitCommand, run: Option<&OnlineRun>, skip: &[bool]) {
        // A search replaced or cancelled is dropped, which cancels it.
        self.job = None;
        if let (BestFitCommand::Find, Some(run)) = (command, run) {
            self.start(run, skip);
        }
    }

    /// The last result, when it belongs to `run` (a result for another model or recording is
    /// stale).
    pub fn result_for(&self, run: &OnlineRun) -> Option<&BestFitResult> {
        self.result.as_ref().filter(|r| r.run == run.identity())
    }

    /// The share done of the search under way for `run`, or `None` when none runs for it (one for
    /// another recording or model, selected since, goes on unseen until it ends or a new search
    /// replaces it).
    pub fn progress_for(&self, run: &OnlineRun) -> Option<f32> {
        progress_of(&self.job, &run.identity())
    }

    /// Takes a finished search; returns whether one is still running.
    pub fn poll(&mut self) -> bool {
        match take_ended(&mut self.job) {
            None => self.job.is_some(),
            Some((for_run, fit)) => {
                if let Some(fit) = fit {
                    self.result = Some(BestFitResult { fit, run: for_run });
                }
                false
            }
        }
    }

    fn start(&mut self, run: &OnlineRun, skip: &[bool]) {
        let samples = samples_kept(run.trajectory(), run.horizon(), skip);
        let model = Arc::clone(run.model());
        let job = Job::spawn_in_slices(move |context| async move {
            let checks = context.counting_checks(BEST_FIT_POLLS);
            Some(best_fit_in_slices(model.as_ref(), &samples, &checks).await)
        });
        self.job = Some((run.identity(), job));
    }
}
