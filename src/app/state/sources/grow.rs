//! A push growing in the whole state, whatever feeds it (`growing`): a live robot's frames
//! (`live_feed`) and the sandbox's (`sandbox_feed`) take this one path. The frames extend the
//! push's recording and the run every recording is learned with (the core's `OnlineRun`, so a
//! grown push and the replay of its recording give the same θ), are learned as they come — every
//! n-th frame when learning cannot keep up, said rather than lagging — and the timeline follows
//! the newest frame until the user scrubs back ("Back to live" returns).

use std::sync::Arc;

use pushlab_core::control::is_away;
use pushlab_core::geometry::Pose2;
use pushlab_core::inspect::ahead;
use pushlab_core::trajectory::{Frame, Trajectory};

use crate::app::platform::Instant;
use crate::app::state::AppState;
use crate::app::state::playback::overview::PathOverview;
use crate::app::state::playback::timeline::{FrameMove, TimelineCommand};
use crate::app::state::recordings::session::RecordingId;
use crate::app::state::sources::growing::{Feed, Growing};

/// Learning one batch of frames longer than this is falling behind: learn every other frame more.
const LEARN_BUDGET_S: f64 = 0.004;
/// The most frames one is learned of, at the worst.
const MAX_EVERY_NTH: usize = 64;
/// Frames a growing push has when its rate and speed are checked against the model's domain.
const DOMAIN_FRAMES: usize = 20;

impl AppState {
    /// `recording` starts growing, fed by `feed`.
    pub(in crate::app::state) fn start_growing(&mut self, recording: RecordingId, feed: Feed) {
        self.growing = Some(Growing::new(recording, feed));
        self.check_growing_domain();
    }

    /// Whether the model fits the growing push, checked as on opening a recording: once its
    /// setting is known (the push starts), again once it has frames enough for its rate and speed,
    /// and when it ends. The status line says a misfit the moment it is found.
    fn check_growing_domain(&mut self) {
        let before = self.fit.clone();
        self.refresh_fit();
        if let Some(mismatch) = &self.fit
            && before.as_ref() != Some(mismatch)
        {
            self.status = Some(format!("warning: {}", mismatch.message));
        }
    }

    /// No more frames come to the growing push (its session ended, its push was made); it stays
    /// shown, followed where it was.
    pub(in crate::app::state) fn close_growing(&mut self) {
        if let Some(growing) = &mut self.growing {
            growing.open = false;
            self.check_growing_domain();
        }
    }

    /// Appends `frames` to the growing push, learns from the samples they complete, and follows
    /// them with the timeline when it is at the newest frame.
    pub(in crate::app::state) fn grow(&mut self, frames: Vec<Frame>) {
        let Some(growing) = &self.growing else {
            return;
        };
        let id = growing.recording;
        let times: Vec<f64> = frames.iter().map(|f| f.time).collect();
        let shown = self.session.selected == Some(id);
        let Some(recording) = (self.session.sets.get_mut(id.set))
            .and_then(|set| set.recordings.get_mut(id.recording))
        else {
            return;
        };
        // The trajectory grows in place only when nothing else holds it: the session lets go of its
        // share while the run (which holds the other) extends it.
        let mut trajectory = std::mem::replace(
            &mut recording.trajectory,
            Arc::new(Trajectory::new(Vec::new())),
        );
        let Some(run) = self.run.as_mut().filter(|_| shown) else {
            Arc::make_mut(&mut trajectory).frames.extend(frames);
            recording.trajectory = trajectory;
            return;
        };
        drop(trajectory);
        self.learning_ahead.cancel();
        recording.trajectory = run.extend(frames);
        let grown = recording.trajectory.len();
        let checked_at_enough = grown >= DOMAIN_FRAMES && grown - times.len() < DOMAIN_FRAMES;
        if grown < 2_000 || grown >= self.overview_frames + self.overview_frames / 64 {
            self.overview = PathOverview::of(&recording.trajectory);
            self.overview_frames = grown;
        }
        self.timeline.extend(times);
        self.learn_grown();
        self.follow_growing_edge();
        if checked_at_enough {
            self.check_growing_domain();
        }
    }

