//! What-if rollouts: from a recorded frame, the model's own predictions fed back for `k` steps
//! along the recorded pusher path. One step is the one-step prediction the online loss scores; after
//! that, each step starts from the pose the model predicted, so errors compound as they would for a
//! planner using the model.

use nalgebra::{Point2, Vector2};

use crate::geometry::Pose2;
use crate::model::{OnlineModel, OnlineParams, SampleInput};
use crate::trajectory::{Frame, Trajectory};

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
        pose = step(model, &pose, frames[frame].robot, next.1.robot, theta);
        frame = next.0;
        poses.push((frame, pose));
    }
    Rollout { start, poses }
}

/// One step: the object at `pose` pushed by the pusher moving from `robot_now` to `robot_next`.
fn step<M: OnlineModel + ?Sized>(
    model: &M,
    pose: &Pose2,
    robot_now: Point2<f64>,
    robot_next: Point2<f64>,
    theta: &OnlineParams,
) -> Pose2 {
    let input = SampleInput {
        robot_in_object: pose.point_in_object(robot_now).into(),
        robot_motion_in_object: pose.vector_in_object(robot_next - robot_now).into(),
    };
    let motion = model.predict(&input, theta).motion;
    pose.moved_by(Vector2::from(motion.translation), motion.rotation)
}

/// The prediction ahead of a push still coming in: where the object will be `horizon` frames after
/// the last of `frames`, if the pusher goes on as it moved over the last `horizon` frames (the
/// future pusher path is not known yet: constant velocity is the assumption, and the live error
/// measures it). The frame it is for and the pose; `None` before `horizon + 1` frames.
pub fn ahead<M: OnlineModel + ?Sized>(
    model: &M,
    frames: &[Frame],
    horizon: usize,
    theta: &OnlineParams,
) -> Option<(usize, Pose2)> {
    let horizon = horizon.max(1);
    let last = frames.len().checked_sub(1)?;
    let before = frames.get(last.checked_sub(horizon)?)?;
    let now = &frames[last];
    let robot_next = now.robot + (now.robot - before.robot);
    Some((
        last + horizon,
        step(model, &now.object, now.robot, robot_next, theta),
    ))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::geometry::Outline;
    use crate::model::{LossScale, PhysicsOnlyModel};

    #[test]
    fn ahead_is_the_one_step_rollout_when_the_pusher_keeps_its_velocity() {
        // A box pushed at constant velocity: the future the prediction assumes is the one recorded.
        let outline = Outline::rectangle(0.2, 0.3).unwrap();
        let unit = LossScale {
            sigma_pos: [1.0, 1.0],
            sigma_rot: 1.0,
        };
        let model = PhysicsOnlyModel::new(outline, 0.01, 0.01, unit);
        let frames: Vec<Frame> = (0..20)
            .map(|k| Frame {
                time: k as f64 * 0.1,
                robot: Point2::new(-0.11 + 0.001 * k as f64, 0.02),
                object: Pose2::new(0.001 * k as f64, 0.0, 0.002 * k as f64),
            })
            .collect();
        let theta = model.theta0();
        let trajectory = Trajectory::new(frames.clone());
        let (frame, pose) = ahead(&model, &frames[..=12], 5, &theta).expect("13 frames");
        assert_eq!(frame, 17);
        let rolled = rollout(&model, &trajectory, 12, 5, 1, &theta);
        // The same step; the extrapolated pusher position differs from the recorded one by rounding.
        let (frame_rolled, rolled) = rolled.poses[0];
        assert_eq!(frame_rolled, 17);
        let (offset, yaw) = rolled.motion_to(&pose);
        assert!(
            offset.norm() < 1e-12 && yaw.abs() < 1e-12,
            "{rolled:?} {pose:?}"
        );
        let (moved, _) = frames[12].object.motion_to(&pose);
        assert!(moved.norm() > 1e-3, "the push moves the box: {moved:?}");
        assert!(ahead(&model, &frames[..5], 5, &theta).is_none(), "5 frames");
    }
}
