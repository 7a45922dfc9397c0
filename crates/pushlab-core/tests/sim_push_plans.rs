//! Every push the simulator's options describe starts clear of the object and first touches it
//! where the plan says: a property test over random convex outlines (points on an ellipse at random
//! angles, so every outline `setting.json` accepts has a like), every side, contact offsets across
//! the whole face, push angles up to ±80°, pusher radii from 2 to 30 mm and approaches up to 5 cm.
//! Before the angle was measured from the touched face's normal, a polygon's tilted face with an
//! angled push started the pusher inside the object (issue 26, #1).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use nalgebra::Point2;
use pushlab_core::geometry::{Outline, Pose2};
use pushlab_core::recording::PushSide;
use pushlab_core::sim::path::face_extent;
use pushlab_core::sim::{PushPlan, SplitMix64};

fn random_outline(rng: &mut SplitMix64) -> Outline {
    let corners = 3 + (rng.uniform(0.0, 1.0) * 9.0) as usize;
    let (a, b) = (
        0.02 + 0.2 * rng.uniform(0.0, 1.0),
        0.02 + 0.2 * rng.uniform(0.0, 1.0),
    );
    let mut angles: Vec<f64> = (0..corners)
        .map(|_| std::f64::consts::TAU * rng.uniform(0.0, 1.0))
        .collect();
    angles.sort_by(f64::total_cmp);
    angles.dedup_by(|x, y| (*x - *y).abs() < 0.05);
    let vertices: Vec<Point2<f64>> = angles
        .iter()
        .map(|t| Point2::new(0.01 + a * t.cos(), -0.02 + b * t.sin()))
        .collect();
    Outline::new(vertices).unwrap_or_else(|_| Outline::rectangle(a, b).unwrap())
}

#[test]
fn every_planned_push_starts_clear_and_touches_its_face_first() {
    let mut rng = SplitMix64::new(26);
    let sides = [
        PushSide::Front,
        PushSide::Back,
        PushSide::Left,
        PushSide::Right,
    ];
    let mut checked = 0;
    for _ in 0..2000 {
        let outline = random_outline(&mut rng);
        let side = sides[(rng.uniform(0.0, 1.0) * 4.0) as usize % 4];
        let (middle, half) = face_extent(&outline, side);
        let plan = PushPlan {
            side,
            contact_offset: middle + half * (1.9 * rng.uniform(0.0, 1.0) - 0.95),
            push_angle_deg: 160.0 * rng.uniform(0.0, 1.0) - 80.0,
            speed: 0.05,
            curvature: 0.0,
            approach: 0.05 * rng.uniform(0.0, 1.0),
        };
        let radius = 0.002 + 0.028 * rng.uniform(0.0, 1.0);
        let pose = Pose2::new(0.3, -0.1, 2.0 * rng.uniform(0.0, 1.0));
        let path = plan
            .path(&outline, &pose, radius)
            .unwrap_or_else(|e| panic!("{plan:?}: {e}"));
        // Along the approach, every position keeps the pusher's disc outside the object, and at
        // its end the disc touches it.
        let duration = plan.approach / plan.speed;
        for k in 0..=20 {
            let t = duration * k as f64 / 20.0;
            let at = pose.point_in_object(path.position(t));
            let gap = outline.closest_boundary_point(at).signed_distance - radius;
            assert!(
                gap > -1e-9,
                "{plan:?}, radius {radius}: at t = {t} the gap is {gap}"
            );
        }
        let end = pose.point_in_object(path.position(duration));
        let gap = outline.closest_boundary_point(end).signed_distance - radius;
        assert!(
            gap.abs() < 1e-9,
            "{plan:?}: touches at the end of the approach ({gap})"
        );
        checked += 1;
    }
    assert_eq!(checked, 2000);
}
