//! Learning far ahead of the online run off the UI thread (a worker thread on the desktop, a slice
//! of each frame in a page: `platform`).
//!
//! Why: a seek, or a model taken into use, at a frame far past what the run has learned learns every
//! frame between — what playing there would have learned — and on a long recording that is seconds
//! of work (a million frames: about 1.5 s), which on the UI thread would freeze the window. Past
//! [`LEARN_AHEAD_FRAMES`] frames the learning runs on a worker, on a copy of the core run, with a
//! progress bar and Cancel in the Steer tab; the copy takes the run's place when it is done, so the
//! θ and losses are those of learning on the UI thread, to the bit. Meanwhile the run is left alone:
//! θ is held at its frontier, playing learns nothing until the copy is back (then the frames passed
//! meanwhile are learned), and every change to the run — steering, a reset, another update rule,
//! another run — drops the copy first, so a late copy never overwrites it. Cancel is not a change
//! to the run: it stops the copy where it got and keeps what it learned. Nor is a label: one
//! painted while the copy learns (bad tracking, seen in the camera at the frame just sought to) is
//! handed to the worker, which holds θ over it if it has not passed it yet — as on the UI thread,
//! where a label counts from when learning passes it.

use crate::app::platform::{Duration, Instant};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use pushlab_core::learn;

use crate::app::state::job::{Job, take_ended};
use crate::app::state::learning::online::OnlineRun;

/// Frames learned on the UI thread in one go at most (about 15 ms); more are learned on a worker.
pub const LEARN_AHEAD_FRAMES: usize = 10_000;
/// Frames the worker learns between looking for a cancel and reporting its progress.
const BLOCK: usize = 4_096;

/// The copy of the run learning ahead on a worker, if any.
#[derive(Default)]
pub struct LearningAhead {
    job: Option<(Target, Job<learn::OnlineRun>)>,
}

/// Which run a copy learns for, up to which frame, since when, the flag that asks it to stop
/// where it got (Cancel: what it learned is kept; dropping the job instead throws it away), and the
/// frames to hold θ over as the labels are now (read by the worker before each block).
#[derive(Clone, Debug)]
struct Target {
    generation: u64,
    to: usize,
    started: Instant,
    stop: Arc<AtomicBool>,
    skip: Arc<Mutex<Arc<[bool]>>>,
}

/// A copy back from the worker.
pub struct Learned {
    pub run: learn::OnlineRun,
    /// The frame it was to learn up to; it learned up to its frontier.
    pub to: usize,
    pub took: Duration,
}

impl Learned {
    /// Whether it was stopped (Cancel) before `to`.
    pub fn stopped(&self) -> bool {
        self.run.frontier() < self.to
    }
}

impl LearningAhead {
    /// Whether learning frames `from..to` of `run` is too long for the UI thread: frames already
    /// learned are passed over, so only those past the frontier count.
    pub fn is_long(run: &learn::OnlineRun, from: usize, to: usize) -> bool {
        let to = to.min(run.sample_count());
        to.saturating_sub(from.max(run.frontier())) > LEARN_AHEAD_FRAMES
    }

    /// Learns frames `from..to` on a copy of `run` on a worker (replacing any copy under way),
    /// holding θ over the frames `skip` marks; `generation` names the run.
    pub fn start(
        &mut self,
        run: &OnlineRun,
        from: usize,
        to: usize,
        skip: Arc<[bool]>,
        generation: u64,
    ) {
        let to = to.min(run.sample_count());
        let mut copy = learn::OnlineRun::clone(run);
        let stop = Arc::new(AtomicBool::new(false));
        let stopping = Arc::clone(&stop);
        let skip = Arc::new(Mutex::new(skip));
        let labelled = Arc::clone(&skip);
        let job = Job::spawn_in_slices(move |context| async move {
            let mut at = from;
            while at < to {
                if context.is_cancelled() {
                    return None;
                }
                if stopping.load(Ordering::Relaxed) {
                    break;
                }
                let next = (at + BLOCK).min(to);
                let skip = Arc::clone(&labelled.lock().unwrap_or_else(PoisonError::into_inner));
                // Learning `from..to` in blocks is learning it in one go: frame by frame in order.
                copy.learn_through(at, next, &skip);
                context.set_progress((next - from) as f32 / (to - from) as f32);
                at = next;
                pushlab_core::slices::pause().await;
            }
            Some(copy)
        });
        let target = Target {
            generation,
            to,
            started: Instant::now(),
            stop,
            skip,
        };
        self.job = Some((target, job));
    }

    /// The share done and the frame learned up to, while a copy learns.
    pub fn progress(&self) -> Option<(f32, usize)> {
        (self.job.as_ref()).map(|(target, job)| (job.progress(), target.to))
    }

    pub fn is_running(&self) -> bool {
        self.job.is_some()
    }

    /// Drops the copy under way, cancelled, what it learned thrown away (the run is about to
    /// change); whether there was one.
    pub fn cancel(&mut self) -> bool {
        self.job.take().is_some()
    }

    /// Asks the copy under way to stop where it got; it comes back, with what it learned, at a
    /// later [`Self::poll`].
    pub fn stop(&self) {
        if let Some((target, _)) = &self.job {
            target.stop.store(true, Ordering::Relaxed);
        }
    }

    /// Hands the frames to hold θ over, as the labels are now, to the copy under way: it holds θ
    /// over those it has not passed yet.
    pub fn follow_labels(&self, skip: Arc<[bool]>) {
        if let Some((target, _)) = &self.job {
            let mut shared = target.skip.lock().unwrap_or_else(PoisonError::into_inner);
            if !Arc::ptr_eq(&shared, &skip) {
                *shared = skip;
            }
        }
    }

    /// The frames the copy under way holds θ over, as last handed to it.
    #[cfg(test)]
    pub fn labels_handed(&self) -> Option<Arc<[bool]>> {
        let (target, _) = self.job.as_ref()?;
        Some(Arc::clone(
            &target.skip.lock().unwrap_or_else(PoisonError::into_inner),
        ))
    }

    /// The copy once it is back; `None` while it learns, or when it was for another run than the
    /// one of `generation`.
    pub fn poll(&mut self, generation: u64) -> Option<Learned> {
        let (target, copy) = take_ended(&mut self.job)?;
        let run = copy.filter(|_| target.generation == generation)?;
        Some(Learned {
            run,
            to: target.to,
            took: target.started.elapsed(),
        })
    }
}
