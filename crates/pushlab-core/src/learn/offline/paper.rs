//! Training the paper's combined model.

use std::sync::atomic::AtomicBool;

use super::{Split, TrainConfig, TrainError, TrainProgress, Trained, Trainee, check, run};
use crate::geometry::Outline;
use crate::learn::adam::SmallAdam;
use crate::model::LossScale;
use crate::model::kernel::{RealSample, loss_gradient};
use crate::model::mlp::BATCH;
use crate::model::normalization::{InputNormalization, Stats2};
use crate::model::paper::{BatchPass, Pass};
use crate::model::{Mlp, Network, OnlineParams, PaperModel, Sample, theta_real};
use crate::rng::SplitMix64;
use crate::simd::MulAdd;

/// The paper model's `θ_online(0)` for training on objects with these outlines: the COM at the centre
/// and `h` of a uniform pressure over the outline when every recording has the same usable outline;
/// `None` otherwise (training then takes the generic guess, see [`TrainConfig::theta0`]). The rule
/// `pushlab train`, `pushlab eval` and the app's training share.
pub fn paper_theta0<'a>(
    outlines: impl IntoIterator<Item = Option<&'a Outline>>,
) -> Option<OnlineParams> {
    let mut outlines = outlines.into_iter();
    let first = outlines.next()??;
    for other in outlines {
        if other? != first {
            return None;
        }
    }
    Some(OnlineParams::for_outline(first))
}

/// Trains the paper's combined model (eq. 12) on trajectories of samples.
pub fn train_paper(
    trajectories: &[Vec<Sample>],
    config: &TrainConfig,
    progress: &mut dyn FnMut(&TrainProgress),
    cancel: &AtomicBool,
) -> Result<Trained<PaperModel>, TrainError> {
    crate::slices::finish(train_paper_in_slices(
        trajectories,
        config,
        progress,
        cancel,
    ))
}

/// [`train_paper`] in slices (`crate::slices`): what a browser tab polls a slice of each frame.
pub async fn train_paper_in_slices(
    trajectories: &[Vec<Sample>],
    config: &TrainConfig,
    progress: &mut dyn FnMut(&TrainProgress),
    cancel: &AtomicBool,
) -> Result<Trained<PaperModel>, TrainError> {
    let slices: Vec<&[Sample]> = trajectories.iter().map(Vec::as_slice).collect();
    check(&slices, config)?;
    let split = Split::new(trajectories, config);
    let theta0 = config
        .theta0
        .unwrap_or_else(|| default_theta0(&split.train))
        .clamped();
    let normalization = InputNormalization {
        position: Stats2::of(split.train.iter().map(|s| {
            let r = s.input.robot_in_object;
            [r[0] - theta0.com_offset[0], r[1] - theta0.com_offset[1]]
        }))
        .isotropic(),
        motion: Stats2::of(split.train.iter().map(|s| s.input.robot_motion_in_object)).isotropic(),
    };
    let loss_scale = config
        .loss_scale
        .unwrap_or_else(|| LossScale::from_samples(&split.train));
    let mut rng = SplitMix64::new(config.seed);
    let network = Network::new(Mlp::<f32>::random(&mut rng, 0.1));
    let model = PaperModel::from_parts(network, normalization, theta0, loss_scale, config.horizon);
    let mut trainee = PaperTrainee {
        model,
        pass: Pass::default(),
        batch: Box::default(),
        theta: theta_real(&theta0),
        theta_adam: config
            .train_online_params
            .then(|| SmallAdam::new(config.learning_rate)),
        theta_grad: [0.0; 3],
    };
    let real = Split {
        train: split.train.iter().map(RealSample::of).collect(),
        validation: split.validation.iter().map(RealSample::of).collect(),
    };
    let report = run(&mut trainee, &real, config, &mut rng, progress, cancel).await;
    let mut model = trainee.model;
    model.theta0 = crate::model::kernel::theta_params(&trainee.theta);
    model.calibrate_theta_scales(&split.train);
    Ok(Trained { model, report })
}

/// `θ_online(0)` when none is given: COM at the centre, `h` half the mean pusher distance.
fn default_theta0(samples: &[Sample]) -> OnlineParams {
    let mean_distance = samples
        .iter()
        .map(|s| {
            let r = s.input.robot_in_object;
            (r[0] * r[0] + r[1] * r[1]).sqrt()
        })
        .sum::<f64>()
        / samples.len().max(1) as f64;
    OnlineParams {
        com_offset: [0.0, 0.0],
        h: 0.5 * mean_distance,
    }
}

struct PaperTrainee {
    model: PaperModel,
    pass: Pass<f32>,
    batch: Box<BatchPass<f32>>,
    theta: [f32; 3],
    theta_adam: Option<SmallAdam<3>>,
    theta_grad: [f64; 3],
}

impl Trainee<{ crate::model::INPUTS }> for PaperTrainee {
    type Real = f32;
    type Item = RealSample<f32>;
    fn network_mut(&mut self) -> &mut Network<f32> {
        &mut self.model.network
    }
    fn snapshot(&self) -> (Network<f32>, [f32; 3]) {
        (self.model.network.clone(), self.theta)
    }
    fn restore(&mut self, snapshot: (Network<f32>, [f32; 3])) {
        (self.model.network, self.theta) = snapshot;
    }
    fn loss_scale(&self) -> LossScale {
        self.model.loss_scale
    }
    /// Layer by layer over the batch (see [`PaperModel::accumulate_batch`]), in chunks of
    /// [`BATCH`] samples.
    #[inline(always)]
    fn accumulate_batch<A: MulAdd>(
        &mut self,
        samples: &[RealSample<f32>],
        batch: &[usize],
        weights: &[f32; 3],
        grad: &mut Mlp<f32>,
    ) -> f32 {
        let mut loss = 0.0;
        for chunk in batch.chunks(BATCH) {
            let theta_gradient = self.theta_adam.is_some().then_some(&mut self.theta_grad);
            loss += self.model.accumulate_batch::<A>(
                samples,
                chunk,
                &self.theta,
                weights,
                &mut self.batch,
                grad,
                theta_gradient,
            );
        }
        loss
    }
    fn total_loss(&mut self, samples: &[RealSample<f32>], w: &[f32; 3]) -> f64 {
        samples
            .iter()
            .map(|s| {
                let output = self.model.forward(&s.input, &self.theta, &mut self.pass);
                f64::from(loss_gradient(output, &s.target, w).0)
            })
            .sum()
    }
    fn after_batch(&mut self, batch: usize) {
        let Some(adam) = &mut self.theta_adam else {
            return;
        };
        // Adam in units of the pusher position's spread.
        let length = self.model.normalization.position.scale();
        let mut scaled = self.theta.map(|t| f64::from(t) / length);
        let grad = self.theta_grad.map(|g| g * length / batch as f64);
        adam.step(&mut scaled, &grad);
        let clamped = OnlineParams::from_array(scaled.map(|t| t * length));
        self.theta = theta_real(&clamped);
        self.theta_grad = [0.0; 3];
    }
}
