//! The pusher's commanded path: where its centre is at every time (the pusher is position-controlled
//! and follows it exactly), and how a push "from this contact point at this angle" becomes one.

use crate::math;
use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

use crate::geometry::{Outline, Pose2, cross, rotate};
use crate::recording::PushSide;

/// A commanded path of the pusher's centre, world frame, starting at time 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PusherPath {
    /// Constant velocity.
    Straight {
        start: Point2<f64>,
        /// m/s, world frame.
        velocity: Vector2<f64>,
    },
    /// Constant speed along a circular arc.
    Arc {
        start: Point2<f64>,
        /// Initial direction of motion, radians, world frame.
        heading: f64,
        /// m/s.
        speed: f64,
        /// 1/m; positive turns left (counter-clockwise).
        curvature: f64,
    },
}

impl PusherPath {
    /// The pusher centre at time `t` seconds.
    pub fn position(&self, t: f64) -> Point2<f64> {
        match *self {
            PusherPath::Straight { start, velocity } => start + velocity * t,
            PusherPath::Arc {
                start,
                heading,
                speed,
                curvature,
            } => {
                let s = speed * t;
                let turn = curvature * s;
                // Chord in the frame of the initial heading, well-conditioned for small curvature.
                let (along, across) = if turn.abs() < 1e-9 {
                    (s, 0.5 * curvature * s * s)
                } else {
                    (
                        math::sin(turn) / curvature,
                        (1.0 - math::cos(turn)) / curvature,
                    )
                };
                start + rotate(Vector2::new(along, across), heading)
            }
        }
    }

    /// Path speed, m/s.
    pub fn speed(&self) -> f64 {
        match *self {
            PusherPath::Straight { velocity, .. } => velocity.norm(),
            PusherPath::Arc { speed, .. } => speed.abs(),
        }
    }
}

/// A push as an experimenter describes it: on a side, from a point along that face, at an angle.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PushPlan {
    /// The pushed face.
    pub side: PushSide,
    /// Where along the face the pusher first touches it, metres from the face's middle, positive to
    /// the left of the push direction (the push direction turned by +90°).
    pub contact_offset: f64,
    /// Angle of the pusher's initial motion from the face normal, degrees, positive counter-clockwise.
    pub push_angle_deg: f64,
    /// Pusher speed, m/s.
    pub speed: f64,
    /// Path curvature, 1/m (0 for a straight push; positive turns counter-clockwise).
    #[serde(default)]
    pub curvature: f64,
    /// Distance the pusher travels before it touches the face, metres.
    #[serde(default)]
    pub approach: f64,
}

/// Why a push plan cannot start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanError {
    #[error(
        "contact offset {offset} m is off the {side} face (it spans {low:.4} to {high:.4} m about \
         its middle)"
    )]
    OffFace {
        offset: f64,
        side: &'static str,
        low: f64,
        high: f64,
    },
    #[error("push angle {0}° is not in (−90°, 90°): the pusher would not move into the face")]
    BadAngle(f64),
    #[error("pusher speed {0} m/s must be positive and finite")]
    BadSpeed(f64),
    #[error(
        "at contact offset {offset} m and {angle_deg}°, the pusher would meet another part of the \
         object before it reaches the {side} face (a notch narrower than the disc, or a part in its \
         way); choose another offset or angle"
    )]
    Blocked {
        offset: f64,
        angle_deg: f64,
        side: &'static str,
    },
}

impl PushPlan {
    /// The commanded path for this plan, for an object at `object_pose` with a pusher of `radius`.
    ///
    /// The pusher starts `approach` metres before contact, moving at the push angle, so that it first
    /// touches the face exactly at the contact point.
    pub fn path(
        &self,
        outline: &Outline,
        object_pose: &Pose2,
        radius: f64,
    ) -> Result<PusherPath, PlanError> {
        if self.push_angle_deg.is_nan() || self.push_angle_deg.abs() >= 90.0 {
            return Err(PlanError::BadAngle(self.push_angle_deg));
        }
        if !(self.speed.is_finite() && self.speed > 0.0) {
            return Err(PlanError::BadSpeed(self.speed));
        }
        let (contact, outward) = face_point(outline, self.side, self.contact_offset)?;
        // From the normal of the face touched, not from the side's push direction: on a polygon the
        // face at an offset may be tilted, and an angle from the side's direction could point along
        // or out of it, starting the pusher inside the object. From the normal, the pusher always
        // moves into the face, and its whole approach stays clear of a convex outline (a non-convex
        // one is checked below).
        let direction_in_object = rotate(-outward, self.push_angle_deg.to_radians());
        let touching = contact + outward * radius;
        let start_in_object = touching - direction_in_object * self.approach.max(0.0);
        // A non-convex outline may be in the disc's way: another face nearer than the contact where
        // the disc touches, or met on the approach.
        if !outline.is_convex() {
            let tolerance = 1e-9 * outline.size();
            let overlaps_at_touch =
                outline.closest_boundary_point(touching).signed_distance - radius < -tolerance;
            let approach = touching - start_in_object;
            let met_before = approach.norm() > tolerance
                && outline
                    .disc_first_touch(start_in_object, approach, radius)
                    .is_some_and(|t| (1.0 - t) * approach.norm() > tolerance);
            if overlaps_at_touch || met_before {
                return Err(PlanError::Blocked {
                    offset: self.contact_offset,
                    angle_deg: self.push_angle_deg,
                    side: self.side.name(),
                });
            }
        }
        let start = object_pose.point_in_world(start_in_object);
        let direction = object_pose.vector_in_world(direction_in_object);
        Ok(if self.curvature == 0.0 {
            PusherPath::Straight {
                start,
                velocity: direction * self.speed,
            }
        } else {
            PusherPath::Arc {
                start,
                heading: math::atan2(direction.y, direction.x),
                speed: self.speed,
                curvature: self.curvature,
            }
        })
    }
}

