//! Offline training's passes for the contact-frame model on a batch of samples: each sample's
//! geometry before and after the network (the lever, the prior, Lynch and eq. 15) on its own, the
//! network one layer for all samples at a time (`mlp/batch.rs`), as the paper kind's `batch.rs`.
//!
//! Every value is computed with the same operations in the same order as the single-sample pass in
//! `pass.rs` — the context's share of the first layer unfused, sums in sample order — so a model
//! trained through these passes is bit for bit the one the single-sample pass trained (tested below).

use super::pass::{OuterGradient, OuterPass, Prepared};
use super::{CONTACT_INPUTS, ContactModel};
use crate::model::kernel::{loss_gradient, loss_weights};
use crate::model::mlp::{BATCH, BatchActivations, HIDDEN, Mlp, OUTPUTS};
use crate::real::Real;
use crate::simd::{MulAdd, Unfused};

/// One training sample: prepared on its object, with its target and the object's `θ_online(0)`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TrainingSample<T> {
    pub prepared: Prepared<T>,
    pub target: [T; 3],
    pub theta: [T; 3],
}

/// Scratch space of the batch passes: a batch's activations, gradients and per-sample passes
/// (about 14 kB for `f32`; boxed by its owners).
#[derive(Clone, Debug)]
pub(crate) struct BatchPass<T> {
    activations: BatchActivations<T, CONTACT_INPUTS>,
    outer: [OuterPass<T>; BATCH],
    /// The network's outputs.
    z: [[T; OUTPUTS]; BATCH],
    /// The gradient with respect to the network's outputs, and per sample the rest of the backward
    /// pass's state.
    d_z: [[T; OUTPUTS]; BATCH],
    gradients: [OuterGradient<T>; BATCH],
    d1: [[T; HIDDEN]; BATCH],
    d_position: [[T; 2]; BATCH],
}

impl<T: Real> Default for BatchPass<T> {
    fn default() -> Self {
        let z = T::zero();
        Self {
            activations: BatchActivations::default(),
            outer: [OuterPass::default(); BATCH],
            z: [[z; OUTPUTS]; BATCH],
            d_z: [[z; OUTPUTS]; BATCH],
            gradients: [OuterGradient::default(); BATCH],
            d1: [[z; HIDDEN]; BATCH],
            d_position: [[z; 2]; BATCH],
        }
    }
}

impl<T: Real> ContactModel<T> {
    /// The forward pass of `samples[i]` for each `i` in `indices` (at most [`BATCH`]) up to the
    /// network's outputs, left in `batch.z` (zero without the network); the network's first-layer
    /// context share is summed with `C`, everything else with `A`. Returns the batch's size.
    #[inline(always)]
    fn forward_network_batch<A: MulAdd, C: MulAdd>(
        &self,
        samples: &[TrainingSample<T>],
        indices: &[usize],
        batch: &mut BatchPass<T>,
    ) -> usize {
        let indices = &indices[..indices.len().min(BATCH)];
        let inputs = batch.activations.input.iter_mut().zip(&mut batch.outer);
        for ((x, outer), &i) in inputs.zip(indices) {
            let s = &samples[i];
            *x = self.network_input::<A>(&s.prepared, &s.theta, outer);
        }
        let n = indices.len();
        if self.options.network {
            self.network
                .forward_batch_with::<A, C>(n, &mut batch.activations, &mut batch.z);
        } else {
            batch.z = [[T::zero(); OUTPUTS]; BATCH];
        }
        n
    }