    /// Learns from every sample the newest frames completed (every n-th when behind), and predicts
    /// ahead of the newest frame.
    fn learn_grown(&mut self) {
        let labels_skip = self.frames_to_skip();
        let labels_skip = self.with_frames_away(labels_skip);
        let (Some(run), Some(growing)) = (self.run.as_mut(), self.growing.as_mut()) else {
            return;
        };
        let (from, to) = (run.frontier(), run.sample_count());
        let started = Instant::now();
        if growing.every_nth <= 1 {
            run.learn_through(from, to, &labels_skip);
        } else {
            // θ held over all but every n-th sample: the labels' frames to skip, and the others.
            let n = growing.every_nth;
            let mut skip = vec![false; to + run.horizon() + 1];
            for (k, flag) in skip.iter_mut().enumerate() {
                *flag = labels_skip.get(k).copied().unwrap_or(false) || (k >= from && k % n != 0);
            }
            run.learn_through(from, to, &skip);
        }
        let took = started.elapsed().as_secs_f64();
        let before = growing.every_nth;
        if took > LEARN_BUDGET_S {
            growing.every_nth = (growing.every_nth * 2).min(MAX_EVERY_NTH);
        } else if took < LEARN_BUDGET_S / 4.0 && growing.every_nth > 1 {
            growing.every_nth /= 2;
        }
        let theta = run.theta_at(run.frontier());
        growing.ahead = ahead(
            run.model().as_ref(),
            &run.trajectory().frames,
            run.horizon(),
            &theta,
        );
        if growing.every_nth != before {
            let maker = growing.feed.maker();
            self.status = Some(if growing.every_nth > 1 {
                format!(
                    "learning falls behind {maker}: learning every {}th frame only, θ held between",
                    growing.every_nth
                )
            } else {
                format!("learning keeps up with {maker} again: every frame learned")
            });
        }
    }

    /// Shows the newest frame when the timeline follows the growing push.
    pub(in crate::app::state) fn follow_growing_edge(&mut self) {
        // Also as the push stops growing: the last frames handed over are shown.
        if self.follows_growing_push() {
            let before = self.timeline.frame();
            self.timeline.apply(TimelineCommand::JumpEnd);
            if self.timeline.frame() != before {
                self.frame_moved(before, FrameMove::Passed);
            }
        }
    }

    /// Shows the newest frame of the growing push again and follows it.
    pub(in crate::app::state) fn back_to_newest(&mut self) {
        if let Some(growing) = &mut self.growing {
            growing.following = true;
        }
        self.follow_growing_edge();
    }

    /// A timeline command while a push grows: one that leaves the newest frame stops following it.
    pub(in crate::app::state) fn growing_timeline_moved(&mut self) {
        let at_edge = self.timeline.frame() == self.timeline.last_frame();
        if let Some(growing) = &mut self.growing
            && !at_edge
        {
            growing.following = false;
        }
    }

    /// The object's pose predicted a horizon after the newest frame, when the frame shown is the
    /// newest of a push still growing: drawn in front of the object.
    pub fn growing_ahead(&self) -> Option<(usize, Pose2)> {
        let growing = self.growing.as_ref()?;
        (self.session.selected == Some(growing.recording)
            && growing.open
            && self.timeline.frame() == self.timeline.last_frame())
        .then_some(growing.ahead)
        .flatten()
    }

    /// Whether the timeline follows the newest frame of a push still growing (the plots keep all of
    /// it in view).
    pub fn growing_following(&self) -> bool {
        self.follows_growing_push() && self.growing.as_ref().is_some_and(|g| g.open)
    }

    /// Whether the timeline follows the newest frame of the growing push shown (open or not).
    fn follows_growing_push(&self) -> bool {
        (self.growing.as_ref())
            .is_some_and(|g| g.following && self.session.selected == Some(g.recording))
    }

    /// The recording frames still come to, when it is shown: it learns as they arrive, not as
    /// the timeline passes them.
    pub(in crate::app::state) fn fed_push_shown(&self) -> bool {
        (self.growing.as_ref())
            .is_some_and(|g| g.open && self.session.selected == Some(g.recording))
    }

    /// The growing push, for the panels (the live strip, the sandbox's pane).
    pub fn growing(&self) -> Option<&Growing> {
        self.growing.as_ref()
    }
}

impl AppState {
    /// `skip` with the frames where the pusher is away from the object flagged too, while the
    /// controller drives the growing push. The flags are kept as the frames arrive: each batch
    /// tests only the frames new since the last.
    pub(in crate::app::state) fn with_frames_away(&mut self, skip: Arc<[bool]>) -> Arc<[bool]> {
        let generation = self.run_generation;
        // The sandbox's controller, or a robot's: never both (a robot's push is not the sandbox's).
        let driving = match self.sandbox.as_mut().and_then(|s| s.driving.as_mut()) {
            Some(driving) => Some(driving),
            None => self.live.driving_mut(),
        };
        let (Some(driving), Some(run)) = (driving, self.run.as_ref()) else {
            return skip;
        };
        let frames = &run.trajectory().frames;
        let (kept_for, away) = &mut driving.away;
        if *kept_for != generation || away.len() > frames.len() {
            *kept_for = generation;
            away.clear();
        }
        let sites = driving.planner.sites();
        let new = frames[away.len()..].iter().map(|f| is_away(sites, f));
        away.extend(new);
        (away.iter().enumerate())
            .map(|(k, &a)| a || skip.get(k).copied().unwrap_or(false))
            .collect()
    }
}
