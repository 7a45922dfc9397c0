//! The contact-frame model's online step, linearisation and both together, each from one prepared
//! sample through the shared kernel (`model::kernel`) in the widest SIMD available.

use super::{OuterPass, Prepared};
use crate::model::contact::CONTACT_INPUTS;
use crate::model::contact::ContactModel;
use crate::model::contact::frame::ContactGeometry;
use crate::model::kernel::{
    DescentRule, Linearization, RealSample, ThetaPass, descend, linearize, linearize_and_descend,
    loss_weights,
};
use crate::model::mlp::{AffinePiece, OUTPUTS};
use crate::model::params::OnlineParams;
use crate::model::{Prediction, Sample};
use crate::real::Real;
use crate::simd::MulAdd;

impl<T: Real> ContactModel<T> {
    /// One online update on an object of this geometry (see [`descend`]).
    pub(crate) fn online_update(
        &self,
        geometry: &ContactGeometry,
        sample: &Sample,
        theta: &OnlineParams,
        steps: usize,
        lr: f64,
    ) -> (Prediction, [f64; 3], OnlineParams) {
        let rule = self.descent_rule(geometry, steps, lr);
        self.online_update_on(geometry, sample, theta, rule)
    }

    /// `steps` gradient-descent steps at `lr` with this model's step scales on an object of this
    /// geometry: the rule of every online update.
    fn descent_rule(&self, geometry: &ContactGeometry, steps: usize, lr: f64) -> DescentRule {
        DescentRule {
            scales: self.theta_scales(geometry),
            steps,
            lr,
        }
    }

    crate::simd::dispatch_simd! {
        /// [`ContactModel::online_update`], preparation included (see [`ContactModel::predict_on`]),
        /// in the widest SIMD available.
        fn online_update_on(&self, geometry: &ContactGeometry, sample: &Sample, theta: &OnlineParams,
            rule: DescentRule) -> (Prediction, [f64; 3], OnlineParams)
            => online_update_portable, online_update_avx2
    }

    #[inline(always)]
    fn online_update_portable<A: MulAdd>(
        &self,
        geometry: &ContactGeometry,
        sample: &Sample,
        theta: &OnlineParams,
        rule: DescentRule,
    ) -> (Prediction, [f64; 3], OnlineParams) {
        let prepared = &self.prepare(geometry, &sample.input);
        let target = &RealSample::<T>::of(sample).target;
        let weights = loss_weights(&self.loss_scale);
        let mut pass = OnlinePass::<T, A>::new(self, prepared);
        descend::<T, A>(&mut pass, target, &weights, theta, rule)
    }
}

impl<T: Real> ContactModel<T> {
    /// The sample's normalised residual and its Jacobian with respect to `θ_online` at `theta`, on
    /// an object of this geometry (see [`linearize`]).
    pub(crate) fn linearize(
        &self,
        geometry: &ContactGeometry,
        sample: &Sample,
        theta: &OnlineParams,
    ) -> Linearization {
        self.linearize_on(geometry, sample, theta)
    }

    crate::simd::dispatch_simd! {
        /// [`ContactModel::linearize`], preparation included (see [`ContactModel::predict_on`]), in
        /// the widest SIMD available.
        fn linearize_on(&self, geometry: &ContactGeometry, sample: &Sample, theta: &OnlineParams)
            -> Linearization
            => linearize_portable, linearize_avx2
    }

    #[inline(always)]
    fn linearize_portable<A: MulAdd>(
        &self,
        geometry: &ContactGeometry,
        sample: &Sample,
        theta: &OnlineParams,
    ) -> Linearization {
        let prepared = &self.prepare(geometry, &sample.input);
        let target = &RealSample::<T>::of(sample).target;
        let mut pass = OnlinePass::<T, A>::new(self, prepared);
        linearize(&mut pass, target, &self.loss_scale, theta)
    }
}

