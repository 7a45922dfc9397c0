//! The loop (see [`super`]): read the session's next event, take a pose as it arrives, and at
//! each control step plan, pass the target through the gate and send what it lets out.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use nalgebra::Point2;

use super::gate::{Command, Halt, Limits, SafetyGate, Workspace};
use crate::control::{ControlStep, Pacing, PoseControl};
use crate::geometry::Pose2;
use crate::live::grid::Stream;
use crate::live::{CommandEncoding, LiveSession, Recorded, SessionError, SessionEvent};
use crate::recording::bag::PlanarPose;

/// How far the workspace taken from the first poses reaches past them and the goal, beyond the
/// object's own size, metres: room to go round the object, not to wander.
pub const WORKSPACE_MARGIN_M: f64 = 0.15;
/// How long a lost link is waited for, to send the hold once it is back.
const HOLD_AFTER_LOSS: Duration = Duration::from_secs(2);

/// Why a drive could not start or go on; each names the server or the file.
#[derive(Debug, thiserror::Error)]
pub enum DriveError {
    #[error(transparent)]
    Session(#[from] SessionError),
}

/// A drive's robot, topics and limits.
#[derive(Clone, Debug)]
pub struct DriveConfig {
    /// The server's address, `ws://HOST:PORT`.
    pub url: String,
    /// The pose topics, as `pushlab live` takes them (`TOPIC` or `TOPIC:CHILD_FRAME`).
    pub pusher_topic: String,
    pub object_topic: String,
    /// Where the pusher's target is published.
    pub command_topic: String,
    /// The target's `header.frame_id`: the pose streams' frame.
    pub frame_id: String,
    /// A new MCAP file every message received and sent goes into.
    pub record: Option<PathBuf>,
    /// `None`: the box around the first poses and the goal (see [`WORKSPACE_MARGIN_M`]).
    pub workspace: Option<Workspace>,
    pub pacing: Pacing,
    /// Armed from the start (`--arm`); else nothing is sent until [`UserAction::Arm`].
    pub arm: bool,
    /// Seconds before the drive ends unreached.
    pub time_limit_s: f64,
}

/// What the user does while the loop runs (the app's buttons).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UserAction {
    Arm,
    Pause,
    Disarm,
}

/// What happened, one thing at a time, for the caller to show.
#[derive(Clone, Debug, PartialEq)]
pub enum DriveEvent {
    /// A control step: what was planned and what the gate let out (sent when `sent`).
    Step {
        step: ControlStep,
        command: Option<Command>,
        sent: bool,
    },
    /// The gate stopped sending; `hold` is what it sent once (if it could).
    Halted {
        why: Halt,
        hold: Option<Command>,
        sent: bool,
    },
    /// Something the user should read (the session's words, the workspace taken).
    Said(String),
}

/// How a drive ended.
#[derive(Debug)]
pub struct DriveEnd {
    pub why: Halt,
    pub steps: usize,
    pub commands_sent: u64,
    pub recorded: Option<Recorded>,
}

/// A drive (see the module documentation).
pub struct Drive {
    session: LiveSession,
    control: PoseControl,
    config: DriveConfig,
    gate: Option<SafetyGate>,
    arm_asked: bool,
    /// The newest pose of each stream (pusher, object) and when it arrived.
    latest: [Option<(PlanarPose, Instant)>; 2],
    steps: usize,
}

impl Drive {
    /// Connects to the robot's server, follows its pose topics and advertises the command
    /// topic: refused, by name, by a server that does not offer client publish. The encoding
    /// the server takes the targets in.
    pub fn open(
        config: DriveConfig,
        control: PoseControl,
        stop: &dyn Fn() -> bool,
    ) -> Result<(Self, CommandEncoding), DriveError> {
        let mut session = LiveSession::open(
            &config.url,
            &config.pusher_topic,
            &config.object_topic,
            config.record.as_deref(),
            stop,
        )?;
        let encoding = session.advertise_command(&config.command_topic, &config.frame_id)?;
        // Half a control step: the clock is looked at often enough to keep the rate.
        session.read_at_most(Duration::from_secs_f64(0.5 / config.pacing.control_hz))?;
        let arm_asked = config.arm;
        Ok((
            Self {
                session,
                control,
                config,
                gate: None,
                arm_asked,
                latest: [None, None],
                steps: 0,
            },
            encoding,
        ))
    }

