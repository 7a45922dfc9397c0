//! What-if rollouts: from a recorded frame, the model's own predictions fed back for `k` steps
//! along the recorded pusher path. One step is the one-step prediction the online loss scores; after
//! that, each step starts from the pose the model predicted, so errors compound as they would for a
//! planner using the model.

use nalgebra::Vector2;

use crate::geometry::Pose2;
use crate::model::{OnlineModel, OnlineParams, SampleInput};
use crate::trajectory::Trajectory;

/// The predicted object poses of a rollout and where they end against the recording.
#[derive(Clone, Debug, PartialEq)]
pub struct Rollout {
    /// The frame the rollout starts from.
    pub start: usize,
    /// `(frame, predicted pose)` for each step, `horizon` frames apart.
    pub poses: Vec<(usize, Pose2)>,
}

impl Rollout {
    /// The last predicted pose's distance from the recorded one (metres) and the yaw difference
    /// (radians, wrapped), or `None` for an empty rollout.
    pub fn final_error(&self, trajectory: &Trajectory) -> Option<(f64, f64)> {
        let (frame, predicted) = self.poses.last()?;
        let recorded = trajectory.frames.get(*frame)?.object;
        let (offset, yaw) = recorded.motion_to(predicted);
        Some((offset.norm(), yaw))
    }
}

/// Rolls `model` with `theta` forward `k` steps of `horizon` frames from `start`: each step's input
/// is the recorded pusher's position and motion seen from the pose predicted so far. Stops early at
/// the end of the recording.
pub fn rollout<M: OnlineModel + ?Sized>(
    model: &M,
    trajectory: &Trajectory,
    start: usize,
    horizon: usize,
    k: usize,
    theta: &OnlineParams,
) -> Rollout {
    let horizon = horizon.max(1);
    let frames = &trajectory.frames;
    let mut poses = Vec::with_capacity(k);
    let Some(first) = frames.get(start) else {
        return Rollout { start, poses };
    };
    let mut pose = first.object;
    let mut frame = start;
    for _ in 0..k {
        let Some(next) = frame
            .checked_add(horizon)
            .and_then(|n| frames.get(n).map(|f| (n, f)))
        else {
            break;
        };
        let robot_now = frames[frame].robot;
        let input = SampleInput {
            robot_in_object: pose.point_in_object(robot_now).into(),
            robot_motion_in_object: pose.vector_in_object(next.1.robot - robot_now).into(),
        };
        let motion = model.predict(&input, theta).motion;
        pose = pose.moved_by(Vector2::from(motion.translation), motion.rotation);
        frame = next.0;
        poses.push((frame, pose));
    }
    Rollout { start, poses }
}
