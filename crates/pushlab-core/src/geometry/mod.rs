//! Planar geometry: poses, frame changes and object outlines (simple polygons).
//!
//! Names carry their frames: a `Pose2` is `world_from_object`, so `pose.point_in_world(p_in_object)`
//! maps a point given in the object frame to the world, and `pose.point_in_object(p_in_world)` back.
//! Angles in trajectories are kept unwrapped; differences of angles are wrapped to (−π, π].

mod clip;
mod outline;
mod polygon;
mod preset;
mod rigid_fit;

pub use clip::clip_to_convex;
pub use outline::{BoundaryPoint, Outline, OutlineError};
pub use polygon::cross;
pub use preset::{PRESET_NAMES, PUSH_T, PushT};
pub use rigid_fit::{RigidFit, fit_rigid};

use crate::math;
use std::f64::consts::PI;

use nalgebra::{Isometry2, Point2, Vector2};
use serde::{Deserialize, Serialize};

/// Pose of a planar body in the world (`world_from_object`): its position and its yaw.
///
/// The yaw is kept as a plain (possibly unwrapped) angle rather than a unit complex number so that a
/// trajectory can carry the total rotation of an object that turned more than half a turn.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose2 {
    /// Position of the object frame's origin in the world, metres.
    pub position: Point2<f64>,
    /// Yaw of the object's x axis in the world, radians. (Not `theta`: in this crate `θ` is always
    /// `θ_online`, the parameters learned online.)
    #[serde(alias = "theta")]
    pub yaw: f64,
}

impl Pose2 {
    /// A pose from its coordinates.
    pub fn new(x: f64, y: f64, yaw: f64) -> Self {
        Self {
            position: Point2::new(x, y),
            yaw,
        }
    }

    /// The same transform as an `Isometry2`, for callers that compose transforms.
    pub fn world_from_object(&self) -> Isometry2<f64> {
        Isometry2::new(self.position.coords, self.yaw)
    }

    /// A point given in the object frame, expressed in the world.
    pub fn point_in_world(&self, point_in_object: Point2<f64>) -> Point2<f64> {
        self.position + rotate(point_in_object.coords, self.yaw)
    }

    /// A point given in the world, expressed in the object frame.
    pub fn point_in_object(&self, point_in_world: Point2<f64>) -> Point2<f64> {
        Point2::from(rotate(point_in_world - self.position, -self.yaw))
    }

    /// A free vector (a motion) given in the object frame, expressed in the world.
    pub fn vector_in_world(&self, vector_in_object: Vector2<f64>) -> Vector2<f64> {
        rotate(vector_in_object, self.yaw)
    }

    /// A free vector given in the world, expressed in the object frame.
    pub fn vector_in_object(&self, vector_in_world: Vector2<f64>) -> Vector2<f64> {
        rotate(vector_in_world, -self.yaw)
    }

    /// The pose reached by moving by `delta_in_object` (expressed in this pose's frame) and turning by
    /// `delta_yaw`: the inverse of [`Pose2::motion_to`].
    pub fn moved_by(&self, delta_in_object: Vector2<f64>, delta_yaw: f64) -> Pose2 {
        Pose2 {
            position: self.position + self.vector_in_world(delta_in_object),
            yaw: self.yaw + delta_yaw,
        }
    }

    /// The motion from this pose to `later`, expressed in this pose's frame (eqs. 3–4 of the paper):
    /// the translation in the object frame and the rotation wrapped to (−π, π].
    pub fn motion_to(&self, later: &Pose2) -> (Vector2<f64>, f64) {
        (
            self.vector_in_object(later.position - self.position),
            wrap_angle(later.yaw - self.yaw),
        )
    }
}

