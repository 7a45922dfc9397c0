//! A push simulated one recorded frame at a time: what [`super::simulate_push`] runs for a whole
//! commanded path, and what a push made while it is watched runs as its pusher's next target
//! arrives (the sandbox: a student dragging the pusher, a controller steering it). One stepper
//! for both, so that a push made frame by frame and the same commanded path simulated at once give
//! the same poses, bit for bit.
//!
//! Each frame's interval is integrated in substeps of at most `max_substep` of pusher travel
//! ([`Sampling::max_substep`](super::Sampling)); the frame recorded is the scene at the interval's
//! end, with tracking noise drawn frame by frame in the order a whole push draws it (the pusher's
//! x and y, the object's x and y, its yaw).

use nalgebra::{Point2, Vector2};

use super::noise::NoiseStream;
use super::world::{PushWorld, SimObject, WorldError};
use super::{ContactMode, PusherPath};
use crate::geometry::Pose2;
use crate::trajectory::Frame;

/// Tracking noise: independent Gaussian errors on each recorded coordinate.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TrackingNoise {
    /// Standard deviation of the robot's and the object's recorded x and y, metres.
    pub position_sd: f64,
    /// Standard deviation of the object's recorded yaw, radians.
    pub yaw_sd: f64,
}

/// How the contact behaved over one recorded frame's interval, counted in integration substeps.
///
/// Frame `k`'s interval is the time from frame `k` to frame `k + 1` (what follows the frame, as a
/// sample from frame `k` predicts it); the last frame, which has no interval after it, takes the one
/// before it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameContact {
    /// Substeps in the interval.
    pub substeps: u32,
    /// Substeps in which the pusher pressed on the object (sticking or sliding).
    pub pressing: u32,
    /// Pressing substeps in which it slid along the edge.
    pub sliding: u32,
}

impl FrameContact {
    /// Whether the pusher pressed on the object for most of the interval.
    pub fn in_contact(&self) -> bool {
        2 * self.pressing > self.substeps
    }

    /// Whether, while pressing, the contact slid along the edge for most of the time.
    pub fn slipping(&self) -> bool {
        2 * self.sliding > self.pressing
    }
}

/// A push being simulated frame by frame (see the module documentation).
#[derive(Clone, Debug)]
pub struct PushStepper {
    world: PushWorld,
    /// Seconds between recorded frames.
    dt: f64,
    /// The frames recorded so far; the next is frame `frames`.
    frames: usize,
    counts: ContactCounts,
}

/// What the contact did over every substep so far.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactCounts {
    pub substeps: usize,
    pub pressing: usize,
    pub sliding: usize,
    /// Largest overlap removed by the normal correction, metres.
    pub max_overlap: f64,
}

/// One recorded frame: as the tracker saw it (with noise, if any) and as it was.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SteppedFrame {
    pub recorded: Frame,
    pub truth: Frame,
    /// What the contact did over the interval that ended at this frame.
    pub contact: FrameContact,
}

impl PushStepper {
    /// A push of `object` resting at `world_from_object`, the pusher's centre at `pusher`, recorded
    /// at `rate_hz`; refused when the pusher starts inside the object.
    pub fn new(
        object: SimObject,
        world_from_object: Pose2,
        pusher: Point2<f64>,
        rate_hz: f64,
    ) -> Result<Self, WorldError> {
        Ok(Self {
            world: PushWorld::new(object, world_from_object, pusher)?,
            dt: 1.0 / rate_hz,
            frames: 0,
            counts: ContactCounts::default(),
        })
    }

    /// Frame 0, the scene as it starts (time 0; no interval before it).
    pub fn first_frame(
        &mut self,
        noise: Option<(&TrackingNoise, &mut NoiseStream)>,
    ) -> SteppedFrame {
        debug_assert_eq!(self.frames, 0);
        self.frames = 1;
        let truth = self.truth_now(0.0);
        SteppedFrame {
            recorded: recorded(truth, noise),
            truth,
            contact: FrameContact::default(),
        }
    }

