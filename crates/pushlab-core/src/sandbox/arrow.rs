//! A push drawn as an arrow on the object: pressed on (or near) its outline and dragged in the
//! direction to push, as long as the push. Read as `pushlab suggest` names a push and the sandbox
//! plans one ([`PushChoice`]): the face whose push direction meets the outline's inward normal at
//! the press best, the offset along that face from its middle (positive to the pusher's left, as
//! `setting.json`'s `contact_offset`), the arrow's angle from that inward normal, and its length.

use crate::math;
use nalgebra::{Point2, Vector2};

use super::table::PushChoice;
use crate::geometry::{Outline, Pose2, cross};
use crate::inspect::PushShape;
use crate::recording::PushSide;

/// Arrows shorter than this are a click, not a push, metres.
pub const SHORTEST_M: f64 = 0.005;

/// The push an arrow from `from` to `to` (world, metres) means on `outline` at `object`; `None`
/// for an arrow too short, or pointing out of the object (more than 85° from the inward normal).
pub fn push_drawn(
    outline: &Outline,
    object: &Pose2,
    from: Point2<f64>,
    to: Point2<f64>,
) -> Option<PushChoice> {
    let press = object.point_in_object(from);
    let arrow: Vector2<f64> = object.vector_in_object(to - from);
    let length = arrow.norm();
    if length.is_nan() || length < SHORTEST_M {
        return None;
    }
    let boundary = outline.closest_boundary_point(press);
    let inward = -boundary.normal;
    let face = PushSide::ALL.into_iter().max_by(|a, b| {
        let along = |side: &PushSide| {
            let [x, y] = side.push_direction();
            Vector2::new(x, y).dot(&inward)
        };
        along(a).total_cmp(&along(b))
    })?;
    let [x, y] = face.push_direction();
    let across = Vector2::new(-y, x);
    let offset = (boundary.point.coords - outline.centroid().coords).dot(&across);
    let angle = math::atan2(cross(inward, arrow), inward.dot(&arrow)).to_degrees();
    (angle.abs() < 85.0).then_some(PushChoice {
        face,
        offset_m: offset,
        angle_deg: angle,
        length_m: length,
    })
}

/// The push a ranked suggestion makes, as the sandbox plans one: the arrow from where its pusher
/// touches the object along the way it goes on, as long as it goes (`shape` in the object's
/// frame, as the ranking describes it). What a student's "do what the ranking says" pushes, and
/// the page's hook offers as `state().sandbox.suggested`.
pub fn push_of_shape(outline: &Outline, shape: &PushShape) -> Option<PushChoice> {
    let from = Point2::from(shape.contact_in_object);
    let to = from + Vector2::from(shape.direction_in_object) * shape.length_m;
    push_drawn(outline, &Pose2::new(0.0, 0.0, 0.0), from, to)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn an_arrow_into_the_front_face_is_a_front_push_at_its_offset_and_angle() {
        let outline = Outline::rectangle(0.3, 0.4).unwrap();
        let at = Pose2::new(0.0, 0.0, 0.0);
        // Pressed on the front face (x = −0.15) 5 cm to the pusher's left, dragged 8 cm in at 20°.
        let from = Point2::new(-0.15, 0.05);
        let direction = Vector2::new(20f64.to_radians().cos(), 20f64.to_radians().sin());
        let choice = push_drawn(&outline, &at, from, from + direction * 0.08).unwrap();
        assert_eq!(choice.face, PushSide::Front);
        assert!((choice.offset_m - 0.05).abs() < 1e-12, "{choice:?}");
        assert!((choice.angle_deg - 20.0).abs() < 1e-9, "{choice:?}");
        assert!((choice.length_m - 0.08).abs() < 1e-12);
        // The same on the object turned a quarter: the arrow turned with it.
        let turned = Pose2::new(0.5, 0.2, std::f64::consts::FRAC_PI_2);
        let from_w = turned.point_in_world(from);
        let to_w = turned.point_in_world(from + direction * 0.08);
        let again = push_drawn(&outline, &turned, from_w, to_w).unwrap();
        assert_eq!(again.face, PushSide::Front);
        assert!((again.angle_deg - 20.0).abs() < 1e-9);
        // Pointing out of the object, or a click: no push.
        assert!(push_drawn(&outline, &at, from, from - direction * 0.08).is_none());
        assert!(push_drawn(&outline, &at, from, from + direction * 0.001).is_none());
    }
}
