//! The live worker's half of Drive (see `live_drive`): the command topic advertised, the core's
//! `Commander` fed every pose as it arrives, and at the control rate the newest target the UI
//! planned passed through it and sent. The user's asks (arm, pause, disarm, the goal reached) are
//! taken from the inbox as they come; a lost link's hold is sent when the link is back within
//! two seconds, as `pushlab control` sends it; the session ending sends one hold.

use std::time::{Duration, Instant};

use pushlab_core::control::drive::{Command, Commander, Gated, Halt};
use pushlab_core::live::grid::Stream;
use pushlab_core::live::{LiveSession, SessionError};
use pushlab_core::recording::bag::PlanarPose;

use crate::app::state::sources::live::WorkerLink;
use crate::app::state::sources::live_drive::{DriveSetup, DriveStatus, WorkerAsk};

/// How long a lost link is waited for, to send the hold once it is back.
const HOLD_AFTER_LOSS: Duration = Duration::from_secs(2);

/// A drive on the worker (see the module documentation).
pub struct Commanding {
    commander: Commander,
    period: Duration,
    next_step: Instant,
    /// The hold of a link lost, until the link is back or it is too late to send it.
    lost_hold: Option<(Command, Instant)>,
    status: DriveStatus,
}

impl Commanding {
    /// Advertises the command topic; a server that does not take client publish is refused by
    /// name, and the session goes on watching.
    pub fn open(session: &mut LiveSession, setup: &DriveSetup) -> Result<Self, SessionError> {
        session.advertise_command(&setup.command, &setup.frame)?;
        let period = Duration::from_secs_f64(1.0 / setup.commander.pacing.control_hz);
        // Half a control step: the clock is looked at often enough to keep the rate.
        session.read_at_most(period / 2)?;
        Ok(Self {
            commander: Commander::new(setup.commander.clone()),
            period,
            next_step: Instant::now() + period,
            lost_hold: None,
            status: DriveStatus::default(),
        })
    }

    /// What the inbox says of a drive refused: why, and nothing else.
    pub fn refused(why: &SessionError) -> DriveStatus {
        DriveStatus {
            refused: Some(format!("cannot drive: {why}; watching only")),
            ..DriveStatus::default()
        }
    }

    pub fn take(&mut self, stream: Stream, pose: &PlanarPose) {
        self.commander.take(stream, pose, Instant::now());
    }

    /// The user's asks, then a control step when its time came: what the commander lets out is
    /// sent. Sentences for the user go to `said`.
    pub fn tick(
        &mut self,
        session: &mut LiveSession,
        link: &WorkerLink,
        said: &mut Vec<String>,
    ) -> Result<(), SessionError> {
        let (asks, target) = link.with(|inbox| {
            let to = &mut inbox.to_worker;
            (std::mem::take(&mut to.asks), to.target)
        });
        for ask in asks {
            match ask {
                WorkerAsk::Arm => self.commander.arm(),
                WorkerAsk::Halt(why) => {
                    let hold = self.commander.halt(why);
                    self.send(session, hold)?;
                }
            }
        }
        let now = Instant::now();
        if now >= self.next_step {
            // Late by more than a step: the next a period from now, not a burst.
            self.next_step += self.period;
            if self.next_step <= now {
                self.next_step = now + self.period;
            }
            match self.commander.command(target, now, &mut |s| said.push(s)) {
                Gated::Nothing => {}
                Gated::Send(command) => self.send(session, Some(command))?,
                Gated::Halted { why, hold } => {
                    said.push(format!("the drive held the pusher: {}", why.describe()));
                    self.send(session, hold)?;
                }
            }
        }
        self.say(link);
        Ok(())
    }

    /// The link dropped: the gate halts, its hold kept for the link's return.
    pub fn lost(&mut self) {
        self.lost_hold = (self.commander.halt(Halt::LinkLost)).map(|hold| (hold, Instant::now()));
    }

    /// The link is back: the hold of its loss sent, if still in time (the session advertised the
    /// command topic again on connecting).
    pub fn reconnected(&mut self, session: &mut LiveSession) -> Result<(), SessionError> {
        if let Some((hold, lost)) = self.lost_hold.take()
            && lost.elapsed() <= HOLD_AFTER_LOSS
        {
            self.send(session, Some(hold))?;
        }
        Ok(())
    }

    /// The session ends (Disconnect, the app closing): one hold, if anything was being sent.
    pub fn finish(&mut self, session: &mut LiveSession, link: &WorkerLink) {
        let hold = self.commander.halt(Halt::Interrupted);
        let _ = self.send(session, hold);
        self.say(link);
    }

    fn send(
        &mut self,
        session: &mut LiveSession,
        command: Option<Command>,
    ) -> Result<(), SessionError> {
        if let Some(command) = command
            && session.send_command(command.point())?
        {
            self.status.sent += 1;
            self.status.last = Some(command);
        }
        Ok(())
    }

    /// The drive as it is now, into the inbox.
    fn say(&mut self, link: &WorkerLink) {
        self.status.armed = self.commander.is_armed();
        self.status.halted = self.commander.halted();
        self.status.workspace = self.commander.gate().map(|g| g.limits().workspace);
        let status = self.status.clone();
        link.with(|inbox| inbox.latest.drive = Some(status));
    }
}
