//! What the controller would do at a frame of a recorded push: its next step from where the frame
//! has the object and the pusher, toward where the push ended, with the model and θ the run has
//! at that frame. A researcher sets it beside what the person or robot that made the push did.
//!
//! A fresh planner for each frame (no push kept from the frame before, its draws seeded by the
//! frame), so that the answer depends on the frame alone and the same frame gives the same
//! answer, scrubbed to or played through. The pacing is the recording's own: its frame rate, and
//! its pusher's speed as [`Trajectory::pusher_speed`] measures it.

use super::Pacing;
use super::goal::Goal;
use super::planner::{Plan, Planner, PlannerConfig};
use crate::geometry::Outline;
use crate::model::{OnlineModel, OnlineParams};
use crate::trajectory::Trajectory;

/// A recorded push seen by the controller: the object's outline and the pusher's radius, the
/// model the run learns with (its horizon, in frames), and the push's pace ([`replay_pacing`]:
/// measured over the whole push, so a caller planning frame after frame measures it once).
pub struct ReplayedPush<'a, M: OnlineModel + ?Sized> {
    pub trajectory: &'a Trajectory,
    pub outline: &'a Outline,
    pub pusher_radius: f64,
    pub model: &'a M,
    pub horizon: usize,
    pub pacing: Pacing,
}

/// Where a replayed push's controller is sent: the object's pose at the push's last frame, with
/// the default tolerances.
pub fn replay_goal(trajectory: &Trajectory) -> Option<Goal> {
    trajectory.frames.last().map(|f| Goal::at(f.object))
}

/// The controller's pacing on a recording: a step per frame at its mean rate, its pusher at the
/// speed it moved (`None` for a push too short to say either).
pub fn replay_pacing(trajectory: &Trajectory) -> Option<Pacing> {
    let rate = trajectory.mean_rate_hz();
    let speed = trajectory.pusher_speed()?;
    (rate.is_finite() && rate > 0.0 && speed.is_finite() && speed > 0.0).then_some(Pacing {
        pusher_speed: speed,
        control_hz: rate,
        grid_hz: rate,
    })
}

impl<M: OnlineModel + ?Sized> ReplayedPush<'_, M> {
    /// The controller's step from `frame` with `theta` (the run's at that frame), toward where
    /// the push ended; `None` past the push's end.
    pub fn plan_at(&self, frame: usize, theta: &OnlineParams) -> Option<(Goal, Plan)> {
        let f = self.trajectory.frames.get(frame)?;
        let goal = replay_goal(self.trajectory)?;
        let config = PlannerConfig {
            seed: frame as u64,
            ..PlannerConfig::default()
        };
        let mut planner = Planner::paced(
            self.outline,
            self.pusher_radius,
            goal,
            self.pacing,
            self.horizon,
            config,
        );
        let plan = planner.step(&f.object, f.robot, self.model, theta).clone();
        Some((goal, plan))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use std::path::Path;

    use super::*;
    use crate::control::Phase;
    use crate::model_file::ModelFile;
    use crate::recording::native::read_set;

    #[test]
    fn from_a_frame_of_a_recorded_push_the_controller_heads_for_where_the_push_ended() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let model = ModelFile::load(&root.join("assets/default-model.json")).unwrap();
        let (set, _) = read_set(&root.join("sample-data/box1-paper-ur-front")).unwrap();
        let recording = &set.recordings[0];
        let outline = set.setting.object.outline().unwrap();
        let geometry = crate::experiment::geometry_of(&set.setting);
        let learner = model.combined.on_object(geometry.as_ref().ok()).unwrap();
        let push = ReplayedPush {
            trajectory: &recording.trajectory,
            outline: &outline,
            pusher_radius: set.setting.pusher_radius,
            model: learner.as_ref(),
            horizon: model.combined.horizon(),
            pacing: replay_pacing(&recording.trajectory).unwrap(),
        };
        let theta = learner.theta0();
        let (goal, plan) = push.plan_at(0, &theta).unwrap();
        let last = recording.trajectory.frames.last().unwrap().object;
        assert_eq!(goal.pose, last);
        // The step is a step of the recording's own pusher, no longer.
        let pacing = push.pacing;
        let first = &recording.trajectory.frames[0];
        let moved = (plan.target - first.robot).norm();
        assert!(moved <= pacing.step_m() + 1e-9, "{moved} m");
        // Far from where it ended, it plans a push that brings the object nearer.
        assert_ne!(plan.phase, Some(Phase::Holding));
        let chosen = plan.push.unwrap();
        assert!(
            chosen.expected_distance_m < goal.distance(&first.object),
            "{chosen:?}"
        );
        // The same frame, the same answer; at the last frame, the object is there: it holds.
        assert_eq!(push.plan_at(0, &theta).unwrap().1, plan);
        let end = recording.trajectory.len() - 1;
        assert_eq!(
            push.plan_at(end, &theta).unwrap().1.phase,
            Some(Phase::Holding)
        );
        assert!(push.plan_at(end + 1, &theta).is_none());
    }
}
