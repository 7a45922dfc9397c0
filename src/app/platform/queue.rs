//! A page's queue of work waiting for its one thread: each call of [`WorkQueue::run_slice`] polls
//! the oldest item for up to a budget of time, then puts it back at the end if it has not ended.
//!
//! Why round the queue: a training a user left running for minutes must not hold back the loss
//! landscape or a bag's topics asked for meanwhile, as it does not on the desktop, where each has
//! a thread. Why a budget and not one pause: a pause comes every millisecond or so of a training's
//! work; a frame's slice of a dozen milliseconds gets through the work at most of the speed it has
//! alone while the page still draws.

use std::collections::VecDeque;
use std::future::Future;
use std::pin::Pin;

use pushlab_core::slices;

use web_time::{Duration, Instant};

/// One item: work in slices, or work in one piece wrapped as work that ends at its first poll.
pub type Work = Pin<Box<dyn Future<Output = ()>>>;

/// The work waiting, oldest first.
#[derive(Default)]
pub struct WorkQueue {
    waiting: VecDeque<Work>,
}

impl WorkQueue {
    pub fn push(&mut self, work: Work) {
        self.waiting.push_back(work);
    }

    pub fn is_empty(&self) -> bool {
        self.waiting.is_empty()
    }

    /// Takes the oldest item out, to be polled while the queue is free for the work to queue more.
    pub fn pop(&mut self) -> Option<Work> {
        self.waiting.pop_front()
    }
}

/// The fewest and the most time a frame gives the work queued (see [`slice_budget`]).
pub const SLICE_BUDGET: (Duration, Duration) =
    (Duration::from_millis(16), Duration::from_millis(100));

/// How long the next slice may run: as long as the page spent on everything else since the last
/// slice ended (drawing, the browser's own work), within [`SLICE_BUDGET`], so that work queued
/// gets about half of the page's time whatever its frame rate. Measured in headless chromium on
/// SwiftShader on this 2-core machine, a frame takes 200–400 ms of which the app's own is 20–60
/// ms: a fixed 16 ms slice left a demo's training a twentieth of the time (6.4 s where it froze the
/// page for 1.5 s in one piece). `None`: no slice ran before.
pub fn slice_budget(since_last_slice: Option<Duration>) -> Duration {
    let (least, most) = SLICE_BUDGET;
    since_last_slice.map_or(least, |d| d.clamp(least, most))
}

/// Polls `work` until it ends or `budget` has passed since `start`; gives it back if it has not
/// ended (to go at the end of the queue).
pub fn run_slice(mut work: Work, start: Instant, budget: Duration) -> Option<Work> {
    loop {
        if slices::poll_once(work.as_mut()).is_some() {
            return None;
        }
        if start.elapsed() >= budget {
            return Some(work);
        }
    }
}

#[cfg(test)]
mod tests {
    use std::cell::RefCell;
    use std::rc::Rc;

    use super::*;

    /// Work that notes its name at each of `slices` slices.
    fn noting(name: &'static str, slices: usize, log: Rc<RefCell<Vec<&'static str>>>) -> Work {
        Box::pin(async move {
            for _ in 0..slices {
                log.borrow_mut().push(name);
                pushlab_core::slices::pause().await;
            }
        })
    }

    #[test]
    fn work_left_unfinished_goes_behind_the_work_queued_after_it() {
        let log = Rc::new(RefCell::new(Vec::new()));
        let mut queue = WorkQueue::default();
        queue.push(noting("training", 3, log.clone()));
        queue.push(noting("landscape", 1, log.clone()));
        // A budget of zero: one slice a turn.
        while let Some(work) = queue.pop() {
            if let Some(unfinished) = run_slice(work, Instant::now(), Duration::ZERO) {
                queue.push(unfinished);
            }
        }
        assert!(queue.is_empty());
        assert_eq!(
            *log.borrow(),
            ["training", "landscape", "training", "training"]
        );
    }

    #[test]
    fn a_slice_lasts_as_long_as_the_page_spent_elsewhere_within_bounds() {
        let ms = Duration::from_millis;
        assert_eq!(slice_budget(None), ms(16));
        assert_eq!(slice_budget(Some(ms(2))), ms(16));
        assert_eq!(slice_budget(Some(ms(40))), ms(40));
        assert_eq!(slice_budget(Some(ms(5_000))), ms(100));
    }

    #[test]
    fn a_budget_runs_many_slices_in_one_turn() {
        let log = Rc::new(RefCell::new(Vec::new()));
        let work = noting("training", 50, log.clone());
        assert!(run_slice(work, Instant::now(), Duration::from_secs(60)).is_none());
        assert_eq!(log.borrow().len(), 50);
    }
}