    /// Runs until the goal is held, `stop` says so (the user's interrupt), the time limit passes,
    /// the poses go stale or the link drops; `user` is asked for the user's actions between
    /// events, and each event goes to `each`.
    pub fn run(
        mut self,
        stop: &dyn Fn() -> bool,
        user: &mut dyn FnMut() -> Option<UserAction>,
        each: &mut dyn FnMut(DriveEvent),
    ) -> Result<DriveEnd, DriveError> {
        let started = Instant::now();
        let period = Duration::from_secs_f64(1.0 / self.config.pacing.control_hz);
        let mut next_step = started + period;
        let why = loop {
            if stop() {
                break self.halt(Halt::Interrupted, each)?;
            }
            if started.elapsed().as_secs_f64() >= self.config.time_limit_s {
                break self.halt(Halt::TimeLimit, each)?;
            }
            match user() {
                Some(UserAction::Arm) => self.arm(),
                Some(UserAction::Pause) => {
                    self.halt(Halt::Paused, each)?;
                }
                Some(UserAction::Disarm) => {
                    self.halt(Halt::Disarmed, each)?;
                    self.arm_asked = false;
                }
                None => {}
            }
            match self.session.next(stop)? {
                Some(SessionEvent::Pose {
                    stream,
                    pose,
                    log_time_ns,
                }) => {
                    self.control.take(stream, &pose, log_time_ns);
                    let slot = match stream {
                        Stream::Pusher => 0,
                        Stream::Object => 1,
                    };
                    self.latest[slot] = Some((pose, Instant::now()));
                }
                Some(SessionEvent::Said(what)) => each(DriveEvent::Said(what)),
                Some(SessionEvent::Lost(why)) => {
                    each(DriveEvent::Said(why));
                    break self.link_lost(stop, each)?;
                }
                Some(SessionEvent::Reconnected { .. } | SessionEvent::Image { .. }) | None => {}
            }
            let now = Instant::now();
            if now < next_step {
                continue;
            }
            // Late by more than a step (a slow read): the next step a period from now, not a burst.
            next_step += period;
            if next_step <= now {
                next_step = now + period;
            }
            if self.step(started, each)? {
                break self.halt(Halt::Reached, each)?;
            }
            if let Some(Halt::Stale) = self.gate.as_ref().and_then(SafetyGate::halted) {
                break Halt::Stale;
            }
        };
        let commands_sent = self.session.commands_sent();
        let recorded = self.session.finish()?;
        Ok(DriveEnd {
            why,
            steps: self.steps,
            commands_sent,
            recorded,
        })
    }

    fn arm(&mut self) {
        self.arm_asked = true;
        if let Some(gate) = self.gate.as_mut() {
            gate.arm();
        }
    }

