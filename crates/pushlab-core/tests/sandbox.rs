//! Push it yourself (`sandbox`): the mystery a seed draws, a push dragged or planned against the
//! simulator's own push, and the score card against the truth.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use nalgebra::{Point2, Vector2};
use pushlab_core::geometry::Pose2;
use pushlab_core::recording::PushSide;
use pushlab_core::sandbox::mystery::{PUSHER_SPEED, RATE_HZ, SANDBOX_NOISE};
use pushlab_core::sandbox::{
    Hidden, Mystery, MysteryObject, PointerPath, PushChoice, Sandbox, SandboxEvent, recorded_pushes,
};
use pushlab_core::sim::stepper::round_frame;
use pushlab_core::sim::{
    NoiseStream, PressureModel, PushPlan, Sampling, push_noise_seed, simulate_push,
};

fn objects() -> [MysteryObject; 3] {
    [MysteryObject::Box, MysteryObject::T, MysteryObject::Ellipse]
}

#[test]
fn a_seed_draws_the_same_mystery_every_time_and_seeds_differ() {
    for object in objects() {
        let a = Mystery::draw(7, object.clone()).unwrap();
        let b = Mystery::draw(7, object.clone()).unwrap();
        assert_eq!(a, b, "{object}");
        let others: Vec<[f64; 2]> = (8..14)
            .map(|seed| {
                Mystery::draw(seed, object.clone())
                    .unwrap()
                    .hidden
                    .com_offset
            })
            .collect();
        assert!(
            others.iter().all(|c| *c != a.hidden.com_offset),
            "{object}: {others:?}"
        );
    }
}

#[test]
fn the_hidden_com_lies_well_inside_the_object_within_the_spread() {
    for object in objects() {
        for seed in 0..40 {
            let m = Mystery::draw(seed, object.clone()).unwrap();
            let com = Point2::from(Vector2::from(m.hidden.com_offset));
            let depth = -m.sim.outline.closest_boundary_point(com).signed_distance;
            assert!(
                depth > 0.02,
                "{object} seed {seed}: COM {com:?} {depth} m inside"
            );
            let from_centroid = com - m.sim.outline.centroid();
            assert!(from_centroid.x.abs() <= 0.06 && from_centroid.y.abs() <= 0.06);
            assert!(m.h > 0.02 && m.h < 0.3, "{object} seed {seed}: h {}", m.h);
            let setting = m.setting();
            assert_eq!(setting.com_offset, Some(m.hidden.com_offset));
            assert_eq!(setting.h, Some(m.h));
        }
    }
}

#[test]
fn a_teachers_hidden_values_are_the_mysterys_and_a_com_outside_is_refused() {
    let hidden = Hidden {
        com_offset: [0.04, -0.03],
        pressure: PressureModel::Uniform,
        pusher_friction: 0.3,
    };
    let m = Mystery::with_hidden(1, MysteryObject::Box, hidden).unwrap();
    assert_eq!(m.sim.com_offset, Vector2::new(0.04, -0.03));
    assert_eq!(m.sim.pusher_friction, 0.3);
    let outside = Hidden {
        com_offset: [0.5, 0.0],
        ..hidden
    };
    let e = Mystery::with_hidden(1, MysteryObject::Box, outside).unwrap_err();
    assert_eq!(
        e.to_string(),
        "the COM offset (0.500, 0.000) m lies outside the object"
    );
    assert_eq!(
        "sphere".parse::<MysteryObject>().unwrap_err(),
        "unknown mystery object 'sphere': expected box, t or ellipse"
    );
}

/// A drag from the pusher's start straight through the object's front face.
fn through_the_front(sandbox: &Sandbox) -> PointerPath {
    let start = sandbox.pusher();
    PointerPath::from_points(&[
        [start.x, start.y, 0.0],
        [start.x + 0.25, start.y + 0.02, 6.0],
    ])
    .unwrap()
}

