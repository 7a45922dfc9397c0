//! The simulator against closed-form truth: pure translation, Lynch's sticking equations, mirror
//! symmetry, the motion cone, contact without penetration, and the turning direction.

#![allow(clippy::unwrap_used)]

use nalgebra::{Point2, Vector2};
use pushlab_core::geometry::{Outline, Pose2, rotate};
use pushlab_core::recording::PushSide;
use pushlab_core::sim::{
    ContactMode, PressureModel, PushPlan, PushWorld, PusherPath, Sampling, SimObject, lynch_h,
    lynch_sticking, motion_cone, pusher_slider_step, simulate_push,
};

const RADIUS: f64 = 0.05;

fn box_object(com_offset: [f64; 2], friction: f64) -> SimObject {
    let outline = Outline::rectangle(0.3, 0.4).expect("valid box");
    let com_offset = Vector2::from(com_offset);
    let h = lynch_h(&outline, PressureModel::Uniform, com_offset, 100).expect("balanced");
    SimObject {
        outline,
        com_offset,
        h,
        pusher_radius: RADIUS,
        pusher_friction: friction,
    }
}

fn straight_push(
    object: &SimObject,
    side: PushSide,
    offset: f64,
    angle_deg: f64,
    start: Pose2,
) -> pushlab_core::sim::SimulatedPush {
    let plan = PushPlan {
        side,
        contact_offset: offset,
        push_angle_deg: angle_deg,
        speed: 0.05,
        curvature: 0.0,
        approach: 0.01,
    };
    let path = plan
        .path(&object.outline, &start, RADIUS)
        .expect("valid plan");
    let sampling = Sampling {
        rate_hz: 10.0,
        duration_s: 6.0,
        max_substep: 2e-4,
    };
    simulate_push(object, start, &path, &sampling, None).expect("simulates")
}

#[test]
fn a_central_push_through_the_com_along_the_face_normal_only_translates() {
    // With the COM off the centre, the push line through the COM is offset too.
    for com in [[0.0, 0.0], [0.03, -0.04]] {
        let object = box_object(com, 0.3);
        let start = Pose2::new(0.2, -0.1, 0.9);
        let push = straight_push(&object, PushSide::Front, com[1], 0.0, start);
        let last = push.truth.frames.last().unwrap();
        let (motion, rotation) = start.motion_to(&last.object);
        assert!(rotation.abs() < 1e-12, "rotation {rotation}");
        assert!(motion.y.abs() < 1e-12, "sideways drift {}", motion.y);
        // Everything the pusher travelled after touching (6 s at 5 cm/s, minus 1 cm of approach).
        assert!((motion.x - 0.29).abs() < 1e-9, "advance {}", motion.x);
        assert_eq!(push.sliding_fraction, 0.0);
    }
}

#[test]
fn a_sticking_step_follows_lynchs_equations_in_the_limit_of_small_steps() {
    let object = box_object([0.02, -0.03], 0.9);
    let world_from_object = Pose2::new(0.4, -0.2, 0.6);
    let h = object.h;
    for (offset, angle_deg) in [(0.0, 0.0), (0.12, 10.0), (-0.15, -20.0), (0.05, 25.0)] {
        let pusher_in_object = Point2::new(-0.15 - RADIUS, offset);
        let direction_in_object = rotate(Vector2::x(), f64::to_radians(angle_deg));
        let mut errors = Vec::new();
        for step in [1e-4, 1e-5, 1e-6] {
            let pusher = world_from_object.point_in_world(pusher_in_object);
            let mut world = PushWorld::new(object.clone(), world_from_object, pusher).unwrap();
            let before = world.world_from_com();
            let u = world_from_object.vector_in_world(direction_in_object * step);
            let report = world.move_pusher_to(pusher + u);
            assert_eq!(report.mode, Some(ContactMode::Sticking));
            let (com_motion, rotation) = before.motion_to(&world.world_from_com());
            let contact = Vector2::new(-0.15, offset) - object.com_offset;
            let (expected, expected_rotation) =
                lynch_sticking(contact, direction_in_object * step, h);
            let error =
                ((com_motion - expected).norm() + (rotation - expected_rotation).abs() * h) / step;
            errors.push(error);
        }
        // The relative error vanishes linearly with the step.
        assert!(
            errors[2] < 1e-5,
            "offset {offset}, angle {angle_deg}: {errors:?}"
        );
        assert!(errors[2] < errors[0] / 50.0, "no convergence: {errors:?}");
    }
}

