//! The pusher's and the object's poses of a live session put on one time grid as they arrive, by
//! the rules a bag import follows (`recording::bag`, `recording::resample`): stamps in seconds since
//! the first pose's, rows whose stamp does not increase dropped, the object's yaw unwrapped, the grid
//! starting where both streams have begun, each grid point interpolated between the two rows around
//! it. A grid frame is given out once both streams have a row after its time: from then on nothing
//! that arrives can change it, so the frames given out are, bit for bit, the first frames of the
//! recording's import at the same rate (`pushlab import --rate`). Only the rows still needed are
//! kept.

use crate::geometry::AngleUnwrapper;
use crate::recording::bag::{PlanarPose, check_pose, seconds_since};
use crate::recording::resample::{MAX_DURATION_S, between, grid_frame, grid_time};
use crate::trajectory::Frame;

/// Which stream a pose belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stream {
    Pusher,
    Object,
}

impl Stream {
    /// "pusher" or "object", for messages.
    pub fn name(self) -> &'static str {
        match self {
            Stream::Pusher => "pusher",
            Stream::Object => "object",
        }
    }
}

/// Why a pose that arrived was not put on the grid.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Refused {
    /// Its stamp is not after the stream's previous one (the import drops it too).
    #[error("its stamp is not after the one before")]
    OutOfOrder,
    /// Not finite, or too far from the origin (the import refuses the whole bag: said by name).
    #[error("{0}")]
    BadValue(String),
}

/// One stream's rows still needed to interpolate the frames to come.
#[derive(Clone, Debug, Default)]
struct Rows {
    /// `[t, x, y, yaw]`; the first is the row at or before the next grid point (once it started).
    rows: Vec<[f64; 4]>,
    /// The stamp of the last row kept, seconds (rows dropped from the front included).
    last_t: Option<f64>,
    /// The object's yaw, unwrapped as the import unwraps it.
    yaw: AngleUnwrapper,
    /// The first row's stamp: where the stream begins.
    first_t: Option<f64>,
}

impl Rows {
    fn push(&mut self, row: [f64; 4], unwrap: bool) -> Result<(), Refused> {
        // The import keeps a row only when its stamp is after the last kept one.
        if self.last_t.is_some_and(|last| row[0] <= last) {
            return Err(Refused::OutOfOrder);
        }
        let mut row = row;
        if unwrap {
            row[3] = self.yaw.next(row[3]).0;
        }
        self.last_t = Some(row[0]);
        self.first_t.get_or_insert(row[0]);
        self.rows.push(row);
        Ok(())
    }

    /// The row at `t`, once a row after `t` has arrived; rows before the segment around `t` are
    /// dropped (grid times only increase).
    fn at(&mut self, t: f64) -> Option<[f64; 4]> {
        if self.last_t.is_none_or(|last| last <= t) {
            return None;
        }
        // As the import's interpolator moves its cursor: to the last row at or before `t`.
        let start = self.rows.iter().skip(1).take_while(|r| r[0] <= t).count();
        self.rows.drain(..start);
        Some(between(self.rows[0], self.rows[1], t))
    }
}

/// The grid of a live session (see the module documentation).
#[derive(Clone, Debug)]
pub struct LiveGrid {
    rate_hz: f64,
    /// The first pose's stamp, nanoseconds: `t = 0`.
    base_ns: Option<u64>,
    pusher: Rows,
    object: Rows,
    /// Grid points given out.
    given: usize,
    /// Whether the grid reached [`MAX_DURATION_S`], the longest push an import takes.
    full: bool,
}

impl LiveGrid {
    /// An empty grid at `rate_hz` (as `pushlab import --rate` takes it).
    pub fn new(rate_hz: f64) -> Self {
        Self {
            rate_hz,
            base_ns: None,
            pusher: Rows::default(),
            object: Rows::default(),
            given: 0,
            full: false,
        }
    }

    /// The grid's rate, Hz.
    pub fn rate_hz(&self) -> f64 {
        self.rate_hz
    }

    /// Unix time of `t = 0`, nanoseconds, once a pose arrived.
    pub fn base_unix_ns(&self) -> Option<u64> {
        self.base_ns
    }

    /// Frames given out so far.
    pub fn frames(&self) -> usize {
        self.given
    }

    /// Whether the grid stopped at [`MAX_DURATION_S`]: the import refuses a longer push.
    pub fn is_full(&self) -> bool {
        self.full
    }

