//! Training the contact-frame combined model: the network and the prior's friction coefficient `μ`
//! by Adam, each sample at its own object's `θ_online(0)`; the prior's contact tolerance, the inputs'
//! clamp range and the online step scales from the offline data. Every pass over the samples runs in
//! batches, one network layer at a time (`model/contact/batch.rs`).

use std::sync::atomic::AtomicBool;

use nalgebra::Vector2;

use super::{Split, TrainConfig, TrainError, TrainProgress, Trained, Trainee, check, run};
use crate::learn::adam::SmallAdam;
use crate::model::LossScale;
use crate::model::contact::{
    BatchPass, CONTACT_INPUTS, ContactGeometry, ContactInputs, Features, TrainingSample,
};
use crate::model::kernel::{RealSample, theta_real};
use crate::model::mlp::{BATCH, Network};
use crate::model::paper::scales_from_curvature;
use crate::model::{ContactModel, Mlp, Sample};
use crate::rng::SplitMix64;
use crate::simd::MulAdd;

/// One recording's samples on its object: what the contact-frame model trains on.
#[derive(Clone, Copy, Debug)]
pub struct ContactTrajectory<'a> {
    pub geometry: &'a ContactGeometry,
    pub samples: &'a [Sample],
}

/// The prior's `μ` before training: between the pusher frictions of common materials.
const INITIAL_FRICTION: f64 = 0.3;
/// `μ` is kept in this range while it is trained.
const FRICTION_RANGE: (f64, f64) = (0.01, 2.0);
/// The contact tolerance is this percentile of the gap while the object moves.
const TOLERANCE_PERCENTILE: f64 = 90.0;

