//! The state's learning along the run: what a frame move learns ("Learn while playing"), on the UI
//! thread or, when it is long, ahead on a worker (`learning_ahead`), and taking the worker's copy
//! back.

use crate::app::state::AppState;
use crate::app::state::learning::ahead::LearningAhead;
use crate::app::state::playback::timeline::FrameMove;

impl AppState {
    /// Learning follows the timeline forward when "Learn while playing" is on, holding θ over frames
    /// labelled to skip in training; a held label hotkey paints every frame passed, in either
    /// direction, but not the frames a seek or a loop's wrap-around jumps over.
    pub(in crate::app::state) fn frame_moved(&mut self, before: usize, how: FrameMove) {
        let now = self.timeline.frame();
        match how {
            FrameMove::Passed => self.labels.stroke_to(now),
            FrameMove::Jumped => self.labels.stroke_jump(now),
            FrameMove::Wrapped => {
                self.labels.stroke_to(self.timeline.last_frame());
                self.labels.stroke_jump(0);
                self.labels.stroke_to(now);
            }
        }
        if now > before {
            self.learn_while_playing(before, now);
        }
    }

    /// Learns from frames `from..to` when "Learn while playing" is on, holding θ over frames
    /// labelled to skip in training: on the UI thread, or on a worker when that is long. While a
    /// worker learns, nothing more is learned here; what the frame shown has passed meanwhile is
    /// learned when its copy is back.
    pub(in crate::app::state) fn learn_while_playing(&mut self, from: usize, to: usize) {
        // A growing push learns as its frames arrive (`sources::grow`), not as the timeline passes
        // them.
        if !self.settings.learn_while_playing
            || self.run.is_none()
            || self.learning_ahead.is_running()
            || self.fed_push_shown()
        {
            return;
        }
        let skip = self.frames_to_skip();
        let Some(run) = &mut self.run else {
            return;
        };
        if LearningAhead::is_long(run, from, to) {
            (self.learning_ahead).start(run, from, to, skip, self.run_generation);
            self.status = Some(
                "learning up to the frame shown in the background (the Steer tab shows how far, \
                 with Cancel)"
                    .to_owned(),
            );
        } else {
            run.learn_through(from, to, &skip);
        }
    }

    /// Drops the copy learning ahead, what it learned thrown away, before the run is changed (the
    /// copy would overwrite the change); says so when there was one.
    pub(in crate::app::state) fn drop_learning_ahead(&mut self) {
        if self.learning_ahead.cancel() {
            let held = self.run.as_ref().map_or(0, |run| run.frontier());
            self.status = Some(format!(
                "stopped learning ahead: θ is held from frame {held} (play or seek to learn on)"
            ));
        }
    }

    /// Hands the labels as they are now to the copy learning ahead, if any (after every command and
    /// every frame: labels change by commands, and by another program's edits noticed on a frame).
    pub(in crate::app::state) fn learning_ahead_follows_labels(&mut self) {
        if self.learning_ahead.is_running() {
            let skip = self.frames_to_skip();
            self.learning_ahead.follow_labels(skip);
        }
    }

    /// Asks the copy learning ahead to stop where it got (Cancel); what it learned is kept when
    /// it is back.
    pub(in crate::app::state) fn stop_learning_ahead(&mut self) {
        self.learning_ahead.stop();
    }

    /// Takes the copy that learned ahead in place of the run once it is back, and learns what the
    /// frame shown passed meanwhile unless it was stopped. Returns whether a copy is still learning.
    pub(in crate::app::state) fn poll_learning_ahead(&mut self) -> bool {
        if let Some(learned) = self.learning_ahead.poll(self.run_generation) {
            let (got_to, stopped) = (learned.run.frontier(), learned.stopped());
            if let Some(run) = &mut self.run {
                run.take_learned_ahead(learned.run);
            }
            let took = learned.took.as_secs_f64();
            if stopped {
                self.status = Some(format!(
                    "stopped learning ahead at frame {got_to} after {took:.1} s: θ is held from \
                     there (play or seek to learn on)"
                ));
            } else {
                self.status = Some(format!(
                    "learned up to frame {} in the background in {took:.1} s",
                    learned.to
                ));
                let now = self.frame();
                if now > learned.to {
                    self.learn_while_playing(learned.to, now);
                }
            }
        }
        self.learning_ahead.is_running()
    }

    /// The copy learning ahead: the share done and the frame it learns up to.
    pub fn learning_ahead(&self) -> Option<(f32, usize)> {
        self.learning_ahead.progress()
    }
}

#[cfg(test)]
mod tests;
