//! A model linear in `θ` whose posterior has a closed form, and its samples: shared by the
//! posterior's tests.

#![allow(dead_code)] // each test file uses its own part

use nalgebra::{Matrix3, Vector3};
use pushlab_core::learn::{OnlineConfig, OnlineState, Optimizer, Posterior, learn_step};
use pushlab_core::model::{
    Descent, Linearization, Loss, LossScale, ObjectMotion, OnlineModel, OnlineParams, OnlineStep,
    Prediction, Sample, SampleInput,
};
use pushlab_core::rng::SplitMix64;

/// One Gauss–Newton step per frame.
pub const GAUSS_NEWTON: OnlineConfig = OnlineConfig {
    steps: 1,
    lr: 0.0,
    optimizer: Optimizer::GaussNewton,
};

/// A model linear in `θ`: the motion is `A(input) θ` with a 3 × 3 matrix built from the input's four
/// numbers, the loss's σ all 1.
pub struct LinearToy;

impl LinearToy {
    pub fn matrix(input: &SampleInput) -> Matrix3<f64> {
        let [a, b] = input.robot_in_object;
        let [c, d] = input.robot_motion_in_object;
        Matrix3::new(a, 0.2 * b, c, b, d, 0.5 * a, c + d, a - b, 1.0)
    }
}

pub fn theta_vector(theta: &OnlineParams) -> Vector3<f64> {
    Vector3::new(theta.com_offset[0], theta.com_offset[1], theta.h)
}

impl OnlineModel for LinearToy {
    fn theta0(&self) -> OnlineParams {
        OnlineParams {
            com_offset: [0.0, 0.0],
            h: 0.5,
        }
    }
    fn theta_scales(&self) -> [f64; 3] {
        [1.0; 3]
    }
    fn loss_scale(&self) -> LossScale {
        LossScale {
            sigma_pos: [1.0, 1.0],
            sigma_rot: 1.0,
        }
    }
    fn predict(&self, input: &SampleInput, theta: &OnlineParams) -> Prediction {
        let y = Self::matrix(input) * theta_vector(theta);
        Prediction {
            motion: ObjectMotion {
                translation: [y[0], y[1]],
                rotation: y[2],
            },
            contact: None,
            contact_motion: None,
        }
    }
    fn online_step(&self, sample: &Sample, theta: &OnlineParams, _: &Descent) -> OnlineStep {
        let prediction = self.predict(&sample.input, theta);
        OnlineStep {
            theta_before: *theta,
            prediction,
            loss: Loss::of(&prediction.motion, &sample.target, &self.loss_scale()),
            gradient: [0.0; 3],
            theta_after: *theta,
        }
    }
    fn linearize(&self, sample: &Sample, theta: &OnlineParams) -> Linearization {
        let prediction = self.predict(&sample.input, theta);
        let (p, t) = (prediction.motion, sample.target);
        let a = Self::matrix(&sample.input);
        Linearization {
            prediction,
            residual: [
                p.translation[0] - t.translation[0],
                p.translation[1] - t.translation[1],
                p.rotation - t.rotation,
            ],
            jacobian: [0, 1, 2].map(|i| [a[(i, 0)], a[(i, 1)], a[(i, 2)]]),
        }
    }
}

/// `frames` samples of the toy with the true `θ` and Gaussian noise of standard deviation `noise`.
pub fn toy_samples(
    rng: &mut SplitMix64,
    truth: &OnlineParams,
    frames: usize,
    noise: f64,
) -> Vec<Sample> {
    (0..frames)
        .map(|frame| {
            let input = SampleInput {
                robot_in_object: [rng.normal(), rng.normal()],
                robot_motion_in_object: [rng.normal(), rng.normal()],
            };
            let y = LinearToy::matrix(&input) * theta_vector(truth);
            Sample {
                input,
                target: ObjectMotion {
                    translation: [y[0] + noise * rng.normal(), y[1] + noise * rng.normal()],
                    rotation: y[2] + noise * rng.normal(),
                },
                frame,
            }
        })
        .collect()
}

/// Algorithm 1 chained over loose samples: [`learn_step`] from `θ_online(0)` and the prior, frame after
/// frame, as the core's `OnlineRun` chains it along a recording. These tests feed samples rather than
/// recordings (a toy model's, or several pushes of one object with θ carried from push to push), so
/// they chain the pure step themselves.
pub struct Chain<M> {
    model: M,
    config: OnlineConfig,
    state: OnlineState,
}

impl<M: OnlineModel> Chain<M> {
    pub fn new(model: M, config: OnlineConfig) -> Self {
        let state = OnlineState::start(&model, config.optimizer);
        Self {
            model,
            config,
            state,
        }
    }

    pub fn step(&mut self, sample: &Sample) -> OnlineStep {
        let (step, next) = learn_step(&self.model, sample, &self.state, &self.config);
        self.state = next;
        step
    }

    pub fn run(&mut self, samples: &[Sample]) -> Vec<OnlineStep> {
        samples.iter().map(|s| self.step(s)).collect()
    }

    pub fn theta(&self) -> OnlineParams {
        self.state.theta
    }

    pub fn posterior(&self) -> Posterior {
        self.state.posterior
    }
}
