//! Training the contact-frame combined model: the network and the prior's friction coefficient `μ`
//! by Adam, each sample at its own object's `θ_online(0)`; the prior's contact tolerance, the inputs'
//! clamp range and the online step scales from the offline data.

use std::sync::atomic::AtomicBool;

use nalgebra::{Point2, Vector2};

use super::{Split, TrainConfig, TrainError, TrainProgress, Trained, Trainee, check, run};
use crate::learn::adam::SmallAdam;
use crate::learn::loss::LossScale;
use crate::model::contact::{CONTACT_INPUTS, ContactGeometry, ContactInputs, Pass, Prepared};
use crate::model::kernel::{RealSample, loss_gradient, loss_weights, theta_real};
use crate::model::mlp::Network;
use crate::model::paper::scales_from_curvature;
use crate::model::{ContactModel, Mlp, Sample};
use crate::rng::SplitMix64;
use crate::simd::{MulAdd, Unfused};

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
    trajectories: &[ContactTrajectory],
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
    let train: Vec<(&ContactGeometry, &Sample)> = split.train.iter().map(sample).collect();
    let loss_scale = config
        .loss_scale
        .unwrap_or_else(|| LossScale::from_samples(train.iter().map(|(_, s)| *s)));
    let (contact_tolerance, motion_floor) = contact_statistics(&train);
    let inputs = input_range(&train, motion_floor);
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
    let items = |list: &[(usize, usize)]| -> Vec<Item> {
        list.iter()
            .map(|pair| {
                let (geometry, s) = sample(pair);
                Item {
                    prepared: model.prepare(geometry, &s.input),
                    target: RealSample::<f32>::of(s).target,
                    theta: theta_real(&model.theta0(geometry)),
                }
            })
            .collect()
    };
    let prepared = Split {
        train: items(&split.train),
        validation: items(&split.validation),
    };
    let mut trainee = ContactTrainee {
        model,
        pass: Pass::default(),
        friction: INITIAL_FRICTION,
        friction_adam: SmallAdam::new(config.learning_rate),
        friction_gradient: 0.0,
    };
    let report = run(&mut trainee, &prepared, config, &mut rng, progress, cancel);
    let mut model = trainee.model;
    model.relative_theta_scales = relative_theta_scales(&model, &prepared.train);
    Ok(Trained { model, report })
}

/// The prior's contact tolerance — the given percentile of the rim's gap to the outline over the
/// samples in which the object moves more than in half of them (so surely in contact), at least 0 —
/// and the motion floor, a tenth of the mean motion length.
fn contact_statistics(train: &[(&ContactGeometry, &Sample)]) -> (f64, f64) {
    let moves: Vec<f64> = train
        .iter()
        .map(|(_, s)| Vector2::from(s.target.translation).norm())
        .collect();
    let median = percentile(moves.clone(), 50.0);
    let gaps: Vec<f64> = train
        .iter()
        .zip(&moves)
        .filter(|&(_, &m)| m > median)
        .map(|((geometry, s), _)| {
            geometry
                .frame(
                    Point2::from(s.input.robot_in_object),
                    Vector2::from(s.input.robot_motion_in_object),
                )
                .gap
        })
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
fn input_range(train: &[(&ContactGeometry, &Sample)], motion_floor: f64) -> ContactInputs {
    let mut low = [f64::INFINITY; CONTACT_INPUTS];
    let mut high = [f64::NEG_INFINITY; CONTACT_INPUTS];
    for (geometry, s) in train {
        let x = ContactModel::<f64>::raw_inputs(geometry, &s.input, motion_floor);
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

/// The `p`-th percentile (0–100) by the nearest rank; 0 for no values.
fn percentile(mut values: Vec<f64>, p: f64) -> f64 {
    values.retain(|v| v.is_finite());
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    let rank = ((p / 100.0) * (values.len() - 1) as f64).round() as usize;
    values[rank.min(values.len() - 1)]
}

/// Online gradient descent's step scales per metre of each object's `θ_online(0)` `h`: the
/// Gauss–Newton diagonal of the loss in `θ_online / h₀` over the training samples, as the paper model
/// calibrates its scales in metres.
fn relative_theta_scales(model: &ContactModel, train: &[Item]) -> [f64; 3] {
    let weights = loss_weights::<f32>(&model.loss_scale);
    let mut curvature = [0.0f64; 3];
    let mut pass = Pass::default();
    for item in train {
        let prepared = model.with_context(&item.prepared);
        model.forward::<Unfused>(&prepared, &item.theta, &mut pass);
        let h0 = f64::from(item.theta[2]);
        for (k, w) in weights.iter().enumerate() {
            let mut d_output = [0.0; 3];
            d_output[k] = 1.0;
            let row = model.backward::<Unfused>(&prepared, &pass, &item.theta, d_output, None);
            for (c, j) in curvature.iter_mut().zip(row) {
                let j = f64::from(j) * h0;
                *c += 2.0 * f64::from(*w) * j * j;
            }
        }
    }
    scales_from_curvature(curvature, train.len(), 1.0)
}

/// One training sample: prepared on its object, with the object's `θ_online(0)`.
#[derive(Clone, Copy, Debug)]
struct Item {
    prepared: Prepared<f32>,
    target: [f32; 3],
    theta: [f32; 3],
}

struct ContactTrainee {
    model: ContactModel,
    pass: Pass<f32>,
    friction: f64,
    friction_adam: SmallAdam<1>,
    friction_gradient: f64,
}

impl Trainee<CONTACT_INPUTS> for ContactTrainee {
    type Real = f32;
    type Item = Item;
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
    #[inline(always)]
    fn accumulate<A: MulAdd>(
        &mut self,
        item: &Item,
        w: &[f32; 3],
        grad: &mut Mlp<f32, CONTACT_INPUTS>,
    ) -> f32 {
        // The first layer's share of the context moves with the weights: recomputed per pass.
        let prepared = self.model.with_context(&item.prepared);
        let output = self
            .model
            .forward::<A>(&prepared, &item.theta, &mut self.pass);
        let (loss, d_output) = loss_gradient(output, &item.target, w);
        let mut d_friction = 0.0f32;
        self.model.backward::<A>(
            &prepared,
            &self.pass,
            &item.theta,
            d_output,
            Some((grad, &mut d_friction)),
        );
        self.friction_gradient += f64::from(d_friction);
        loss
    }
    fn loss(&mut self, item: &Item, w: &[f32; 3]) -> f32 {
        let prepared = self.model.with_context(&item.prepared);
        let output = self
            .model
            .forward::<Unfused>(&prepared, &item.theta, &mut self.pass);
        loss_gradient(output, &item.target, w).0
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
