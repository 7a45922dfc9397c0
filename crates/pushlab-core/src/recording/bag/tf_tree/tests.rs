//! Unit tests of the transform tree: composition in closed form, slerp, timing and drops, loops
//! and two parents.
#![allow(clippy::unwrap_used)]
use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::Vector3;

use super::*;

fn quat(axis: [f64; 3], angle: f64) -> [f64; 4] {
    let q = UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(axis.into()), angle);
    [q.i, q.j, q.k, q.w]
}

/// Adds `parent → child` at `ns` to `topic`'s transforms.
fn add(
    tf: &mut Transforms,
    topic: &str,
    ns: u64,
    (parent, child): (&str, &str),
    translation: [f64; 3],
    rotation: [f64; 4],
) {
    let slot = tf.slot(topic);
    let transforms = &mut tf.topics[slot];
    let index = transforms.index;
    transforms.index += 1;
    let transform = Transform {
        stamp_ns: ns,
        parent: parent.as_bytes(),
        child: child.as_bytes(),
        translation,
        rotation,
    };
    let sample = Sample {
        ns,
        stamped: true,
        file: 0,
        index,
        translation,
        rotation,
    };
    transforms.add(&transform, sample);
}

fn poses(tf: &Transforms, topic: &str, frame: &str) -> Vec<[f64; 4]> {
    let chain = tf.chain(topic, frame).unwrap().unwrap();
    let found = chain.poses(frame).unwrap();
    found
        .poses
        .iter()
        .map(|p| [p.at.ns as f64, p.x, p.y, p.yaw])
        .collect()
}

fn assert_close(got: [f64; 4], want: [f64; 4]) {
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() < 1e-12, "{got:?} vs {want:?}");
    }
}

#[test]
fn a_quarter_turn_then_a_translation_composes_in_closed_form() {
    let mut tf = Transforms::default();
    let z = [0.0, 0.0, 1.0];
    // world_from_arm turns a quarter about z and moves to (1, 2); arm_from_tip is 0.5 m along
    // the arm's x, turned by 0.3: the tip is at (1, 2.5), turned by π/2 + 0.3.
    add(
        &mut tf,
        TF_STATIC,
        5,
        ("world", "arm"),
        [1.0, 2.0, 0.0],
        quat(z, FRAC_PI_2),
    );
    for ns in [10, 20] {
        add(
            &mut tf,
            "/tf",
            ns,
            ("arm", "tip"),
            [0.5, 0.0, 0.0],
            quat(z, 0.3),
        );
    }
    let chain = tf.chain("/tf", "tip").unwrap().unwrap();
    assert_eq!(chain.frames, ["tip", "arm", "world"]);
    let got = poses(&tf, "/tf", "tip");
    assert_eq!(got.len(), 2);
    assert_close(got[0], [10.0, 1.0, 2.5, FRAC_PI_2 + 0.3]);
}

#[test]
fn a_tilted_wrist_that_a_static_tip_untilts_gives_a_planar_tip() {
    let mut tf = Transforms::default();
    let x = [1.0, 0.0, 0.0];
    // The wrist points down (half a turn about x); the tip turns it back and adds a yaw of -0.4,
    // so the tip is planar: its offset (0.1, 0.2, 0.3) in the wrist is (0.1, -0.2, -0.3) in the
    // world, and its yaw is -0.4 (not +0.4, as composing yaws alone would give).
    let back = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI)
        * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), -0.4);
    let back = [back.i, back.j, back.k, back.w];
    add(
        &mut tf,
        TF_STATIC,
        0,
        ("wrist", "tip"),
        [0.1, 0.2, 0.3],
        back,
    );
    for ns in [100, 200, 300] {
        add(
            &mut tf,
            "/tf",
            ns,
            ("world", "wrist"),
            [0.0, 0.0, 1.0],
            quat(x, PI),
        );
    }
    // The tip is static: the times are the wrist's.
    let got = poses(&tf, "/tf", "tip");
    assert_eq!(got.len(), 3);
    assert_close(got[2], [300.0, 0.1, -0.2, -0.4]);
}