/// The extent of the outline across `side`'s push direction, about the centroid: the middle and half
/// the length of the range of contact offsets that touch the face.
pub fn face_extent(outline: &Outline, side: PushSide) -> (f64, f64) {
    let (low, high) = across_range(outline, side);
    (0.5 * (low + high), 0.5 * (high - low))
}

/// The contact offsets at `fractions` of `side`'s half extent from its middle (−1 and 1 are the
/// face's two ends; see [`face_extent`]), metres rounded to 1 µm so that offsets read back from
/// `setting.json` look like the fractions that made them. The one grid of contact offsets: a
/// sample-data spec's push grids and `pushlab simulate --pushes` both take theirs from here.
pub fn contact_offsets(outline: &Outline, side: PushSide, fractions: &[f64]) -> Vec<f64> {
    let (middle, half) = face_extent(outline, side);
    fractions
        .iter()
        .map(|fraction| ((middle + fraction * half) * 1e6).round() / 1e6)
        .collect()
}

/// `count` fractions for [`contact_offsets`], evenly spaced over the middle 80 % of the face
/// (−0.8 to 0.8; the middle alone for one): pushes that spread over the face without starting at
/// a corner.
pub fn spread_fractions(count: usize) -> Vec<f64> {
    (0..count)
        .map(|i| {
            if count == 1 {
                0.0
            } else {
                -0.8 + 1.6 * i as f64 / (count - 1) as f64
            }
        })
        .collect()
}

fn across_range(outline: &Outline, side: PushSide) -> (f64, f64) {
    let [dx, dy] = side.push_direction();
    let across = Vector2::new(-dy, dx);
    let centroid = outline.centroid().coords;
    outline
        .vertices()
        .iter()
        .map(|v| (v.coords - centroid).dot(&across))
        .fold((f64::MAX, f64::MIN), |(lo, hi), s| (lo.min(s), hi.max(s)))
}

/// The point of `side`'s face at `offset` from its middle (the centroid's projection onto the face) and
/// the outward normal there: where the line along the push direction through that offset first enters
/// the outline (on a non-convex outline, the first of the faces it crosses, which may lie deep in a
/// notch).
pub fn face_point(
    outline: &Outline,
    side: PushSide,
    offset: f64,
) -> Result<(Point2<f64>, Vector2<f64>), PlanError> {
    let [dx, dy] = side.push_direction();
    let push = Vector2::new(dx, dy);
    let across = Vector2::new(-push.y, push.x);
    let centroid = outline.centroid().coords;
    let (low, high) = across_range(outline, side);
    let off_face = || PlanError::OffFace {
        offset,
        side: side.name(),
        low,
        high,
    };
    if !(offset > low && offset < high) {
        return Err(off_face());
    }
    let base = centroid + across * offset;
    if !outline.is_convex() {
        return first_entry(outline, Point2::from(base), push).ok_or_else(off_face);
    }
    // Entry of the line {centroid + offset·across + s·push} into the outline: the largest s at which
    // it crosses an edge whose outward normal faces against the push.
    let mut entry: Option<(f64, Vector2<f64>)> = None;
    for (a, b) in outline.edges() {
        let e = b - a;
        let outward = Vector2::new(e.y, -e.x).normalize();
        let facing = outward.dot(&push);
        if facing >= 0.0 {
            continue;
        }
        let s = (a.coords - base).dot(&outward) / facing;
        if entry.is_none_or(|(best, _)| s > best) {
            entry = Some((s, outward));
        }
    }
    let (s, outward) = entry.ok_or_else(off_face)?;
    Ok((Point2::from(base + push * s), outward))
}