#[test]
fn mirrored_pushes_give_mirrored_motion() {
    // Mirroring about the object's x axis maps the front face to itself: COM (x, y) → (x, −y),
    // contact offset o → −o, push angle a → −a; the motion mirrors: y → −y, θ → −θ.
    for (offset, angle) in [(0.08, 15.0), (-0.12, -5.0), (0.0, 25.0)] {
        let a = straight_push(
            &box_object([0.03, 0.04], 0.4),
            PushSide::Front,
            offset,
            angle,
            Pose2::new(0.0, 0.0, 0.0),
        );
        let b = straight_push(
            &box_object([0.03, -0.04], 0.4),
            PushSide::Front,
            -offset,
            -angle,
            Pose2::new(0.0, 0.0, 0.0),
        );
        let mut turned = 0.0f64;
        for (fa, fb) in a.truth.frames.iter().zip(&b.truth.frames) {
            assert!((fa.object.position.x - fb.object.position.x).abs() < 1e-9);
            assert!((fa.object.position.y + fb.object.position.y).abs() < 1e-9);
            assert!((fa.object.yaw + fb.object.yaw).abs() < 1e-9);
            assert!((fa.robot.y + fb.robot.y).abs() < 1e-9);
            turned = turned.max(fa.object.yaw.abs());
        }
        assert!(
            turned > 0.05,
            "the test needs a push that turns the object ({turned})"
        );
    }
}

#[test]
fn the_pusher_never_penetrates_during_a_long_turning_push() {
    // An arc that keeps pushing an off-centre point: the object turns by more than 30° and the
    // contact slides along the edge.
    let object = box_object([0.04, 0.05], 0.3);
    let start = Pose2::new(0.0, 0.0, 0.0);
    let plan = PushPlan {
        side: PushSide::Front,
        contact_offset: -0.13,
        push_angle_deg: 10.0,
        speed: 0.05,
        curvature: 1.5,
        approach: 0.005,
    };
    let path = plan.path(&object.outline, &start, RADIUS).unwrap();
    let mut world = PushWorld::new(object, start, path.position(0.0)).unwrap();
    let (mut worst, mut sliding, mut pressing) = (f64::MAX, 0, 0);
    // 1.4 m in steps of 0.2 mm.
    for i in 1..=7_000 {
        let report = world.move_pusher_to(path.position(i as f64 * 0.004));
        worst = worst.min(world.gap());
        if let Some(mode) = report.mode.filter(|m| *m != ContactMode::Separating) {
            pressing += 1;
            sliding += usize::from(mode.is_sliding());
        }
    }
    assert!(worst >= -1e-10, "overlap {}", -worst);
    assert!(
        world.world_from_object().yaw.abs() > 0.5,
        "turned only {}",
        world.world_from_object().yaw
    );
    assert!(
        pressing > 6_000 && sliding > 100,
        "pressing {pressing}, sliding {sliding}"
    );
}

#[test]
fn the_object_never_moves_without_contact() {
    let object = box_object([0.0, 0.0], 0.5);
    let start = Pose2::new(0.1, 0.2, 0.3);
    // Touching the front face, then moving straight away and then sliding past the face at 1 mm.
    let touching = start.point_in_world(Point2::new(-0.15 - RADIUS, 0.05));
    let mut world = PushWorld::new(object.clone(), start, touching).unwrap();
    let away = start.vector_in_world(Vector2::new(-1e-4, 0.0));
    for i in 1..=100 {
        let report = world.move_pusher_to(touching + away * i as f64);
        assert_ne!(report.mode, Some(ContactMode::Sticking));
    }
    assert_eq!(world.world_from_object(), start);
    // Passing by along the left face, 1 mm clear, past both corners.
    let beside = start.point_in_world(Point2::new(-0.3, 0.2 + RADIUS + 1e-3));
    let mut world = PushWorld::new(object.clone(), start, beside).unwrap();
    let along = start.vector_in_world(Vector2::new(2e-3, 0.0));
    for i in 1..=300 {
        world.move_pusher_to(beside + along * i as f64);
    }
    assert_eq!(world.world_from_object(), start);
    // Tangent to a corner at 1 µm: the disc grazes past the corner without touching.
    let grazing = start.point_in_world(Point2::new(-0.3, -0.2 - RADIUS - 1e-6));
    let mut world = PushWorld::new(object, start, grazing).unwrap();
    for i in 1..=30 {
        world.move_pusher_to(grazing + along * (10.0 * i as f64));
    }
    assert_eq!(world.world_from_object(), start);
}

