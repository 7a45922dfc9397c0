//! Named outlines: objects that datasets share, so that a `setting.json` can name one instead of
//! listing its vertices. Today one: the T of Push-T.
//!
//! **The Push-T T.** gym-pusht (`gym_pusht/envs/pusht.py`, `PushTEnv.add_tee`, with `scale = 30`,
//! `length = 4`) builds the T in pymunk from two boxes in the body's local frame, in pixels of its
//! 512 × 512 arena: the bar `(−60, 0)…(60, 30)` (120 × 30 px) and the stem `(−15, 30)…(15, 120)`
//! (30 × 90 px). Its local origin — what the environment's state reports as the block's position —
//! is the middle of the bar's outer edge. Three points along the T's axis (x = 0) matter:
//! - the local origin, y = 0;
//! - the **area centroid**, `y = (3600 · 15 + 2700 · 75) / 6300 = 285/7 ≈ 40.714 px`: pushlab's
//!   geometric centre, the origin of the object frame;
//! - the **centre of gravity** pymunk is given, `(0, 45) px`: the mean of the two boxes' centroids,
//!   not weighted by their areas — so the T's COM lies `45 − 285/7 = 30/7 ≈ 4.286 px` from its
//!   geometric centre toward the stem's end, a real COM offset (pushlab's `com_offset`, COM −
//!   geometric centre, is `(0, 30/7) px` times the scale).
//!
//! pushlab's object frame for the T is pymunk's local frame, same axes (so the same yaw), moved to the
//! area centroid and scaled by `metres_per_px`: `p_object = (p_local − (0, 285/7)) · metres_per_px`.
//! The agent (the pusher) is a disc of radius 15 px.

use nalgebra::{Point2, Vector2};

use super::outline::{Outline, OutlineError};

/// The name of the Push-T T in `setting.json` and on the command line.
pub const PUSH_T: &str = "push-t";

/// Every preset's name, for messages and help texts.
pub const PRESET_NAMES: &[&str] = &[PUSH_T];

/// The Push-T T's geometry in pymunk's local frame, pixels (see the module's documentation).
#[derive(Clone, Copy, Debug)]
pub struct PushT;

impl PushT {
    /// The outline in pymunk's local frame, pixels, counter-clockwise: along the bar's outer edge
    /// (y = 0), up its right end, in along its inner edge to the stem, up the stem and back.
    pub const LOCAL_VERTICES_PX: [[f64; 2]; 8] = [
        [-60.0, 0.0],
        [60.0, 0.0],
        [60.0, 30.0],
        [15.0, 30.0],
        [15.0, 120.0],
        [-15.0, 120.0],
        [-15.0, 30.0],
        [-60.0, 30.0],
    ];
    /// The T's eight corners in the order gym-pusht's `PushTEnv.get_keypoints` lists them (the bar's
    /// box, then the stem's, each as pymunk keeps its vertices): what a LeRobot Push-T dataset's
    /// `observation.environment_state` holds, x0, y0, x1, y1 …, in the arena's pixels. Read from the
    /// environment by `tests/pusht/make_fixtures.py` (`truth.json`, `local_keypoints_px`).
    pub const KEYPOINTS_PX: [[f64; 2]; 8] = [
        [-60.0, 0.0],
        [60.0, 0.0],
        [60.0, 30.0],
        [-60.0, 30.0],
        [-15.0, 30.0],
        [15.0, 30.0],
        [15.0, 120.0],
        [-15.0, 120.0],
    ];
    /// The area centroid in the local frame, pixels: `(0, 285/7)`.
    pub const CENTROID_PX: [f64; 2] = [0.0, 285.0 / 7.0];
    /// The centre of gravity gym-pusht gives the body, local frame, pixels.
    pub const CENTRE_OF_GRAVITY_PX: [f64; 2] = [0.0, 45.0];
    /// The agent's (pusher's) radius, pixels.
    pub const AGENT_RADIUS_PX: f64 = 15.0;
    /// The scale `pushlab` assumes unless told: a millimetre per pixel (a 120 mm T, a 15 mm pusher).
    pub const DEFAULT_METRES_PER_PX: f64 = 0.001;