    /// Takes a pose of `stream` (its header stamp, or, when it has none, the message's log time, as
    /// the import does); refuses one the grid cannot take, saying why.
    pub fn push(
        &mut self,
        stream: Stream,
        pose: &PlanarPose,
        log_time_ns: u64,
    ) -> Result<(), Refused> {
        let ns = if pose.stamp_ns == 0 {
            log_time_ns
        } else {
            pose.stamp_ns
        };
        let base = *self.base_ns.get_or_insert(ns);
        check_pose(stream.name(), 0, pose.x, pose.y, pose.yaw)
            .map_err(|problem| Refused::BadValue(problem.to_string()))?;
        let row = [seconds_since(base, ns), pose.x, pose.y, pose.yaw];
        match stream {
            Stream::Pusher => self.pusher.push(row, false),
            Stream::Object => self.object.push(row, true),
        }
    }

    /// The grid frames that became final since the last call, in order.
    pub fn take_frames(&mut self) -> Vec<Frame> {
        let (Some(a), Some(b)) = (self.pusher.first_t, self.object.first_t) else {
            return Vec::new();
        };
        let start = a.max(b);
        let mut frames = Vec::new();
        while !self.full {
            let t = grid_time(start, self.given, self.rate_hz);
            if t - start > MAX_DURATION_S {
                self.full = true;
                break;
            }
            let (Some(tip), Some(obj)) = (self.pusher.at(t), self.object.at(t)) else {
                break;
            };
            frames.push(grid_frame(self.given, self.rate_hz, tip, obj));
            self.given += 1;
        }
        frames
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    fn pose(stamp_ns: u64, x: f64, yaw: f64) -> PlanarPose {
        PlanarPose {
            stamp_ns,
            x,
            y: 0.0,
            yaw,
        }
    }

    #[test]
    fn a_frame_is_given_once_both_streams_passed_it() {
        let mut grid = LiveGrid::new(10.0);
        let ms = 1_000_000;
        grid.push(Stream::Pusher, &pose(1000 * ms, 0.0, 0.0), 0)
            .unwrap();
        grid.push(Stream::Object, &pose(1000 * ms, 1.0, 0.0), 0)
            .unwrap();
        assert!(grid.take_frames().is_empty(), "no row after t = 0 yet");
        grid.push(Stream::Pusher, &pose(1250 * ms, 0.25, 0.0), 0)
            .unwrap();
        assert!(grid.take_frames().is_empty(), "the object has not passed 0");
        grid.push(Stream::Object, &pose(1150 * ms, 1.15, 0.0), 0)
            .unwrap();
        let frames = grid.take_frames();
        // t = 0 and 0.1 s: the object's last row is at 0.15 s.
        assert_eq!(frames.len(), 2);
        assert!((frames[1].robot.x - 0.1).abs() < 1e-12);
        assert!((frames[1].object.position.x - 1.1).abs() < 1e-12);
        assert_eq!(grid.frames(), 2);
    }

    #[test]
    fn out_of_order_and_bad_poses_are_refused_by_name() {
        let mut grid = LiveGrid::new(10.0);
        grid.push(Stream::Object, &pose(2, 0.0, 0.0), 0).unwrap();
        assert_eq!(
            grid.push(Stream::Object, &pose(1, 0.0, 0.0), 0),
            Err(Refused::OutOfOrder)
        );
        let Err(Refused::BadValue(why)) = grid.push(Stream::Pusher, &pose(3, f64::NAN, 0.0), 0)
        else {
            panic!("a NaN pose is refused");
        };
        assert!(why.contains("expected a finite number"), "{why}");
    }

    #[test]
    fn the_object_yaw_is_unwrapped_across_pi() {
        let mut grid = LiveGrid::new(10.0);
        let ms = 1_000_000;
        for (i, yaw) in [3.1, -3.1, -3.0].into_iter().enumerate() {
            let t = (i as u64) * 100 * ms + ms;
            grid.push(Stream::Pusher, &pose(t, 0.0, 0.0), 0).unwrap();
            grid.push(Stream::Object, &pose(t, 0.0, yaw), 0).unwrap();
        }
        let frames = grid.take_frames();
        assert_eq!(frames.len(), 2);
        assert!(frames[1].object.yaw > 3.1, "{}", frames[1].object.yaw);
    }
}
