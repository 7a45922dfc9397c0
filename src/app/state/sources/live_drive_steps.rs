//! Drive's control steps on the UI thread (see `live_drive`): a step per new frame of the live
//! push shown, planned with the run the app learns it with, the target handed to the worker
//! stamped; the drive's buttons passed to the worker's commander.

use nalgebra::Point2;
use pushlab_core::control::drive::Halt;
use pushlab_core::control::{Goal, PlanWith, plan_step};
use pushlab_core::geometry::Pose2;

use crate::app::platform::Instant;
use crate::app::state::AppState;
use crate::app::state::sources::growing::Feed;
use crate::app::state::sources::live_drive::{DriveCommand, LiveDrive, WorkerAsk};

impl AppState {
    /// The drive of the live push shown, for the scene to draw its goal and plan.
    pub fn live_drive_shown(&self) -> Option<&LiveDrive> {
        let running = self.live.running()?;
        (self.session.selected == Some(running.recording))
            .then_some(running.drive.as_ref())
            .flatten()
    }

    /// The drive's buttons, passed to the worker's commander, and a goal dragged in the scene.
    pub(in crate::app::state) fn apply_drive(&mut self, command: DriveCommand) {
        let Some(running) = self.live.running_mut() else {
            return;
        };
        let Some(drive) = running.drive.as_mut() else {
            return;
        };
        let (ask, said) = match command {
            DriveCommand::Arm => {
                drive.reached = false;
                drive.driving.held = 0;
                drive.armed_at_s.get_or_insert(drive.driving.time_s());
                let said = format!(
                    "ARMED: the controller's targets go to the robot, planned with {}",
                    drive.driving.plan_with.description()
                );
                (WorkerAsk::Arm, said)
            }
            DriveCommand::Pause => (
                WorkerAsk::Halt(Halt::Paused),
                "paused: the pusher is held where it is".to_owned(),
            ),
            DriveCommand::Disarm => (
                WorkerAsk::Halt(Halt::Disarmed),
                "disarmed: nothing is sent to the robot".to_owned(),
            ),
            DriveCommand::SetGoal(goal) => return self.move_drive_goal(goal),
        };
        running.link.with(|inbox| inbox.to_worker.asks.push(ask));
        self.status = Some(said);
    }

    /// The goal dragged to `x, y, yaw`: refused (and said) where the object would not fit the
    /// workspace the targets are kept in; else the planner heads for it, the form's choice
    /// remembers it, and an armed drive pauses with one hold. Re-aiming a robot that is pushing
    /// is the user's to confirm with Arm, as the sandbox's run stops when its goal moves.
    fn move_drive_goal(&mut self, [x, y, yaw]: [f64; 3]) {
        let Some(running) = self.live.running_mut() else {
            return;
        };
        let Some(drive) = running.drive.as_mut() else {
            return;
        };
        if !(x.is_finite() && y.is_finite() && yaw.is_finite()) {
            return;
        }
        let status = running.latest.drive.clone().unwrap_or_default();
        if let Some(w) = status.workspace
            && !w.fits(Point2::new(x, y), drive.object_reach)
        {
            self.status = Some(format!(
                "the goal was not moved to ({x:.3} m, {y:.3} m): the object there would leave the \
                 workspace the pusher's targets are kept in (x {:.3} to {:.3} m, y {:.3} to {:.3} m)",
                w.min[0], w.max[0], w.min[1], w.max[1]
            ));
            return;
        }
        (drive.driving.planner).set_goal(Goal::at(Pose2::new(x, y, yaw)));
        drive.reached = false;
        drive.driving.held = 0;
        drive.armed_at_s = None;
        running.choice.drive.goal = [x, y, yaw];
        let sending = status.armed && status.halted.is_none();
        if sending {
            (running.link).with(|inbox| inbox.to_worker.asks.push(WorkerAsk::Halt(Halt::Paused)));
        }
        let choice = running.choice.clone();
        self.live.remember(choice);
        let at = format!("({x:.3} m, {y:.3} m, {:.0}°)", yaw.to_degrees());
        let paused = match sending || status.halted == Some(Halt::Paused) {
            true => ": paused, the pusher held",
            false => "",
        };
        self.status = Some(format!("the goal moved to {at}{paused}; Arm to push to it"));
    }

    /// A control step per new frame of the live push shown: planned with its run, the target
    /// handed to the worker. The goal held still ends the drive with the worker's one hold.
    pub(in crate::app::state) fn drive_live(&mut self) {
        let Some(running) = self.live.running() else {
            return;
        };
        if (running.latest.drive.as_ref()).is_some_and(|d| d.refused.is_some()) {
            // The server cannot be driven: the session watches, nothing is planned.
            if let Some(running) = self.live.running_mut() {
                running.drive = None;
            }
            return;
        }
        let Some(drive) = running.drive.as_ref().filter(|d| !d.reached) else {
            return;
        };
        let recording = running.recording;
        let growing = (self.growing.as_ref())
            .is_some_and(|g| g.feed == Feed::Live && g.open && g.recording == recording);
        let Some(run) = self
            .run
            .as_ref()
            .filter(|_| growing && self.session.selected == Some(recording))
        else {
            return;
        };
        let frames = run.trajectory().len();
        let Some(last) = run.trajectory().frames.last() else {
            return;
        };
        if frames <= drive.driving.frames_seen {
            return;
        }
        let (object, pusher) = (last.object, last.robot);
        let plan_with = drive.driving.plan_with;
        let truth = drive.truth.unwrap_or(run.theta0());
        let run = match plan_with {
            PlanWith::Physics => run.physics_beside(),
            _ => Some(&**run),
        };
        let Some(running) = self.live.running_mut() else {
            return;
        };
        let Some(drive) = running.drive.as_mut() else {
            return;
        };
        let driving = &mut drive.driving;
        let plan = run.and_then(|run| {
            plan_step(
                &mut driving.planner,
                run,
                plan_with,
                &truth,
                (&object, pusher),
            )
        });
        let Some(plan) = plan else {
            running.drive = None;
            running.link.with(|inbox| {
                (inbox.to_worker.asks).push(WorkerAsk::Halt(Halt::Disarmed));
            });
            self.status = Some(
                "the drive stopped: physics alone and the weighted prediction plan with the \
                 physics run beside the model's (turn on the weighting)"
                    .to_owned(),
            );
            return;
        };
        let (target, phase) = (Point2::new(plan.target.x, plan.target.y), plan.phase);
        let reached = driving.count(frames, phase);
        let time_s = driving.time_s() - drive.armed_at_s.unwrap_or(0.0);
        running.link.with(|inbox| {
            let to = &mut inbox.to_worker;
            match reached {
                true => to.asks.push(WorkerAsk::Halt(Halt::Reached)),
                false => to.target = Some((target, Instant::now())),
            }
        });
        if reached {
            drive.reached = true;
            self.status = Some(format!(
                "the goal is reached and held in {time_s:.1} s from Arm, planned with {}: the \
                 pusher is held",
                plan_with.description()
            ));
        }
    }
}
