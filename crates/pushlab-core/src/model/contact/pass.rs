//! The contact-frame model's forward and backward pass on one sample (its online step on them:
//! `online.rs`).
//!
//! The chain, with `R = [n, t]` the contact frame (inward normal, tangent) and `θ = (o, h)`:
//! `g = Rᵀ(q − o)`, `x = clamp(g / h, context)`, `z = φ(x)`,
//! `c = R (g + h z₀₁)`, `u_c = R (cone(g, sweep(m), h, μ) + |m| z₂₃)`, then Lynch and eq. 15.

use nalgebra::{Point2, Vector2};

use super::frame::ContactGeometry;
use super::prior::{ConePass, cone_backward, cone_forward, swept_motion};
use super::{CONTACT_INPUTS, ContactModel};
use crate::model::mlp::{Activations, HIDDEN, OUTPUTS};
use crate::model::params::OnlineParams;
use crate::model::tail::TailPass;
use crate::model::{Prediction, SampleInput};
use crate::real::Real;
use crate::simd::{MulAdd, Unfused};

/// Everything about one sample on one object that does not depend on `θ_online`: the contact frame,
/// the context inputs and their share of the first layer, the swept motion.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Prepared<T> {
    /// The frame's axes in the object frame: inward normal and tangent.
    normal: [T; 2],
    tangent: [T; 2],
    /// The contact point `q` in frame coordinates (`g = q_frame − Rᵀ o`).
    point: [T; 2],
    /// The network's input with the context (inputs 2…5) filled in and clamped.
    input: [T; CONTACT_INPUTS],
    context_part: [T; HIDDEN],
    /// The prior's swept pushing motion, frame coordinates.
    swept: [T; 2],
    /// The pusher's motion, frame coordinates.
    motion: [T; 2],
    /// Length of the pusher's motion, metres.
    motion_length: T,
}

impl<T: Real> Default for Pass<T> {
    fn default() -> Self {
        Self {
            activations: Activations::default(),
            outer: OuterPass::default(),
        }
    }
}

/// The contact frame of one sample and the pusher's offset and motion in it: the part of preparing a
/// sample that searches the outline, which training computes once per sample for its statistics,
/// clamp range and prepared samples.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Features {
    frame: super::frame::ContactFrame,
    /// The contact point `q`, frame coordinates.
    point: [f64; 2],
    /// The pusher's offset from `q`, frame coordinates.
    offset: [f64; 2],
    /// The pusher's motion, frame coordinates, and its length.
    motion: [f64; 2],
    length: f64,
}

impl Features {
    #[inline(always)]
    pub(crate) fn of(geometry: &ContactGeometry, input: &SampleInput) -> Self {
        let pusher = Point2::from(input.robot_in_object);
        let motion = Vector2::from(input.robot_motion_in_object);
        let frame = geometry.frame(pusher, motion);
        let m = frame.in_frame(motion);
        Self {
            point: frame.in_frame(frame.point.coords),
            offset: frame.in_frame(pusher - frame.point),
            motion: m,
            length: (m[0] * m[0] + m[1] * m[1] + 1e-12).sqrt(),
            frame,
        }
    }

    /// Distance from the pusher's rim to the outline (negative when they overlap), metres.
    pub(crate) fn gap(&self) -> f64 {
        self.frame.gap
    }

    /// Inputs 2…5: the gap and the tangential offset per motion length, the motion's direction.
    #[inline(always)]
    fn context(&self, motion_floor: f64) -> [f64; 4] {
        let per_motion = 1.0 / (self.length + motion_floor);
        [
            self.frame.gap * per_motion,
            self.offset[1] * per_motion,
            self.motion[0] / self.length,
            self.motion[1] / self.length,
        ]
    }
}

/// What the forward pass keeps for the backward pass.
#[derive(Clone, Debug)]
pub(crate) struct Pass<T> {
    activations: Activations<T, CONTACT_INPUTS>,
    pub outer: OuterPass<T>,
}

