//! A push held on one contact, seen as the object's body twist per metre of pusher travel: the
//! model predicts the object's motion for one push of its horizon, and a push continued on the
//! same contact in the same direction (the direction re-aimed in the object's frame, as the
//! controller re-aims it each step) repeats that motion, so the object moves along a circular arc.
//! One prediction then gives the whole arc in closed form, where a rollout would predict at every
//! step: what lets the planner weigh hundreds of pushes within a control step.

use crate::math;
use nalgebra::Vector2;

use crate::geometry::Pose2;

/// Below this rotation, the arc is a straight line to second order.
const STRAIGHT_RAD: f64 = 1e-9;

/// The object's motion per metre of pusher travel in its own frame: the velocity of its geometric
/// centre (object frame) and its rate of turn.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyTwist {
    pub velocity_in_object: Vector2<f64>,
    pub turn_per_m: f64,
}

impl BodyTwist {
    /// The twist whose arc over `travel_m` is the motion `translation_in_object`, `rotation` (the
    /// model's prediction for a push of that length): the inverse of [`BodyTwist::motion_over`].
    pub fn of_motion(translation_in_object: Vector2<f64>, rotation: f64, travel_m: f64) -> Self {
        if travel_m.is_nan() || travel_m <= 0.0 {
            return Self::default();
        }
        let velocity = inverse_arc(rotation) * translation_in_object;
        Self {
            velocity_in_object: velocity / travel_m,
            turn_per_m: rotation / travel_m,
        }
    }

    /// The motion (translation in the object frame at the start, rotation) after `travel_m` of
    /// pushing: the exponential of the twist.
    pub fn motion_over(&self, travel_m: f64) -> (Vector2<f64>, f64) {
        let angle = self.turn_per_m * travel_m;
        (arc(angle) * (self.velocity_in_object * travel_m), angle)
    }

    /// Where an object at `pose` is after `travel_m` of this push.
    pub fn pose_after(&self, pose: &Pose2, travel_m: f64) -> Pose2 {
        let (translation, rotation) = self.motion_over(travel_m);
        pose.moved_by(translation, rotation)
    }
}

/// `V(φ)`: the matrix that takes a constant body velocity integrated over a turn of `φ` to the
/// translation it makes, `[sin φ/φ, −(1−cos φ)/φ; (1−cos φ)/φ, sin φ/φ]`.
fn arc(angle: f64) -> nalgebra::Matrix2<f64> {
    let (a, b) = if angle.abs() < STRAIGHT_RAD {
        (1.0, angle / 2.0)
    } else {
        (math::sin(angle) / angle, (1.0 - math::cos(angle)) / angle)
    };
    nalgebra::Matrix2::new(a, -b, b, a)
}

/// `V(φ)⁻¹`, which exists for every turn short of a whole one.
fn inverse_arc(angle: f64) -> nalgebra::Matrix2<f64> {
    let v = arc(angle);
    let det = v[(0, 0)] * v[(0, 0)] + v[(1, 0)] * v[(1, 0)];
    nalgebra::Matrix2::new(v[(0, 0)], v[(1, 0)], -v[(1, 0)], v[(0, 0)]) / det
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_arc_of_a_motion_gives_the_motion_back() {
        let twist = BodyTwist::of_motion(Vector2::new(0.03, -0.01), 0.2, 0.04);
        let (t, r) = twist.motion_over(0.04);
        assert!((t - Vector2::new(0.03, -0.01)).norm() < 1e-12, "{t:?}");
        assert!((r - 0.2).abs() < 1e-12);
    }

    #[test]
    fn repeating_a_motion_is_travelling_twice_as_far() {
        // Closed form against composing the one motion twice.
        let pose = Pose2::new(0.1, -0.2, 0.7);
        let (t, r) = (Vector2::new(0.02, 0.005), -0.15);
        let twice = pose.moved_by(t, r).moved_by(t, r);
        let arc = BodyTwist::of_motion(t, r, 0.04).pose_after(&pose, 0.08);
        assert!(
            (twice.position - arc.position).norm() < 1e-12,
            "{twice:?} {arc:?}"
        );
        assert!((twice.yaw - arc.yaw).abs() < 1e-12);
    }

    #[test]
    fn a_pure_turn_keeps_the_centre_on_a_circle_about_the_turning_point() {
        // Velocity (0, 1) with turn 1 per metre: a circle of radius 1 about (−1, 0).
        let twist = BodyTwist {
            velocity_in_object: Vector2::new(0.0, 1.0),
            turn_per_m: 1.0,
        };
        let quarter = twist.pose_after(&Pose2::new(0.0, 0.0, 0.0), std::f64::consts::FRAC_PI_2);
        assert!((quarter.position.x - -1.0).abs() < 1e-12, "{quarter:?}");
        assert!((quarter.position.y - 1.0).abs() < 1e-12);
    }
}