/// Rotates a vector by `angle` radians counter-clockwise.
pub fn rotate(v: Vector2<f64>, angle: f64) -> Vector2<f64> {
    let (s, c) = math::sin_cos(angle);
    Vector2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// Wraps an angle to (−π, π].
pub fn wrap_angle(angle: f64) -> f64 {
    let mut a = (angle + PI).rem_euclid(2.0 * PI) - PI;
    if a <= -PI {
        a += 2.0 * PI;
    }
    a
}

/// Unwraps a sequence of angles in place so that consecutive values never differ by more than π.
///
/// Returns how many wraps were removed, so that importers can report them.
pub fn unwrap_angles(angles: &mut [f64]) -> usize {
    let mut unwrapper = AngleUnwrapper::default();
    let mut wraps = 0;
    for angle in angles.iter_mut() {
        let (unwrapped, wrapped) = unwrapper.next(*angle);
        *angle = unwrapped;
        wraps += usize::from(wrapped);
    }
    wraps
}

/// [`unwrap_angles`] one angle at a time, for angles that arrive one by one (a live stream): the
/// same operations in the same order, so a stream unwrapped as it arrives and the file it was
/// recorded to, unwrapped whole, hold the same bits.
#[derive(Clone, Copy, Debug, Default)]
pub struct AngleUnwrapper {
    /// What is added to each raw angle.
    offset: f64,
    /// The previous angle, unwrapped.
    previous: Option<f64>,
}

impl AngleUnwrapper {
    /// The next angle unwrapped, and whether it wrapped.
    pub fn next(&mut self, angle: f64) -> (f64, bool) {
        let mut wrapped = false;
        if let Some(previous) = self.previous {
            let raw_previous = previous - self.offset;
            let step = angle - raw_previous;
            if step > PI {
                self.offset -= 2.0 * PI * ((step + PI) / (2.0 * PI)).floor();
                wrapped = true;
            } else if step < -PI {
                self.offset += 2.0 * PI * ((-step + PI) / (2.0 * PI)).floor();
                wrapped = true;
            }
        }
        let unwrapped = if self.previous.is_some() {
            angle + self.offset
        } else {
            angle
        };
        self.previous = Some(unwrapped);
        (unwrapped, wrapped)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn frame_changes_round_trip() {
        let pose = Pose2::new(0.3, -1.2, 2.5);
        let p = Point2::new(0.05, 0.07);
        let back = pose.point_in_object(pose.point_in_world(p));
        assert!((back - p).norm() < 1e-15);
        let v = Vector2::new(-0.2, 0.4);
        assert!((pose.vector_in_object(pose.vector_in_world(v)) - v).norm() < 1e-15);
        // Same as nalgebra's isometry.
        let iso = pose.world_from_object();
        assert!((iso * p - pose.point_in_world(p)).norm() < 1e-15);
    }

    #[test]
    fn point_in_world_rotates_then_translates() {
        let pose = Pose2::new(1.0, 2.0, PI / 2.0);
        let p = pose.point_in_world(Point2::new(1.0, 0.0));
        assert!(close(p.x, 1.0, 1e-12) && close(p.y, 3.0, 1e-12));
    }

    #[test]
    fn motion_to_and_moved_by_are_inverse() {
        let a = Pose2::new(0.1, 0.2, 3.0);
        let b = Pose2::new(0.15, 0.18, 3.5);
        let (d, dyaw) = a.motion_to(&b);
        let c = a.moved_by(d, dyaw);
        assert!((c.position - b.position).norm() < 1e-15);
        assert!(close(c.yaw, b.yaw, 1e-12));
    }

    #[test]
    fn wrap_angle_maps_into_half_open_interval() {
        assert!(close(wrap_angle(PI), PI, 1e-15));
        assert!(close(wrap_angle(-PI), PI, 1e-15));
        assert!(close(wrap_angle(3.0 * PI / 2.0), -PI / 2.0, 1e-12));
        assert!(close(wrap_angle(-7.0), -7.0 + 2.0 * PI, 1e-12));
    }

    #[test]
    fn unwrap_removes_jumps_and_counts_them() {
        let mut a = vec![3.0, -3.1, -2.9, 3.1, 0.0];
        let wraps = unwrap_angles(&mut a);
        assert_eq!(wraps, 2);
        for w in a.windows(2).take(3) {
            assert!((w[1] - w[0]).abs() < PI);
        }
        assert!(close(a[1], -3.1 + 2.0 * PI, 1e-12));
    }
}
