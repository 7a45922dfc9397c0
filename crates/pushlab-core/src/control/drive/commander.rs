//! What stands between a planner and a robot's command topic, whoever plans: the newest pose of
//! each stream and when it arrived, the safety gate opened on the first poses (its workspace
//! taken around them and the goal unless one was given), the user's arming, and how old the
//! newest plan is. `pushlab control ws://…` ([`super::Drive`]) plans on the same thread; the
//! app plans on its UI thread with the run it shows and hands the targets to its live worker,
//! which runs this. Either way the targets go through here, so every rule holds for both.
//!
//! Pure, with the time passed in: what to send is returned, the caller sends it.

use std::time::{Duration, Instant};

use nalgebra::Point2;

use super::gate::{Command, Halt, Limits, STALE_AFTER, SafetyGate, Workspace};
use crate::control::Pacing;
use crate::geometry::{Outline, Pose2};
use crate::live::grid::Stream;
use crate::recording::bag::PlanarPose;

/// How far the workspace taken from the first poses reaches past them and the goal, beyond the
/// object's own size, metres: room to go round the object, not to wander.
pub const WORKSPACE_MARGIN_M: f64 = 0.15;

/// What bounds a commander: the pacing's speed and rate, the workspace (or the object's size
/// and the goal to take one around), and whether it is armed from the start.
#[derive(Clone, Debug)]
pub struct CommanderConfig {
    pub pacing: Pacing,
    /// `None`: the box around the first poses and the goal (see [`WORKSPACE_MARGIN_M`]).
    pub workspace: Option<Workspace>,
    /// Where the object should go: the workspace taken reaches it.
    pub goal: Point2<f64>,
    /// Half the diagonal of the object's outline, metres: the workspace taken reaches round it.
    pub object_reach: f64,
    /// Armed from the start (`--arm`); else nothing is sent until [`Commander::arm`].
    pub arm: bool,
}

impl CommanderConfig {
    /// Half the diagonal of `outline`'s bounding box: how far the object reaches from its origin.
    pub fn reach_of(outline: &Outline) -> f64 {
        let (low, high) = outline.bounding_box();
        (high - low).norm() / 2.0
    }
}

/// What the user does while a drive runs (the app's buttons).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UserAction {
    Arm,
    Pause,
    Disarm,
}

/// What a control step lets out.
#[derive(Clone, Debug, PartialEq)]
pub enum Gated {
    /// Nothing to send: no poses of both streams yet, no plan yet, or not armed.
    Nothing,
    /// The bounded target to send.
    Send(Command),
    /// The gate halted: its one hold (the pusher's own position), to send once.
    Halted { why: Halt, hold: Option<Command> },
}

/// The poses and the gate (see the module documentation).
#[derive(Clone, Debug)]
pub struct Commander {
    config: CommanderConfig,
    gate: Option<SafetyGate>,
    arm_asked: bool,
    /// The newest pose of each stream (pusher, object) and when it arrived.
    latest: [Option<(PlanarPose, Instant)>; 2],
}

impl Commander {
    pub fn new(config: CommanderConfig) -> Self {
        let arm_asked = config.arm;
        Self {
            config,
            gate: None,
            arm_asked,
            latest: [None, None],
        }
    }

    /// A pose as it arrived at `now`.
    pub fn take(&mut self, stream: Stream, pose: &PlanarPose, now: Instant) {
        let slot = match stream {
            Stream::Pusher => 0,
            Stream::Object => 1,
        };
        self.latest[slot] = Some((*pose, now));
    }

    /// The pusher's and the object's newest poses, once both streams have one.
    pub fn poses(&self) -> Option<(Point2<f64>, Pose2)> {
        let [Some((pusher, _)), Some((object, _))] = self.latest else {
            return None;
        };
        Some((
            Point2::new(pusher.x, pusher.y),
            Pose2::new(object.x, object.y, object.yaw),
        ))
    }

    /// The gate, once the first poses of both streams opened it.
    pub fn gate(&self) -> Option<&SafetyGate> {
        self.gate.as_ref()
    }

    /// Whether targets are being sent.
    pub fn is_armed(&self) -> bool {
        self.gate
            .as_ref()
            .map_or(self.arm_asked, SafetyGate::is_armed)
    }

    /// Why the gate stopped sending, since it was last armed.
    pub fn halted(&self) -> Option<Halt> {
        self.gate.as_ref().and_then(SafetyGate::halted)
    }

    /// The user arms it: targets are sent from the next control step on.
    pub fn arm(&mut self) {
        self.arm_asked = true;
        if let Some(gate) = self.gate.as_mut() {
            gate.arm();
        }
    }

