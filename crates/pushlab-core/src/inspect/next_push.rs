//! A push not yet made, seen through the model: where the object would go, what the push would teach
//! about `θ_online`, and what kind of push it is.
//!
//! A candidate push is a pusher path relative to the object's pose at its start (a recorded push of
//! the same object, or one laid out on a grid). Its outcome is not known, so the object's poses are
//! the model's own prediction with today's `θ` ([`predicted_poses`]), and each frame's Jacobian is
//! taken there: the Fisher information of the push ([`information_of`]). The posterior then says
//! how much the push would shrink the COM's uncertainty
//! (`learn::Posterior::com_covariance_after`). Nothing here reads the object's recorded motion
//! after the push's first frame.

use crate::math;
use nalgebra::Vector2;

use super::rollout::rollout;
use crate::geometry::{Outline, Pose2};
use crate::learn::PushInformation;
use crate::model::{ObjectMotion, OnlineModel, OnlineParams, Sample, SampleInput};
use crate::trajectory::Trajectory;

/// How close the pusher's disc must come to the outline (metres, gap between disc and outline) for a
/// push to count as touching it.
pub const TOUCH_M: f64 = 0.003;

/// How far after the touch the pusher's direction is read (metres): far enough that 2 mm of tracking
/// noise turns it by about 3° (a line fitted to the frames), near enough to describe how a curved path starts.
pub const DIRECTION_OVER_M: f64 = 0.05;

/// A pusher whose disc never comes within this of the outline (metres) misses the object.
pub const MISS_M: f64 = 0.01;

/// The object's pose at every frame of `trajectory`, as the model predicts it with `theta` along
/// the recorded pusher path from the recorded first pose: steps of `horizon` frames fed back
/// ([`rollout`]), the frames between them interpolated, the last pose held after the last step.
pub fn predicted_poses<M: OnlineModel + ?Sized>(
    model: &M,
    trajectory: &Trajectory,
    horizon: usize,
    theta: &OnlineParams,
) -> Vec<Pose2> {
    let frames = trajectory.frames.len();
    let Some(first) = trajectory.frames.first() else {
        return Vec::new();
    };
    let horizon = horizon.max(1);
    let steps = rollout(model, trajectory, 0, horizon, frames / horizon, theta);
    let mut knots = vec![(0, first.object)];
    knots.extend(steps.poses);
    let mut poses = Vec::with_capacity(frames);
    for pair in knots.windows(2) {
        let ((a, from), (b, to)) = (pair[0], pair[1]);
        let (offset, yaw) = from.motion_to(&to);
        for frame in a..b {
            let t = (frame - a) as f64 / (b - a) as f64;
            poses.push(from.moved_by(offset * t, yaw * t));
        }
    }
    let last = knots.last().map_or(first.object, |k| k.1);
    poses.resize(frames, last);
    poses
}

/// What learning `trajectory`'s frames would teach about `θ_online` if the object moved as the
/// model predicts with `theta`: each sample's Jacobian at the predicted poses, summed as the
/// posterior would take them in.
pub fn information_of<M: OnlineModel + ?Sized>(
    model: &M,
    trajectory: &Trajectory,
    horizon: usize,
    theta: &OnlineParams,
) -> PushInformation {
    let poses = predicted_poses(model, trajectory, horizon, theta);
    information_along(model, trajectory, &poses, horizon, theta)
}

/// [`information_of`] at given poses of the object (one per frame).
pub fn information_along<M: OnlineModel + ?Sized>(
    model: &M,
    trajectory: &Trajectory,
    poses: &[Pose2],
    horizon: usize,
    theta: &OnlineParams,
) -> PushInformation {
    let horizon = horizon.max(1);
    let robot = |i: usize| trajectory.frames[i].robot;
    let mut information = PushInformation::none();
    let ahead = poses.len().saturating_sub(horizon);
    for (frame, pose) in poses.iter().enumerate().take(ahead) {
        let input = SampleInput {
            robot_in_object: pose.point_in_object(robot(frame)).into(),
            robot_motion_in_object: pose
                .vector_in_object(robot(frame + horizon) - robot(frame))
                .into(),
        };
        // The target is never read: a Jacobian does not depend on it.
        let sample = Sample {
            input,
            target: ObjectMotion::default(),
            frame,
        };
        information.add(&model.linearize(&sample, theta));
    }
    information
}

