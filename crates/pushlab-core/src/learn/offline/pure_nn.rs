//! Training the pure-network baseline (the paper's "Offline NN").

use std::sync::atomic::AtomicBool;

use super::{Split, TrainConfig, TrainError, TrainProgress, Trained, Trainee, check, run};
use crate::model::LossScale;
use crate::model::kernel::RealSample;
use crate::model::mlp::Activations;
use crate::model::normalization::{InputNormalization, Stats1, Stats2};
use crate::model::{Mlp, Network, OutputNormalization, PureNnModel, Sample};
use crate::rng::SplitMix64;
use crate::simd::MulAdd;

/// Trains the pure network baseline on trajectories of samples.
pub fn train_pure_nn(
    trajectories: &[Vec<Sample>],
    config: &TrainConfig,
    progress: &mut dyn FnMut(&TrainProgress),
    cancel: &AtomicBool,
) -> Result<Trained<PureNnModel>, TrainError> {
    crate::slices::finish(train_pure_nn_in_slices(
        trajectories,
        config,
        progress,
        cancel,
    ))
}

/// [`train_pure_nn`] in slices (`crate::slices`): what a browser tab polls a slice of each frame.
pub async fn train_pure_nn_in_slices(
    trajectories: &[Vec<Sample>],
    config: &TrainConfig,
    progress: &mut dyn FnMut(&TrainProgress),
    cancel: &AtomicBool,
) -> Result<Trained<PureNnModel>, TrainError> {
    let slices: Vec<&[Sample]> = trajectories.iter().map(Vec::as_slice).collect();
    check(&slices, config)?;
    let split = Split::new(trajectories, config);
    let input = InputNormalization {
        position: Stats2::of(split.train.iter().map(|s| s.input.robot_in_object)),
        motion: Stats2::of(split.train.iter().map(|s| s.input.robot_motion_in_object)),
    };
    let output = OutputNormalization {
        translation: Stats2::of(split.train.iter().map(|s| s.target.translation)),
        rotation: Stats1::of(split.train.iter().map(|s| s.target.rotation)),
    };
    let loss_scale = config
        .loss_scale
        .unwrap_or_else(|| LossScale::from_samples(&split.train));
    let mut rng = SplitMix64::new(config.seed);
    let model = PureNnModel {
        network: Network::new(Mlp::<f32>::random(&mut rng, 0.1)),
        input,
        output,
        loss_scale,
        horizon: config.horizon,
    };
    let mut trainee = PureNnTrainee {
        model,
        activations: Activations::default(),
    };
    let real = Split {
        train: split.train.iter().map(RealSample::of).collect(),
        validation: split.validation.iter().map(RealSample::of).collect(),
    };
    let report = run(&mut trainee, &real, config, &mut rng, progress, cancel).await;
    Ok(Trained {
        model: trainee.model,
        report,
    })
}

struct PureNnTrainee {
    model: PureNnModel,
    activations: Activations<f32>,
}

impl Trainee<{ crate::model::INPUTS }> for PureNnTrainee {
    type Real = f32;
    type Item = RealSample<f32>;
    fn network_mut(&mut self) -> &mut Network<f32> {
        &mut self.model.network
    }
    fn snapshot(&self) -> (Network<f32>, [f32; 3]) {
        (self.model.network.clone(), [0.0; 3])
    }
    fn restore(&mut self, snapshot: (Network<f32>, [f32; 3])) {
        self.model.network = snapshot.0;
    }
    fn loss_scale(&self) -> LossScale {
        self.model.loss_scale
    }
    #[inline(always)]
    fn accumulate_batch<A: MulAdd>(
        &mut self,
        samples: &[RealSample<f32>],
        batch: &[usize],
        w: &[f32; 3],
        grad: &mut Mlp<f32>,
    ) -> f32 {
        let mut loss = 0.0;
        for &i in batch {
            loss += self
                .model
                .accumulate_gradient(&samples[i], w, &mut self.activations, grad);
        }
        loss
    }
    fn total_loss(&mut self, samples: &[RealSample<f32>], w: &[f32; 3]) -> f64 {
        samples
            .iter()
            .map(|s| {
                let y = self.model.forward(&s.input, &mut self.activations);
                f64::from((0..3).fold(0.0, |acc, i| acc + w[i] * (y[i] - s.target[i]).powi(2)))
            })
            .sum()
    }
}
