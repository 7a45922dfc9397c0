//! Runs one push and samples it like a tracking camera would: at a fixed rate, optionally with
//! Gaussian noise on every recorded position and yaw.

use super::SimError;
use super::noise::NoiseStream;
use super::path::PusherPath;
use super::stepper::PushStepper;
pub use super::stepper::{FrameContact, TrackingNoise};
use super::world::SimObject;
use crate::geometry::Pose2;
use crate::trajectory::Trajectory;

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
    noise: Option<(&TrackingNoise, &mut NoiseStream)>,
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

    let mut stepper = PushStepper::new(
        object.clone(),
        world_from_object,
        path.position(0.0),
        sampling.rate_hz,
    )?;
    let mut noise = noise;
    let mut recorded = Vec::with_capacity(frames);
    let mut truth = Vec::with_capacity(frames);
    let mut frame_contacts = Vec::with_capacity(frames);
    let first = stepper.first_frame(noise.as_mut().map(|(n, rng)| (*n, &mut **rng)));
    recorded.push(first.recorded);
    truth.push(first.truth);
    for _ in 1..frames {
        let frame = stepper.step_along(
            path,
            substeps,
            noise.as_mut().map(|(n, rng)| (*n, &mut **rng)),
        );
        recorded.push(frame.recorded);
        truth.push(frame.truth);
        // The interval from frame k − 1 to k belongs to frame k − 1.
        frame_contacts.push(frame.contact);
    }
    // The last frame has no interval after it: it takes the one before it.
    frame_contacts.push(frame_contacts.last().copied().unwrap_or_default());
    let counts = stepper.counts();
    Ok(SimulatedPush {
        trajectory: Trajectory::new(recorded),
        truth: Trajectory::new(truth),
        contact_fraction: ratio(counts.pressing, counts.substeps),
        sliding_fraction: ratio(counts.sliding, counts.pressing),
        max_overlap: counts.max_overlap,
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