/// What one sample's pass keeps outside the network — the lever and the clamp before it, the prior
/// and the tail after it — apart from the network's activations, so that a batch pass can keep one
/// per sample around one layer-by-layer network pass (`batch.rs`).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct OuterPass<T> {
    cone: ConePass<T>,
    pub tail: TailPass<T>,
    /// `g`, frame coordinates.
    lever: [T; 2],
    /// The network's outputs.
    z: [T; OUTPUTS],
    /// Whether `g / h` was inside the clamp range, per component.
    unclamped: [bool; 2],
}

#[cfg(test)]
impl<T> OuterPass<T> {
    /// Whether the last forward pass slid (for tests that must exercise the sliding branch).
    pub fn sliding_for_tests(&self) -> bool {
        self.cone.sliding_for_tests()
    }

    /// Whether the last forward pass's lever was inside the clamp range, per component.
    pub fn unclamped_for_tests(&self) -> [bool; 2] {
        self.unclamped
    }
}

/// The backward pass from the prediction to the network's outputs, and what the rest of the
/// backward pass to `θ_online` needs besides the network's input gradient.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct OuterGradient<T> {
    /// With respect to the network's outputs.
    pub d_z: [T; OUTPUTS],
    /// With respect to the prior's `μ`.
    pub d_friction: T,
    /// With respect to the lever `g` and `h`, through the contact point and the prior.
    d_lever: [T; 2],
    d_h: T,
    /// With respect to the COM offset through eq. 15.
    d_com_offset: [T; 2],
}

impl<T: Real> ContactModel<T> {
    /// The network's inputs for a sample on an object before clamping, with `θ_online` at the
    /// object's `θ_online(0)` (the COM at the centre, so `g = q`): what the clamp range is taken from.
    pub(crate) fn raw_inputs(
        f: &Features,
        geometry: &ContactGeometry,
        motion_floor: f64,
    ) -> [f64; CONTACT_INPUTS] {
        let context = f.context(motion_floor);
        let h0 = OnlineParams {
            com_offset: [0.0, 0.0],
            h: geometry.uniform_h(),
        }
        .clamped()
        .h;
        [
            f.point[0] / h0,
            f.point[1] / h0,
            context[0],
            context[1],
            context[2],
            context[3],
        ]
    }

    /// The part of a pass that does not depend on `θ_online`.
    #[inline(always)]
    pub(crate) fn prepare(&self, geometry: &ContactGeometry, input: &SampleInput) -> Prepared<T> {
        self.prepare_features(&Features::of(geometry, input))
    }

    /// [`ContactModel::prepare`] from the sample's [`Features`].
    #[inline(always)]
    pub(crate) fn prepare_features(&self, f: &Features) -> Prepared<T> {
        let mut x = [T::zero(); CONTACT_INPUTS];
        for (j, value) in f.context(self.inputs.motion_floor).into_iter().enumerate() {
            let k = j + 2;
            x[k] = T::of(value.clamp(self.inputs.low[k], self.inputs.high[k]));
        }
        let swept = swept_motion(f.motion, f.frame.gap, self.contact_tolerance);
        let t = |v: [f64; 2]| v.map(T::of);
        Prepared {
            normal: t([f.frame.normal_in.x, f.frame.normal_in.y]),
            tangent: t([f.frame.tangent.x, f.frame.tangent.y]),
            point: t(f.point),
            input: x,
            context_part: self.network.first_layer_context::<Unfused>(&x),
            swept: t(swept),
            motion: t(f.motion),
            motion_length: T::of(f.length),
        }
    }

    /// `prepared` with the first layer's share of its context recomputed from the current weights,
    /// as training's batch pass computes it: the single-sample reference of its tests.
    #[cfg(test)]
    pub(crate) fn with_context(&self, prepared: &Prepared<T>) -> Prepared<T> {
        Prepared {
            context_part: self.network.first_layer_context::<Unfused>(&prepared.input),
            ..*prepared
        }
    }

