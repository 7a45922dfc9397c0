//! The simulator on a non-convex object, the Push-T T: the quasi-static motion uses the T's own `h`
//! (Lynch's sticking equations with it), a push along its axis through the COM only translates, and
//! a disc pressed into the concave corner between bar and stem pushes the T ahead without entering
//! either face.

#![allow(clippy::unwrap_used)]

use nalgebra::{Point2, Vector2};
use pushlab_core::geometry::{Outline, Pose2, PushT};
use pushlab_core::recording::PushSide;
use pushlab_core::sim::{
    PressureModel, PushPlan, PusherPath, Sampling, SimObject, lynch_h, simulate_push,
};

const SCALE: f64 = 0.001;
const RADIUS: f64 = 0.015;

fn t_object(com_offset: Vector2<f64>) -> SimObject {
    let outline = PushT::outline(SCALE).unwrap();
    let h = lynch_h(&outline, PressureModel::Uniform, com_offset, 200).unwrap();
    SimObject {
        outline,
        com_offset,
        h,
        pusher_radius: RADIUS,
        pusher_friction: 0.5,
    }
}

fn local(x: f64, y: f64) -> Point2<f64> {
    PushT::object_from_local(Point2::new(x, y), SCALE)
}

/// Distance from `p` to the segment `ab`.
fn distance_to_segment(p: Point2<f64>, a: Point2<f64>, b: Point2<f64>) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
    (p - (a + ab * t)).norm()
}

#[test]
fn a_push_along_the_axis_of_the_t_through_its_com_only_translates() {
    // Pushed at the stem's end toward the bar (local −y is "left": the face at +y pushed toward −y),
    // on the axis: the push line passes through the COM, which is on the axis wherever it is.
    for com in [Vector2::zeros(), PushT::com_offset(SCALE)] {
        let object = t_object(com);
        let plan = PushPlan {
            side: PushSide::Left,
            contact_offset: 0.0,
            push_angle_deg: 0.0,
            speed: 0.05,
            curvature: 0.0,
            approach: 0.01,
        };
        let start = Pose2::new(0.1, 0.2, 0.4);
        let path = plan.path(&object.outline, &start, RADIUS).unwrap();
        let sampling = Sampling {
            rate_hz: 10.0,
            duration_s: 2.0,
            max_substep: 2e-4,
        };
        let push = simulate_push(&object, start, &path, &sampling, None).unwrap();
        let (motion, rotation) = start.motion_to(&push.truth.frames.last().unwrap().object);
        assert!(rotation.abs() < 1e-12, "rotation {rotation}");
        assert!(motion.x.abs() < 1e-12, "sideways {}", motion.x);
        assert!((motion.y + 0.09).abs() < 1e-9, "advance {}", motion.y);
    }
}

#[test]
fn a_sticking_push_on_the_bar_follows_lynch_with_the_ts_own_h() {
    // A small push on the bar's outer edge (local y = 0) off the axis, where it sticks: the first
    // substeps move the object as eqs. (9)–(11) with the T's h say.
    let object = t_object(Vector2::zeros());
    let h_t = object.h;
    let h_box = Outline::rectangle(0.12, 0.12)
        .unwrap()
        .uniform_pressure_h(Point2::origin(), 200);
    assert!((h_t - h_box).abs() > 1e-3, "the T's h {h_t} is its own");
    let contact = local(30.0, 0.0);
    let start = Pose2::new(0.0, 0.0, 0.0);
    let pusher = contact - Vector2::new(0.0, RADIUS);
    let motion = Vector2::new(0.0, 1e-5);
    let path = PusherPath::Straight {
        start: pusher,
        velocity: motion,
    };
    let sampling = Sampling {
        rate_hz: 1.0,
        duration_s: 1.0,
        max_substep: 1e-6,
    };
    let push = simulate_push(&object, start, &path, &sampling, None).unwrap();
    let (translation, rotation) = start.motion_to(&push.truth.frames[1].object);
    let (expected, expected_rotation) =
        pushlab_core::sim::lynch_sticking(contact.coords, motion, h_t);
    assert!(
        (translation - expected).norm() < 1e-3 * motion.norm(),
        "{translation} vs {expected}"
    );
    assert!(
        (rotation - expected_rotation).abs() < 1e-3 * expected_rotation.abs(),
        "{rotation} vs {expected_rotation}"
    );
}

#[test]
fn a_disc_pressed_into_the_concave_corner_pushes_the_t_without_entering_either_face() {
    let object = t_object(Vector2::zeros());
    // The right notch's corner is local (15, 30) px; the disc of 15 px touches both the bar's inner
    // edge (y = 30) and the stem's side (x = 15) when its centre is at (30, 45) px. Start 10 px further
    // out along the diagonal and push into the corner.
    let start = Pose2::new(0.0, 0.0, 0.0);
    let diagonal = Vector2::new(-1.0, -1.0).normalize();
    let path = PusherPath::Straight {
        start: local(40.0, 55.0),
        velocity: diagonal * 0.05,
    };
    let sampling = Sampling {
        rate_hz: 20.0,
        duration_s: 1.5,
        max_substep: 2e-4,
    };
    let push = simulate_push(&object, start, &path, &sampling, None).unwrap();
    let (bar_inner, stem_side) = (
        (local(60.0, 30.0), local(15.0, 30.0)),
        (local(15.0, 30.0), local(15.0, 120.0)),
    );
    let mut deepest = 0.0f64;
    for frame in &push.truth.frames {
        let at = frame.object.point_in_object(frame.robot);
        for (a, b) in [bar_inner, stem_side] {
            deepest = deepest.max(RADIUS - distance_to_segment(at, a, b));
        }
    }
    assert!(deepest < 1e-9, "the disc entered a face by {deepest} m");
    // Contact after 10√2 px; the rest of the 75 mm travel pushes the T ahead.
    let last = push.truth.frames.last().unwrap();
    let pushed = 0.075 - 0.010 * 2f64.sqrt();
    let advance = (last.object.position - start.position).dot(&diagonal);
    let (_, rotation) = start.motion_to(&last.object);
    eprintln!(
        "corner push: advance {advance:.5} m of {pushed:.5} m pushed, rotation {:.3}°, max overlap \
         before correction {:.2e} m, sliding {:.0} %",
        rotation.to_degrees(),
        push.max_overlap,
        100.0 * push.sliding_fraction
    );
    // With μ = 0.5 both contacts cannot stick (the friction needed at the bar's face to cancel the
    // turning about the COM exceeds its cone), so the disc slides along the faces and the T turns
    // clockwise (the bar's contact is far right of the COM) while moving ahead.
    assert!(
        advance > 0.5 * pushed && advance < pushed + 1e-9,
        "advance {advance}"
    );
    assert!(rotation < 0.0 && push.sliding_fraction > 0.5);
    // Still in the corner at the end: within a hair of both faces.
    let at = last.object.point_in_object(last.robot);
    for (a, b) in [bar_inner, stem_side] {
        assert!(
            distance_to_segment(at, a, b) - RADIUS < 1e-3,
            "left the corner"
        );
    }
}
