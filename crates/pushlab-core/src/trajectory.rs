//! A recorded push: time-stamped robot positions and object poses in the world.

use nalgebra::Point2;
use serde::{Deserialize, Serialize};

use crate::geometry::Pose2;

/// The time over which [`Trajectory::pusher_speed`] takes the pusher's net displacement, seconds.
pub const SPEED_WINDOW_S: f64 = 1.0;

/// One time step of a push, world frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Frame {
    /// Seconds since the start of the recording (or any fixed origin).
    pub time: f64,
    /// Centre of the pusher disc, metres.
    pub robot: Point2<f64>,
    /// Geometric centre of the object's footprint and the yaw of its x axis (unwrapped), metres and
    /// radians. Not the COM: the COM offset is what online learning estimates.
    pub object: Pose2,
}

/// A push as a sequence of frames, time strictly increasing.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Trajectory {
    /// The frames in time order.
    pub frames: Vec<Frame>,
}

impl Trajectory {
    /// A trajectory from frames already in time order.
    pub fn new(frames: Vec<Frame>) -> Self {
        Self { frames }
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// Whether there are no frames.
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// Duration from the first to the last frame, seconds.
    pub fn duration(&self) -> f64 {
        match (self.frames.first(), self.frames.last()) {
            (Some(a), Some(b)) => b.time - a.time,
            _ => 0.0,
        }
    }

    /// Mean sampling rate in Hz (0 for fewer than two frames).
    pub fn mean_rate_hz(&self) -> f64 {
        let d = self.duration();
        if self.frames.len() < 2 || d <= 0.0 {
            0.0
        } else {
            (self.frames.len() - 1) as f64 / d
        }
    }

    /// The pusher's speed over the push, m/s: its net displacement over each window of
    /// [`SPEED_WINDOW_S`] (the whole push when shorter), divided by the window's time, averaged over
    /// the windows starting at every frame; `None` for fewer than two frames or no duration.
    ///
    /// The one speed rule of pushlab: the browser's Speed column and the model domain's pushing
    /// speeds both read it. Why net displacement over a second, not the summed length of
    /// frame-to-frame steps: tracking noise adds to every step's length, the more the shorter the
    /// steps, so summed steps read a push simulated at 0.05 m/s with 2 mm noise as 0.06 m/s at
    /// 10 Hz, 0.19 m/s at 50 Hz and 0.89 m/s at 250 Hz. A window's two end points carry the same
    /// noise at any frame rate, and in a second the pusher moves far more than the noise at usual
    /// speeds; averaging the windows that start at every frame averages it further. Measured on
    /// simulated pushes at 10–250 Hz with 0–2 mm noise, 0.01–0.15 m/s, straight and curved: within
    /// 7 % of the true speed (0.4 % at the sample data's 0.04–0.05 m/s). Shorter windows let the
    /// noise back in (0.5 s: 25 % high at 0.01 m/s); longer ones become the whole push on short
    /// pushes and cut the corners of curved ones; subtracting the noise's share from squared steps
    /// (estimated from second differences) failed at 50 Hz and above, where it is almost all of a
    /// step. The table is in `crates/pushlab-core/tests/pusher_speed.rs`.
    pub fn pusher_speed(&self) -> Option<f64> {
        let frames = &self.frames;
        let duration = self.duration();
        if frames.len() < 2 || duration.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let window = duration.min(SPEED_WINDOW_S);
        let (mut sum, mut count, mut end) = (0.0, 0usize, 0);
        for (start, first) in frames.iter().enumerate() {
            end = end.max(start);
            while end < frames.len() && frames[end].time < first.time + window {
                end += 1;
            }
            let Some(last) = frames.get(end) else {
                break;
            };
            sum += (last.robot - first.robot).norm() / (last.time - first.time);
            count += 1;
        }
        (count > 0).then(|| sum / count as f64)
    }
}