    /// The forward pass at `theta = [o_x, o_y, h]`: the predicted `[Δp_x, Δp_y, Δω]`.
    #[inline(always)]
    pub(crate) fn forward<A: MulAdd>(
        &self,
        prepared: &Prepared<T>,
        theta: &[T; 3],
        pass: &mut Pass<T>,
    ) -> [T; 3] {
        let x = self.network_input::<A>(prepared, theta, &mut pass.outer);
        let z = if self.options.network {
            self.network
                .forward_from::<A>(&prepared.context_part, &x, &mut pass.activations)
        } else {
            [T::zero(); OUTPUTS]
        };
        self.forward_outer::<A>(prepared, theta, z, &mut pass.outer)
    }

    /// The forward pass up to the network: its input at `theta`, the lever and the clamp kept in
    /// `outer`.
    #[inline(always)]
    pub(crate) fn network_input<A: MulAdd>(
        &self,
        prepared: &Prepared<T>,
        theta: &[T; 3],
        outer: &mut OuterPass<T>,
    ) -> [T; CONTACT_INPUTS] {
        let p = prepared;
        let inv_h = T::one() / theta[2];
        let (n, t) = (p.normal, p.tangent);
        let offset_in_frame = [
            A::mul_add(n[0], theta[0], n[1] * theta[1]),
            A::mul_add(t[0], theta[0], t[1] * theta[1]),
        ];
        let g = [
            p.point[0] - offset_in_frame[0],
            p.point[1] - offset_in_frame[1],
        ];
        outer.lever = g;
        let mut x = p.input;
        for k in 0..2 {
            let raw = g[k] * inv_h;
            let (low, high) = (self.constants.low[k], self.constants.high[k]);
            outer.unclamped[k] = raw >= low && raw <= high;
            x[k] = raw.max(low).min(high);
        }
        x
    }

    /// The forward pass from the network's outputs `z` (zero without the network) to the predicted
    /// `[Δp_x, Δp_y, Δω]`: the prior, the contact point and motion, Lynch and eq. 15.
    #[inline(always)]
    pub(crate) fn forward_outer<A: MulAdd>(
        &self,
        prepared: &Prepared<T>,
        theta: &[T; 3],
        z: [T; OUTPUTS],
        outer: &mut OuterPass<T>,
    ) -> [T; 3] {
        let p = prepared;
        let h = theta[2];
        let (n, t) = (p.normal, p.tangent);
        let g = outer.lever;
        outer.z = z;
        let prior = if self.options.prior {
            cone_forward(g, p.swept, h, self.constants.friction, &mut outer.cone)
        } else {
            outer.cone = ConePass::default();
            p.motion
        };
        let contact_f = [A::mul_add(h, z[0], g[0]), A::mul_add(h, z[1], g[1])];
        let motion_f = [
            A::mul_add(p.motion_length, z[2], prior[0]),
            A::mul_add(p.motion_length, z[3], prior[1]),
        ];
        let to_object = |v: [T; 2]| {
            [
                A::mul_add(n[0], v[0], t[0] * v[1]),
                A::mul_add(n[1], v[0], t[1] * v[1]),
            ]
        };
        outer
            .tail
            .forward::<A>(to_object(contact_f), to_object(motion_f), theta);
        outer.tail.output()
    }

    /// The backward pass: the gradient with respect to `θ_online` of a scalar whose gradient with
    /// respect to the predicted `[Δp_x, Δp_y, Δω]` is `d_output`; with `weights`, also the gradient
    /// with respect to the network's weights and to `μ`, added to them. The single-sample reference
    /// of the tests: training takes its batch pass (`batch.rs`), online learning the network's affine
    /// piece (`pass/online.rs`).
    #[cfg(test)]
    pub(crate) fn backward<A: MulAdd>(
        &self,
        prepared: &Prepared<T>,
        pass: &Pass<T>,
        theta: &[T; 3],
        d_output: [T; 3],
        weights: Option<(&mut crate::model::mlp::Mlp<T, CONTACT_INPUTS>, &mut T)>,
    ) -> [T; 3] {
        let outer = self.backward_outer::<A>(prepared, &pass.outer, theta, d_output);
        let grad = weights.map(|(grad, d_friction)| {
            *d_friction = *d_friction + outer.d_friction;
            grad
        });
        let d_x = if self.options.network {
            self.network
                .position_and_weight_gradient::<A>(&pass.activations, &outer.d_z, grad)
        } else {
            [T::zero(); 2]
        };
        self.theta_gradient::<A>(prepared, &pass.outer, theta, d_x, &outer)
    }