    /// One control step, once both streams have a pose: plan, gate, send. Whether the goal is
    /// now held.
    fn step(
        &mut self,
        started: Instant,
        each: &mut dyn FnMut(DriveEvent),
    ) -> Result<bool, DriveError> {
        let [Some((pusher, pusher_at)), Some((object, object_at))] = self.latest else {
            return Ok(false);
        };
        let pusher_at_now = Point2::new(pusher.x, pusher.y);
        let object_pose = Pose2::new(object.x, object.y, object.yaw);
        if self.gate.is_none() {
            self.open_gate(pusher_at_now, &object_pose, each);
        }
        let step = self
            .control
            .plan(started.elapsed().as_secs_f64(), pusher_at_now, object_pose);
        self.steps += 1;
        let Some(gate) = self.gate.as_mut() else {
            return Ok(false);
        };
        let planned = Point2::new(step.target[0], step.target[1]);
        let command = gate.command(
            planned,
            pusher_at_now,
            pusher_at.elapsed(),
            object_at.elapsed(),
        );
        match (command, gate.halted()) {
            (Some(hold @ Command::Hold { .. }), Some(why)) => {
                let sent = self.session.send_command(hold.point())?;
                each(DriveEvent::Step {
                    step,
                    command: None,
                    sent: false,
                });
                each(DriveEvent::Halted {
                    why,
                    hold: Some(hold),
                    sent,
                });
                Ok(false)
            }
            (command, _) => {
                let sent = match command {
                    Some(c) => self.session.send_command(c.point())?,
                    None => false,
                };
                each(DriveEvent::Step {
                    step,
                    command,
                    sent,
                });
                Ok(self.control.is_done())
            }
        }
    }

    /// The gate, once the first poses give the workspace (unless it was given).
    fn open_gate(&mut self, pusher: Point2<f64>, object: &Pose2, each: &mut dyn FnMut(DriveEvent)) {
        let workspace = self.config.workspace.unwrap_or_else(|| {
            let (low, high) = self.control.planner().sites().outline().bounding_box();
            let reach = (high - low).norm() / 2.0 + WORKSPACE_MARGIN_M;
            let goal = self.control.planner().goal().pose.position;
            let w = Workspace::around(&[pusher, object.position, goal], reach);
            each(DriveEvent::Said(format!(
                "workspace: x {:.3} to {:.3} m, y {:.3} to {:.3} m (around the first poses and the goal; --workspace sets it)",
                w.min[0], w.max[0], w.min[1], w.max[1]
            )));
            w
        });
        let mut gate = SafetyGate::new(Limits {
            speed: self.config.pacing.pusher_speed,
            control_hz: self.config.pacing.control_hz,
            workspace,
        });
        if self.arm_asked {
            gate.arm();
        }
        self.gate = Some(gate);
    }

    /// The gate halted for `why`: its one hold sent, said. `why` again, to end the loop with.
    fn halt(&mut self, why: Halt, each: &mut dyn FnMut(DriveEvent)) -> Result<Halt, DriveError> {
        let pusher = self.latest[0].map(|(p, _)| Point2::new(p.x, p.y));
        let hold = self.gate.as_mut().and_then(|g| g.halt(why, pusher));
        let sent = match hold {
            Some(c) => self.session.send_command(c.point())?,
            None => false,
        };
        each(DriveEvent::Halted { why, hold, sent });
        Ok(why)
    }

    /// The link dropped: the gate halts; its hold is sent if the link comes back within
    /// [`HOLD_AFTER_LOSS`] (the session connects again and advertises the command topic anew).
    fn link_lost(
        &mut self,
        stop: &dyn Fn() -> bool,
        each: &mut dyn FnMut(DriveEvent),
    ) -> Result<Halt, DriveError> {
        let pusher = self.latest[0].map(|(p, _)| Point2::new(p.x, p.y));
        let hold = self
            .gate
            .as_mut()
            .and_then(|g| g.halt(Halt::LinkLost, pusher));
        let mut sent = false;
        if let Some(hold) = hold {
            let lost = Instant::now();
            let give_up = || stop() || lost.elapsed() >= HOLD_AFTER_LOSS;
            while !give_up() {
                if let Some(SessionEvent::Reconnected { .. }) = self.session.next(&give_up)? {
                    sent = self.session.send_command(hold.point())?;
                    break;
                }
            }
        }
        each(DriveEvent::Halted {
            why: Halt::LinkLost,
            hold,
            sent,
        });
        Ok(Halt::LinkLost)
    }
}
