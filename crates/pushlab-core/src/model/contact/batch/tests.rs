//! The batch passes against the single-sample pass whose gradients are checked against central
//! differences (`pass/tests.rs`): the same bits, in both compiled variants.

use super::*;
use crate::model::Sample;
use crate::model::contact::ContactOptions;
use crate::model::contact::pass::Pass;
use crate::model::contact::pass::tests::{model_f64, sample, square};
use crate::model::kernel::RealSample;
use crate::rng::SplitMix64;
use crate::simd::{Fused, Unfused};

/// Pushes around the test push on the square's front face, varied so that different ReLUs are
/// active, some pushes slide and some stick, and the clamp range cuts some levers.
fn varied_samples(count: usize) -> Vec<Sample> {
    let mut rng = SplitMix64::new(9);
    (0..count)
        .map(|frame| {
            let mut s = sample();
            s.input.robot_in_object[0] += 0.01 * rng.normal();
            s.input.robot_in_object[1] += 0.06 * rng.normal();
            s.input.robot_motion_in_object[0] += 0.004 * rng.normal();
            s.input.robot_motion_in_object[1] += 0.02 * rng.normal();
            s.target.rotation += 0.01 * rng.normal();
            s.frame = frame;
            s
        })
        .collect()
}

/// The model of the gradient checks in `T`, with a clamp range that cuts the lever's tangential
/// component for some of [`varied_samples`], and the samples prepared on the square.
fn setup<T: Real>(count: usize) -> (ContactModel<T>, Vec<TrainingSample<T>>) {
    let mut model = model_f64(6);
    model.inputs.low[1] = -0.5;
    model.inputs.high[1] = 0.5;
    let model = model.cast::<T>();
    let geometry = square();
    let samples = varied_samples(count)
        .iter()
        .enumerate()
        .map(|(k, s)| TrainingSample {
            prepared: model.prepare(&geometry, &s.input),
            target: RealSample::<T>::of(s).target,
            // A few objects' θ_online(0).
            theta: [0.01, -0.015 * (k % 3) as f64, 0.06 + 0.01 * (k % 2) as f64].map(T::of),
        })
        .collect();
    (model, samples)
}

/// What the single-sample pass gives for `samples[i]`, `i` in `indices`, summed in order: the weight
/// gradient, the loss and the `μ` gradient (added as training adds them).
fn per_sample<T: Real, A: MulAdd>(
    model: &ContactModel<T>,
    samples: &[TrainingSample<T>],
    indices: &[usize],
) -> (Mlp<T, CONTACT_INPUTS>, T, f64) {
    let weights = loss_weights(&model.loss_scale);
    let mut grad = Mlp::zeros();
    let (mut loss, mut d_friction) = (T::zero(), 0.0);
    let mut pass = Pass::default();
    for &i in indices {
        let s = &samples[i];
        let prepared = model.with_context(&s.prepared);
        let output = model.forward::<A>(&prepared, &s.theta, &mut pass);
        let (l, d_output) = loss_gradient(output, &s.target, &weights);
        loss = loss + l;
        let mut d_mu = T::zero();
        model.backward::<A>(
            &prepared,
            &pass,
            &s.theta,
            d_output,
            Some((&mut grad, &mut d_mu)),
        );
        d_friction += d_mu.as_f64();
    }
    (grad, loss, d_friction)
}

fn batched<T: Real, A: MulAdd>(
    model: &ContactModel<T>,
    samples: &[TrainingSample<T>],
    indices: &[usize],
) -> (Mlp<T, CONTACT_INPUTS>, T, f64) {
    let weights = loss_weights(&model.loss_scale);
    let mut grad = Mlp::zeros();
    let (mut loss, mut d_friction) = (T::zero(), 0.0);
    let mut batch = Box::<BatchPass<T>>::default();
    for chunk in indices.chunks(BATCH) {
        model.accumulate_batch::<A>(
            samples,
            chunk,
            &weights,
            &mut batch,
            &mut grad,
            &mut loss,
            &mut d_friction,
        );
    }
    (grad, loss, d_friction)
}

#[test]
fn batch_gradient_is_the_sum_of_per_sample_gradients_bit_for_bit() {
    // A full batch and a short last one, in a shuffled order; f32 as training runs it and f64 as the
    // gradient checks do; unfused and fused; with and without the network and the prior.
    let indices: Vec<usize> = (0..45).map(|k| (k * 7) % 45).collect();
    let (model, samples) = setup::<f32>(45);
    let (model64, samples64) = setup::<f64>(45);
    let options = [(true, true), (false, true), (true, false)];
    for (network, prior) in options {
        let mut m = model.clone();
        m.options = ContactOptions { network, prior };
        let mut m64 = model64.clone();
        m64.options = m.options;
        assert_eq!(
            batched::<_, Unfused>(&m, &samples, &indices),
            per_sample::<_, Unfused>(&m, &samples, &indices)
        );
        assert_eq!(
            batched::<_, Fused>(&m, &samples, &indices),
            per_sample::<_, Fused>(&m, &samples, &indices)
        );
        assert_eq!(
            batched::<_, Unfused>(&m64, &samples64, &indices),
            per_sample::<_, Unfused>(&m64, &samples64, &indices)
        );
    }
    // The test data exercises every branch the backward pass has.
    let mut pass = Pass::default();
    let (mut sliding, mut clamped) = (0, 0);
    for s in &samples64 {
        let prepared = model64.with_context(&s.prepared);
        model64.forward::<Unfused>(&prepared, &s.theta, &mut pass);
        sliding += usize::from(pass.outer.sliding_for_tests());
        clamped += usize::from(!pass.outer.unclamped_for_tests()[1]);
    }
    assert!((5..40).contains(&sliding), "{sliding} of 45 slide");
    assert!((5..40).contains(&clamped), "{clamped} of 45 clamped");
}

#[test]
fn batch_loss_and_curvature_are_those_of_the_single_sample_pass() {
    // 45 samples run on this thread; the larger set is shared with another where there are cores
    // (the curvature's later samples), and must keep the bits of the serial sum all the same.
    for count in [45, 2 * crate::parallel::SAMPLES_PER_WORKER + 7] {
        loss_and_curvature_match_the_single_sample_pass(count);
    }
}

fn loss_and_curvature_match_the_single_sample_pass(count: usize) {
    let (model, samples) = setup::<f32>(count);
    let weights = loss_weights(&model.loss_scale);
    let mut batch = Box::<BatchPass<f32>>::default();
    let mut pass = Pass::default();
    let mut expected_loss = 0.0;
    let mut expected_curvature = [0.0f64; 3];
    for s in &samples {
        let prepared = model.with_context(&s.prepared);
        let output = model.forward::<Unfused>(&prepared, &s.theta, &mut pass);
        expected_loss += f64::from(loss_gradient(output, &s.target, &weights).0);
        let h0 = f64::from(s.theta[2]);
        for (k, w) in weights.iter().enumerate() {
            let mut d_output = [0.0; 3];
            d_output[k] = 1.0;
            let row = model.backward::<Unfused>(&prepared, &pass, &s.theta, d_output, None);
            for (c, j) in expected_curvature.iter_mut().zip(row) {
                let j = f64::from(j) * h0;
                *c += 2.0 * f64::from(*w) * j * j;
            }
        }
    }
    assert_eq!(
        model.total_loss(&samples, &weights, &mut batch),
        expected_loss
    );
    assert_eq!(model.theta_curvature(&samples), expected_curvature);
    assert!(expected_curvature.iter().all(|&c| c > 0.0));
}
