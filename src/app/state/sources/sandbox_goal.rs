//! Push to goal in the sandbox: the core's controller (`control::Planner`) pushing the mystery
//! object to a goal the student placed, planning each frame from the newest pose with the model as
//! the growing push's run has learned it (or `θ_online(0)`, physics alone, the hidden truth: the
//! student switches and runs the same goal again to see the difference). Its pusher target is
//! held as a drag holds it, so its push grows and is learned on the one path every push takes;
//! frames where the pusher is away from the object are held over (`control::is_away`), as the
//! CLI's controller holds them.

use nalgebra::Point2;
use pushlab_core::control::{Goal, Pacing, PlanWith, Planner, PlannerConfig, plan_step};
use pushlab_core::geometry::Pose2;
use pushlab_core::model::OnlineParams;

use crate::app::state::AppState;
use crate::app::state::sources::growing::Feed;
use crate::app::state::sources::sandbox::Driving;

impl AppState {
    /// A goal for the sandbox's object; a push to the old goal stops.
    pub(in crate::app::state) fn set_sandbox_goal(&mut self, [x, y, yaw]: [f64; 3]) {
        if !(x.is_finite() && y.is_finite() && yaw.is_finite()) {
            return;
        }
        self.stop_push_to_goal("the goal moved");
        if let Some(s) = &mut self.sandbox {
            s.goal = Some(Pose2::new(x, y, yaw));
        }
    }

    pub(in crate::app::state) fn set_plan_with(&mut self, with: PlanWith) {
        if let Some(s) = &mut self.sandbox {
            s.plan_with = with;
        }
    }

    /// The controller starts pushing to the goal (refused, said, without a goal, while a push is
    /// being made by hand, or for physics alone without the physics run beside).
    pub(in crate::app::state) fn push_to_goal(&mut self) {
        let Some(s) = &self.sandbox else { return };
        let Some(goal) = s.goal else {
            self.status = Some("place the goal first: Set a goal, then drag it".into());
            return;
        };
        if s.sandbox.is_pushing() {
            self.status = Some("let the push being made end first".into());
            return;
        }
        let plan_with = s.plan_with;
        let mystery = s.sandbox.mystery();
        let horizon = self.models.horizon();
        let planner = Planner::paced(
            &mystery.sim.outline,
            mystery.sim.pusher_radius,
            Goal::at(goal),
            Pacing::sandbox(),
            horizon,
            PlannerConfig {
                seed: mystery.seed,
                ..PlannerConfig::default()
            },
        );
        if let Some(s) = &mut self.sandbox {
            s.driving = Some(Driving::new(
                planner,
                plan_with,
                pushlab_core::sandbox::mystery::RATE_HZ,
                self.run_generation,
            ));
            s.last_drive = None;
        }
        self.status = Some(format!(
            "pushing to the goal with {}",
            plan_with.description()
        ));
    }

    /// The controller lets go where the pusher is; `why` goes on the status line.
    pub(in crate::app::state) fn stop_push_to_goal(&mut self, why: &str) {
        let Some(s) = &mut self.sandbox else { return };
        let Some(driving) = s.driving.take() else {
            return;
        };
        let pusher = s.sandbox.pusher();
        s.sandbox.release(pusher);
        s.last_drive = Some((false, driving.time_s(), driving.plan_with));
        self.status = Some(format!(
            "push to goal {why} after {:.1} s",
            driving.time_s()
        ));
    }

    /// One control step per new frame of the push being driven: plan from the newest pose with
    /// the θ chosen, hold the pusher's target; the goal held still for half a second ends it.
    pub(in crate::app::state) fn drive_sandbox(&mut self) {
        let Some(s) = &self.sandbox else { return };
        let Some(driving) = &s.driving else { return };
        let growing = self
            .growing
            .as_ref()
            .filter(|g| g.feed == Feed::Sandbox && g.open);
        let run = self.run.as_ref().filter(|_| growing.is_some());
        let frames = run.map_or(0, |r| r.trajectory().len());
        if frames > 0 && frames <= driving.frames_seen {
            return;
        }
        let (object, pusher) = match run.and_then(|r| r.trajectory().frames.last()) {
            Some(f) => (f.object, f.robot),
            None => (s.sandbox.object_pose(), s.sandbox.pusher()),
        };
        let mystery = s.sandbox.mystery();
        let truth = OnlineParams {
            com_offset: mystery.hidden.com_offset,
            h: mystery.h,
        };
        let plan_with = driving.plan_with;
        // The first step, before the push's run exists, plans with the combined model (or physics
        // alone's start) at its starting θ; the weighted prediction's weights come with the run.
        let start = match run {
            Some(_) => None,
            None => match self.sandbox_start_model(plan_with, &truth) {
                Some(start) => Some(start),
                None => return self.cannot_plan(),
            },
        };
        // Physics alone is the app's physics run beside the model's.
        let planned_in = match (run, plan_with) {
            (Some(run), PlanWith::Physics) => run.physics_beside(),
            (run, _) => run.map(|r| &**r),
        };
        let Some(s) = &mut self.sandbox else { return };
        let Some(driving) = &mut s.driving else {
            return;
        };
        let plan = match (planned_in, &start) {
            (_, Some((model, theta))) => {
                Some(driving.planner.step(&object, pusher, model.as_ref(), theta))
            }
            (Some(run), None) => plan_step(
                &mut driving.planner,
                run,
                plan_with,
                &truth,
                (&object, pusher),
            ),
            (None, None) => None,
        };
        let Some(plan) = plan else {
            return self.cannot_plan();
        };
        let (target, phase) = (plan.target, plan.phase);
        if driving.count(frames, phase) {
            let time_s = driving.time_s();
            s.last_drive = Some((true, time_s, plan_with));
            s.driving = None;
            s.sandbox.release(pusher);
            self.status = Some(format!(
                "the goal is reached in {time_s:.1} s with {}",
                plan_with.description()
            ));
            return;
        }
        let events = s.sandbox.hold(Point2::new(target.x, target.y));
        self.take_sandbox_events(events);
    }

    /// The push to goal stops: what it plans with is not there.
    fn cannot_plan(&mut self) {
        self.stop_push_to_goal(
            "cannot plan: physics alone and the weighted prediction plan with the physics run \
             beside the model's (turn on the weighting), and the first step needs a trained model",
        );
    }

    /// The model and θ to plan the first step with, before the push's run exists: the model on
    /// the mystery at `θ_online(0)` (or the truth), or the carried θ of the last push.
    fn sandbox_start_model(
        &self,
        plan_with: PlanWith,
        truth: &OnlineParams,
    ) -> Option<(pushlab_core::model::SharedOnlineModel, OnlineParams)> {
        let s = self.sandbox.as_ref()?;
        let setting = s.sandbox.mystery().public_setting();
        let geometry = pushlab_core::experiment::geometry_of(&setting).ok();
        let model = self
            .models
            .combined
            .as_ref()?
            .on_object(geometry.as_ref())
            .ok()?;
        let theta = match plan_with {
            PlanWith::Truth => *truth,
            PlanWith::Online | PlanWith::Physics | PlanWith::Weighted => s
                .next_start
                .as_ref()
                .map_or(model.theta0(), |c| c.start.theta),
            PlanWith::Fixed => model.theta0(),
        };
        Some((model, theta))
    }
}
