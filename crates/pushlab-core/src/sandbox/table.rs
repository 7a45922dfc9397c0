//! The mystery object on the table and the pushes made on it, frame by frame: the simulator's
//! stepper ([`crate::sim::stepper`]) driven by a student's pointer or by a push chosen on the
//! object, in real time at the mystery's frame rate.
//!
//! Each push is one recording: it starts where the last left the object (and, for a drag, the
//! pusher), and ends a second after the pusher stopped, so that the model's last samples have the
//! frames they predict. A planned push starts its pusher where `pushlab simulate` starts one (its
//! approach before the face), as a robot lifted to its next push would be. Frames are what a
//! tracker records, rounded as the simulator writes its sets, with tracking noise when asked (one
//! stream per push, seeded from the mystery's seed and the push's number, as `pushlab simulate`
//! seeds its pushes), so a push made here and its pointer path replayed by `pushlab simulate
//! --pointer-path` give the same poses.

use nalgebra::Point2;

use super::mystery::{Mystery, PUSHER_SPEED, RATE_HZ};
use super::pointer::{PointerPath, follow};
use crate::geometry::Pose2;
use crate::recording::PushSide;
use crate::sim::stepper::{PushStepper, round_frame, substeps_for};
use crate::sim::{
    NoiseStream, PlanError, PushPlan, PusherPath, Sampling, TrackingNoise, WorldError,
    push_noise_seed,
};
use crate::trajectory::{Frame, Trajectory};

/// Frames a push goes on after its pusher stopped: a second, so that a model of horizon up to
/// ten frames at 10 Hz learns from every frame of the push.
pub const SETTLE_S: f64 = 1.0;
/// How far before the face a planned push's pusher starts, metres (the grid's approach).
pub const APPROACH_M: f64 = crate::experiment::suggest::APPROACH_M;

/// A push chosen on the object, as `pushlab suggest` prints one and `setting.json` names its face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PushChoice {
    pub face: PushSide,
    /// Metres from the face's middle, positive to the pusher's left.
    pub offset_m: f64,
    /// Degrees from the face's normal, counter-clockwise positive.
    pub angle_deg: f64,
    /// How far the pusher goes once it touches, metres.
    pub length_m: f64,
}

/// What drives the push being made.
#[derive(Clone, Debug)]
enum Drive {
    /// The pointer is held here: the pusher follows it.
    Held(Point2<f64>),
    /// The pointer was let go here: the pusher reaches it, then the push settles.
    Released(Point2<f64>),
    /// A pointer path given whole (a scripted drag, a replay), times from the push's start.
    Path(PointerPath),
    /// A planned push: its commanded path, for this many frames of motion.
    Planned { path: PusherPath, frames: usize },
}

/// The push being made.
#[derive(Clone, Debug)]
struct Pushing {
    stepper: PushStepper,
    drive: Drive,
    rng: NoiseStream,
    /// Frames left once the pusher stopped; `None` while it moves.
    settle_left: Option<usize>,
    /// The frame the pusher stopped at (its settling's first): its path ends there.
    stopped_at: Option<usize>,
    /// Real time not yet made into frames, seconds.
    clock_s: f64,
    /// The pusher's commanded position at each frame (it follows it exactly).
    pusher_path: Vec<(f64, Point2<f64>)>,
    /// Whether the pusher pressed on the object over each frame's interval.
    pressing: Vec<bool>,
    object_start: Pose2,
}

/// What the sandbox did, for whoever shows it: a push began (its first frame), frames came, a push
/// ended.
#[derive(Clone, Debug, PartialEq)]
pub enum SandboxEvent {
    PushStarted { push: usize, first: Frame },
    Frames { push: usize, frames: Vec<Frame> },
    PushEnded { push: usize },
}

