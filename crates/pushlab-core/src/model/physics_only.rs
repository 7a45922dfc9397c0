//! The physics-only baseline: no network. The contact point comes from the object's outline and the
//! pusher disc, the contact moves with the pusher (`u_c = u_r`, a sticking contact), and Lynch's model
//! with the COM correction does the rest.

use super::bounds::PhysicalBounds;
use super::kernel::{DescentRule, Linearization, ThetaPass, descend, linearize, loss_weights};
use super::params::OnlineParams;
use super::tail::TailPass;
use super::{ObjectMotion, Prediction, RealSample, Sample, SampleInput};
use crate::geometry::Outline;
use crate::model::{Loss, LossScale};
use crate::simd::Unfused;

/// How far the pusher's rim may be from the outline and still count as touching it, metres, unless a
/// user says otherwise. Tracked poses are noisy (the sample data: 2 mm, 0.5°, about 3 mm on the gap)
/// and over a prediction horizon of many frames a pusher short of the object reaches it: without
/// contact the physics-only model predicts no motion. One value for the CLI and the app.
pub const DEFAULT_CONTACT_TOLERANCE: f64 = 0.01;

/// Lynch's model on geometric contact: what physics alone predicts.
#[derive(Clone, Debug, PartialEq)]
pub struct PhysicsOnlyModel {
    outline: Outline,
    bounds: PhysicalBounds,
    pusher_radius: f64,
    contact_tolerance: f64,
    loss_scale: LossScale,
}

impl PhysicsOnlyModel {
    /// A model for an object of this outline pushed by a disc of this radius. The disc counts as in
    /// contact while its rim is within `contact_tolerance` of the outline. `loss_scale` normalises its
    /// losses like the other models'.
    pub fn new(
        outline: Outline,
        pusher_radius: f64,
        contact_tolerance: f64,
        loss_scale: LossScale,
    ) -> Self {
        Self {
            bounds: PhysicalBounds::of(&outline),
            outline,
            pusher_radius,
            contact_tolerance,
            loss_scale,
        }
    }

    /// The object's outline.
    pub fn outline(&self) -> &Outline {
        &self.outline
    }

    /// Where `θ_online` can physically be on the object.
    pub fn bounds(&self) -> &PhysicalBounds {
        &self.bounds
    }

    /// The σ that normalise the losses.
    pub fn loss_scale(&self) -> LossScale {
        self.loss_scale
    }

    /// The contact tolerance, metres.
    pub fn contact_tolerance(&self) -> f64 {
        self.contact_tolerance
    }

    /// `θ_online(0)`: the COM at the centre, `h` of a uniform pressure over the outline.
    pub fn theta0(&self) -> OnlineParams {
        OnlineParams::for_outline(&self.outline)
    }

    /// Online gradient descent's step scales: half the object's size for every component.
    pub fn theta_scales(&self) -> [f64; 3] {
        [self.outline.size() / 2.0; 3]
    }

    /// The contact point (relative to the geometric centre), if the disc touches the outline and moves
    /// into it.
    fn contact(&self, input: &SampleInput) -> Option<[f64; 2]> {
        let boundary = self.outline.disc_contact(
            input.robot_point(),
            self.pusher_radius,
            self.contact_tolerance,
        )?;
        let u = input.robot_motion_in_object;
        let inward = -(boundary.normal.x * u[0] + boundary.normal.y * u[1]);
        (inward > 0.0).then_some([boundary.point.x, boundary.point.y])
    }

    /// Predicts the object's motion for `θ_online`: no motion without contact.
    pub fn predict(&self, input: &SampleInput, theta: &OnlineParams) -> Prediction {
        let mut pass = self.pass(input);
        let theta = crate::model::theta_real::<f64>(theta);
        pass.forward(&theta);
        pass.prediction(&theta)
    }

    /// The prediction for `sample`, its loss, and the gradient of the loss with respect to
    /// `θ_online`.
    pub fn loss_and_gradient(
        &self,
        sample: &Sample,
        theta: &OnlineParams,
    ) -> (Prediction, Loss, [f64; 3]) {
        let (prediction, gradient, _) = self.online_update(sample, theta, 0, 0.0);
        let loss = Loss::of(&prediction.motion, &sample.target, &self.loss_scale);
        (prediction, loss, gradient)
    }

    /// One online update (see [`descend`]) with this model's step scales.
    pub(crate) fn online_update(
        &self,
        sample: &Sample,
        theta: &OnlineParams,
        steps: usize,
        lr: f64,
    ) -> (Prediction, [f64; 3], OnlineParams) {
        let real = RealSample::<f64>::of(sample);
        let weights = loss_weights(&self.loss_scale);
        descend::<f64, Unfused>(
            &mut self.pass(&sample.input),
            &real.target,
            &weights,
            theta,
            DescentRule {
                scales: self.theta_scales(),
                steps,
                lr,
            },
        )
    }

    /// The sample's normalised residual and its Jacobian with respect to `θ_online` at `theta`.
    pub(crate) fn linearize(&self, sample: &Sample, theta: &OnlineParams) -> Linearization {
        let real = RealSample::<f64>::of(sample);
        linearize(
            &mut self.pass(&sample.input),
            &real.target,
            &self.loss_scale,
            theta,
        )
    }

    fn pass(&self, input: &SampleInput) -> PhysicsPass {
        PhysicsPass {
            contact: self.contact(input),
            motion: input.robot_motion_in_object,
            tail: TailPass::default(),
        }
    }
}

/// One sample's contact (found once) and the tail's pass.
struct PhysicsPass {
    contact: Option<[f64; 2]>,
    motion: [f64; 2],
    tail: TailPass<f64>,
}

impl ThetaPass<f64> for PhysicsPass {
    fn forward(&mut self, theta: &[f64; 3]) -> [f64; 3] {
        match self.contact {
            Some(point) => {
                let relative = [point[0] - theta[0], point[1] - theta[1]];
                self.tail.forward::<Unfused>(relative, self.motion, theta);
                self.tail.output()
            }
            None => [0.0; 3],
        }
    }

    fn backward(&mut self, theta: &[f64; 3], d_output: [f64; 3]) -> [f64; 3] {
        if self.contact.is_none() {
            return [0.0; 3];
        }
        let d = self.tail.backward::<Unfused>(theta, d_output);
        // The contact point relative to the COM is `point − offset`.
        [
            d.com_offset[0] - d.contact[0],
            d.com_offset[1] - d.contact[1],
            d.h,
        ]
    }

    fn prediction(&self, theta: &[f64; 3]) -> Prediction {
        match self.contact {
            Some(_) => self.tail.prediction(theta),
            None => Prediction {
                motion: ObjectMotion::default(),
                contact: None,
                contact_motion: None,
            },
        }
    }
}
