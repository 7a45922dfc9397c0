//! A push that grows as its frames arrive, whatever feeds it: a robot's server (`live`) or the
//! sandbox (`sandbox`). What both share is kept here, and grown by one path (`grow`): the push's
//! recording and the run extended, the new samples learned (every n-th frame when learning falls
//! behind), the prediction a horizon ahead of the newest frame, the timeline following the newest
//! frame until the user scrubs back.

use pushlab_core::geometry::Pose2;

use crate::app::state::recordings::session::RecordingId;

/// What feeds a growing push: said in its status lines ("the robot", "the pushes").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feed {
    Live,
    Sandbox,
}

impl Feed {
    /// What makes the frames, for "learning falls behind …".
    pub fn maker(self) -> &'static str {
        match self {
            Feed::Live => "the robot",
            Feed::Sandbox => "the pushes",
        }
    }
}

/// A growing push (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct Growing {
    /// The recording the frames go to.
    pub recording: RecordingId,
    pub feed: Feed,
    /// Whether frames still come (a live session running, a sandbox push being made).
    pub open: bool,
    /// Whether the timeline follows the newest frame.
    pub following: bool,
    /// Learning keeps up by learning every n-th frame only, holding θ over the others (1: all).
    pub every_nth: usize,
    /// Where the object is predicted to be a horizon after the newest frame, the pusher keeping its
    /// velocity: drawn in front of the object at the edge.
    pub ahead: Option<(usize, Pose2)>,
}

impl Growing {
    /// A push of `recording` starting to grow, fed by `feed`: followed, every frame learned.
    pub fn new(recording: RecordingId, feed: Feed) -> Self {
        Self {
            recording,
            feed,
            open: true,
            following: true,
            every_nth: 1,
            ahead: None,
        }
    }
}