#[test]
fn sliding_starts_exactly_where_the_push_leaves_the_motion_cone() {
    let h = 0.1;
    let inward = Vector2::new(1.0, 0.0);
    for (contact, friction) in [
        (Vector2::new(-0.15, 0.1), 0.3),
        (Vector2::new(-0.15, -0.05), 0.6),
        (Vector2::new(-0.15, 0.0), 0.2),
    ] {
        let cone = motion_cone(contact, inward, friction, h);
        for (edge, outside_sign, mode) in [
            (cone[0], 1.0, ContactMode::SlidingPositive),
            (cone[1], -1.0, ContactMode::SlidingNegative),
        ] {
            let edge_angle = edge.y.atan2(edge.x);
            let inside = rotate(Vector2::x(), edge_angle - outside_sign * 1e-6) * 1e-4;
            let outside = rotate(Vector2::x(), edge_angle + outside_sign * 1e-6) * 1e-4;
            let step_in = pusher_slider_step(contact, inward, friction, h, inside);
            let step_out = pusher_slider_step(contact, inward, friction, h, outside);
            assert_eq!(
                step_in.mode,
                ContactMode::Sticking,
                "{contact:?} {friction}"
            );
            assert_eq!(step_out.mode, mode, "{contact:?} {friction}");
            // At the boundary both modes agree: the motion is continuous.
            let difference = (step_in.com_motion - step_out.com_motion).norm();
            assert!(difference < 1e-9, "jump {difference}");
        }
    }
}

#[test]
fn sliding_in_the_world_matches_the_motion_cone() {
    // The same decision through the whole simulator: at a given contact, push at angles just inside
    // and just outside the cone and read the reported mode.
    let object = box_object([0.0, 0.0], 0.25);
    let start = Pose2::new(0.0, 0.0, 0.0);
    let contact = Vector2::new(-0.15, 0.08);
    let cone = motion_cone(contact, Vector2::x(), 0.25, object.h);
    let pusher = Point2::new(-0.15 - RADIUS, 0.08);
    for (edge, sign) in [(cone[0], 1.0), (cone[1], -1.0)] {
        let edge_angle = edge.y.atan2(edge.x);
        for (delta, sliding) in [(-1e-4, false), (1e-4, true)] {
            let mut world = PushWorld::new(object.clone(), start, pusher).unwrap();
            let u = rotate(Vector2::x(), edge_angle + sign * delta) * 1e-6;
            let report = world.move_pusher_to(pusher + u);
            assert_eq!(
                report.mode.map(ContactMode::is_sliding),
                Some(sliding),
                "{edge:?} {delta}"
            );
        }
    }
}

#[test]
fn a_push_right_of_the_com_turns_the_object_counter_clockwise() {
    // Front face, pushed toward +x. "Right" of the push direction is −y: the right-hand end of the
    // face advances, so the object turns counter-clockwise (θ grows); and the other way round.
    let object = box_object([0.0, 0.0], 0.5);
    let start = Pose2::new(0.0, 0.0, 0.0);
    let right = straight_push(&object, PushSide::Front, -0.1, 0.0, start);
    let left = straight_push(&object, PushSide::Front, 0.1, 0.0, start);
    let theta = |p: &pushlab_core::sim::SimulatedPush| p.truth.frames.last().unwrap().object.yaw;
    assert!(
        theta(&right) > 0.1,
        "right push turned by {}",
        theta(&right)
    );
    assert!(theta(&left) < -0.1, "left push turned by {}", theta(&left));
    // A COM moved to +y makes a central push pass right of the COM: counter-clockwise again.
    let heavy_left = box_object([0.0, 0.05], 0.5);
    let central = straight_push(&heavy_left, PushSide::Front, 0.0, 0.0, start);
    assert!(theta(&central) > 0.05, "turned by {}", theta(&central));
    // The left face is pushed toward −y; its right-hand side (looking along −y) is −x.
    let left_face = straight_push(&object, PushSide::Left, -0.08, 0.0, start);
    assert!(theta(&left_face) > 0.1, "turned by {}", theta(&left_face));
}

#[test]
fn a_straight_path_is_followed_exactly() {
    let object = box_object([0.02, 0.0], 0.3);
    let start = Pose2::new(0.0, 0.0, 0.0);
    let path = PusherPath::Straight {
        start: Point2::new(-0.3, 0.05),
        velocity: Vector2::new(0.04, 0.01),
    };
    let sampling = Sampling {
        rate_hz: 4.0,
        duration_s: 25.0,
        max_substep: 2e-4,
    };
    let push = simulate_push(&object, start, &path, &sampling, None).unwrap();
    assert_eq!(push.truth.len(), 101);
    for f in &push.truth.frames {
        assert!((f.robot - path.position(f.time)).norm() < 1e-12);
    }
    assert!(push.contact_fraction > 0.5);
}
