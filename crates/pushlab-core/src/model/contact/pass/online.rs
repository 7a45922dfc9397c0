//! The contact-frame model's online step, linearisation and both together, each from one prepared
//! sample through the shared kernel (`model::kernel`) in the widest SIMD available.

use super::{Pass, Prepared};
use crate::model::contact::ContactModel;
use crate::model::contact::frame::ContactGeometry;
use crate::model::kernel::{
    DescentRule, Linearization, RealSample, ThetaPass, descend, linearize, linearize_and_descend,
    loss_weights,
};
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

/// One prepared sample of the contact-frame model, as the shared online step sees it.
struct OnlinePass<'a, T: Real, A> {
    model: &'a ContactModel<T>,
    prepared: &'a Prepared<T>,
    pass: Pass<T>,
    multiply_add: std::marker::PhantomData<A>,
}

impl<'a, T: Real, A> OnlinePass<'a, T, A> {
    /// A pass over one prepared sample, nothing computed yet.
    #[inline(always)]
    fn new(model: &'a ContactModel<T>, prepared: &'a Prepared<T>) -> Self {
        Self {
            model,
            prepared,
            pass: Pass::default(),
            multiply_add: std::marker::PhantomData,
        }
    }
}

impl<T: Real, A: MulAdd> ThetaPass<T> for OnlinePass<'_, T, A> {
    #[inline(always)]
    fn forward(&mut self, theta: &[T; 3]) -> [T; 3] {
        self.model
            .forward::<A>(self.prepared, theta, &mut self.pass)
    }

    #[inline(always)]
    fn backward(&mut self, theta: &[T; 3], d_output: [T; 3]) -> [T; 3] {
        self.model
            .backward::<A>(self.prepared, &self.pass, theta, d_output, None)
    }

    #[inline(always)]
    fn backward_many<const N: usize>(
        &mut self,
        theta: &[T; 3],
        d_outputs: [[T; 3]; N],
    ) -> [[T; 3]; N] {
        self.model
            .backward_many::<A, N>(self.prepared, &self.pass, theta, d_outputs)
    }

    #[inline(always)]
    fn prediction(&self, theta: &[T; 3]) -> Prediction {
        self.pass.outer.tail.prediction(theta)
    }
}