    /// A point of the T's local frame (pixels) in pushlab's object frame (metres).
    pub fn object_from_local(local_px: Point2<f64>, metres_per_px: f64) -> Point2<f64> {
        Point2::from((local_px - Point2::from(Self::CENTROID_PX)) * metres_per_px)
    }

    /// The outline in the object frame at `metres_per_px`.
    pub fn outline(metres_per_px: f64) -> Result<Outline, OutlineError> {
        if !(metres_per_px.is_finite() && metres_per_px > 0.0) {
            return Err(OutlineError::BadScale(metres_per_px));
        }
        Outline::new(
            Self::LOCAL_VERTICES_PX
                .iter()
                .map(|&v| Self::object_from_local(Point2::from(v), metres_per_px))
                .collect(),
        )
    }

    /// The true COM offset (COM − geometric centre, object frame) at `metres_per_px`: `(0, 30/7)` px.
    pub fn com_offset(metres_per_px: f64) -> Vector2<f64> {
        Self::object_from_local(Point2::from(Self::CENTRE_OF_GRAVITY_PX), metres_per_px).coords
    }
}

impl Outline {
    /// The preset outline named `name` (one of [`PRESET_NAMES`]) at `metres_per_px`.
    pub fn preset(name: &str, metres_per_px: f64) -> Result<Outline, OutlineError> {
        match name {
            PUSH_T => PushT::outline(metres_per_px),
            _ => Err(OutlineError::UnknownPreset {
                name: name.to_owned(),
                known: PRESET_NAMES,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Closed forms from the two boxes, independent of the outline code: areas add, and the centroid
    /// is the area-weighted mean of the boxes' centres.
    #[test]
    fn the_t_has_the_area_and_centroid_of_its_two_boxes() {
        let t = PushT::outline(1.0).expect("the T is a simple outline");
        assert_eq!(t.vertices().len(), 8);
        assert!(!t.is_convex());
        assert!((t.area() - (120.0 * 30.0 + 30.0 * 90.0)).abs() < 1e-9);
        // In the object frame the centroid is the origin; in pymunk's frame it is (0, 40.714) px.
        assert!(t.centroid().coords.norm() < 1e-12, "{}", t.centroid());
        let local_centroid = (120.0 * 30.0 * 15.0 + 30.0 * 90.0 * 75.0) / 6300.0;
        assert!((PushT::CENTROID_PX[1] - local_centroid).abs() < 1e-12);
        assert!((local_centroid - 40.714).abs() < 1e-3);
        // The COM offset the issue quotes: (0, 4.3) px toward the stem's end.
        let offset = PushT::com_offset(1.0);
        assert!(offset.x == 0.0 && (offset.y - 30.0 / 7.0).abs() < 1e-12);
        assert!((PushT::com_offset(0.001).y - 0.0042857).abs() < 1e-7);
    }

    #[test]
    fn inside_and_outside_at_chosen_points_of_the_t() {
        let t = PushT::outline(0.001).expect("valid");
        let at = |x: f64, y: f64| t.contains(PushT::object_from_local(Point2::new(x, y), 0.001));
        assert!(at(0.0, 15.0), "the bar's middle");
        assert!(at(-55.0, 5.0), "the bar's left end");
        assert!(at(0.0, 110.0), "the stem's end");
        assert!(!at(40.0, 60.0), "the notch right of the stem");
        assert!(!at(-16.0, 31.0), "just inside the left notch's corner");
        assert!(at(-14.0, 31.0), "just inside the stem at that corner");
        assert!(!at(0.0, 125.0) && !at(0.0, -1.0) && !at(61.0, 10.0));
    }

    #[test]
    fn the_scale_and_the_name_are_checked() {
        assert_eq!(PushT::outline(0.0), Err(OutlineError::BadScale(0.0)));
        let error = Outline::preset("push-x", 0.001).expect_err("unknown");
        assert_eq!(
            error.to_string(),
            "unknown preset 'push-x', expected one of: push-t"
        );
        let t = Outline::preset("push-t", 0.002).expect("known");
        assert!((t.size() - 0.24).abs() < 1e-12);
    }
}