#[test]
fn a_drag_pushes_the_object_and_its_pusher_path_replayed_gives_the_same_poses_to_the_bit() {
    for noise in [None, Some(SANDBOX_NOISE)] {
        let mystery = Mystery::draw(3, MysteryObject::Box).unwrap();
        let mut sandbox = Sandbox::new(mystery.clone(), noise);
        let path = through_the_front(&sandbox);
        let events = sandbox.drag(path.clone()).unwrap();
        let pushes = recorded_pushes(&events);
        assert_eq!(pushes.len(), 1);
        let push = &pushes[0];
        let (first, last) = (push.frames[0], *push.frames.last().unwrap());
        let moved = (last.object.position - first.object.position).norm();
        assert!(moved > 0.05, "the object moved only {moved} m");
        // The pusher never went faster than its speed (noise aside).
        let made = &sandbox.made()[0];
        for w in made.pusher_path.windows(2) {
            let step = (w[1].1 - w[0].1).norm();
            assert!(step <= PUSHER_SPEED / RATE_HZ * (1.0 + 1e-12), "{step}");
        }
        assert!(made.pressed_length() > 0.05);

        // The same drag again, and the pusher's own path replayed: the same frames, bit for bit.
        let mut again = Sandbox::new(mystery.clone(), noise);
        assert_eq!(recorded_pushes(&again.drag(path).unwrap()), pushes);
        let mut replay = Sandbox::new(mystery, noise);
        let replayed = recorded_pushes(&replay.drag(made.pointer_path()).unwrap());
        assert_eq!(replayed, pushes);
    }
}

#[test]
fn a_planned_push_is_the_simulators_push_of_that_plan() {
    let mystery = Mystery::draw(11, MysteryObject::Box).unwrap();
    let mut sandbox = Sandbox::new(mystery.clone(), Some(SANDBOX_NOISE));
    let choice = PushChoice {
        face: PushSide::Left,
        offset_m: 0.05,
        angle_deg: 10.0,
        length_m: 0.08,
    };
    let mut events = sandbox.plan(choice).unwrap();
    events.extend(sandbox.run_to_end());
    let made = recorded_pushes(&events).remove(0);

    let plan = PushPlan {
        side: PushSide::Left,
        contact_offset: 0.05,
        push_angle_deg: 10.0,
        speed: PUSHER_SPEED,
        curvature: 0.0,
        approach: 0.01,
    };
    let start = Pose2::new(0.0, 0.0, 0.0);
    let path = plan
        .path(&mystery.sim.outline, &start, mystery.sim.pusher_radius)
        .unwrap();
    let sampling = Sampling {
        rate_hz: RATE_HZ,
        duration_s: (made.frames.len() - 1) as f64 / RATE_HZ,
        ..Sampling::default()
    };
    let mut rng = NoiseStream::new(push_noise_seed(mystery.seed, 0));
    let simulated = simulate_push(
        &mystery.sim,
        start,
        &path,
        &sampling,
        Some((&SANDBOX_NOISE, &mut rng)),
    )
    .unwrap();
    // The simulator's push runs its path to the end; the sandbox's stops the pusher after the
    // push's length and settles: the same frames up to there.
    let moving = ((0.01 + 0.08) / PUSHER_SPEED * RATE_HZ).ceil() as usize;
    let simulated: Vec<_> = simulated.trajectory.frames[..=moving]
        .iter()
        .map(|f| round_frame(*f))
        .collect();
    assert_eq!(made.frames[..=moving], simulated[..]);
    let rested = made.frames[moving..].windows(2).all(|w| {
        (w[1].object.position - w[0].object.position).norm() < 0.01 // noise only
    });
    assert!(rested, "the object moved after the push ended");
}

