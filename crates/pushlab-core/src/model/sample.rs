//! Training and prediction samples in the object frame (paper eqs. 1–4).

use nalgebra::Point2;
use serde::{Deserialize, Serialize};

use crate::trajectory::Trajectory;

/// What the model sees at time t: where the robot is and how it will move, both in the object frame
/// of time t (origin at the object's geometric centre).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SampleInput {
    /// `p_r^o`: pusher centre relative to the object's geometric centre, object frame, metres (eq. 1).
    pub robot_in_object: [f64; 2],
    /// `u_r^o`: pusher motion from t to t+k, object frame of t, metres (eq. 2).
    pub robot_motion_in_object: [f64; 2],
}

/// How the object moves from t to t+k: its geometric centre's translation in the object frame of t
/// (eq. 3) and its rotation, wrapped to (−π, π] (eq. 4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ObjectMotion {
    /// `Δp_o`, metres.
    pub translation: [f64; 2],
    /// `Δω_o`, radians.
    pub rotation: f64,
}

/// One `(x, y)` pair.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// `x`.
    pub input: SampleInput,
    /// `y`.
    pub target: ObjectMotion,
    /// Index of frame t in its trajectory, so that per-frame labels and plots can refer back.
    pub frame: usize,
}

/// The samples of a trajectory for a prediction horizon of `horizon` frames: sample i predicts the
/// motion from frame i to frame i + horizon. A horizon of 0 is treated as 1.
pub fn samples_from_trajectory(trajectory: &Trajectory, horizon: usize) -> Vec<Sample> {
    (0..sample_count(trajectory, horizon))
        .filter_map(|i| sample_at(trajectory, i, horizon))
        .collect()
}

/// The samples of a trajectory at `horizon` without those [`sample_is_skipped`] leaves out for
/// `frame_mask`: what training, evaluation and online learning take from a recording.
pub fn samples_kept(trajectory: &Trajectory, horizon: usize, frame_mask: &[bool]) -> Vec<Sample> {
    (0..sample_count(trajectory, horizon))
        .filter(|&i| !sample_is_skipped(frame_mask, i, horizon))
        .filter_map(|i| sample_at(trajectory, i, horizon))
        .collect()
}

/// How many samples a trajectory has at `horizon` frames: one per frame but the last `horizon`.
pub fn sample_count(trajectory: &Trajectory, horizon: usize) -> usize {
    trajectory.frames.len().saturating_sub(horizon.max(1))
}

/// The sample that predicts from frame `frame` over `horizon` frames (0 is treated as 1), or `None`
/// within the horizon of the end. The one rule behind [`samples_from_trajectory`], for callers that
/// must not hold every sample of a long recording at once.
pub fn sample_at(trajectory: &Trajectory, frame: usize, horizon: usize) -> Option<Sample> {
    let k = horizon.max(1);
    let now = trajectory.frames.get(frame)?;
    let later = trajectory.frames.get(frame.checked_add(k)?)?;
    let object = now.object;
    let robot_in_object = object.point_in_object(now.robot);
    let robot_motion_in_object = object.vector_in_object(later.robot - now.robot);
    let (translation, rotation) = object.motion_to(&later.object);
    Some(Sample {
        input: SampleInput {
            robot_in_object: [robot_in_object.x, robot_in_object.y],
            robot_motion_in_object: [robot_motion_in_object.x, robot_motion_in_object.y],
        },
        target: ObjectMotion {
            translation: [translation.x, translation.y],
            rotation,
        },
        frame,
    })
}

/// Whether the sample from `frame` to `frame + horizon` (a horizon of 0 counts as 1) touches a frame
/// flagged in `frame_mask` (labels mark frames of bad tracking: `labels::pipeline::frames_to_skip`): a sample is made from exactly those two frames,
/// so training, evaluation and the app's online learning leave it out. Frames past the mask's end
/// are not flagged.
pub fn sample_is_skipped(frame_mask: &[bool], frame: usize, horizon: usize) -> bool {
    let flagged = |f: usize| frame_mask.get(f).copied().unwrap_or(false);
    flagged(frame) || flagged(frame + horizon.max(1))
}

impl SampleInput {
    /// The pusher centre as a point, object frame.
    pub fn robot_point(&self) -> Point2<f64> {
        Point2::from(self.robot_in_object)
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::FRAC_PI_2;

    use super::*;
    use crate::geometry::Pose2;
    use crate::trajectory::Frame;

    fn frame(time: f64, robot: [f64; 2], object: [f64; 3]) -> Frame {
        Frame {
            time,
            robot: Point2::from(robot),
            object: Pose2::new(object[0], object[1], object[2]),
        }
    }

    #[test]
    fn hand_made_trajectory_gives_object_frame_samples() {
        // The object faces +y (yaw π/2) at (1, 1); the robot is 0.2 m below it in the world, i.e. at
        // −x in the object frame, and pushes it 0.01 m along world +y, which is object +x.
        let trajectory = Trajectory::new(vec![
            frame(0.0, [1.0, 0.8], [1.0, 1.0, FRAC_PI_2]),
            frame(0.1, [1.0, 0.81], [1.0, 1.01, FRAC_PI_2 + 0.02]),
            frame(0.2, [1.0, 0.82], [1.0, 1.02, FRAC_PI_2 + 0.03]),
        ]);
        let samples = samples_from_trajectory(&trajectory, 1);
        assert_eq!(samples.len(), 2);
        let s = samples[0];
        assert!((s.input.robot_in_object[0] + 0.2).abs() < 1e-12);
        assert!(s.input.robot_in_object[1].abs() < 1e-12);
        assert!((s.input.robot_motion_in_object[0] - 0.01).abs() < 1e-12);
        assert!(s.input.robot_motion_in_object[1].abs() < 1e-12);
        assert!((s.target.translation[0] - 0.01).abs() < 1e-12);
        assert!(s.target.translation[1].abs() < 1e-12);
        assert!((s.target.rotation - 0.02).abs() < 1e-12);
        assert_eq!(samples[1].frame, 1);

        let long = samples_from_trajectory(&trajectory, 2);
        assert_eq!(long.len(), 1);
        assert!((long[0].target.rotation - 0.03).abs() < 1e-12);
        assert!((long[0].input.robot_motion_in_object[0] - 0.02).abs() < 1e-12);
        assert!(samples_from_trajectory(&trajectory, 3).is_empty());
    }

    #[test]
    fn rotation_is_wrapped_across_the_unwrapped_yaw() {
        let trajectory = Trajectory::new(vec![
            frame(0.0, [0.0, 0.0], [0.0, 0.0, 3.1]),
            frame(0.1, [0.0, 0.0], [0.0, 0.0, 3.1 + 6.3]),
        ]);
        let s = samples_from_trajectory(&trajectory, 1)[0];
        assert!((s.target.rotation - (6.3 - 2.0 * std::f64::consts::PI)).abs() < 1e-12);
    }
}
