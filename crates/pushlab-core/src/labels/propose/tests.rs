//! Closed-form cases of the proposal rules: a pusher at a known distance, a contact point drifting
//! at a known rate, a known glitch, residual spikes at known samples, and a known tracking noise.

#![allow(clippy::unwrap_used)]

use nalgebra::Point2;

use super::rules::{self, NoiseEstimate};
use super::*;
use crate::geometry::Pose2;
use crate::sim::NoiseStream;
use crate::trajectory::Frame;

const RATE_HZ: f64 = 10.0;
/// A 0.2 m square box with its geometric centre at the origin; its front face is at x = −0.1.
const HALF: f64 = 0.1;
const RADIUS: f64 = 0.01;

fn square() -> Outline {
    Outline::rectangle(2.0 * HALF, 2.0 * HALF).unwrap()
}

/// Frames from `(robot, object)` pairs at 10 Hz.
fn trajectory(poses: impl IntoIterator<Item = (Point2<f64>, Pose2)>) -> Trajectory {
    Trajectory::new(
        poses
            .into_iter()
            .enumerate()
            .map(|(k, (robot, object))| Frame {
                time: k as f64 / RATE_HZ,
                robot,
                object,
            })
            .collect(),
    )
}

/// The pusher's centre with its rim `gap` in front of the front face, at height `y` on it, for an
/// object at `x` (not turned).
fn pusher(object_x: f64, gap: f64, y: f64) -> Point2<f64> {
    Point2::new(object_x - HALF - RADIUS - gap, y)
}

/// Proposals polled to their end, as the command line and the desktop run them.
fn propose(
    trajectory: &Trajectory,
    outline: &Outline,
    pusher_radius: f64,
    residuals: Option<Residuals<'_>>,
    options: &ProposeOptions,
    progress: &mut dyn FnMut(f32) -> bool,
) -> Result<Proposals, ProposeError> {
    crate::slices::finish(propose_in_slices(
        trajectory,
        outline,
        pusher_radius,
        residuals,
        options,
        progress,
    ))
}

fn run(trajectory: &Trajectory) -> Proposals {
    propose(
        trajectory,
        &square(),
        RADIUS,
        None,
        &ProposeOptions::default(),
        &mut |_| true,
    )
    .unwrap()
}

fn labels_at(proposals: &Proposals, frame: usize) -> Vec<&'static str> {
    let mut labels: Vec<_> = proposals.at(frame).map(|p| p.label).collect();
    labels.sort_unstable();
    labels
}

#[test]
fn a_pusher_at_a_known_distance_is_no_contact_and_its_gap_is_that_distance() {
    // Standing 25 mm from the front face, sliding along it; the object never moves.
    let t = trajectory((0..60).map(|k| {
        (
            pusher(0.0, 0.025, -0.05 + 0.001 * k as f64),
            Pose2::new(0.0, 0.0, 0.0),
        )
    }));
    let p = run(&t);
    for e in &p.evidence {
        assert!((f64::from(e.gap) - 0.025).abs() < 1e-6, "{e:?}");
        assert!(e.drift.is_nan());
    }
    assert_eq!(p.segments.len(), 1);
    assert_eq!(p.segments[0].label, NO_CONTACT);
    assert_eq!(p.segments[0].frames, 0..60);
    // 25 mm is thousands of noise σ (the noise floor is 10 µm): certain.
    assert!(p.segments[0].confidence > 0.999);
    assert!(
        p.why(10)[0].starts_with("no contact: the pusher's rim is 25.0 mm from the outline"),
        "{:?}",
        p.why(10)
    );
}

/// 30 frames of approach at 1 mm per frame, then 70 frames of pushing at 5 mm per frame in which
/// the pusher slides along the face at `slide` metres per frame (0: sticking).
fn approach_then_push(slide: f64, noise: f64, seed: u64) -> Trajectory {
    let mut rng = NoiseStream::new(seed);
    let mut jitter = move || noise * rng.normal();
    trajectory((0..100usize).map(|k| {
        let pushed = k.saturating_sub(30) as f64;
        let object_x = 0.005 * pushed;
        let gap = 0.001 * 30usize.saturating_sub(k) as f64;
        let robot = pusher(object_x, gap, slide * pushed - 0.07);
        (
            Point2::new(robot.x + jitter(), robot.y + jitter()),
            Pose2::new(object_x + jitter(), jitter(), 0.0),
        )
    }))
}