#[test]
fn slerp_at_the_midpoint_halves_the_turn_and_the_way() {
    let z = Vector3::z_axis();
    let at = |x: f64, yaw: f64| {
        Isometry3::from_parts(
            Translation3::new(x, 2.0 * x, 0.0),
            UnitQuaternion::from_axis_angle(&z, yaw),
        )
    };
    let samples = [(10, at(0.0, 0.0)), (20, at(2.0, 1.0)), (40, at(2.0, 3.0))];
    let mid = interpolate(&samples, 15).unwrap();
    assert!((mid.translation.vector - Vector3::new(1.0, 2.0, 0.0)).norm() < 1e-12);
    assert!((mid.rotation.angle() - 0.5).abs() < 1e-12);
    let quarter = interpolate(&samples, 25).unwrap();
    assert!((quarter.rotation.angle() - 1.5).abs() < 1e-12);
    assert_eq!(interpolate(&samples, 20), Some(samples[1].1));
    // Not extrapolated on either side.
    assert_eq!(interpolate(&samples, 9), None);
    assert_eq!(interpolate(&samples, 41), None);
}

#[test]
fn a_frame_is_evaluated_at_its_own_stamps_and_drops_those_a_parent_does_not_span() {
    let mut tf = Transforms::default();
    let z = [0.0, 0.0, 1.0];
    // The table moves 1 m along x from ns 100 to 200; the object sits still on it.
    add(
        &mut tf,
        "/tf",
        100,
        ("world", "table"),
        [0.0, 0.0, 0.0],
        quat(z, 0.0),
    );
    add(
        &mut tf,
        "/tf",
        200,
        ("world", "table"),
        [1.0, 0.0, 0.0],
        quat(z, 1.0),
    );
    for ns in [50, 125, 150, 250] {
        add(
            &mut tf,
            "/tf",
            ns,
            ("table", "object"),
            [0.0, 1.0, 0.0],
            quat(z, 0.0),
        );
    }
    let chain = tf.chain("/tf", "object").unwrap().unwrap();
    let found = chain.poses("/tf:object").unwrap();
    let got: Vec<_> = found
        .poses
        .iter()
        .map(|p| [p.at.ns as f64, p.x, p.y, p.yaw])
        .collect();
    assert_eq!(got.len(), 2);
    // At 150 the table is half way and half turned (0.5 rad): the object, 1 m along the
    // table's y, is at (0.5 - sin 0.5, cos 0.5).
    assert_close(got[1], [150.0, 0.5 - 0.5f64.sin(), 0.5f64.cos(), 0.5]);
    let dropped = found.dropped.unwrap();
    assert_eq!((dropped.count, found.candidates), (2, 4));
    assert_eq!(dropped.link, "world → table");
    assert_eq!(dropped.span_ns, (100, 200));
}

#[test]
fn a_loop_and_a_frame_with_two_parents_are_refused() {
    let mut tf = Transforms::default();
    let id = [0.0, 0.0, 0.0, 1.0];
    add(&mut tf, "/tf", 1, ("b", "a"), [0.0; 3], id);
    add(&mut tf, "/tf", 1, ("c", "b"), [0.0; 3], id);
    add(&mut tf, TF_STATIC, 1, ("a", "c"), [0.0; 3], id);
    let p = tf.chain("/tf", "a").unwrap_err();
    assert!(matches!(&p, BagProblem::FrameLoop { chain, .. } if chain == &["a", "b", "c", "a"]));
    assert!(p.to_string().contains("a → b → c → a"), "{p}");

    let mut tf = Transforms::default();
    add(&mut tf, "/tf", 1, ("world", "tip"), [0.0; 3], id);
    add(&mut tf, "/tf", 2, ("odom", "tip"), [0.0; 3], id);
    let p = tf.chain("/tf", "tip").unwrap_err();
    assert_eq!(
        p.to_string(),
        "topic `/tf` message 1: frame `tip` has two parents, `world` and `odom`; expected one \
         tree (each frame published under one parent)"
    );
    assert!(tf.chain("/tf", "elsewhere").unwrap().is_none());
}
