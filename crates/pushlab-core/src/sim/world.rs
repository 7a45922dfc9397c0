//! The simulated scene: one object on the floor and one disc pusher that follows its commanded
//! positions exactly. Each call to [`PushWorld::move_pusher_to`] is one substep: the pusher moves
//! freely until it touches the object, then pushes it quasi-statically; any remaining overlap (second
//! order in the step) is removed by pushing the object further along the contact normal, so the pusher
//! never penetrates.
//!
//! **One contact at a time, also in a concave corner.** The pusher pushes at the outline point nearest
//! its centre (the deepest contact; the lower-numbered edge on an exact tie). A disc pressed into a
//! concave corner of a non-convex object (the notch between the T's bar and stem) touches two faces:
//! each substep pushes on the nearer one, and the overlap that remains with the other is then removed
//! by pushes along *its* normal, nearest face first, until no face overlaps. Over many small substeps
//! the two faces take turns, so the object follows a disc jammed in the corner without being
//! penetrated; this sequence of single-contact pushes approximates, but is not, the two-contact
//! quasi-static solution (whose friction at both faces at once would decide whether the object only
//! translates with the pusher). Frame truths report the face pushed last.

use crate::math;
use nalgebra::{Point2, Vector2};

use super::contact::{ContactMode, ObjectStep, pusher_slider_step};
use crate::geometry::{BoundaryPoint, Outline, Pose2};

/// A pusher closer than this to the outline (metres) is in contact.
pub const CONTACT_TOLERANCE: f64 = 1e-9;

/// The physical description of an object and pusher, everything the simulation needs.
#[derive(Clone, Debug, PartialEq)]
pub struct SimObject {
    /// Footprint, object frame (the origin is the geometric centre that recordings report).
    pub outline: Outline,
    /// True COM − geometric centre, object frame, metres.
    pub com_offset: Vector2<f64>,
    /// Lynch's `h` about the COM, metres.
    pub h: f64,
    /// Pusher disc radius, metres.
    pub pusher_radius: f64,
    /// Pusher–object Coulomb friction coefficient.
    pub pusher_friction: f64,
}

/// Why a simulation cannot start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WorldError {
    #[error("the pusher starts inside the object (overlap {0:.6} m)")]
    StartsInside(f64),
    #[error("{field} must be {expected}, got {value}")]
    BadParameter {
        field: &'static str,
        expected: &'static str,
        value: f64,
    },
}

/// What happened during a substep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubstepReport {
    /// The contact mode of the pushing part of the step (`None` when the pusher never touched).
    pub mode: Option<ContactMode>,
    /// The largest overlap seen before correction, metres (second order in the step).
    pub overlap_before_correction: f64,
}

/// The object's and the pusher's state.
#[derive(Clone, Debug)]
pub struct PushWorld {
    object: SimObject,
    /// Pose of the COM frame (object axes, origin at the COM) in the world.
    world_from_com: Pose2,
    pusher: Point2<f64>,
}

impl PushWorld {
    /// A scene with the object's geometric centre frame at `world_from_object` and the pusher's centre
    /// at `pusher`; refused when the pusher would start inside the object.
    pub fn new(
        object: SimObject,
        world_from_object: Pose2,
        pusher: Point2<f64>,
    ) -> Result<Self, WorldError> {
        for (field, value, expected, ok) in [
            ("h", object.h, "a finite length > 0", object.h > 0.0),
            (
                "pusher_radius",
                object.pusher_radius,
                "a finite length ≥ 0",
                object.pusher_radius >= 0.0,
            ),
            (
                "pusher_friction",
                object.pusher_friction,
                "a finite coefficient ≥ 0",
                object.pusher_friction >= 0.0,
            ),
        ] {
            if !(ok && value.is_finite()) {
                return Err(WorldError::BadParameter {
                    field,
                    expected,
                    value,
                });
            }
        }
        let world_from_com = Pose2 {
            position: world_from_object.point_in_world(Point2::from(object.com_offset)),
            yaw: world_from_object.yaw,
        };
        let world = Self {
            object,
            world_from_com,
            pusher,
        };
        let gap = world.gap();
        if gap < -CONTACT_TOLERANCE {
            return Err(WorldError::StartsInside(-gap));
        }
        Ok(world)
    }

    /// The object: its pose as recordings report it (geometric centre and yaw).
    pub fn world_from_object(&self) -> Pose2 {
        Pose2 {
            position: self
                .world_from_com
                .point_in_world(Point2::from(-self.object.com_offset)),
            yaw: self.world_from_com.yaw,
        }
    }

    /// The pose of the COM frame (object axes, origin at the COM).
    pub fn world_from_com(&self) -> Pose2 {
        self.world_from_com
    }

    /// The pusher's centre, world frame.
    pub fn pusher(&self) -> Point2<f64> {
        self.pusher
    }

    /// The simulated object.
    pub fn object(&self) -> &SimObject {
        &self.object
    }

    /// Distance between the pusher disc and the object's outline, metres (negative: overlap).
    pub fn gap(&self) -> f64 {
        self.gap_at(self.pusher)
    }

    /// Where the pusher is closest to the object, object frame.
    pub fn closest_point(&self) -> BoundaryPoint {
        let pusher_in_object = self.world_from_object().point_in_object(self.pusher);
        self.object.outline.closest_boundary_point(pusher_in_object)
    }