    /// The user's action: arming, or the halt it makes with its one hold to send.
    pub fn act(&mut self, action: UserAction) -> Option<(Halt, Option<Command>)> {
        match action {
            UserAction::Arm => {
                self.arm();
                None
            }
            UserAction::Pause => Some((Halt::Paused, self.halt(Halt::Paused))),
            UserAction::Disarm => Some((Halt::Disarmed, self.halt(Halt::Disarmed))),
        }
    }

    /// Stops sending for `why`: the hold to send once, at the pusher's newest position, if
    /// anything was being sent. Disarming also forgets the arming asked before the gate opened.
    pub fn halt(&mut self, why: Halt) -> Option<Command> {
        if why == Halt::Disarmed {
            self.arm_asked = false;
        }
        let pusher = self.latest[0].map(|(p, _)| Point2::new(p.x, p.y));
        self.gate.as_mut().and_then(|g| g.halt(why, pusher))
    }

    /// A control step at `now` for the target `planned` at `planned_at` (`None`: nothing planned
    /// yet). The poses stale, or the plan older than [`Commander::plan_stale_after`] (the
    /// planner stopped: a frozen window), halt with one hold. `said` hears the workspace taken when the gate opens.
    pub fn command(
        &mut self,
        planned: Option<(Point2<f64>, Instant)>,
        now: Instant,
        said: &mut dyn FnMut(String),
    ) -> Gated {
        let [Some((pusher, pusher_at)), Some((object, object_at))] = self.latest else {
            return Gated::Nothing;
        };
        let pusher = Point2::new(pusher.x, pusher.y);
        if self.gate.is_none() {
            self.open_gate(pusher, Point2::new(object.x, object.y), said);
        }
        let plan_stale_after = self.plan_stale_after();
        let Some(gate) = self.gate.as_mut() else {
            return Gated::Nothing;
        };
        let age = |at: Instant| now.saturating_duration_since(at);
        let (pusher_age, object_age) = (age(pusher_at), age(object_at));
        let command = match planned {
            Some((_, at)) if gate.is_armed() && age(at) > plan_stale_after => {
                let hold = gate.halt(Halt::PlanStale, Some(pusher));
                return Gated::Halted {
                    why: Halt::PlanStale,
                    hold,
                };
            }
            Some((target, _)) => gate.command(target, pusher, pusher_age, object_age),
            // Nothing planned: the pusher stays, but stale poses still halt an armed gate.
            None if pusher_age.max(object_age) > STALE_AFTER => {
                gate.command(pusher, pusher, pusher_age, object_age)
            }
            None => None,
        };
        match (command, gate.halted()) {
            (Some(hold @ Command::Hold { .. }), Some(why)) => Gated::Halted {
                why,
                hold: Some(hold),
            },
            (Some(c), _) if planned.is_some() => Gated::Send(c),
            _ => Gated::Nothing,
        }
    }

    /// How old a plan may be before an armed commander holds the pusher: [`STALE_AFTER`] past
    /// the grid's frame period, since a planner that plans a step per new frame of the grid
    /// (the app's) plans no more often than that, and its window may take a frame to notice. At
    /// 10 Hz, 300 ms.
    pub fn plan_stale_after(&self) -> Duration {
        STALE_AFTER + Duration::from_secs_f64(1.0 / self.config.pacing.grid_hz)
    }

    /// How long ago the newest pose of either stream came, at `now` (`None` before both came).
    pub fn poses_age(&self, now: Instant) -> Option<Duration> {
        let [Some((_, a)), Some((_, b))] = self.latest else {
            return None;
        };
        Some(now.saturating_duration_since(a.min(b)))
    }

