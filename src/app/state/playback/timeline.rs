//! Playback time over the frames of one trajectory, apart from any drawing.
//!
//! Like rerun's `TimeControl`: a plain struct that the UI only reads and changes through
//! [`TimelineCommand`]s. Time is always passed in (`update(dt)`), never read from a clock, so every
//! behaviour is unit-testable.

/// Slowest playback speed offered, as a multiple of real time.
pub const MIN_SPEED: f64 = 0.1;
/// Fastest playback speed offered.
pub const MAX_SPEED: f64 = 8.0;

/// Everything that changes the timeline. The UI sends these; nothing else mutates the timeline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TimelineCommand {
    /// Play if paused, pause if playing (at the end without looping: restart from the start).
    TogglePlay,
    /// Pause and move by this many frames (clamped to the trajectory).
    Step(i64),
    /// Pause-free seek to a frame index (clamped).
    SeekTo(usize),
    /// Seek to the first frame.
    JumpStart,
    /// Seek to the last frame.
    JumpEnd,
    /// Playback speed, clamped to [`MIN_SPEED`, `MAX_SPEED`].
    SetSpeed(f64),
    /// Whether playback wraps around at the end.
    SetLoop(bool),
}

/// How the shown frame changed, which decides what a held paint key covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameMove {
    /// Stepped or played over the frames between.
    Passed,
    /// Seeked or jumped: the frames between were not shown.
    Jumped,
    /// Looping playback went past the end and on from the first frame.
    Wrapped,
}

/// Playback state: which frame is shown, whether and how fast time runs.
#[derive(Clone, Debug, PartialEq)]
pub struct Timeline {
    /// Time stamps of the frames, seconds, strictly increasing.
    frame_times: Vec<f64>,
    /// Current playback time, seconds, in `[first, last]` of `frame_times`.
    time: f64,
    /// Index of the frame shown: the last frame whose time is not after `time`.
    frame: usize,
    /// Whether time advances in `update`.
    pub playing: bool,
    /// Multiple of real time.
    pub speed: f64,
    /// Whether playback wraps around to the start at the end.
    pub looping: bool,
}

impl Timeline {
    /// A paused timeline at the first frame.
    pub fn new(frame_times: Vec<f64>) -> Self {
        let time = frame_times.first().copied().unwrap_or(0.0);
        Self {
            frame_times,
            time,
            frame: 0,
            playing: false,
            speed: 1.0,
            looping: false,
        }
    }

    /// Index of the frame shown.
    pub fn frame(&self) -> usize {
        self.frame
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.frame_times.len()
    }

    /// Whether there are no frames.
    pub fn is_empty(&self) -> bool {
        self.frame_times.is_empty()
    }

    /// Index of the last frame (0 when empty).
    pub fn last_frame(&self) -> usize {
        self.frame_times.len().saturating_sub(1)
    }

    /// The time stamp of the frame shown, seconds on the recording's clock (0 when empty).
    pub fn frame_time(&self) -> f64 {
        self.frame_times.get(self.frame).copied().unwrap_or(0.0)
    }

    /// Seconds from the first frame to the frame shown: what the scene and the Inspect tab show,
    /// not the playback clock between two frames (paused 2.96 s into a 10 Hz push, frame 29 is
    /// shown: 2.90 s, where the clock would say 2.96 and, rounded, 3.0 beside "frame 29").
    pub fn elapsed(&self) -> f64 {
        self.frame_time() - self.frame_times.first().copied().unwrap_or(0.0)
    }

    /// Applies one command.
    pub fn apply(&mut self, command: TimelineCommand) {
        match command {
            TimelineCommand::TogglePlay => {
                if !self.playing && self.frame == self.last_frame() && !self.looping {
                    self.seek(0);
                }
                self.playing = !self.playing && !self.is_empty();
            }
            TimelineCommand::Step(delta) => {
                self.playing = false;
                let target = (self.frame as i64 + delta).clamp(0, self.last_frame() as i64);
                self.seek(target as usize);
            }
            TimelineCommand::SeekTo(frame) => self.seek(frame),
            TimelineCommand::JumpStart => self.seek(0),
            TimelineCommand::JumpEnd => self.seek(self.last_frame()),
            TimelineCommand::SetSpeed(speed) => {
                if speed.is_finite() {
                    self.speed = speed.clamp(MIN_SPEED, MAX_SPEED);
                }
            }
            TimelineCommand::SetLoop(looping) => self.looping = looping,
        }
    }

    /// Appends frames that arrived (a live session's), their times after the last; the frame shown
    /// stays where it is (at frame 0 when the timeline was empty).
    pub fn extend(&mut self, times: impl IntoIterator<Item = f64>) {
        let was_empty = self.is_empty();
        self.frame_times.extend(times);
        if was_empty && let Some(&first) = self.frame_times.first() {
            self.time = first;
        }
    }

    /// Advances playback by `dt` seconds of real time. Returns whether the shown frame changed.
    pub fn update(&mut self, dt: f64) -> bool {
        if !self.playing || self.is_empty() || !(dt.is_finite() && dt > 0.0) {
            return false;
        }
        let before = self.frame;
        let (first, last) = (self.frame_times[0], self.frame_times[self.last_frame()]);
        self.time += dt * self.speed;
        if self.time > last {
            if self.looping && last > first {
                self.time = first + (self.time - first) % (last - first);
            } else {
                self.time = last;
                self.playing = false;
            }
        }
        self.frame = self.frame_at(self.time);
        self.frame != before
    }