#[test]
fn contact_starts_where_the_gap_closes() {
    let p = run(&approach_then_push(0.0, 0.0, 1));
    // The running median sees 1 mm at frame 29 (gaps 3, 2, 1, 0, 0 mm) and 0 from frame 30.
    assert_eq!(labels_at(&p, 29), vec![NO_CONTACT]);
    assert_eq!(labels_at(&p, 30), vec![CONTACT, STICKING]);
    assert_eq!(labels_at(&p, 99), vec![CONTACT, STICKING]);
    let contact: Vec<_> = p.segments.iter().filter(|s| s.label == CONTACT).collect();
    assert_eq!(contact.len(), 1);
    assert_eq!(contact[0].frames, 30..100);
    // Without noise the tolerance is the noise floor: 3 × √2 × 10 µm (pusher and object) and the
    // yaw's 10 µrad at the pusher's arm of 0.11 m.
    let floor = 3.0 * (2.0 * 1e-10 + (1e-5 * 0.11f64).powi(2)).sqrt();
    assert!(
        (p.contact_tolerance - floor).abs() < 1e-6,
        "{}",
        p.contact_tolerance
    );
}

#[test]
fn a_contact_point_drifting_at_a_known_rate_is_slipping_at_that_rate() {
    // 2 mm per frame along the face at 10 Hz: 20 mm/s against the pusher's √(50² + 20²) mm/s.
    let p = run(&approach_then_push(0.002, 0.0, 1));
    for k in 32..98 {
        let e = &p.evidence[k];
        assert!(
            (f64::from(e.drift) - 0.020).abs() < 1e-6,
            "frame {k}: {e:?}"
        );
        assert!(
            (f64::from(e.pusher_speed) - 0.050f64.hypot(0.020)).abs() < 1e-6,
            "frame {k}"
        );
        assert_eq!(labels_at(&p, k), vec![CONTACT, SLIPPING], "frame {k}");
    }
    assert!(
        p.why(50)[1].starts_with(
            "slipping: the pusher drifts 20.0 mm/s over the object, 37 % of its speed"
        ),
        "{:?}",
        p.why(50)
    );
}

#[test]
fn with_tracking_noise_the_noise_is_estimated_and_a_clear_drift_is_still_slipping() {
    let sd = 0.001;
    let t = approach_then_push(0.002, sd, 7);
    let noise = NoiseEstimate::of(&t);
    for estimate in [noise.robot_sd, noise.object_sd] {
        assert!((estimate / sd - 1.0).abs() < 0.25, "{noise:?}");
    }
    let p = run(&t);
    // The tolerance grows with the noise: at least 3 σ of two positions' noise.
    assert!(
        p.contact_tolerance > 3.0 * 2f64.sqrt() * sd * 0.75,
        "{}",
        p.contact_tolerance
    );
    let slipping = (35..95)
        .filter(|&k| labels_at(&p, k) == vec![CONTACT, SLIPPING])
        .count();
    assert!(slipping >= 55, "{slipping} of 60 frames slipping");
    // The same push without the drift sticks.
    let p = run(&approach_then_push(0.0, sd, 7));
    let sticking = (35..95)
        .filter(|&k| labels_at(&p, k) == vec![CONTACT, STICKING])
        .count();
    assert!(sticking >= 55, "{sticking} of 60 frames sticking");
}

#[test]
fn a_pose_glitch_is_bad_tracking_on_its_frame_only() {
    let mut t = approach_then_push(0.0, 0.0, 1);
    t.frames[60].object.position.y += 0.05;
    t.frames[80].object.yaw += 0.3;
    let p = run(&t);
    let bad: Vec<_> = p
        .segments
        .iter()
        .filter(|s| s.label == BAD_TRACKING)
        .map(|s| s.frames.clone())
        .collect();
    assert_eq!(bad, vec![60..61, 80..81]);
    assert!(
        p.why(60)
            .iter()
            .any(|w| w.starts_with("bad tracking: the object jumped")),
        "{:?}",
        p.why(60)
    );
    // A move the pusher explains (the object following a 5 mm push) is not a jump.
    assert_eq!(p.evidence[50].jump_z, 0.0);
}