    /// The backward pass from the prediction to the network's outputs (see [`OuterGradient`]).
    #[inline(always)]
    pub(crate) fn backward_outer<A: MulAdd>(
        &self,
        prepared: &Prepared<T>,
        outer: &OuterPass<T>,
        theta: &[T; 3],
        d_output: [T; 3],
    ) -> OuterGradient<T> {
        let p = prepared;
        let h = theta[2];
        let (n, t) = (p.normal, p.tangent);
        let d_tail = outer.tail.backward::<A>(theta, d_output);
        let to_frame = |v: [T; 2]| {
            [
                A::mul_add(n[0], v[0], n[1] * v[1]),
                A::mul_add(t[0], v[0], t[1] * v[1]),
            ]
        };
        let d_contact_f = to_frame(d_tail.contact);
        let d_motion_f = to_frame(d_tail.contact_motion);
        let z = outer.z;
        let d_z = [
            h * d_contact_f[0],
            h * d_contact_f[1],
            p.motion_length * d_motion_f[0],
            p.motion_length * d_motion_f[1],
        ];
        let mut d_g = d_contact_f;
        let mut d_h = A::mul_add(d_contact_f[0], z[0], d_contact_f[1] * z[1]) + d_tail.h;
        let d_cone = cone_backward(outer.lever, h, &outer.cone, d_motion_f);
        d_g[0] = d_g[0] + d_cone.contact[0];
        d_g[1] = d_g[1] + d_cone.contact[1];
        d_h = d_h + d_cone.h;
        OuterGradient {
            d_z,
            d_friction: d_cone.friction,
            d_lever: d_g,
            d_h,
            d_com_offset: d_tail.com_offset,
        }
    }

    /// The rest of the backward pass to `θ_online`, from the gradient `d_x` with respect to the
    /// network's position inputs (zero without the network).
    #[inline(always)]
    pub(crate) fn theta_gradient<A: MulAdd>(
        &self,
        prepared: &Prepared<T>,
        outer: &OuterPass<T>,
        theta: &[T; 3],
        d_x: [T; 2],
        gradient: &OuterGradient<T>,
    ) -> [T; 3] {
        let (n, t) = (prepared.normal, prepared.tangent);
        let inv_h = T::one() / theta[2];
        let (mut d_g, mut d_h) = (gradient.d_lever, gradient.d_h);
        // x = g / h inside the clamp range.
        for k in 0..2 {
            if outer.unclamped[k] {
                d_g[k] = A::mul_add(d_x[k], inv_h, d_g[k]);
                d_h = d_h - d_x[k] * outer.lever[k] * inv_h * inv_h;
            }
        }
        // g = q_frame − Rᵀ o, so ∂/∂o = −R d_g.
        let d_offset = gradient.d_com_offset;
        [
            d_offset[0] - A::mul_add(n[0], d_g[0], t[0] * d_g[1]),
            d_offset[1] - A::mul_add(n[1], d_g[0], t[1] * d_g[1]),
            d_h,
        ]
    }

    crate::simd::dispatch_simd! {
        /// A sample prepared and passed forward to a [`Prediction`]. The preparation runs inside the
        /// AVX2 copy too (its arithmetic is unfused, so its bits do not change): it is a third of a
        /// prediction.
        pub(crate) fn predict_on(&self, geometry: &ContactGeometry, input: &SampleInput,
            theta: &[T; 3]) -> Prediction
            => predict_portable, predict_avx2
    }

    #[inline(always)]
    fn predict_portable<A: MulAdd>(
        &self,
        geometry: &ContactGeometry,
        input: &SampleInput,
        theta: &[T; 3],
    ) -> Prediction {
        let prepared = self.prepare(geometry, input);
        let mut pass = Pass::default();
        self.forward::<A>(&prepared, theta, &mut pass);
        pass.outer.tail.prediction(theta)
    }
}

mod online;

#[cfg(test)]
pub(crate) mod tests;
