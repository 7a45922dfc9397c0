//! Work on a worker thread that the UI thread polls: one result, the share done, and cancel.
//!
//! Why one type: the app runs its searches and reads — the best θ, the loss landscape, label
//! proposals, a bag's topics, a dataset's features — off the UI thread the same way: a cancel flag
//! the worker checks, a share done that a progress bar reads, one result over a channel, a job
//! replaced or dropped cancelled, a cancelled job's late result never delivered, and a worker that
//! died told apart from one still running. Each sub-state had written that plumbing again, and
//! copies drift (one forgot to cancel on drop, another to say the worker stopped); here it is once.
//! Offline training (a stream of epochs) and loading (the core's own `LoadProgress`) report more
//! than one result and keep their own channels.

use std::future::Future;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError, channel};

/// A running job's owner side, polled by the UI thread. Dropping it cancels the work.
pub struct Job<T> {
    shared: Arc<Shared>,
    receiver: Receiver<T>,
}

/// What the worker sees of its job: whether it was cancelled, and where to report the share done.
pub struct JobContext {
    shared: Arc<Shared>,
}

#[derive(Default)]
struct Shared {
    cancelled: AtomicBool,
    /// The most of the job reported done, in [0, 1], as `f32` bits (which, for non-negative
    /// floats, sort as the floats do: the highest report wins, whichever thread made it last).
    done: AtomicU32,
}

/// What a poll found.
#[derive(Debug, PartialEq)]
pub enum Polled<T> {
    /// Still working.
    Running,
    /// Finished with this result.
    Done(T),
    /// Ended without a result: the work returned none, the job was cancelled, its thread
    /// panicked, or its result was taken by an earlier poll.
    Stopped,
}

impl<T: Send + 'static> Job<T> {
    /// Starts `work` off the UI thread (`platform::spawn`). Its result is delivered unless it is
    /// `None` or the job was cancelled meanwhile.
    pub fn spawn(work: impl FnOnce(&JobContext) -> Option<T> + Send + 'static) -> Self {
        Self::spawn_in_slices(move |context| async move { work(&context) })
    }

    /// [`Self::spawn`] for work written in slices (`pushlab_core::slices`): to its end on a thread
    /// on the desktop, a slice of each frame in a page (`platform::spawn_in_slices`). `work` is
    /// given the job's context to keep: it checks the cancel and reports progress across its
    /// pauses.
    pub fn spawn_in_slices<F>(work: impl FnOnce(JobContext) -> F + Send + 'static) -> Self
    where
        F: Future<Output = Option<T>> + 'static,
    {
        let shared = Arc::new(Shared::default());
        let context = JobContext {
            shared: Arc::clone(&shared),
        };
        let (sender, receiver) = channel();
        crate::app::platform::spawn_in_slices(move || {
            let after = JobContext {
                shared: Arc::clone(&context.shared),
            };
            let work = work(context);
            async move {
                if let Some(result) = work.await
                    && !after.is_cancelled()
                {
                    // The receiver is gone only when the job was dropped meanwhile: nobody wants it.
                    let _ = sender.send(result);
                }
            }
        });
        Self { shared, receiver }
    }
}

impl<T> Job<T> {
    /// Asks the worker to stop at its next check; its result, if any, is not delivered.
    pub fn cancel(&self) {
        self.shared.cancelled.store(true, Ordering::Relaxed);
    }

    /// The most of the job the worker reported done, in [0, 1].
    pub fn progress(&self) -> f32 {
        f32::from_bits(self.shared.done.load(Ordering::Relaxed))
    }

    /// Takes the result if the work finished, without waiting. A cancelled job has none, even
    /// when the work finished just before the cancel was seen.
    pub fn poll(&self) -> Polled<T> {
        if self.is_cancelled() {
            return Polled::Stopped;
        }
        match self.receiver.try_recv() {
            Ok(result) => Polled::Done(result),
            Err(TryRecvError::Empty) => Polled::Running,
            Err(TryRecvError::Disconnected) => Polled::Stopped,
        }
    }

    /// Waits for the result (work started from the command line, tests); `None` whenever
    /// [`Self::poll`] would say [`Polled::Stopped`].
    /// In a page, where work waits for the one thread, the queued work is run here until the
    /// result is in (`platform::run_queued`; on the desktop nothing is queued and this blocks).
    pub fn wait(&self) -> Option<T> {
        let result = loop {
            match self.receiver.try_recv() {
                Ok(result) => break Some(result),
                Err(TryRecvError::Disconnected) => break None,
                Err(TryRecvError::Empty) if crate::app::platform::run_queued() => {}
                Err(TryRecvError::Empty) => break self.receiver.recv().ok(),
            }
        };
        result.filter(|_| !self.is_cancelled())
    }

    fn is_cancelled(&self) -> bool {
        self.shared.cancelled.load(Ordering::Relaxed)
    }
}

/// Takes the job kept in `slot` beside what it is for, once it has ended: `None` while it runs (it
/// stays in `slot`); otherwise what it was for and its result (`None`: it stopped without one).
pub fn take_ended<K, T>(slot: &mut Option<(K, Job<T>)>) -> Option<(K, Option<T>)> {
    let result = match slot.as_ref()?.1.poll() {
        Polled::Running => return None,
        Polled::Done(result) => Some(result),
        Polled::Stopped => None,
    };
    slot.take().map(|(key, _)| (key, result))
}