#[test]
fn a_push_into_the_ts_notch_and_one_off_the_object_are_the_simulators() {
    // Into the concave corner between the bar and the stem: the disc pushes on both faces in
    // turn and never enters the object.
    let mystery = Mystery::draw(5, MysteryObject::T).unwrap();
    let mut sandbox = Sandbox::new(mystery.clone(), None);
    let outline = &mystery.sim.outline;
    let (min, max) = outline.bounding_box();
    let start = sandbox.pusher();
    let corner_ish = Point2::new(0.5 * (min.x + max.x), max.y - 0.05);
    let path =
        PointerPath::from_points(&[[start.x, start.y, 0.0], [corner_ish.x, corner_ish.y, 8.0]])
            .unwrap();
    let events = sandbox.drag(path).unwrap();
    assert!(matches!(
        events.last(),
        Some(SandboxEvent::PushEnded { push: 0 })
    ));
    let world_after = sandbox.object_pose();
    let pusher_in_object = world_after.point_in_object(sandbox.pusher());
    let gap = outline
        .closest_boundary_point(pusher_in_object)
        .signed_distance
        - mystery.sim.pusher_radius;
    assert!(gap > -1e-6, "the pusher ended {gap} m inside the T");

    // A drag that never reaches the object leaves it where it was.
    let mut sandbox = Sandbox::new(Mystery::draw(5, MysteryObject::Box).unwrap(), None);
    let start = sandbox.pusher();
    let away =
        PointerPath::from_points(&[[start.x, start.y, 0.0], [start.x - 0.2, start.y + 0.3, 5.0]])
            .unwrap();
    let pushes = recorded_pushes(&sandbox.drag(away).unwrap());
    let frames = &pushes[0].frames;
    assert!(frames.iter().all(|f| f.object == frames[0].object));
}

#[test]
fn pushes_follow_one_another_from_where_the_last_left_the_object() {
    let mut sandbox = Sandbox::new(Mystery::draw(2, MysteryObject::Ellipse).unwrap(), None);
    let first = through_the_front(&sandbox);
    let one = recorded_pushes(&sandbox.drag(first).unwrap());
    let rest = sandbox.object_pose();
    let events = sandbox
        .plan(PushChoice {
            face: PushSide::Right,
            offset_m: 0.0,
            angle_deg: 0.0,
            length_m: 0.05,
        })
        .unwrap();
    let SandboxEvent::PushStarted { push: 1, first } = &events[0] else {
        panic!("{events:?}");
    };
    let end_of_one = one[0].frames.last().unwrap().object;
    assert_eq!(first.object, end_of_one);
    assert_eq!(sandbox.made()[0].object_start, Pose2::new(0.0, 0.0, 0.0));
    sandbox.run_to_end();
    assert_eq!(sandbox.made()[1].object_start, rest);
    // A push while one is being made is refused.
    sandbox.hold(Point2::new(0.0, -1.0));
    assert!(
        sandbox
            .plan(PushChoice {
                face: PushSide::Front,
                offset_m: 0.0,
                angle_deg: 0.0,
                length_m: 0.05
            })
            .is_err()
    );
}

#[test]
fn real_time_frames_come_at_the_rate_and_a_released_push_settles_then_ends() {
    let mut sandbox = Sandbox::new(Mystery::draw(9, MysteryObject::Box).unwrap(), None);
    assert!(sandbox.advance(1.0).is_empty(), "no frames between pushes");
    let target = sandbox.pusher() + Vector2::new(0.02, 0.0);
    let started = sandbox.hold(target);
    assert!(matches!(
        started[0],
        SandboxEvent::PushStarted { push: 0, .. }
    ));
    let frames = |events: &[SandboxEvent]| -> usize {
        events
            .iter()
            .map(|e| match e {
                SandboxEvent::Frames { frames, .. } => frames.len(),
                _ => 0,
            })
            .sum()
    };
    assert_eq!(frames(&sandbox.advance(0.35)), 3);
    assert_eq!(
        frames(&sandbox.advance(0.05)),
        1,
        "the half frame left over counts"
    );
    sandbox.release(target);
    let mut ended = false;
    for _ in 0..100 {
        if sandbox
            .advance(0.1)
            .iter()
            .any(|e| matches!(e, SandboxEvent::PushEnded { push: 0 }))
        {
            ended = true;
            break;
        }
    }
    assert!(ended && !sandbox.is_pushing());
}
