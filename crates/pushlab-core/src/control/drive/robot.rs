//! The loop (see [`super`]): read the session's next event, take a pose as it arrives, and at
//! each control step plan, pass the target through the gate and send what it lets out.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use nalgebra::Point2;

use super::commander::{Commander, CommanderConfig, Gated, UserAction};
use super::gate::{Command, Halt, Workspace};
use crate::control::{ControlStep, Pacing, PoseControl};
use crate::live::{CommandEncoding, LiveSession, Recorded, SessionError, SessionEvent};

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
    /// `None`: the box around the first poses and the goal (see
    /// [`super::WORKSPACE_MARGIN_M`]).
    pub workspace: Option<Workspace>,
    pub pacing: Pacing,
    /// Armed from the start (`--arm`); else nothing is sent until [`UserAction::Arm`].
    pub arm: bool,
    /// Seconds before the drive ends unreached.
    pub time_limit_s: f64,
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
    commander: Commander,
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
        let commander = Commander::new(CommanderConfig {
            pacing: config.pacing,
            workspace: config.workspace,
            goal: control.planner().goal().pose.position,
            object_reach: CommanderConfig::reach_of(control.planner().sites().outline()),
            arm: config.arm,
        });
        Ok((
            Self {
                session,
                control,
                config,
                commander,
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
            if let Some((why, hold)) = user().and_then(|a| self.commander.act(a)) {
                self.say_halt(why, hold, each)?;
            }
            match self.session.next(stop)? {
                Some(SessionEvent::Pose {
                    stream,
                    pose,
                    log_time_ns,
                }) => {
                    self.control.take(stream, &pose, log_time_ns);
                    self.commander.take(stream, &pose, Instant::now());
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
            if let Some(Halt::Stale) = self.commander.halted() {
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

    /// One control step, once both streams have a pose: plan, gate, send. Whether the goal is
    /// now held.
    fn step(
        &mut self,
        started: Instant,
        each: &mut dyn FnMut(DriveEvent),
    ) -> Result<bool, DriveError> {
        let Some((pusher, object)) = self.commander.poses() else {
            return Ok(false);
        };
        let step = (self.control).plan(started.elapsed().as_secs_f64(), pusher, object);
        self.steps += 1;
        let planned = Point2::new(step.target[0], step.target[1]);
        let now = Instant::now();
        let gated = self
            .commander
            .command(Some((planned, now)), now, &mut |said| {
                each(DriveEvent::Said(said))
            });
        match gated {
            Gated::Halted { why, hold } => {
                each(DriveEvent::Step {
                    step,
                    command: None,
                    sent: false,
                });
                self.say_halt(why, hold, each)?;
                Ok(false)
            }
            Gated::Send(command) => {
                let sent = self.session.send_command(command.point())?;
                each(DriveEvent::Step {
                    step,
                    command: Some(command),
                    sent,
                });
                Ok(self.control.is_done())
            }
            Gated::Nothing => {
                each(DriveEvent::Step {
                    step,
                    command: None,
                    sent: false,
                });
                Ok(self.control.is_done())
            }
        }
    }

    /// The commander halted for `why`: its one hold (if any) sent, and said.
    fn say_halt(
        &mut self,
        why: Halt,
        hold: Option<Command>,
        each: &mut dyn FnMut(DriveEvent),
    ) -> Result<(), DriveError> {
        let sent = match hold {
            Some(c) => self.session.send_command(c.point())?,
            None => false,
        };
        each(DriveEvent::Halted { why, hold, sent });
        Ok(())
    }

    /// The gate halted for `why`: its one hold sent, said. `why` again, to end the loop with.
    fn halt(&mut self, why: Halt, each: &mut dyn FnMut(DriveEvent)) -> Result<Halt, DriveError> {
        let hold = self.commander.halt(why);
        self.say_halt(why, hold, each)?;
        Ok(why)
    }

    /// The link dropped: the gate halts; its hold is sent if the link comes back within
    /// [`HOLD_AFTER_LOSS`] (the session connects again and advertises the command topic anew).
    fn link_lost(
        &mut self,
        stop: &dyn Fn() -> bool,
        each: &mut dyn FnMut(DriveEvent),
    ) -> Result<Halt, DriveError> {
        let hold = self.commander.halt(Halt::LinkLost);
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
