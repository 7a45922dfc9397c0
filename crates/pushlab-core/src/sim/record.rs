//! Runs one push and samples it like a tracking camera would: at a fixed rate, optionally with
//! Gaussian noise on every recorded position and yaw.

use nalgebra::Vector2;

use super::SimError;
use super::noise::SplitMix64;
use super::path::PusherPath;
use super::world::{PushWorld, SimObject};
use crate::geometry::Pose2;
use crate::trajectory::{Frame, Trajectory};

/// How often and how long to record, and how finely to integrate in between.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampling {
    /// Recorded frames per second.
    pub rate_hz: f64,
    /// Length of the recording, seconds; frames at `0, 1/rate, …` up to and including it.
    pub duration_s: f64,
    /// Largest pusher travel per substep, metres: the quasi-static step is first order, so this sets
    /// the integration error (0.2 mm keeps it far below any tracking noise).
    pub max_substep: f64,
}

impl Default for Sampling {
    fn default() -> Self {
        Self {
            rate_hz: 10.0,
            duration_s: 10.0,
            max_substep: 2e-4,
        }
    }
}

/// Tracking noise: independent Gaussian errors on each recorded coordinate.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TrackingNoise {
    /// Standard deviation of the robot's and the object's recorded x and y, metres.
    pub position_sd: f64,
    /// Standard deviation of the object's recorded yaw, radians.
    pub yaw_sd: f64,
}

/// A simulated push: what a tracker would record, the noise-free truth, and how the contact behaved.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulatedPush {
    /// The recorded frames (with tracking noise, if any).
    pub trajectory: Trajectory,
    /// The same frames without noise.
    pub truth: Trajectory,
    /// Fraction of substeps in which the pusher pressed on the object.
    pub contact_fraction: f64,
    /// Fraction of the pressing substeps in which it slid along the edge.
    pub sliding_fraction: f64,
    /// Largest overlap removed by the normal correction, metres (second order in the substep).
    pub max_overlap: f64,
    /// What the contact did after each recorded frame: the true labels a labeling assist is measured
    /// against (`pushlab simulate --truth-labels`).
    pub frame_contacts: Vec<FrameContact>,
}

/// How the contact behaved over one recorded frame's interval, counted in integration substeps.
///
/// Frame `k`'s interval is the time from frame `k` to frame `k + 1` (what follows the frame, as a
/// sample from frame `k` predicts it); the last frame, which has no interval after it, takes the one
/// before it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameContact {
    /// Substeps in the interval.
    pub substeps: u32,
    /// Substeps in which the pusher pressed on the object (sticking or sliding).
    pub pressing: u32,
    /// Pressing substeps in which it slid along the edge.
    pub sliding: u32,
}

impl FrameContact {
    /// Whether the pusher pressed on the object for most of the interval.
    pub fn in_contact(&self) -> bool {
        2 * self.pressing > self.substeps
    }

    /// Whether, while pressing, the contact slid along the edge for most of the time.
    pub fn slipping(&self) -> bool {
        2 * self.sliding > self.pressing
    }
}

/// Why the sampling parameters are unusable.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SamplingError {
    #[error("{field} must be positive and finite, got {value}")]
    NotPositive { field: &'static str, value: f64 },
    #[error("{frames} frames is too many for one push (at most 1,000,000)")]
    TooManyFrames { frames: f64 },
}

/// Simulates one push of `object`, starting at `world_from_object`, by a pusher following `path`.
pub fn simulate_push(
    object: &SimObject,
    world_from_object: Pose2,
    path: &PusherPath,
    sampling: &Sampling,
    noise: Option<(&TrackingNoise, &mut SplitMix64)>,
) -> Result<SimulatedPush, SimError> {
    for (field, value) in [
        ("sample_rate_hz", sampling.rate_hz),
        ("duration_s", sampling.duration_s),
        ("max_substep", sampling.max_substep),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(SamplingError::NotPositive { field, value }.into());
        }
    }
    let frames = (sampling.duration_s * sampling.rate_hz + 1e-9).floor();
    if frames > 1e6 {
        return Err(SamplingError::TooManyFrames { frames }.into());
    }
    let frames = frames as usize + 1;
    let dt = 1.0 / sampling.rate_hz;
    let substeps = ((path.speed() * dt / sampling.max_substep).ceil() as usize).max(1);

    let mut world = PushWorld::new(object.clone(), world_from_object, path.position(0.0))?;
    let mut truth = Vec::with_capacity(frames);
    let mut frame_contacts = Vec::with_capacity(frames);
    let (mut pressing, mut sliding, mut total, mut max_overlap) = (0usize, 0usize, 0usize, 0.0f64);
    for k in 0..frames {
        let time = k as f64 * dt;
        if k > 0 {
            let mut interval = FrameContact::default();
            for j in 1..=substeps {
                let t = (k - 1) as f64 * dt + dt * j as f64 / substeps as f64;
                let report = world.move_pusher_to(path.position(t));
                total += 1;
                interval.substeps += 1;
                max_overlap = max_overlap.max(report.overlap_before_correction);
                if let Some(mode) = report.mode.filter(|m| *m != super::ContactMode::Separating) {
                    pressing += 1;
                    sliding += usize::from(mode.is_sliding());
                    interval.pressing += 1;
                    interval.sliding += u32::from(mode.is_sliding());
                }
            }
            // The interval from frame k − 1 to k belongs to frame k − 1.
            frame_contacts.push(interval);
        }
        truth.push(Frame {
            time,
            robot: world.pusher(),
            object: world.world_from_object(),
        });
    }
    let recorded = match noise {
        Some((noise, rng)) => truth
            .iter()
            .map(|f| {
                let mut jitter = || Vector2::new(rng.normal(), rng.normal()) * noise.position_sd;
                let robot = f.robot + jitter();
                let position = f.object.position + jitter();
                Frame {
                    time: f.time,
                    robot,
                    object: Pose2 {
                        position,
                        yaw: f.object.yaw + rng.normal() * noise.yaw_sd,
                    },
                }
            })
            .collect(),
        None => truth.clone(),
    };
    // The last frame has no interval after it: it takes the one before it.
    frame_contacts.push(frame_contacts.last().copied().unwrap_or_default());
    Ok(SimulatedPush {
        trajectory: Trajectory::new(recorded),
        truth: Trajectory::new(truth),
        contact_fraction: ratio(pressing, total),
        sliding_fraction: ratio(sliding, pressing),
        max_overlap,
        frame_contacts,
    })
}

fn ratio(part: usize, whole: usize) -> f64 {
    if whole == 0 {
        0.0
    } else {
        part as f64 / whole as f64
    }
}