/// Why a push could not be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PushRefused {
    #[error("{0}")]
    Plan(#[from] PlanError),
    #[error("{0}")]
    World(#[from] WorldError),
    #[error("a push is being made: let it end first")]
    Busy,
    #[error("the push length {0} m is not a positive finite number")]
    BadLength(f64),
}

/// A finished push, for saving and scoring.
#[derive(Clone, Debug, PartialEq)]
pub struct MadePush {
    /// The pusher's commanded position at each frame (`t`, world metres).
    pub pusher_path: Vec<(f64, Point2<f64>)>,
    /// The frame its pusher stopped at: the push settled from there to its end.
    pub stopped_at: usize,
    /// Whether the pusher pressed on the object over each frame's interval (frame k to k + 1).
    pub pressing: Vec<bool>,
    /// The object's true pose at the push's first frame.
    pub object_start: Pose2,
}

impl MadePush {
    /// How far the pusher went while it pressed on the object, metres.
    pub fn pressed_length(&self) -> f64 {
        super::review::pressed_length(&self.pusher_path, &self.pressing)
    }

    /// The pusher's commanded path up to where it stopped, as a pointer path: replayed by
    /// `pushlab simulate --pointer-path` from the same start, it makes this push again, pose for
    /// pose (the replay settles after it as the push did).
    pub fn pointer_path(&self) -> PointerPath {
        PointerPath::of_frames(self.pusher_path[..self.stopped_at].iter().copied())
    }
}

/// The mystery object on the table (see the module documentation).
#[derive(Clone, Debug)]
pub struct Sandbox {
    mystery: Mystery,
    noise: Option<TrackingNoise>,
    /// Where the object rests between pushes (true pose).
    object: Pose2,
    /// Where the pusher rests between pushes.
    pusher: Point2<f64>,
    pushing: Option<Pushing>,
    made: Vec<MadePush>,
}

impl Sandbox {
    /// The mystery object resting at the origin, the pusher a few centimetres before its front
    /// face; tracking noise on every recorded pose when given.
    pub fn new(mystery: Mystery, noise: Option<TrackingNoise>) -> Self {
        let outline = &mystery.sim.outline;
        let front = outline.bounding_box().0.x;
        let pusher = Point2::new(front - mystery.sim.pusher_radius - 0.05, 0.0);
        Self {
            mystery,
            noise,
            object: Pose2::new(0.0, 0.0, 0.0),
            pusher,
            pushing: None,
            made: Vec::new(),
        }
    }

    pub fn mystery(&self) -> &Mystery {
        &self.mystery
    }

    /// The object's true pose now (between frames, the last frame's).
    pub fn object_pose(&self) -> Pose2 {
        match &self.pushing {
            Some(p) => p.stepper.world().world_from_object(),
            None => self.object,
        }
    }

    /// The pusher's position now.
    pub fn pusher(&self) -> Point2<f64> {
        match &self.pushing {
            Some(p) => p.stepper.world().pusher(),
            None => self.pusher,
        }
    }

    /// Whether a push is being made.
    pub fn is_pushing(&self) -> bool {
        self.pushing.is_some()
    }

    /// The pushes finished.
    pub fn made(&self) -> &[MadePush] {
        &self.made
    }

    /// The pointer is pressed or moved to `at`: the pusher follows it, starting a push if none
    /// is being made (a push that was settling goes on instead).
    pub fn hold(&mut self, at: Point2<f64>) -> Vec<SandboxEvent> {
        if let Some(p) = &mut self.pushing
            && matches!(p.drive, Drive::Held(_) | Drive::Released(_))
        {
            p.drive = Drive::Held(at);
            p.settle_left = None;
            return Vec::new();
        }
        if self.pushing.is_some() {
            return Vec::new();
        }
        let start = self.pusher;
        self.start(start, Drive::Held(at)).unwrap_or_default()
    }

    /// The pointer is let go at `at`.
    pub fn release(&mut self, at: Point2<f64>) {
        if let Some(p) = &mut self.pushing
            && matches!(p.drive, Drive::Held(_))
        {
            p.drive = Drive::Released(at);
        }
    }

    /// Makes a whole push along a pointer path at once (times from now): the push's events, every
    /// frame made. The sandbox's drag as a script (the page's hook, tests) and `pushlab simulate
    /// --pointer-path` run this.
    pub fn drag(&mut self, path: PointerPath) -> Result<Vec<SandboxEvent>, PushRefused> {
        if self.pushing.is_some() {
            return Err(PushRefused::Busy);
        }
        let mut events = self.start(self.pusher, Drive::Path(path))?;
        events.extend(self.run_to_end());
        Ok(events)
    }

    /// Starts a push chosen on the object, planned as `pushlab simulate` plans one; its frames
    /// come as time passes ([`advance`](Self::advance)), or at once with [`run_to_end`].
    pub fn plan(&mut self, choice: PushChoice) -> Result<Vec<SandboxEvent>, PushRefused> {
        if self.pushing.is_some() {
            return Err(PushRefused::Busy);
        }
        if !(choice.length_m.is_finite() && choice.length_m > 0.0) {
            return Err(PushRefused::BadLength(choice.length_m));
        }
        let plan = PushPlan {
            side: choice.face,
            contact_offset: choice.offset_m,
            push_angle_deg: choice.angle_deg,
            speed: PUSHER_SPEED,
            curvature: 0.0,
            approach: APPROACH_M,
        };
        let sim = &self.mystery.sim;
        let path = plan.path(&sim.outline, &self.object, sim.pusher_radius)?;
        let frames = ((APPROACH_M + choice.length_m) / PUSHER_SPEED * RATE_HZ).ceil() as usize;
        self.start(path.position(0.0), Drive::Planned { path, frames })
    }

    /// Makes every frame of the push being made until it ends.
    pub fn run_to_end(&mut self) -> Vec<SandboxEvent> {
        let mut events = Vec::new();
        let mut frames = Vec::new();
        let push = self.made.len();
        while self.pushing.is_some() {
            match self.next_frame() {
                Some(frame) => frames.push(frame),
                None => break,
            }
        }
        if !frames.is_empty() {
            events.push(SandboxEvent::Frames { push, frames });
        }
        events.push(SandboxEvent::PushEnded { push });
        events
    }

    /// Lets `dt` seconds of real time pass: the frames the push being made makes in it, at the
    /// mystery's rate (none between pushes).
    pub fn advance(&mut self, dt: f64) -> Vec<SandboxEvent> {
        let Some(p) = &mut self.pushing else {
            return Vec::new();
        };
        p.clock_s += dt.max(0.0);
        let step = p.stepper.dt();
        let push = self.made.len();
        let mut frames = Vec::new();
        let mut ended = false;
        // A frame is due once its interval has passed, to a nanosecond: time handed over in
        // pieces (0.35 s, then 0.05 s) adds up to whole frames despite rounding.
        while let Some(p) = &mut self.pushing
            && p.clock_s >= step - 1e-9
        {
            p.clock_s -= step;
            match self.next_frame() {
                Some(frame) => frames.push(frame),
                None => {
                    ended = true;
                    break;
                }
            }
            ended = self.pushing.is_none();
        }
        let mut events = Vec::new();
        if !frames.is_empty() {
            events.push(SandboxEvent::Frames { push, frames });
        }
        if ended {
            events.push(SandboxEvent::PushEnded { push });
        }
        events
    }

    fn start(
        &mut self,
        pusher: Point2<f64>,
        drive: Drive,
    ) -> Result<Vec<SandboxEvent>, PushRefused> {
        let mut stepper = PushStepper::new(self.mystery.sim.clone(), self.object, pusher, RATE_HZ)?;
        let push = self.made.len();
        let mut rng = NoiseStream::new(push_noise_seed(self.mystery.seed, push));
        let noise = self.noise;
        let first = stepper.first_frame(noise.as_ref().map(|n| (n, &mut rng)));
        self.pushing = Some(Pushing {
            stepper,
            drive,
            rng,
            settle_left: None,
            stopped_at: None,
            clock_s: 0.0,
            pusher_path: vec![(first.truth.time, first.truth.robot)],
            pressing: Vec::new(),
            object_start: self.object,
        });
        Ok(vec![SandboxEvent::PushStarted {
            push,
            first: round_frame(first.recorded),
        }])
    }

    /// The next frame of the push being made, or `None` (the push ended) once it settled.
    fn next_frame(&mut self) -> Option<Frame> {
        let noise = self.noise;
        let p = self.pushing.as_mut()?;
        let dt = p.stepper.dt();
        let k = p.stepper.frames();
        let t = k as f64 * dt;
        let now = p.stepper.world().pusher();
        let target = match &p.drive {
            Drive::Held(at) | Drive::Released(at) => Some(follow(now, *at, PUSHER_SPEED, dt)),
            Drive::Path(path) => path.at(t).map(|at| follow(now, at, PUSHER_SPEED, dt)),
            Drive::Planned { .. } => None,
        };
        let moving = match &p.drive {
            Drive::Held(_) => true,
            Drive::Released(_) => target.is_some_and(|to| to != now),
            Drive::Path(path) => t <= path.end() || target.is_some_and(|to| to != now),
            Drive::Planned { frames, .. } => k <= *frames,
        };
        if moving {
            p.settle_left = None;
            p.stopped_at = None;
        } else {
            p.stopped_at.get_or_insert(k);
            let left = p
                .settle_left
                .get_or_insert((SETTLE_S * RATE_HZ).round() as usize);
            if *left == 0 {
                self.end_push();
                return None;
            }
            *left -= 1;
        }
        let noise = noise.as_ref().map(|n| (n, &mut p.rng));
        let max_substep = Sampling::default().max_substep;
        let frame = match (&p.drive, moving) {
            // As `pushlab simulate` makes a planned push: along its path, in the substeps its speed
            // needs.
            (Drive::Planned { path, .. }, true) => {
                let substeps = substeps_for(path.speed() * dt, max_substep);
                p.stepper.step_along(path, substeps, noise)
            }
            _ => p
                .stepper
                .step_to(target.filter(|_| moving).unwrap_or(now), max_substep, noise),
        };
        p.pusher_path.push((frame.truth.time, frame.truth.robot));
        p.pressing.push(frame.contact.pressing > 0);
        Some(round_frame(frame.recorded))
    }

    fn end_push(&mut self) {
        if let Some(p) = self.pushing.take() {
            self.object = p.stepper.world().world_from_object();
            self.pusher = p.stepper.world().pusher();
            self.made.push(MadePush {
                stopped_at: p.stopped_at.unwrap_or(p.pusher_path.len()),
                pusher_path: p.pusher_path,
                pressing: p.pressing,
                object_start: p.object_start,
            });
        }
    }
}

/// The recordings events make: each push's first frame and the frames after it, by push.
pub fn recorded_pushes(events: &[SandboxEvent]) -> Vec<Trajectory> {
    let mut pushes: Vec<Vec<Frame>> = Vec::new();
    for event in events {
        match event {
            SandboxEvent::PushStarted { push, first } => {
                pushes.resize_with((*push + 1).max(pushes.len()), Vec::new);
                pushes[*push] = vec![*first];
            }
            SandboxEvent::Frames { push, frames } => {
                if let Some(recorded) = pushes.get_mut(*push) {
                    recorded.extend_from_slice(frames);
                }
            }
            SandboxEvent::PushEnded { .. } => {}
        }
    }
    pushes.into_iter().map(Trajectory::new).collect()
}
