//! A recorded push: time-stamped robot positions and object poses in the world.

use nalgebra::Point2;
use serde::{Deserialize, Serialize};

use crate::geometry::Pose2;

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
}