impl<T: Real> ContactModel<T> {
    /// [`ContactModel::linearize`] and [`ContactModel::online_update`] from the same `theta`, with the
    /// sample prepared once and one forward pass at `theta` between them (see
    /// [`linearize_and_descend`]): the same numbers, bit for bit.
    pub(crate) fn linearize_and_update(
        &self,
        geometry: &ContactGeometry,
        sample: &Sample,
        theta: &OnlineParams,
        steps: usize,
        lr: f64,
    ) -> (Linearization, (Prediction, [f64; 3], OnlineParams)) {
        let rule = self.descent_rule(geometry, steps, lr);
        self.linearize_and_update_on(geometry, sample, theta, rule)
    }

    crate::simd::dispatch_simd! {
        /// [`ContactModel::linearize_and_update`], preparation included (see
        /// [`ContactModel::predict_on`]), in the widest SIMD available.
        fn linearize_and_update_on(&self, geometry: &ContactGeometry, sample: &Sample,
            theta: &OnlineParams, rule: DescentRule)
            -> (Linearization, (Prediction, [f64; 3], OnlineParams))
            => linearize_and_update_portable, linearize_and_update_avx2
    }

    #[inline(always)]
    fn linearize_and_update_portable<A: MulAdd>(
        &self,
        geometry: &ContactGeometry,
        sample: &Sample,
        theta: &OnlineParams,
        rule: DescentRule,
    ) -> (Linearization, (Prediction, [f64; 3], OnlineParams)) {
        let prepared = &self.prepare(geometry, &sample.input);
        let target = &RealSample::<T>::of(sample).target;
        let mut pass = OnlinePass::<T, A>::new(self, prepared);
        linearize_and_descend::<T, A>(&mut pass, target, &self.loss_scale, theta, rule)
    }
}

/// One prepared sample of the contact-frame model, as the shared online step sees it: the network
/// through its affine piece around the last input it ran at ([`AffinePiece`]), taken again only
/// where a step leaves it.
struct OnlinePass<'a, T: Real, A> {
    model: &'a ContactModel<T>,
    prepared: &'a Prepared<T>,
    outer: OuterPass<T>,
    piece: Option<AffinePiece<T>>,
    /// How many pieces were taken: the tests' check that a step left one.
    #[cfg(test)]
    pieces_taken: usize,
    multiply_add: std::marker::PhantomData<A>,
}

impl<'a, T: Real, A: MulAdd> OnlinePass<'a, T, A> {
    /// A pass over one prepared sample, nothing computed yet.
    #[inline(always)]
    fn new(model: &'a ContactModel<T>, prepared: &'a Prepared<T>) -> Self {
        Self {
            model,
            prepared,
            outer: OuterPass::default(),
            piece: None,
            #[cfg(test)]
            pieces_taken: 0,
            multiply_add: std::marker::PhantomData,
        }
    }

    /// The network's outputs at `input`: on the current piece if `input` is on it, else from a
    /// piece taken there.
    #[inline(always)]
    fn network_output(&mut self, input: &[T; CONTACT_INPUTS]) -> [T; OUTPUTS] {
        let position = [input[0], input[1]];
        if let Some(z) = self.piece.as_ref().and_then(|p| p.output_at::<A>(position)) {
            return z;
        }
        let piece = self
            .model
            .network
            .piece_at::<A>(&self.prepared.context_part, input);
        let z = piece.output();
        self.piece = Some(piece);
        #[cfg(test)]
        {
            self.pieces_taken += 1;
        }
        z
    }
}