/// Trains the contact-frame combined model (eq. 12) on recordings of objects of known outline.
pub fn train_contact(
    trajectories: &[ContactTrajectory<'_>],
    config: &TrainConfig,
    progress: &mut dyn FnMut(&TrainProgress),
    cancel: &AtomicBool,
) -> Result<Trained<ContactModel>, TrainError> {
    crate::slices::finish(train_contact_in_slices(
        trajectories,
        config,
        progress,
        cancel,
    ))
}

/// [`train_contact`] in slices (`crate::slices`): what a browser tab polls a slice of each frame.
pub async fn train_contact_in_slices(
    trajectories: &[ContactTrajectory<'_>],
    config: &TrainConfig,
    progress: &mut dyn FnMut(&TrainProgress),
    cancel: &AtomicBool,
) -> Result<Trained<ContactModel>, TrainError> {
    let slices: Vec<&[Sample]> = trajectories.iter().map(|t| t.samples).collect();
    check(&slices, config)?;
    // Which samples are trained on and which validate: the same trajectories as every other model
    // trained with this seed.
    let indexed: Vec<Vec<(usize, usize)>> = trajectories
        .iter()
        .enumerate()
        .map(|(t, tr)| (0..tr.samples.len()).map(|i| (t, i)).collect())
        .collect();
    let split = Split::new(&indexed, config);
    let sample = |&(t, i): &(usize, usize)| (trajectories[t].geometry, &trajectories[t].samples[i]);
    // Each sample's contact frame, once: the statistics, the clamp range and the prepared samples all
    // start from it, and it is the costly part (a pass over the outline's edges).
    let features = |list: &[(usize, usize)]| -> Vec<Features> {
        list.iter()
            .map(|pair| {
                let (geometry, s) = sample(pair);
                Features::of(geometry, &s.input)
            })
            .collect()
    };
    let (train_features, validation_features) =
        (features(&split.train), features(&split.validation));
    let train: Vec<(&ContactGeometry, &Sample)> = split.train.iter().map(sample).collect();
    let loss_scale = config
        .loss_scale
        .unwrap_or_else(|| LossScale::from_samples(train.iter().map(|(_, s)| *s)));
    let (contact_tolerance, motion_floor) = contact_statistics(&train, &train_features);
    let inputs = input_range(&train, &train_features, motion_floor);
    let mut rng = SplitMix64::new(config.seed);
    let network = Network::new(Mlp::<f32, CONTACT_INPUTS>::random(&mut rng, 0.1));
    let model = ContactModel::from_parts(
        network,
        inputs,
        INITIAL_FRICTION,
        contact_tolerance,
        loss_scale,
        config.horizon,
        config.contact,
    );
    let items = |list: &[(usize, usize)], features: &[Features]| -> Vec<TrainingSample<f32>> {
        list.iter()
            .zip(features)
            .map(|(pair, f)| {
                let (geometry, s) = sample(pair);
                TrainingSample {
                    prepared: model.prepare_features(f),
                    target: RealSample::<f32>::of(s).target,
                    theta: theta_real(&model.theta0(geometry)),
                }
            })
            .collect()
    };
    let prepared = Split {
        train: items(&split.train, &train_features),
        validation: items(&split.validation, &validation_features),
    };
    // Each sample's contact frame was the costly part of the preparation.
    crate::slices::pause().await;
    let mut trainee = ContactTrainee {
        model,
        batch: Box::default(),
        friction: INITIAL_FRICTION,
        friction_adam: SmallAdam::new(config.learning_rate),
        friction_gradient: 0.0,
    };
    let report = run(&mut trainee, &prepared, config, &mut rng, progress, cancel).await;
    let mut model = trainee.model;
    // Online gradient descent's step scales per metre of each object's `θ_online(0)` `h`: the
    // Gauss–Newton diagonal of the loss in `θ_online / h₀` over the training samples, as the paper
    // model calibrates its scales in metres.
    let curvature = model.theta_curvature(&prepared.train);
    model.relative_theta_scales = scales_from_curvature(curvature, prepared.train.len(), 1.0);
    Ok(Trained { model, report })
}

/// The prior's contact tolerance — the given percentile of the rim's gap to the outline over the
/// samples in which the object moves more than in half of them (so surely in contact), at least 0 —
/// and the motion floor, a tenth of the mean motion length.
fn contact_statistics(train: &[(&ContactGeometry, &Sample)], features: &[Features]) -> (f64, f64) {
    let moves: Vec<f64> = train
        .iter()
        .map(|(_, s)| Vector2::from(s.target.translation).norm())
        .collect();
    let median = percentile(moves.clone(), 50.0);
    let gaps: Vec<f64> = features
        .iter()
        .zip(&moves)
        .filter(|&(_, &m)| m > median)
        .map(|(f, _)| f.gap())
        .collect();
    let tolerance = percentile(gaps, TOLERANCE_PERCENTILE).max(0.0);
    let mean_motion = train
        .iter()
        .map(|(_, s)| Vector2::from(s.input.robot_motion_in_object).norm())
        .sum::<f64>()
        / train.len().max(1) as f64;
    (tolerance, 0.1 * mean_motion)
}

/// The clamp range of the network's inputs: their extent over the training samples at each object's
/// `θ_online(0)`.
fn input_range(
    train: &[(&ContactGeometry, &Sample)],
    features: &[Features],
    motion_floor: f64,
) -> ContactInputs {
    let mut low = [f64::INFINITY; CONTACT_INPUTS];
    let mut high = [f64::NEG_INFINITY; CONTACT_INPUTS];
    for ((geometry, _), f) in train.iter().zip(features) {
        let x = ContactModel::<f64>::raw_inputs(f, geometry, motion_floor);
        for k in 0..CONTACT_INPUTS {
            low[k] = low[k].min(x[k]);
            high[k] = high[k].max(x[k]);
        }
    }
    if train.is_empty() {
        low = [-1.0; CONTACT_INPUTS];
        high = [1.0; CONTACT_INPUTS];
    }
    ContactInputs {
        low,
        high,
        motion_floor,
    }
}

/// The `p`-th percentile (0–100) by the nearest rank; 0 for no values. Selected rather than sorted
/// (linear time): the value at a rank of the total order is the same either way.
fn percentile(mut values: Vec<f64>, p: f64) -> f64 {
    values.retain(|v| v.is_finite());
    if values.is_empty() {
        return 0.0;
    }
    let rank = ((p / 100.0) * (values.len() - 1) as f64).round() as usize;
    let rank = rank.min(values.len() - 1);
    *values.select_nth_unstable_by(rank, f64::total_cmp).1
}

struct ContactTrainee {
    model: ContactModel,
    batch: Box<BatchPass<f32>>,
    friction: f64,
    friction_adam: SmallAdam<1>,
    friction_gradient: f64,
}

impl Trainee<CONTACT_INPUTS> for ContactTrainee {
    type Real = f32;
    type Item = TrainingSample<f32>;
    fn network_mut(&mut self) -> &mut Network<f32, CONTACT_INPUTS> {
        &mut self.model.network
    }
    fn snapshot(&self) -> (Network<f32, CONTACT_INPUTS>, [f32; 3]) {
        (self.model.network.clone(), [self.friction as f32, 0.0, 0.0])
    }
    fn restore(&mut self, snapshot: (Network<f32, CONTACT_INPUTS>, [f32; 3])) {
        self.model.network = snapshot.0;
        self.friction = f64::from(snapshot.1[0]);
        self.model.set_friction(self.friction);
    }
    fn loss_scale(&self) -> LossScale {
        self.model.loss_scale
    }
    /// Layer by layer over the batch (see [`ContactModel::accumulate_batch`]), in chunks of
    /// [`BATCH`] samples.
    #[inline(always)]
    fn accumulate_batch<A: MulAdd>(
        &mut self,
        samples: &[TrainingSample<f32>],
        batch: &[usize],
        weights: &[f32; 3],
        grad: &mut Mlp<f32, CONTACT_INPUTS>,
    ) -> f32 {
        let mut loss = 0.0;
        for chunk in batch.chunks(BATCH) {
            self.model.accumulate_batch::<A>(
                samples,
                chunk,
                weights,
                &mut self.batch,
                grad,
                &mut loss,
                &mut self.friction_gradient,
            );
        }
        loss
    }
    fn total_loss(&mut self, samples: &[TrainingSample<f32>], weights: &[f32; 3]) -> f64 {
        self.model.total_loss(samples, weights, &mut self.batch)
    }
    fn after_batch(&mut self, batch: usize) {
        let mut friction = [self.friction];
        let gradient = [self.friction_gradient / batch.max(1) as f64];
        self.friction_adam.step(&mut friction, &gradient);
        self.friction = friction[0].clamp(FRICTION_RANGE.0, FRICTION_RANGE.1);
        self.model.set_friction(self.friction);
        self.friction_gradient = 0.0;
    }
}

#[cfg(test)]
mod tests {
    use super::percentile;
    use crate::rng::SplitMix64;

    #[test]
    fn percentile_is_the_nearest_rank_of_the_sorted_finite_values() {
        let mut rng = SplitMix64::new(3);
        let values: Vec<f64> = (0..101)
            .map(|k| if k % 7 == 0 { 0.5 } else { rng.normal() })
            .chain([f64::NAN, f64::INFINITY, -0.0, 0.0])
            .collect();
        let mut sorted: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
        sorted.sort_by(f64::total_cmp);
        for p in [0.0, 10.0, 50.0, 90.0, 100.0] {
            let rank = ((p / 100.0) * (sorted.len() - 1) as f64).round() as usize;
            assert_eq!(
                percentile(values.clone(), p).to_bits(),
                sorted[rank].to_bits()
            );
        }
        assert_eq!(percentile(vec![f64::NAN], 50.0), 0.0);
    }
}