    fn gap_at(&self, pusher: Point2<f64>) -> f64 {
        let pusher_in_object = self.world_from_object().point_in_object(pusher);
        self.object
            .outline
            .closest_boundary_point(pusher_in_object)
            .signed_distance
            - self.object.pusher_radius
    }

    /// One substep: moves the pusher's centre to `target` (world frame) and the object with it.
    pub fn move_pusher_to(&mut self, target: Point2<f64>) -> SubstepReport {
        let mut report = SubstepReport {
            mode: None,
            overlap_before_correction: 0.0,
        };
        let start = self.pusher;
        let motion = target - start;
        // Free motion until the disc touches the outline.
        let start_gap = self.gap();
        if start_gap > CONTACT_TOLERANCE {
            // Both ends of the step may be clear while its middle grazes a corner, so when the disc
            // could touch at all, look for the minimum of the gap (convex along a line: the distance
            // to a convex set) and find the first touch before it. The gap to a non-convex outline
            // can have several minima along the step; there the disc is swept exactly.
            let touch_before = if !self.object.outline.is_convex() {
                let object = self.world_from_object();
                self.object.outline.disc_first_touch(
                    object.point_in_object(start),
                    object.vector_in_object(motion),
                    self.object.pusher_radius,
                )
            } else if self.gap_at(target) < 0.0 {
                Some(1.0)
            } else if start_gap < motion.norm() {
                let (mut a, mut b) = (0.0, 1.0);
                for _ in 0..80 {
                    let (m1, m2) = (a + (b - a) / 3.0, b - (b - a) / 3.0);
                    if self.gap_at(start + motion * m1) <= self.gap_at(start + motion * m2) {
                        b = m2;
                    } else {
                        a = m1;
                    }
                }
                let closest = 0.5 * (a + b);
                (self.gap_at(start + motion * closest) < 0.0).then_some(closest)
            } else {
                None
            };
            let Some(touch_before) = touch_before else {
                self.pusher = target;
                return report;
            };
            let (mut low, mut high) = (0.0, touch_before);
            for _ in 0..60 {
                let mid = 0.5 * (low + high);
                if self.gap_at(start + motion * mid) > 0.0 {
                    low = mid;
                } else {
                    high = mid;
                }
            }
            self.pusher = start + motion * low;
        }
        let remaining = target - self.pusher;
        let step = self.push(remaining);
        report.mode = Some(step.mode);
        self.pusher = target;
        // Remove the second-order overlap by pushing along the contact normal, as a position-controlled
        // pusher would.
        for _ in 0..50 {
            let overlap = -self.gap();
            report.overlap_before_correction = report.overlap_before_correction.max(overlap);
            if overlap <= 1e-13 {
                break;
            }
            let normal_in_world = self
                .world_from_object()
                .vector_in_world(-self.closest_point().normal);
            self.push(normal_in_world * overlap);
        }
        report
    }

    /// Moves the object as the pusher, touching it now, moves by `motion_in_world` (the pusher itself is
    /// not moved here).
    fn push(&mut self, motion_in_world: Vector2<f64>) -> ObjectStep {
        let contact = self.closest_point();
        let contact_from_com = contact.point.coords - self.object.com_offset;
        let inward_normal = -contact.normal;
        let motion_in_com = self.world_from_com.vector_in_object(motion_in_world);
        let step = pusher_slider_step(
            contact_from_com,
            inward_normal,
            self.object.pusher_friction,
            self.object.h,
            motion_in_com,
        );
        if step.mode != ContactMode::Separating {
            self.world_from_com = apply_twist(&self.world_from_com, &step);
        }
        step
    }
}

/// The pose reached by moving with a constant body twist for one unit of time (the exponential map of
/// SE(2)), so that a step's rotation and translation are integrated together.
fn apply_twist(pose: &Pose2, step: &ObjectStep) -> Pose2 {
    let w = step.rotation;
    let (a, b) = if w.abs() < 1e-9 {
        (1.0 - w * w / 6.0, w / 2.0)
    } else {
        (math::sin(w) / w, (1.0 - math::cos(w)) / w)
    };
    let v = step.com_motion;
    let translation = Vector2::new(a * v.x - b * v.y, b * v.x + a * v.y);
    pose.moved_by(translation, w)
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    fn object(h: f64) -> SimObject {
        SimObject {
            outline: Outline::rectangle(0.2, 0.2).unwrap(),
            com_offset: Vector2::zeros(),
            h,
            pusher_radius: 0.05,
            pusher_friction: 0.3,
        }
    }

    #[test]
    fn a_pusher_starting_inside_or_a_bad_h_is_refused_with_the_reason() {
        let pose = Pose2::new(0.0, 0.0, 0.0);
        let inside = PushWorld::new(object(0.08), pose, Point2::new(-0.12, 0.0)).unwrap_err();
        assert_eq!(
            inside.to_string(),
            "the pusher starts inside the object (overlap 0.030000 m)"
        );
        let bad_h = PushWorld::new(object(-1.0), pose, Point2::new(-0.5, 0.0)).unwrap_err();
        assert_eq!(bad_h.to_string(), "h must be a finite length > 0, got -1");
    }
}