/// What kind of push a pusher path is, seen from the object: the face it touches first, where, in
/// which direction and how far the pusher goes after.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PushShape {
    /// The frame the pusher first touches the object.
    pub touch_frame: usize,
    /// The face touched: the outline's edge from vertex `face` to `face + 1`.
    pub face: usize,
    /// Where on the outline, object frame, metres.
    pub contact_in_object: [f64; 2],
    /// Along the face from its middle, metres, positive to the left as the pusher faces it (as
    /// `setting.json`'s `contact_offset` and `pushlab simulate` count it).
    pub offset_m: f64,
    /// The pusher's direction after the touch against the face's inward normal, radians
    /// (counter-clockwise positive): 0 pushes straight in.
    pub angle_rad: f64,
    /// The pusher's direction after the touch, object frame, unit length.
    pub direction_in_object: [f64; 2],
    /// How far the pusher travels from the touch to the end of the push, metres.
    pub length_m: f64,
}

/// The shape of the push `trajectory` makes on an object of `outline` at `poses` (one per frame; the
/// first is where it rests until touched), pushed by a disc of `pusher_radius`; `None` when the disc
/// never comes within [`MISS_M`] of where the object rests.
pub fn shape_of(
    outline: &Outline,
    pusher_radius: f64,
    trajectory: &Trajectory,
    poses: &[Pose2],
) -> Option<PushShape> {
    let frames = poses.len().min(trajectory.frames.len());
    // The object does not move before the pusher touches it, so the touch is found against its
    // pose at the start: a prediction interpolated between steps of the horizon has it drifting
    // away before the touch, which would put the touch late.
    let met = poses.first()?;
    let gap = |i: usize| {
        let robot_in_object = met.point_in_object(trajectory.frames[i].robot);
        outline
            .closest_boundary_point(robot_in_object)
            .signed_distance
            - pusher_radius
    };
    // The pusher goes on into where the object was once it moved away, so the gap falls below
    // zero; a pusher that never came within MISS_M of where it was never touched it. Tracking
    // noise of millimetres may touch a frame early.
    let closest = (0..frames).map(gap).fold(f64::INFINITY, f64::min);
    if closest.is_nan() || closest > MISS_M {
        return None;
    }
    let touch = (0..frames).find(|&i| gap(i) <= closest.max(0.0) + TOUCH_M)?;
    let boundary =
        outline.closest_boundary_point(met.point_in_object(trajectory.frames[touch].robot));
    let vertices = outline.vertices();
    let (a, b) = (
        vertices[boundary.edge],
        vertices[(boundary.edge + 1) % vertices.len()],
    );
    let along = (b - a).normalize();
    let middle = a + (b - a) / 2.0;
    let robot = |i: usize| trajectory.frames[i].robot;
    let length_m: f64 = (touch + 1..trajectory.frames.len())
        .map(|i| (robot(i) - robot(i - 1)).norm())
        .sum();
    // The direction over the first few centimetres after the touch (or the rest of a shorter push),
    // fitted to every frame's position in that stretch: a curved path is described by how it
    // starts, and millimetres of tracking noise turn the direction between two frames a centimetre
    // apart by tens of degrees.
    let stretch: Vec<usize> = (touch..frames)
        .take_while(|&i| (robot(i) - robot(touch)).norm() <= DIRECTION_OVER_M)
        .collect();
    let ahead = fitted_direction(&stretch, |i| met.vector_in_object(robot(i) - robot(touch)))
        .unwrap_or(-boundary.normal);
    let direction = ahead.normalize();
    let inward = -boundary.normal;
    let angle_rad = math::atan2(
        inward.x * direction.y - inward.y * direction.x,
        inward.dot(&direction),
    );
    Some(PushShape {
        touch_frame: touch,
        face: boundary.edge,
        contact_in_object: boundary.point.into(),
        // Counter-clockwise along the face is to the pusher's right.
        offset_m: -(boundary.point - middle).dot(&along),
        angle_rad,
        direction_in_object: direction.into(),
        length_m,
    })
}

/// The least-squares direction of the points `at(i)` over the frames `stretch`, in the order of
/// the frames (the slope of each coordinate against the frame's place): `None` for fewer than two
/// frames or no motion.
fn fitted_direction(stretch: &[usize], at: impl Fn(usize) -> Vector2<f64>) -> Option<Vector2<f64>> {
    let n = stretch.len() as f64;
    if stretch.len() < 2 {
        return None;
    }
    let mean_place = (n - 1.0) / 2.0;
    let mean = stretch.iter().map(|&i| at(i)).sum::<Vector2<f64>>() / n;
    let slope: Vector2<f64> = stretch
        .iter()
        .enumerate()
        .map(|(k, &i)| (at(i) - mean) * (k as f64 - mean_place))
        .sum();
    (slope.norm() > 0.0).then(|| slope.normalize())
}

#[cfg(test)]
mod tests;
