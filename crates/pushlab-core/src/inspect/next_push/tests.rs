#![allow(clippy::unwrap_used)]

use nalgebra::{Point2, Vector2};

use super::*;
use crate::geometry::rotate;
use crate::model::{LossScale, PhysicsOnlyModel};
use crate::trajectory::Frame;

const RADIUS: f64 = 0.01;

fn square() -> Outline {
    Outline::rectangle(0.1, 0.1).unwrap()
}

fn physics() -> PhysicsOnlyModel {
    let unit = LossScale {
        sigma_pos: [0.01, 0.01],
        sigma_rot: 0.05,
    };
    PhysicsOnlyModel::new(square(), RADIUS, 0.01, unit)
}

/// The pusher from `start` along `direction` at 3 cm/s for 3 s at 30 Hz, the object resting at
/// `object` (its recorded motion: the model's predictions never read it).
fn straight(start: [f64; 2], direction: Vector2<f64>, object: Pose2) -> Trajectory {
    Trajectory::new(
        (0..90)
            .map(|i| {
                let t = i as f64 / 30.0;
                Frame {
                    time: t,
                    robot: Point2::from(start) + direction.normalize() * 0.03 * t,
                    object,
                }
            })
            .collect(),
    )
}

fn theta() -> OnlineParams {
    OnlineParams {
        com_offset: [0.0, 0.0],
        h: 0.03,
    }
}

#[test]
fn a_push_is_described_by_the_face_it_touches_where_and_at_what_angle() {
    // Into the left face (x = −5 cm), 2 cm above its middle, 20° counter-clockwise of straight in.
    let angle = 20f64.to_radians();
    let direction = rotate(Vector2::x(), angle);
    let at_rest = Pose2::new(0.0, 0.0, 0.0);
    // Starting 4 cm left of the face, aimed to meet it 2 cm above its middle.
    let push = straight([-0.09, 0.02 - 0.03 * angle.tan()], direction, at_rest);
    let poses = vec![at_rest; push.len()];
    let shape = shape_of(&square(), RADIUS, &push, &poses).unwrap();
    assert!(
        (shape.contact_in_object[0] + 0.05).abs() < 1e-9,
        "{shape:?}"
    );
    // Pushed along +x, 2 cm above the face's middle is 2 cm to the pusher's left.
    assert!((shape.offset_m - 0.02).abs() < 3e-3, "{shape:?}");
    assert!(
        (shape.angle_rad.to_degrees() - 20.0).abs() < 0.5,
        "{shape:?}"
    );
    let d = shape.direction_in_object;
    assert!((d[0] - direction.x).abs() < 1e-9 && (d[1] - direction.y).abs() < 1e-9);
    // 3 s at 3 cm/s, less the way to the face.
    assert!(shape.length_m > 0.04 && shape.length_m < 0.09, "{shape:?}");
    // The same push on the object turned a quarter turn touches another face.
    let turned = Pose2::new(0.0, 0.0, std::f64::consts::FRAC_PI_2);
    let other = shape_of(&square(), RADIUS, &push, &vec![turned; push.len()]).unwrap();
    assert_ne!(other.face, shape.face);
}

#[test]
fn a_push_that_misses_the_object_has_no_shape_and_teaches_nothing() {
    let at_rest = Pose2::new(0.0, 0.0, 0.0);
    let miss = straight([-0.09, 0.2], Vector2::x(), at_rest);
    let poses = predicted_poses(&physics(), &miss, 3, &theta());
    assert!(poses.iter().all(|p| *p == at_rest));
    assert_eq!(shape_of(&square(), RADIUS, &miss, &poses), None);
    let information = information_of(&physics(), &miss, 3, &theta());
    assert_eq!(*information.jtj(), nalgebra::Matrix3::zeros());
}

#[test]
fn predicted_poses_follow_the_models_rollout_and_fill_the_frames_between() {
    let at_rest = Pose2::new(0.0, 0.0, 0.3);
    let push = straight(
        [-0.08 * 0.3f64.cos() + 0.01, -0.08 * 0.3f64.sin()],
        rotate(Vector2::x(), 0.3),
        at_rest,
    );
    let horizon = 4;
    let poses = predicted_poses(&physics(), &push, horizon, &theta());
    assert_eq!(poses.len(), push.len());
    let steps = rollout(&physics(), &push, 0, horizon, push.len(), &theta());
    for (frame, pose) in &steps.poses {
        assert_eq!(poses[*frame], *pose);
    }
    // The object moved, and in between two knots it lies between them.
    let (moved, _) = poses[0].motion_to(poses.last().unwrap());
    assert!(moved.norm() > 0.02, "{moved}");
    let (a, b, mid) = (poses[40].position, poses[44].position, poses[42].position);
    assert!((mid - (a + (b - a) / 2.0)).norm() < 1e-4);
}

#[test]
fn a_push_teaches_the_com_across_it_far_better_than_its_depth_along_it() {
    // Pushed along x, the turn the push starts says where the COM lies across the push (y); where
    // it lies along the push changes the motion little: one push cannot see the COM's depth (the
    // trust experiment's finding on MuJoCo pushes). A push along y sees the other way round.
    let at_rest = Pose2::new(0.0, 0.0, 0.0);
    let along_x = straight([-0.08, 0.01], Vector2::x(), at_rest);
    let along_y = straight([0.01, -0.08], Vector2::y(), at_rest);
    let info = |push: &Trajectory| *information_of(&physics(), push, 3, &theta()).jtj();
    let (x, y) = (info(&along_x), info(&along_y));
    assert!(x[(1, 1)] > 5.0 * x[(0, 0)], "{x}");
    assert!(y[(0, 0)] > 5.0 * y[(1, 1)], "{y}");
}
