//! The live chain against closed forms: a base turning at a constant rate and sliding at a constant
//! velocity (so that the import's interpolation is exact), an arm link on it published at other
//! stamps, a static tip; poses waiting for a link, dropped when a link began after them or stopped,
//! memory held bounded, bad transforms refused, a root that gets a parent said.
#![allow(clippy::unwrap_used)]

use super::*;
use crate::recording::bag::{Transform, encode_tf_message};

const MS: u64 = 1_000_000;
const T0: u64 = 1_700_000_000_000_000_000;

fn tf(stamp_ns: u64, parent: &str, child: &str, xyz: [f64; 3], yaw: f64) -> Vec<u8> {
    let (s, c) = (yaw / 2.0).sin_cos();
    encode_tf_message(&[Transform {
        stamp_ns,
        parent: parent.as_bytes(),
        child: child.as_bytes(),
        translation: xyz,
        rotation: [0.0, 0.0, s, c],
    }])
}

/// `world → base` at `t` seconds: sliding at (0.1, −0.05) m/s, turning at 0.4 rad/s.
fn base(t: f64) -> ([f64; 3], f64) {
    ([0.2 + 0.1 * t, -0.05 * t, 0.0], 0.4 * t)
}

/// `base → tool0` at `t` seconds: sliding along the base's x at 0.2 m/s, turning at −0.3 rad/s.
fn tool(t: f64) -> ([f64; 3], f64) {
    ([0.3 + 0.2 * t, 0.1, 0.5], -0.3 * t)
}

/// `tool0 → tip` (static): 5 cm out along the tool's x.
const TIP: [f64; 3] = [0.05, 0.0, 0.0];

/// The tip in the world at `t`, in closed form.
fn tip_in_world(t: f64) -> (f64, f64, f64) {
    let ((b, by), (l, ly)) = (base(t), tool(t));
    let rot = |yaw: f64, v: [f64; 2]| {
        let (s, c) = yaw.sin_cos();
        [c * v[0] - s * v[1], s * v[0] + c * v[1]]
    };
    let tip_in_base = {
        let r = rot(ly, [TIP[0], TIP[1]]);
        [l[0] + r[0], l[1] + r[1]]
    };
    let r = rot(by, tip_in_base);
    (b[0] + r[0], b[1] + r[1], by + ly)
}

/// Feeds a base at 50 Hz and a tool at 100 Hz (3 ms after), a static tip after 40 ms, for
/// `seconds`; the poses given.
fn run(chain: &mut LiveChain, seconds: f64) -> Vec<PlanarPose> {
    let mut poses = Vec::new();
    let mut add = |chain: &mut LiveChain, bytes: Vec<u8>, ns: u64, is_static: bool| {
        let read = chain.add(&bytes, ns, is_static).unwrap();
        poses.extend(read.poses);
    };
    let steps = (seconds * 100.0) as u64;
    for k in 0..steps {
        let t_ns = k * 10 * MS;
        if k % 2 == 0 {
            let (xyz, yaw) = base(t_ns as f64 * 1e-9);
            add(
                chain,
                tf(T0 + t_ns, "world", "base", xyz, yaw),
                T0 + t_ns,
                false,
            );
        }
        let tool_ns = t_ns + 3 * MS;
        let (xyz, yaw) = tool(tool_ns as f64 * 1e-9);
        add(
            chain,
            tf(T0 + tool_ns, "base", "tool0", xyz, yaw),
            T0 + tool_ns,
            false,
        );
        if k == 4 {
            add(chain, tf(0, "tool0", "tip", TIP, 0.0), T0 + t_ns, true);
        }
    }
    poses
}

#[test]
fn a_tip_under_a_moving_arm_is_posed_in_the_world_as_the_closed_form_says() {
    let mut chain = LiveChain::new("tip", true);
    let poses = run(&mut chain, 2.0);
    assert_eq!(
        chain.frames().unwrap(),
        ["tip", "tool0", "base", "world"],
        "the chain"
    );
    // The times are the tool's (the tip's own link is static); the first tool transforms came before
    // the base's second one, so all but the last wait or are posed.
    assert!(poses.len() > 190, "{} poses", poses.len());
    for p in &poses {
        let t = (p.stamp_ns - T0) as f64 * 1e-9;
        let (x, y, yaw) = tip_in_world(t);
        assert!(
            (p.x - x).abs() < 1e-12 && (p.y - y).abs() < 1e-12 && (p.yaw - yaw).abs() < 1e-12,
            "at {t} s: {p:?} against ({x}, {y}, {yaw})"
        );
        assert_eq!(
            (p.stamp_ns - T0 - 3 * MS) % (10 * MS),
            0,
            "at the tool's stamps"
        );
    }
    assert_eq!(chain.dropped(), 0);
    // Held: the poses waiting for the next base transform and the base's two around them.
    assert!(chain.held() <= 6, "{} held", chain.held());
}

