//! Offline training's passes for the contact-frame model on a batch of samples: each sample's
//! geometry before and after the network (the lever, the prior, Lynch and eq. 15) on its own, the
//! network one layer for all samples at a time (`mlp/batch.rs`), as the paper kind's `batch.rs`.
//!
//! Every value is computed with the same operations in the same order as the single-sample pass in
//! `pass.rs` — the context's share of the first layer unfused, sums in sample order — so a model
//! trained through these passes is bit for bit the one the single-sample pass trained (tested below).

use super::pass::{OuterGradient, OuterPass, Prepared};
use super::{CONTACT_INPUTS, ContactModel};
use crate::model::kernel::{CurvatureTerms, curvature_sum, loss_gradient, loss_weights};
use crate::model::mlp::{BATCH, BatchActivations, HIDDEN, Mlp, OUTPUTS};
use crate::real::Real;
use crate::simd::{MulAdd, Unfused};

/// One training sample: prepared on its object, with its target and the object's `θ_online(0)`.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct TrainingSample<T> {
    pub prepared: Prepared<T>,
    pub target: [T; 3],
    pub theta: [T; 3],
}

/// Scratch space of the batch passes (about 19 kB for `f32`; boxed by its owners): a shuffled
/// batch's samples gathered in one place, and the batch's state.
#[derive(Clone, Debug)]
pub(crate) struct BatchPass<T> {
    /// Gathered in one pass of independent loads before anything is computed: a shuffled batch's
    /// samples lie anywhere in the training set, and fetched one at a time inside the pass their
    /// cache misses did not overlap (one load was a fifth of the epoch's time).
    gathered: [TrainingSample<T>; BATCH],
    state: BatchState<T>,
}

/// A batch's activations, gradients and per-sample passes.
#[derive(Clone, Debug)]
struct BatchState<T> {
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
            gathered: [TrainingSample::default(); BATCH],
            state: BatchState {
                activations: BatchActivations::default(),
                outer: [OuterPass::default(); BATCH],
                z: [[z; OUTPUTS]; BATCH],
                d_z: [[z; OUTPUTS]; BATCH],
                gradients: [OuterGradient::default(); BATCH],
                d1: [[z; HIDDEN]; BATCH],
                d_position: [[z; 2]; BATCH],
            },
        }
    }
}

impl<T: Real> ContactModel<T> {
    /// The forward pass of `chunk` (at most [`BATCH`] samples) up to the network's outputs, left in
    /// `state.z` (zero without the network); the network's first-layer context share is summed with
    /// `C`, everything else with `A`.
    #[inline(always)]
    fn forward_network_batch<A: MulAdd, C: MulAdd>(
        &self,
        chunk: &[TrainingSample<T>],
        state: &mut BatchState<T>,
    ) {
        let chunk = &chunk[..chunk.len().min(BATCH)];
        let inputs = state.activations.input.iter_mut().zip(&mut state.outer);
        for ((x, outer), s) in inputs.zip(chunk) {
            *x = self.network_input::<A>(&s.prepared, &s.theta, outer);
        }
        if self.options.network {
            self.network.forward_batch_with::<A, C>(
                chunk.len(),
                &mut state.activations,
                &mut state.z,
            );
        } else {
            state.z = [[T::zero(); OUTPUTS]; BATCH];
        }
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
        let n = indices.len().min(BATCH);
        for (slot, &i) in batch.gathered.iter_mut().zip(&indices[..n]) {
            *slot = samples[i];
        }
        let (chunk, state) = (&batch.gathered[..n], &mut batch.state);
        self.forward_network_batch::<A, Unfused>(chunk, state);
        let per_sample = state.z.iter().zip(&mut state.outer).zip(&mut state.d_z);
        for (((z, outer), d_z), s) in per_sample.zip(chunk) {
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
                &state.activations,
                &state.d_z,
                grad,
                &mut state.d1,
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
        let state = &mut batch.state;
        let mut total = 0.0;
        for chunk in samples.chunks(BATCH) {
            self.forward_network_batch::<Unfused, Unfused>(chunk, state);
            for ((z, outer), s) in state.z.iter().zip(&mut state.outer).zip(chunk) {
                let output = self.forward_outer::<Unfused>(&s.prepared, &s.theta, *z, outer);
                total += loss_gradient(output, &s.target, weights).0.as_f64();
            }
        }
        total
    }

    /// The Gauss–Newton diagonal of the loss in `θ_online / h₀` summed over `samples` (each
    /// sample's `h₀` is its `θ_online(0)`'s): what the online step scales are calibrated from. The
    /// bits of the single-sample passes this replaced, with the later samples on the machine's other
    /// cores ([`curvature_sum`]): half the time on two.
    pub(crate) fn theta_curvature(&self, samples: &[TrainingSample<T>]) -> [f64; 3]
    where
        T: Sync,
    {
        curvature_sum(samples, |part, each| {
            self.theta_curvature_terms(part, &mut Box::default(), each)
        })
    }

    crate::simd::dispatch_simd! {
        /// Each sample's terms of [`ContactModel::theta_curvature`], by output and component, handed
        /// to `each` in sample order. Unfused, as the single-sample passes it replaced; run in the
        /// AVX2 copy for its wider registers.
        fn theta_curvature_terms(&self, samples: &[TrainingSample<T>], batch: &mut BatchPass<T>,
            each: &mut dyn FnMut(CurvatureTerms)) -> () => unfused
            theta_curvature_terms_portable, theta_curvature_terms_avx2
    }

    #[inline(always)]
    fn theta_curvature_terms_portable(
        &self,
        samples: &[TrainingSample<T>],
        batch: &mut BatchPass<T>,
        each: &mut dyn FnMut(CurvatureTerms),
    ) {
        let weights = loss_weights::<T>(&self.loss_scale);
        let state = &mut batch.state;
        let mut rows = [[[T::zero(); 3]; 3]; BATCH];
        for chunk in samples.chunks(BATCH) {
            self.forward_network_batch::<Unfused, Unfused>(chunk, state);
            for ((z, outer), s) in state.z.iter().zip(&mut state.outer).zip(chunk) {
                self.forward_outer::<Unfused>(&s.prepared, &s.theta, *z, outer);
            }
            // One row of the Jacobian of the prediction with respect to θ_online per output.
            for k in 0..3 {
                let mut d_output = [T::zero(); 3];
                d_output[k] = T::one();
                let per_sample = state.outer.iter().zip(&mut state.gradients);
                for (((outer, gradient), d_z), s) in per_sample.zip(&mut state.d_z).zip(chunk) {
                    *gradient =
                        self.backward_outer::<Unfused>(&s.prepared, outer, &s.theta, d_output);
                    *d_z = gradient.d_z;
                }
                if self.options.network {
                    self.network.position_gradient_batch::<Unfused>(
                        chunk.len(),
                        &state.activations,
                        &state.d_z,
                        &mut state.d_position,
                    );
                } else {
                    state.d_position = [[T::zero(); 2]; BATCH];
                }
                let per_sample = state.outer.iter().zip(&state.gradients);
                let per_sample = per_sample.zip(&state.d_position).zip(chunk);
                for ((((outer, gradient), d_x), s), row) in per_sample.zip(&mut rows) {
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
                each(std::array::from_fn(|k| {
                    sample_rows[k].map(|j| {
                        let j = j.as_f64() * h0;
                        2.0 * weights[k].as_f64() * j * j
                    })
                }));
            }
        }
    }
}

#[cfg(test)]
mod tests;