/// The share done of the job kept in `slot` when it is for `key` (`None` when none runs, or the one
/// running is for something else: a run selected away from goes on unseen).
pub fn progress_of<K: PartialEq, T>(slot: &Option<(K, Job<T>)>, key: &K) -> Option<f32> {
    let (_, job) = slot.as_ref().filter(|(for_key, _)| for_key == key)?;
    Some(job.progress())
}

impl<T> Drop for Job<T> {
    fn drop(&mut self) {
        self.cancel();
    }
}

impl JobContext {
    /// Whether the job was cancelled or dropped: the work should stop and return.
    pub fn is_cancelled(&self) -> bool {
        self.shared.cancelled.load(Ordering::Relaxed)
    }

    /// Reports the share done (clamped to [0, 1]); a report below an earlier one is ignored, so
    /// that a bar fed from several threads never steps back.
    pub fn set_progress(&self, done: f32) {
        let done = if done.is_nan() {
            0.0
        } else {
            done.clamp(0.0, 1.0)
        };
        self.shared
            .done
            .fetch_max(done.to_bits(), Ordering::Relaxed);
    }

    /// A cancel check for core functions that take one and call it a known number of `times`
    /// (the best-θ search's polls, the landscape's rows): each call counts as that share done.
    /// The check may be called from several threads at once (the landscape's rows run on both
    /// cores).
    pub fn counting_checks(&self, times: usize) -> impl Fn() -> bool + Sync + '_ {
        let calls = AtomicUsize::new(0);
        move || {
            let calls = calls.fetch_add(1, Ordering::Relaxed) + 1;
            self.set_progress(calls as f32 / times.max(1) as f32);
            self.is_cancelled()
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::mpsc::sync_channel;
    use std::time::{Duration, Instant};

    use super::*;

    /// Polls until the job is no longer running (a test's worker takes milliseconds).
    fn settle<T>(job: &Job<T>) -> Polled<T> {
        let deadline = Instant::now() + Duration::from_secs(10);
        loop {
            match job.poll() {
                Polled::Running if Instant::now() < deadline => {
                    std::thread::sleep(Duration::from_millis(1))
                }
                other => return other,
            }
        }
    }

    #[test]
    fn a_finished_job_delivers_its_result_once() {
        let job = Job::spawn(|_| Some(42));
        assert_eq!(settle(&job), Polled::Done(42));
        assert_eq!(settle(&job), Polled::Stopped);
    }

    #[test]
    fn a_cancelled_job_delivers_nothing_even_if_the_work_finishes() {
        let (go, wait) = sync_channel::<()>(0);
        let job = Job::spawn(move |_| {
            wait.recv().ok();
            Some("late")
        });
        job.cancel();
        go.send(()).expect("the worker waits for go");
        assert_eq!(settle(&job), Polled::Stopped);
    }

    #[test]
    fn dropping_a_job_cancels_its_work() {
        let (seen, cancelled) = sync_channel(1);
        let (go, wait) = sync_channel::<()>(0);
        let job = Job::<()>::spawn(move |context| {
            wait.recv().ok();
            seen.send(context.is_cancelled()).ok();
            None
        });
        drop(job);
        go.send(()).expect("the worker waits for go");
        assert_eq!(cancelled.recv_timeout(Duration::from_secs(10)), Ok(true));
    }

    #[test]
    fn a_panicking_worker_is_told_apart_from_a_running_one() {
        let job = Job::<u8>::spawn(|_| panic!("worker failed on purpose"));
        assert_eq!(settle(&job), Polled::Stopped);
    }

    #[test]
    fn take_ended_leaves_a_running_job_and_takes_an_ended_one() {
        let (go, wait) = sync_channel::<()>(0);
        let mut slot = Some((
            "for this",
            Job::spawn(move |_| {
                wait.recv().ok();
                Some(7)
            }),
        ));
        assert_eq!(take_ended(&mut slot), None);
        assert!(slot.is_some());
        go.send(()).expect("the worker waits for go");
        let deadline = Instant::now() + Duration::from_secs(10);
        let ended = loop {
            match take_ended(&mut slot) {
                None if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(1)),
                ended => break ended,
            }
        };
        assert_eq!(ended, Some(("for this", Some(7))));
        assert!(slot.is_none());
    }

    #[test]
    fn progress_never_steps_back() {
        let (reported, results) = sync_channel(1);
        let job = Job::<()>::spawn(move |context| {
            context.set_progress(0.5);
            context.set_progress(0.25);
            reported.send(()).ok();
            None
        });
        results
            .recv_timeout(Duration::from_secs(10))
            .expect("the worker reports");
        assert_eq!(job.progress(), 0.5);
    }

    #[test]
    fn counting_checks_report_their_share_and_the_cancel() {
        let (go, wait) = sync_channel::<()>(0);
        let (polled, results) = sync_channel(2);
        let job = Job::<()>::spawn(move |context| {
            let check = context.counting_checks(4);
            polled.send(check()).ok();
            wait.recv().ok();
            polled.send(check()).ok();
            None
        });
        assert_eq!(results.recv_timeout(Duration::from_secs(10)), Ok(false));
        assert_eq!(job.progress(), 0.25);
        job.cancel();
        go.send(()).expect("the worker waits for go");
        assert_eq!(results.recv_timeout(Duration::from_secs(10)), Ok(true));
        assert_eq!(job.progress(), 0.5);
    }
}