/// Where the line `base + s·push` first enters a (non-convex) outline and the outward normal there:
/// the smallest `s` at which it crosses an edge facing against the push.
fn first_entry(
    outline: &Outline,
    base: Point2<f64>,
    push: Vector2<f64>,
) -> Option<(Point2<f64>, Vector2<f64>)> {
    let mut entry: Option<(f64, Vector2<f64>)> = None;
    for (a, b) in outline.edges() {
        let e = b - a;
        let outward = Vector2::new(e.y, -e.x).normalize();
        let denominator = cross(push, e);
        if outward.dot(&push) >= 0.0 || denominator == 0.0 {
            continue;
        }
        let w = a - base;
        let (s, u) = (cross(w, e) / denominator, cross(w, push) / denominator);
        if (0.0..=1.0).contains(&u) && entry.is_none_or(|(best, _)| s < best) {
            entry = Some((s, outward));
        }
    }
    entry.map(|(s, outward)| (base + push * s, outward))
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn face_points_of_a_box() {
        let b = Outline::rectangle(0.3, 0.4).unwrap();
        let (p, n) = face_point(&b, PushSide::Front, 0.05).unwrap();
        assert!((p - Point2::new(-0.15, 0.05)).norm() < 1e-12 && (n.x + 1.0).abs() < 1e-12);
        // Left face: pushed toward −y; "left of the push direction" is +x.
        let (p, n) = face_point(&b, PushSide::Left, 0.1).unwrap();
        assert!((p - Point2::new(0.1, 0.2)).norm() < 1e-12 && (n.y - 1.0).abs() < 1e-12);
        assert!(face_point(&b, PushSide::Front, 0.25).is_err());
    }

    #[test]
    fn a_plan_touches_the_face_after_its_approach() {
        let b = Outline::rectangle(0.3, 0.4).unwrap();
        let plan = PushPlan {
            side: PushSide::Front,
            contact_offset: -0.05,
            push_angle_deg: 20.0,
            speed: 0.05,
            curvature: 0.0,
            approach: 0.01,
        };
        let pose = Pose2::new(1.0, 2.0, 0.7);
        let path = plan.path(&b, &pose, 0.1).unwrap();
        let at_contact = pose.point_in_object(path.position(0.01 / 0.05));
        assert!((at_contact - Point2::new(-0.25, -0.05)).norm() < 1e-12);
    }

    #[test]
    fn face_points_of_the_t_lie_on_the_first_face_crossed() {
        use crate::geometry::PushT;
        let t = PushT::outline(0.001).unwrap();
        let local = |x: f64, y: f64| PushT::object_from_local(Point2::new(x, y), 0.001);
        // Pushed toward −y from +y ("left"): through the stem at x = 0, the stem's end (y = 120 px);
        // at x = 40 px, down the notch to the bar's inner edge (y = 30 px).
        let (p, n) = face_point(&t, PushSide::Left, 0.0).unwrap();
        assert!((p - local(0.0, 120.0)).norm() < 1e-12 && (n.y - 1.0).abs() < 1e-12);
        let (p, n) = face_point(&t, PushSide::Left, 0.04).unwrap();
        assert!((p - local(40.0, 30.0)).norm() < 1e-12 && (n.y - 1.0).abs() < 1e-12);
        // A 15 mm disc fits the 45 mm notch at 40 mm, but not at 20 mm from the axis (5 mm from
        // the stem).
        let plan = |offset: f64| PushPlan {
            side: PushSide::Left,
            contact_offset: offset,
            push_angle_deg: 0.0,
            speed: 0.05,
            curvature: 0.0,
            approach: 0.02,
        };
        let pose = Pose2::new(0.0, 0.0, 0.0);
        assert!(plan(0.04).path(&t, &pose, 0.015).is_ok());
        let blocked = plan(0.02).path(&t, &pose, 0.015).unwrap_err();
        assert!(matches!(blocked, PlanError::Blocked { .. }), "{blocked}");
        assert!(
            blocked
                .to_string()
                .contains("before it reaches the left face")
        );
    }

    #[test]
    fn arcs_have_constant_speed_and_turn_left_for_positive_curvature() {
        let arc = PusherPath::Arc {
            start: Point2::origin(),
            heading: 0.0,
            speed: 0.1,
            curvature: 2.0,
        };
        // A quarter circle of radius 0.5 takes (π/4)/0.1 s.
        let t = std::f64::consts::FRAC_PI_4 / 0.1;
        assert!((arc.position(t) - Point2::new(0.5, 0.5)).norm() < 1e-12);
        let step = (arc.position(1.0 + 1e-6) - arc.position(1.0)).norm() / 1e-6;
        assert!((step - 0.1).abs() < 1e-6);
    }
}