#[test]
fn residual_spikes_point_at_the_frame_two_samples_share() {
    // Horizon 3, 40 samples over 43 frames: a bad frame 13 spoils the samples starting at 10 and 13.
    let mut scores = vec![0.0; 40];
    scores[10] = 9.0;
    scores[13] = 9.0;
    // A spike alone is the model's error: nothing marked.
    scores[25] = 9.0;
    // At the ends the partner sample does not exist: the first frame, and the last.
    scores[1] = 9.0;
    scores[39] = 9.0;
    let bad = rules::residual_frames(&scores, 3, 43, 6.0);
    let frames: Vec<usize> = (0..43).filter(|&k| bad[k]).collect();
    assert_eq!(frames, vec![1, 13, 42]);
    // A pair at the start points at their common frame 3, not at frame 0 as well.
    let mut scores = vec![0.0; 40];
    scores[0] = 9.0;
    scores[3] = 9.0;
    let bad = rules::residual_frames(&scores, 3, 43, 6.0);
    assert_eq!((0..43).filter(|&k| bad[k]).collect::<Vec<_>>(), vec![3]);
    // Robust scores: errors (√ loss) 1 m, rising to 3 m over the middle (the model's own error,
    // which the running median follows), with one of 11 m at sample 21 and a noise of ±0.1 m.
    let errors: Vec<f64> = (0..50)
        .map(|k| {
            let level = if (15..35).contains(&k) { 3.0 } else { 1.0 };
            let noise = if k % 2 == 0 { 0.1 } else { -0.1 };
            if k == 21 { 11.0 } else { level + noise }
        })
        .collect();
    let losses: Vec<f64> = errors.iter().map(|e| e * e).collect();
    let z = rules::residual_scores(&losses, 0.0);
    // Away from the steps each error is 0.1 m from its running median (the median of ±0.1 around
    // the level is +0.1 or −0.1 m), so σ = 0.2 × 1.4826 at most and the spike stands ≥ 26 σ out.
    assert!(z[21] > 26.0, "{}", z[21]);
    let largest_other = (0..50)
        .filter(|&k| k != 21)
        .map(|k| z[k].abs())
        .fold(0.0, f64::max);
    assert!(largest_other < 6.0, "{largest_other}");
}

#[test]
fn confidence_is_the_normal_distribution_of_the_margin() {
    assert!((rules::confidence(0.0) - 0.5).abs() < 1e-6);
    assert!((rules::confidence(1.0) - 0.841_344_7).abs() < 1e-6);
    assert!((rules::confidence(-3.0) - 0.998_650_1).abs() < 1e-6);
    assert_eq!(rules::confidence(f64::INFINITY), 1.0);
}

#[test]
fn proposals_become_labels_that_a_labels_file_accepts_and_stopping_is_an_error() {
    let mut t = approach_then_push(0.002, 0.0, 1);
    t.frames[60].object.position.y += 0.05;
    let p = run(&t);
    let mut set = crate::labels::LabelSet::default();
    set.recordings
        .insert("push_000.csv".into(), p.to_labels(0.0));
    set.normalise_and_validate().unwrap();
    let stopped = propose(
        &t,
        &square(),
        RADIUS,
        None,
        &ProposeOptions::default(),
        &mut |_| false,
    );
    assert_eq!(stopped, Err(ProposeError::Cancelled));
}

/// What a page does with proposals: polls them a slice at a time. A long push stops every 4,096
/// frames of the gap pass and between the stages, and gives what the proposals in one piece give.
#[test]
fn proposals_in_slices_pause_through_a_long_push_and_match_the_proposals_in_one_piece() {
    let short = approach_then_push(0.002, 0.0, 1);
    // A push of about 10,000 frames: the short one again and again, the clock running on.
    let frames: Vec<Frame> = (0..10_000)
        .map(|k| {
            let mut frame = short.frames[k % short.frames.len()];
            frame.time = k as f64 / RATE_HZ;
            frame
        })
        .collect();
    let long = Trajectory::new(frames);
    let whole = run(&long);
    let outline = square();
    let options = ProposeOptions::default();
    let mut progress = |_| true;
    let mut work = Box::pin(propose_in_slices(
        &long,
        &outline,
        RADIUS,
        None,
        &options,
        &mut progress,
    ));
    let mut polls = 1;
    let sliced = loop {
        if let Some(done) = crate::slices::poll_once(work.as_mut()) {
            break done.unwrap();
        }
        polls += 1;
    };
    drop(work);
    // Frames 0, 4,096 and 8,192 of the gap pass, then two stages: five pauses.
    assert_eq!(polls, 6);
    // Compared as printed: the evidence holds NaN where a rule has no value, and NaN ≠ NaN.
    assert!(
        format!("{sliced:?}") == format!("{whole:?}"),
        "the proposals in slices differ"
    );
}