#[test]
fn the_chain_waits_for_tf_static_and_says_what_it_follows() {
    let mut chain = LiveChain::new("tip", true);
    let (xyz, yaw) = base(0.0);
    let read = chain
        .add(&tf(T0, "world", "base", xyz, yaw), T0, false)
        .unwrap();
    assert_eq!(read, ChainRead::default(), "nothing before /tf_static");
    let (xyz, yaw) = tool(0.0);
    chain
        .add(&tf(T0, "base", "tool0", xyz, yaw), T0, false)
        .unwrap();
    let read = chain
        .add(&tf(0, "tool0", "tip", TIP, 0.0), T0, true)
        .unwrap();
    assert_eq!(read.said, ["following tip through tool0 → base → world"]);
    assert_eq!(
        read.poses.len(),
        1,
        "the tool's transform at the base's time"
    );
}

#[test]
fn without_tf_static_the_chain_is_fixed_after_half_a_second() {
    let mut chain = LiveChain::new("tool0", false);
    let poses = run(&mut chain, 0.2);
    assert_eq!(chain.frames().unwrap(), ["tool0", "base", "world"]);
    assert!(!poses.is_empty());
    // Advertised but never sent: fixed once the stamps span half a second.
    let mut chain = LiveChain::new("base", true);
    for k in 0..60u64 {
        let (xyz, yaw) = base(k as f64 * 0.01);
        let read = chain
            .add(&tf(T0 + k * 10 * MS, "world", "base", xyz, yaw), 0, false)
            .unwrap();
        assert_eq!(chain.frames().is_some(), k >= 50, "at {k}: {read:?}");
    }
}

#[test]
fn poses_a_link_cannot_reach_are_dropped_and_counted() {
    // `/tf_static` advertised and never sent: the chain is fixed after half a second.
    let mut chain = LiveChain::new("tool0", true);
    // The tool's transforms before the base's first: they cannot be composed.
    for k in 0..5u64 {
        let (xyz, yaw) = tool(k as f64 * 0.01);
        chain
            .add(&tf(T0 + k * 10 * MS, "base", "tool0", xyz, yaw), 0, false)
            .unwrap();
    }
    let (xyz, yaw) = base(0.045);
    chain
        .add(&tf(T0 + 45 * MS, "world", "base", xyz, yaw), 0, false)
        .unwrap();
    assert!(chain.frames().is_none(), "not settled yet");
    // The base stops; the tool goes on: poses wait a second, then are dropped.
    let mut posed = 0;
    for k in 5..200u64 {
        let (xyz, yaw) = tool(k as f64 * 0.01);
        let read = chain
            .add(&tf(T0 + k * 10 * MS, "base", "tool0", xyz, yaw), 0, false)
            .unwrap();
        posed += read.poses.len();
    }
    assert_eq!(
        posed, 0,
        "nothing can be posed after the base's one transform"
    );
    // The five before the base began, and those that waited a second (up to 0.99 s).
    assert_eq!(chain.dropped(), 5 + 95, "dropped");
    assert!(chain.held() <= 101, "{} held", chain.held());
}

#[test]
fn a_bad_transform_refuses_its_message_by_name() {
    let mut chain = LiveChain::new("tip", false);
    let bytes = encode_tf_message(&[Transform {
        stamp_ns: T0,
        parent: b"tool0",
        child: b"tip",
        translation: [f64::NAN, 0.0, 0.0],
        rotation: [0.0, 0.0, 0.0, 1.0],
    }]);
    let error = chain.add(&bytes, T0, false).unwrap_err();
    assert!(
        error.starts_with("transform tool0 → tip has translation [NaN, 0.0, 0.0]"),
        "{error}"
    );
    let error = chain.add(&bytes[..20], T0, false).unwrap_err();
    assert!(!error.is_empty());
}

#[test]
fn a_root_that_gets_a_parent_later_is_said_and_the_poses_stay_in_it() {
    let mut chain = LiveChain::new("tool0", false);
    run(&mut chain, 0.7);
    assert_eq!(chain.frames().unwrap(), ["tool0", "base", "world"]);
    let read = chain
        .add(
            &tf(T0 + 800 * MS, "map", "world", [1.0, 0.0, 0.0], 0.0),
            0,
            false,
        )
        .unwrap();
    assert_eq!(
        read.said,
        [
            "the frame world got the parent map after the poses of tool0 began in it: they stay in world"
        ]
    );
    assert_eq!(chain.frames().unwrap(), ["tool0", "base", "world"]);
}
