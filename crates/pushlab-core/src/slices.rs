//! Long work that can stop between two slices and go on later: offline training, loading, the best
//! θ, the loss landscape and label proposals, each written once as an `async fn` that [`pause`]s
//! where it checks for a cancel.
//!
//! Why: a browser tab has one thread, and the app's page draws its frames on it. Work that runs to
//! its end there freezes the page — a demo's training froze it for 1.5 s, a Train tab run on real
//! recordings for minutes, with a Cancel button that could not be pressed. Written as a future, the
//! same code is a state machine the page polls for a slice of each frame (`app::platform`), while
//! the desktop's worker thread and the command line run it to the end with [`finish`]. There is
//! one copy of each rule: the blocking functions (`learn::train_paper`, `experiment::train_combined`,
//! `recording::load_paths_with`, `experiment::best_fit`, …) are [`finish`] over their `_in_slices`
//! twins.
//!
//! Nothing here knows of a clock or of the page: a pause only says "a slice may end here"; whoever
//! polls decides how long a slice is.

use std::future::Future;
use std::pin::{Pin, pin};
use std::task::{Context, Poll, Waker};

/// A point where work run in slices may stop until its next poll. Polled to the end by
/// [`finish`], it costs one return and one resume.
pub fn pause() -> Pause {
    Pause { paused: false }
}

/// The future [`pause`] returns: pending once, then done.
#[derive(Debug)]
#[must_use = "a pause does nothing unless awaited"]
pub struct Pause {
    paused: bool,
}

impl Future for Pause {
    type Output = ();

    fn poll(mut self: Pin<&mut Self>, context: &mut Context<'_>) -> Poll<()> {
        if self.paused {
            return Poll::Ready(());
        }
        self.paused = true;
        // Ready to go on at once: whoever polls decides when.
        context.waker().wake_by_ref();
        Poll::Pending
    }
}

/// Runs work written in slices to its end on this thread (the desktop's workers, the command line,
/// tests).
pub fn finish<F: Future>(work: F) -> F::Output {
    let mut work = pin!(work);
    let mut context = Context::from_waker(Waker::noop());
    loop {
        if let Poll::Ready(output) = work.as_mut().poll(&mut context) {
            return output;
        }
    }
}

/// Polls `work` once: its output if it ended, `None` if it paused. For whoever runs work a slice
/// at a time (the page's queue, tests).
pub fn poll_once<F: Future + ?Sized>(work: Pin<&mut F>) -> Option<F::Output> {
    let mut context = Context::from_waker(Waker::noop());
    match work.poll(&mut context) {
        Poll::Ready(output) => Some(output),
        Poll::Pending => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    async fn count_to(n: usize, seen: &mut Vec<usize>) -> usize {
        for k in 0..n {
            seen.push(k);
            pause().await;
        }
        n
    }

    #[test]
    fn work_polled_once_stops_at_its_next_pause_and_goes_on_from_there() {
        let mut seen = Vec::new();
        let mut work = Box::pin(count_to(3, &mut seen));
        let mut polls = 0;
        let output = loop {
            polls += 1;
            if let Some(output) = poll_once(work.as_mut()) {
                break output;
            }
        };
        drop(work);
        assert_eq!(output, 3);
        // One poll per pause, and one more to end.
        assert_eq!(polls, 4);
        assert_eq!(seen, [0, 1, 2]);
    }

    #[test]
    fn finish_runs_work_to_its_end() {
        let mut seen = Vec::new();
        assert_eq!(finish(count_to(5, &mut seen)), 5);
        assert_eq!(seen, [0, 1, 2, 3, 4]);
    }
}