    /// The gate, from the workspace given or the box around the first poses and the goal.
    fn open_gate(
        &mut self,
        pusher: Point2<f64>,
        object: Point2<f64>,
        said: &mut dyn FnMut(String),
    ) {
        let config = &self.config;
        let workspace = config.workspace.unwrap_or_else(|| {
            let reach = config.object_reach + WORKSPACE_MARGIN_M;
            let w = Workspace::around(&[pusher, object, config.goal], reach);
            said(format!(
                "workspace: x {:.3} to {:.3} m, y {:.3} to {:.3} m (around the first poses and the goal; --workspace sets it)",
                w.min[0], w.max[0], w.min[1], w.max[1]
            ));
            w
        });
        let mut gate = SafetyGate::new(Limits {
            speed: config.pacing.pusher_speed,
            control_hz: config.pacing.control_hz,
            workspace,
        });
        if self.arm_asked {
            gate.arm();
        }
        self.gate = Some(gate);
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    fn commander(arm: bool) -> Commander {
        Commander::new(CommanderConfig {
            pacing: Pacing {
                pusher_speed: 0.04,
                control_hz: 10.0,
                grid_hz: 50.0,
            },
            workspace: None,
            goal: Point2::new(0.3, 0.0),
            object_reach: 0.05,
            arm,
        })
    }

    fn pose(x: f64, y: f64) -> PlanarPose {
        PlanarPose {
            stamp_ns: 0,
            x,
            y,
            yaw: 0.0,
        }
    }

    fn fed(arm: bool, now: Instant) -> Commander {
        let mut c = commander(arm);
        c.take(Stream::Pusher, &pose(-0.05, 0.0), now);
        c.take(Stream::Object, &pose(0.0, 0.0), now);
        c
    }

    #[test]
    fn the_workspace_is_taken_around_the_first_poses_and_the_goal_and_said() {
        let t0 = Instant::now();
        let mut c = fed(true, t0);
        let mut said = Vec::new();
        let sent = c.command(Some((Point2::new(-0.04, 0.0), t0)), t0, &mut |s| {
            said.push(s)
        });
        assert!(
            matches!(sent, Gated::Send(Command::Move { .. })),
            "{sent:?}"
        );
        let w = c.gate().unwrap().limits().workspace;
        assert!((w.min[0] - (-0.05 - 0.2)).abs() < 1e-12, "{w:?}");
        assert!((w.max[0] - (0.3 + 0.2)).abs() < 1e-12, "{w:?}");
        assert_eq!(said.len(), 1, "{said:?}");
        assert!(
            said[0].starts_with("workspace: x -0.250 to 0.500 m"),
            "{said:?}"
        );
    }

    #[test]
    fn a_plan_older_than_a_grid_frame_past_200_ms_sends_one_hold_then_nothing() {
        let t0 = Instant::now();
        let mut c = fed(true, t0);
        // The grid at 50 Hz: a plan 210 ms old is still in time, 230 ms is not.
        assert_eq!(c.plan_stale_after(), Duration::from_millis(220));
        let fine = t0 + Duration::from_millis(210);
        c.take(Stream::Pusher, &pose(-0.05, 0.0), fine);
        c.take(Stream::Object, &pose(0.0, 0.0), fine);
        let planned = Some((Point2::new(-0.04, 0.0), t0));
        assert!(matches!(
            c.command(planned, fine, &mut |_| {}),
            Gated::Send(_)
        ));
        let at = t0 + Duration::from_millis(230);
        // The poses keep coming; the plan does not.
        c.take(Stream::Pusher, &pose(-0.04, 0.0), at);
        c.take(Stream::Object, &pose(0.0, 0.0), at);
        let planned = Some((Point2::new(-0.03, 0.0), t0));
        assert_eq!(
            c.command(planned, at, &mut |_| {}),
            Gated::Halted {
                why: Halt::PlanStale,
                hold: Some(Command::Hold { at: [-0.04, 0.0] })
            }
        );
        assert_eq!(c.command(planned, at, &mut |_| {}), Gated::Nothing);
        // A fresh plan sends nothing either, until armed again.
        let fresh = Some((Point2::new(-0.03, 0.0), at));
        assert_eq!(c.command(fresh, at, &mut |_| {}), Gated::Nothing);
        c.arm();
        assert!(matches!(c.command(fresh, at, &mut |_| {}), Gated::Send(_)));
    }

    #[test]
    fn stale_poses_halt_an_armed_gate_even_with_nothing_planned() {
        let t0 = Instant::now();
        let mut c = fed(true, t0);
        let planned = Some((Point2::new(-0.04, 0.0), t0));
        assert!(matches!(
            c.command(planned, t0, &mut |_| {}),
            Gated::Send(_)
        ));
        let late = t0 + Duration::from_millis(300);
        assert_eq!(
            c.command(None, late, &mut |_| {}),
            Gated::Halted {
                why: Halt::Stale,
                hold: Some(Command::Hold { at: [-0.05, 0.0] })
            }
        );
    }

    #[test]
    fn nothing_is_sent_unarmed_and_a_disarm_forgets_an_arming_asked_early() {
        let t0 = Instant::now();
        let mut c = fed(false, t0);
        let planned = Some((Point2::new(-0.04, 0.0), t0));
        assert_eq!(c.command(planned, t0, &mut |_| {}), Gated::Nothing);
        assert_eq!(c.halt(Halt::Paused), None, "no hold: nothing was sent");

        // Armed and disarmed before any pose came: still nothing once the poses come.
        let mut early = commander(false);
        early.arm();
        assert!(early.is_armed());
        assert_eq!(early.halt(Halt::Disarmed), None);
        assert!(!early.is_armed());
        early.take(Stream::Pusher, &pose(-0.05, 0.0), t0);
        early.take(Stream::Object, &pose(0.0, 0.0), t0);
        assert_eq!(early.command(planned, t0, &mut |_| {}), Gated::Nothing);
    }
}