impl<T: Real, A: MulAdd> ThetaPass<T> for OnlinePass<'_, T, A> {
    #[inline(always)]
    fn forward(&mut self, theta: &[T; 3]) -> [T; 3] {
        let model = self.model;
        let input = model.network_input::<A>(self.prepared, theta, &mut self.outer);
        let z = if model.options.network {
            self.network_output(&input)
        } else {
            [T::zero(); OUTPUTS]
        };
        model.forward_outer::<A>(self.prepared, theta, z, &mut self.outer)
    }

    #[inline(always)]
    fn backward(&mut self, theta: &[T; 3], d_output: [T; 3]) -> [T; 3] {
        let model = self.model;
        let gradient = model.backward_outer::<A>(self.prepared, &self.outer, theta, d_output);
        let d_x = match (&self.piece, model.options.network) {
            (Some(piece), true) => piece.position_gradient::<A>(&gradient.d_z),
            _ => [T::zero(); 2],
        };
        model.theta_gradient::<A>(self.prepared, &self.outer, theta, d_x, &gradient)
    }

    #[inline(always)]
    fn prediction(&self, theta: &[T; 3]) -> Prediction {
        self.outer.tail.prediction(theta)
    }
}

#[cfg(test)]
mod tests {
    use super::super::Pass;
    use super::super::tests::{model_f64, sample, square};
    use super::*;
    use crate::simd::Unfused;

    /// The online step's pass as it was before the affine piece: the whole network forward and back
    /// at every step.
    struct FullPass<'a> {
        model: &'a ContactModel<f64>,
        prepared: &'a Prepared<f64>,
        pass: Pass<f64>,
    }

    impl ThetaPass<f64> for FullPass<'_> {
        fn forward(&mut self, theta: &[f64; 3]) -> [f64; 3] {
            self.model
                .forward::<Unfused>(self.prepared, theta, &mut self.pass)
        }

        fn backward(&mut self, theta: &[f64; 3], d_output: [f64; 3]) -> [f64; 3] {
            self.model
                .backward::<Unfused>(self.prepared, &self.pass, theta, d_output, None)
        }

        fn prediction(&self, theta: &[f64; 3]) -> Prediction {
            self.pass.outer.tail.prediction(theta)
        }
    }

    #[test]
    fn the_online_step_through_the_networks_piece_is_the_step_through_the_whole_network() {
        let geometry = square();
        let s = sample();
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-10 * a.abs().max(b.abs()).max(1e-6);
        for seed in [1, 2, 3] {
            let model = model_f64(seed);
            let prepared = model.prepare(&geometry, &s.input);
            let target = RealSample::<f64>::of(&s).target;
            let weights = loss_weights(&model.loss_scale);
            // A small learning rate stays on one piece; a large one crosses kinks of the network.
            let mut pieces = Vec::new();
            for lr in [0.005, 0.5] {
                let theta = OnlineParams {
                    com_offset: [0.012, -0.018],
                    h: 0.07,
                };
                let rule = model.descent_rule(&geometry, 5, lr);
                let mut piece = OnlinePass::<f64, Unfused>::new(&model, &prepared);
                let (prediction, gradient, after) =
                    descend::<f64, Unfused>(&mut piece, &target, &weights, &theta, rule);
                let mut full = FullPass {
                    model: &model,
                    prepared: &prepared,
                    pass: Pass::default(),
                };
                let expected = descend::<f64, Unfused>(&mut full, &target, &weights, &theta, rule);
                assert_eq!(prediction, expected.0, "seed {seed}: the prediction at θ");
                let (learned, reference) = (after.to_array(), expected.2.to_array());
                for k in 0..3 {
                    assert!(
                        close(gradient[k], expected.1[k]),
                        "seed {seed}, lr {lr}, ∂ℓ/∂θ[{k}]: {} against {}",
                        gradient[k],
                        expected.1[k]
                    );
                    assert!(
                        close(learned[k], reference[k]),
                        "seed {seed}, lr {lr}, θ[{k}] after: {} against {}",
                        learned[k],
                        reference[k]
                    );
                }
                assert_ne!(after, theta, "seed {seed}, lr {lr}: the step must learn");
                pieces.push(piece.pieces_taken);
            }
            assert!(
                pieces[1] > 1,
                "seed {seed}: lr 0.5 stayed on one piece ({pieces:?})"
            );
        }
    }
}