    /// Moves the pusher along `path` (time from the push's start) over the next frame's interval in
    /// `substeps` substeps, as a whole push along that path moves it.
    pub fn step_along(
        &mut self,
        path: &PusherPath,
        substeps: usize,
        noise: Option<(&TrackingNoise, &mut NoiseStream)>,
    ) -> SteppedFrame {
        let k = self.frames;
        let dt = self.dt;
        self.step(
            substeps,
            |j| path.position((k - 1) as f64 * dt + dt * j as f64 / substeps as f64),
            noise,
        )
    }

    /// Moves the pusher in a straight line to `target` over the next frame's interval, in substeps
    /// of at most `max_substep` of its travel (at least one).
    pub fn step_to(
        &mut self,
        target: Point2<f64>,
        max_substep: f64,
        noise: Option<(&TrackingNoise, &mut NoiseStream)>,
    ) -> SteppedFrame {
        let from = self.world.pusher();
        let travel: Vector2<f64> = target - from;
        let substeps = substeps_for(travel.norm(), max_substep);
        self.step(
            substeps,
            |j| {
                if j == substeps {
                    target
                } else {
                    from + travel * (j as f64 / substeps as f64)
                }
            },
            noise,
        )
    }

    fn step(
        &mut self,
        substeps: usize,
        position: impl Fn(usize) -> Point2<f64>,
        noise: Option<(&TrackingNoise, &mut NoiseStream)>,
    ) -> SteppedFrame {
        if self.frames == 0 {
            self.frames = 1;
        }
        let mut contact = FrameContact::default();
        for j in 1..=substeps {
            let report = self.world.move_pusher_to(position(j));
            self.counts.substeps += 1;
            contact.substeps += 1;
            self.counts.max_overlap = self
                .counts
                .max_overlap
                .max(report.overlap_before_correction);
            if let Some(mode) = report.mode.filter(|m| *m != ContactMode::Separating) {
                self.counts.pressing += 1;
                self.counts.sliding += usize::from(mode.is_sliding());
                contact.pressing += 1;
                contact.sliding += u32::from(mode.is_sliding());
            }
        }
        let time = self.frames as f64 * self.dt;
        self.frames += 1;
        let truth = self.truth_now(time);
        SteppedFrame {
            recorded: recorded(truth, noise),
            truth,
            contact,
        }
    }

    fn truth_now(&self, time: f64) -> Frame {
        Frame {
            time,
            robot: self.world.pusher(),
            object: self.world.world_from_object(),
        }
    }

    /// The scene now: the object, the pusher and where they are.
    pub fn world(&self) -> &PushWorld {
        &self.world
    }

    /// The frames recorded so far.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// Seconds between recorded frames.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// What the contact did over every substep so far.
    pub fn counts(&self) -> ContactCounts {
        self.counts
    }

    /// The simulated object.
    pub fn object(&self) -> &SimObject {
        self.world.object()
    }
}

/// Substeps for `travel` metres of pusher motion, each at most `max_substep` (at least one).
pub fn substeps_for(travel: f64, max_substep: f64) -> usize {
    ((travel / max_substep).ceil() as usize).max(1)
}

/// The frame a tracker records of `truth`: with Gaussian noise on the pusher's and the object's
/// positions and the object's yaw, drawn in that order.
fn recorded(truth: Frame, noise: Option<(&TrackingNoise, &mut NoiseStream)>) -> Frame {
    let Some((noise, rng)) = noise else {
        return truth;
    };
    let mut jitter = || Vector2::new(rng.normal(), rng.normal()) * noise.position_sd;
    let robot = truth.robot + jitter();
    let position = truth.object.position + jitter();
    Frame {
        time: truth.time,
        robot,
        object: Pose2 {
            position,
            yaw: truth.object.yaw + rng.normal() * noise.yaw_sd,
        },
    }
}

/// A frame as the simulator writes it: positions and yaw rounded to 1 µm and 1 µrad, the time to
/// 1 ns. Dividing the rounded integer gives the double nearest the short decimal, which prints short
/// and reads back exactly.
pub fn round_frame(f: Frame) -> Frame {
    let round = |x: f64, per_unit: f64| (x * per_unit).round() / per_unit;
    Frame {
        time: round(f.time, 1e9),
        robot: Point2::new(round(f.robot.x, 1e6), round(f.robot.y, 1e6)),
        object: Pose2::new(
            round(f.object.position.x, 1e6),
            round(f.object.position.y, 1e6),
            round(f.object.yaw, 1e6),
        ),
    }
}
