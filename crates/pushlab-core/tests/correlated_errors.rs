//! The posterior when a push's errors are not independent: on a model linear in `θ` whose inputs
//! drift slowly from frame to frame (as a push's contact does), AR(1) noise with a known correlation
//! must widen the 95 % ellipse enough to hold the truth about as often as independent noise does
//! (without the batch-means factor it held the truth in 30 % of these pushes), and independent noise
//! must not widen it.

use crate::toy;

use nalgebra::Vector3;
use pushlab_core::model::{ObjectMotion, OnlineParams, Sample, SampleInput};
use pushlab_core::rng::SplitMix64;
use toy::{Chain, GAUSS_NEWTON, LinearToy, theta_vector};

const TRUTH: OnlineParams = OnlineParams {
    com_offset: [0.03, -0.02],
    h: 0.42,
};

/// `frames` samples whose inputs follow a slow random walk (each frame keeps 98 % of the last and
/// adds a little) and whose noise is AR(1) with lag-one correlation `rho` and variance 1.
fn drifting_samples(rng: &mut SplitMix64, frames: usize, rho: f64) -> Vec<Sample> {
    let mut input = [rng.normal(), rng.normal(), rng.normal(), rng.normal()];
    let mut noise = [rng.normal(), rng.normal(), rng.normal()];
    let innovation = (1.0 - rho * rho).sqrt();
    (0..frames)
        .map(|frame| {
            for x in &mut input {
                *x = 0.98 * *x + 0.2 * rng.normal();
            }
            for e in &mut noise {
                *e = rho * *e + innovation * rng.normal();
            }
            let input = SampleInput {
                robot_in_object: [input[0], input[1]],
                robot_motion_in_object: [input[2], input[3]],
            };
            let y: Vector3<f64> =
                LinearToy::matrix(&input) * theta_vector(&TRUTH) + Vector3::from(noise);
            Sample {
                input,
                target: ObjectMotion {
                    translation: [y[0], y[1]],
                    rotation: y[2],
                },
                frame,
            }
        })
        .collect()
}

/// Over `trials` pushes of `frames` frames: how often the final 95 % ellipse holds the true COM,
/// and the median correlation factor.
fn coverage(seed: u64, trials: usize, frames: usize, rho: f64) -> (f64, f64) {
    let mut rng = SplitMix64::new(seed);
    let mut factors = Vec::new();
    let held = (0..trials)
        .filter(|_| {
            let samples = drifting_samples(&mut rng, frames, rho);
            let mut learner = Chain::new(LinearToy, GAUSS_NEWTON);
            learner.run(&samples);
            let posterior = learner.posterior();
            factors.push(posterior.correlation_factor());
            posterior.com_within_95(learner.theta().com_offset, TRUTH.com_offset)
        })
        .count();
    factors.sort_by(f64::total_cmp);
    eprintln!(
        "rho {rho}: held {held}/{trials}, median factor {:.2}",
        factors[trials / 2]
    );
    (held as f64 / trials as f64, factors[trials / 2])
}

#[test]
fn correlated_errors_widen_the_ellipse_until_it_holds_the_truth() {
    let (held, factor) = coverage(5, 300, 400, 0.8);
    assert!(
        factor > 4.0,
        "AR(1) noise at ρ = 0.8 (long-run factor 9) counts each frame as {factor:.2} frames"
    );
    assert!(
        held >= 0.85,
        "the 95 % ellipse held the truth in {:.1} % of pushes with correlated errors",
        100.0 * held
    );
}

#[test]
fn independent_errors_leave_the_ellipse_as_it_was() {
    let (held, factor) = coverage(6, 300, 200, 0.0);
    assert!(factor < 1.6, "independent noise: factor {factor:.2}");
    assert!(
        (0.9..=0.995).contains(&held),
        "the 95 % ellipse held the truth in {:.1} % of pushes with independent errors",
        100.0 * held
    );
}

#[test]
fn too_few_frames_to_compare_batches_leave_the_information_alone() {
    let mut rng = SplitMix64::new(7);
    // Errors that never decorrelate, but only three frames: three batches of one, fewer than the
    // four the scatter needs.
    let samples = drifting_samples(&mut rng, 3, 0.999);
    let mut learner = Chain::new(LinearToy, GAUSS_NEWTON);
    learner.run(&samples);
    assert_eq!(learner.posterior().score_batches(), (3, 1));
    assert_eq!(learner.posterior().correlation_factor(), 1.0);
    // Forty frames of them: ten batches of four, and the factor says the evidence is overstated.
    let samples = drifting_samples(&mut rng, 40, 0.999);
    let mut learner = Chain::new(LinearToy, GAUSS_NEWTON);
    learner.run(&samples);
    assert_eq!(learner.posterior().score_batches(), (10, 4));
    assert!(learner.posterior().correlation_factor() > 1.5);
}