    /// Offline training's hot loop for one batch (`samples[i]` for each `i` in `indices`, at most
    /// [`BATCH`]): the forward pass, the loss (eq. 8) and the backward pass. Adds each sample's loss to
    /// `loss`, its `μ` gradient to `d_friction` and the network's weight gradient to `grad`, in sample
    /// order.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn accumulate_batch<A: MulAdd>(
        &self,
        samples: &[TrainingSample<T>],
        indices: &[usize],
        weights: &[T; 3],
        batch: &mut BatchPass<T>,
        grad: &mut Mlp<T, CONTACT_INPUTS>,
        loss: &mut T,
        d_friction: &mut f64,
    ) {
        let n = self.forward_network_batch::<A, Unfused>(samples, indices, batch);
        let per_sample = batch.z.iter().zip(&mut batch.outer).zip(&mut batch.d_z);
        for (((z, outer), d_z), &i) in per_sample.zip(&indices[..n]) {
            let s = &samples[i];
            let output = self.forward_outer::<A>(&s.prepared, &s.theta, *z, outer);
            let (l, d_output) = loss_gradient(output, &s.target, weights);
            *loss = *loss + l;
            let gradient = self.backward_outer::<A>(&s.prepared, outer, &s.theta, d_output);
            *d_z = gradient.d_z;
            // As the single-sample pass adds it to a zero of the model's float type.
            *d_friction += (T::zero() + gradient.d_friction).as_f64();
        }
        if self.options.network {
            self.network.backward_batch::<A>(
                n,
                &batch.activations,
                &batch.d_z,
                grad,
                &mut batch.d1,
            );
        }
    }

    crate::simd::dispatch_simd! {
        /// The summed loss of `samples` (the validation split), added in order in `f64`. Unfused like
        /// the single-sample loss it replaced, so early stopping sees the same bits; run in the AVX2
        /// copy for its wider registers.
        pub(crate) fn total_loss(&self, samples: &[TrainingSample<T>], weights: &[T; 3],
            batch: &mut BatchPass<T>) -> f64
            => unfused total_loss_portable, total_loss_avx2
    }

    #[inline(always)]
    fn total_loss_portable(
        &self,
        samples: &[TrainingSample<T>],
        weights: &[T; 3],
        batch: &mut BatchPass<T>,
    ) -> f64 {
        let mut total = 0.0;
        let mut indices = [0; BATCH];
        for start in (0..samples.len()).step_by(BATCH) {
            let n = (samples.len() - start).min(BATCH);
            for (k, index) in indices[..n].iter_mut().enumerate() {
                *index = start + k;
            }
            self.forward_network_batch::<Unfused, Unfused>(samples, &indices[..n], batch);
            let per_sample = batch.z.iter().zip(&mut batch.outer);
            for ((z, outer), s) in per_sample.zip(&samples[start..start + n]) {
                let output = self.forward_outer::<Unfused>(&s.prepared, &s.theta, *z, outer);
                total += loss_gradient(output, &s.target, weights).0.as_f64();
            }
        }
        total
    }

    crate::simd::dispatch_simd! {
        /// The Gauss–Newton diagonal of the loss in `θ_online / h₀` summed over `samples` (each
        /// sample's `h₀` is its `θ_online(0)`'s): what the online step scales are calibrated from.
        /// Unfused and summed in the order of the single-sample passes it replaced (sample, output,
        /// component), so the stored scales keep their bits; run in the AVX2 copy for its wider
        /// registers.
        pub(crate) fn theta_curvature(&self, samples: &[TrainingSample<T>], batch: &mut BatchPass<T>)
            -> [f64; 3] => unfused theta_curvature_portable, theta_curvature_avx2
    }

    #[inline(always)]
    fn theta_curvature_portable(
        &self,
        samples: &[TrainingSample<T>],
        batch: &mut BatchPass<T>,
    ) -> [f64; 3] {
        let weights = loss_weights::<T>(&self.loss_scale);
        let mut curvature = [0.0f64; 3];
        let mut indices = [0; BATCH];
        let mut rows = [[[T::zero(); 3]; 3]; BATCH];
        for start in (0..samples.len()).step_by(BATCH) {
            let n = (samples.len() - start).min(BATCH);
            for (k, index) in indices[..n].iter_mut().enumerate() {
                *index = start + k;
            }
            let chunk = &samples[start..start + n];
            self.forward_network_batch::<Unfused, Unfused>(samples, &indices[..n], batch);
            for ((z, outer), s) in batch.z.iter().zip(&mut batch.outer).zip(chunk) {
                self.forward_outer::<Unfused>(&s.prepared, &s.theta, *z, outer);
            }
            // One row of the Jacobian of the prediction with respect to θ_online per output.
            for k in 0..3 {
                let mut d_output = [T::zero(); 3];
                d_output[k] = T::one();
                let per_sample = batch.outer.iter().zip(&mut batch.gradients);
                for (((outer, gradient), d_z), s) in per_sample.zip(&mut batch.d_z).zip(chunk) {
                    *gradient =
                        self.backward_outer::<Unfused>(&s.prepared, outer, &s.theta, d_output);
                    *d_z = gradient.d_z;
                }
                if self.options.network {
                    self.network.position_gradient_batch::<Unfused>(
                        n,
                        &batch.activations,
                        &batch.d_z,
                        &mut batch.d_position,
                    );
                } else {
                    batch.d_position = [[T::zero(); 2]; BATCH];
                }
                let per_sample = batch
                    .outer
                    .iter()
                    .zip(&batch.gradients)
                    .zip(&batch.d_position);
                for ((((outer, gradient), d_x), s), row) in per_sample.zip(chunk).zip(&mut rows) {
                    row[k] = self.theta_gradient::<Unfused>(
                        &s.prepared,
                        outer,
                        &s.theta,
                        *d_x,
                        gradient,
                    );
                }
            }
            for (s, sample_rows) in chunk.iter().zip(&rows) {
                let h0 = s.theta[2].as_f64();
                for (w, row) in weights.iter().zip(sample_rows) {
                    for (c, j) in curvature.iter_mut().zip(row) {
                        let j = j.as_f64() * h0;
                        *c += 2.0 * w.as_f64() * j * j;
                    }
                }
            }
        }
        curvature
    }
}

#[cfg(test)]
mod tests;