    fn seek(&mut self, frame: usize) {
        if self.is_empty() {
            return;
        }
        self.frame = frame.min(self.last_frame());
        self.time = self.frame_times[self.frame];
    }

    /// The last frame whose time is not after `time`.
    fn frame_at(&self, time: f64) -> usize {
        self.frame_times
            .partition_point(|&t| t <= time)
            .saturating_sub(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ten_hz(n: usize) -> Timeline {
        Timeline::new((0..n).map(|i| i as f64 * 0.1).collect())
    }

    #[test]
    fn playing_advances_by_speed_times_dt() {
        let mut t = ten_hz(100);
        t.apply(TimelineCommand::TogglePlay);
        assert!(t.update(0.25));
        assert_eq!(t.frame(), 2);
        t.apply(TimelineCommand::SetSpeed(4.0));
        t.update(0.25); // 1 s of recording
        assert_eq!(t.frame(), 12);
    }

    #[test]
    fn paused_does_not_move() {
        let mut t = ten_hz(10);
        assert!(!t.update(1.0));
        assert_eq!(t.frame(), 0);
    }

    #[test]
    fn step_pauses_and_moves_exactly_one_frame() {
        let mut t = ten_hz(100);
        t.apply(TimelineCommand::TogglePlay);
        t.update(0.33);
        let at = t.frame();
        t.apply(TimelineCommand::Step(1));
        assert!(!t.playing);
        assert_eq!(t.frame(), at + 1);
        t.apply(TimelineCommand::Step(-10));
        assert_eq!(t.frame(), (at + 1).saturating_sub(10));
        t.apply(TimelineCommand::Step(-1000));
        assert_eq!(t.frame(), 0);
        t.apply(TimelineCommand::Step(1000));
        assert_eq!(t.frame(), 99);
    }

    #[test]
    fn stops_at_the_end_without_loop_and_wraps_with_loop() {
        let mut t = ten_hz(11); // 0 .. 1 s
        t.apply(TimelineCommand::TogglePlay);
        t.update(5.0);
        assert_eq!(t.frame(), 10);
        assert!(!t.playing);
        // Play again at the end restarts.
        t.apply(TimelineCommand::TogglePlay);
        assert_eq!(t.frame(), 0);
        assert!(t.playing);
        t.apply(TimelineCommand::SetLoop(true));
        t.update(1.25);
        assert!(t.playing);
        assert_eq!(t.frame(), 2);
    }

    #[test]
    fn speed_is_clamped_and_nan_ignored() {
        let mut t = ten_hz(3);
        t.apply(TimelineCommand::SetSpeed(100.0));
        assert_eq!(t.speed, MAX_SPEED);
        t.apply(TimelineCommand::SetSpeed(0.0));
        assert_eq!(t.speed, MIN_SPEED);
        t.apply(TimelineCommand::SetSpeed(f64::NAN));
        assert_eq!(t.speed, MIN_SPEED);
    }

    #[test]
    fn jumps_and_seeks_are_clamped() {
        let mut t = ten_hz(20);
        t.apply(TimelineCommand::JumpEnd);
        assert_eq!(t.frame(), 19);
        t.apply(TimelineCommand::SeekTo(500));
        assert_eq!(t.frame(), 19);
        t.apply(TimelineCommand::JumpStart);
        assert_eq!(t.frame(), 0);
        assert!((t.elapsed()).abs() < 1e-12);
    }

    #[test]
    fn the_time_said_is_the_shown_frames_not_the_clock_between_frames() {
        let mut t = Timeline::new((0..100).map(|i| 1.5 + i as f64 * 0.1).collect());
        t.apply(TimelineCommand::TogglePlay);
        t.update(2.96);
        t.apply(TimelineCommand::TogglePlay);
        assert_eq!(t.frame(), 29);
        assert!((t.elapsed() - 2.9).abs() < 1e-9, "{}", t.elapsed());
    }

    #[test]
    fn a_growing_timeline_keeps_the_frame_shown_and_seeks_into_what_came() {
        let mut t = Timeline::new(Vec::new());
        t.extend([2.0, 2.1, 2.2]);
        assert_eq!((t.frame(), t.frame_time()), (0, 2.0));
        t.apply(TimelineCommand::JumpEnd);
        t.extend((3..10).map(|i| 2.0 + f64::from(i) * 0.1));
        assert_eq!((t.len(), t.frame()), (10, 2));
        t.apply(TimelineCommand::JumpEnd);
        assert_eq!(t.frame(), 9);
        assert!((t.elapsed() - 0.9).abs() < 1e-9);
    }

    #[test]
    fn empty_timeline_never_plays() {
        let mut t = Timeline::new(Vec::new());
        t.apply(TimelineCommand::TogglePlay);
        assert!(!t.playing);
        assert!(!t.update(1.0));
        t.apply(TimelineCommand::Step(1));
        assert_eq!(t.frame(), 0);
    }
}
