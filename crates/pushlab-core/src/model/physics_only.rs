//! The physics-only baseline: no network. The contact point comes from the object's outline and the
//! pusher disc, the contact moves with the pusher (`u_c = u_r`, a sticking contact), and Lynch's model
//! with the COM correction does the rest.

use super::params::OnlineParams;
use super::physics::{centre_motion, centre_motion_backward, lynch, lynch_backward};
use super::{ObjectMotion, Prediction, Sample, SampleInput};
use crate::geometry::Outline;
use crate::learn::{Loss, LossScale};

/// Lynch's model on geometric contact: what physics alone predicts.
#[derive(Clone, Debug, PartialEq)]
pub struct PhysicsOnlyModel {
    outline: Outline,
    pusher_radius: f64,
    contact_tolerance: f64,
    loss_scale: LossScale,
}

/// Where and how the pusher touches the object in one sample, object frame.
struct Contact {
    /// Contact point relative to the geometric centre.
    point: [f64; 2],
}

impl PhysicsOnlyModel {
    /// A model for an object of this outline pushed by a disc of this radius. The disc counts as in
    /// contact while its rim is within `contact_tolerance` of the outline (tracking noise keeps a real
    /// pusher from touching exactly). `loss_scale` normalises its losses like the other models'.
    pub fn new(
        outline: Outline,
        pusher_radius: f64,
        contact_tolerance: f64,
        loss_scale: LossScale,
    ) -> Self {
        Self {
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

    /// The σ that normalise the losses.
    pub fn loss_scale(&self) -> LossScale {
        self.loss_scale
    }

    /// The contact, if the disc touches the outline and moves into it.
    fn contact(&self, input: &SampleInput) -> Option<Contact> {
        let boundary = self.outline.disc_contact(
            input.robot_point(),
            self.pusher_radius,
            self.contact_tolerance,
        )?;
        let u = input.robot_motion_in_object;
        let inward = -(boundary.normal.x * u[0] + boundary.normal.y * u[1]);
        (inward > 0.0).then_some(Contact {
            point: [boundary.point.x, boundary.point.y],
        })
    }

    /// Predicts the object's motion for `θ_online`: no motion without contact.
    pub fn predict(&self, input: &SampleInput, theta: &OnlineParams) -> Prediction {
        self.predict_with_gradient(input, theta, None).0
    }

    /// The prediction and, when `target` is given, the loss and its gradient with respect to
    /// `θ_online` (`[com_x, com_y, h]`).
    pub fn predict_with_gradient(
        &self,
        input: &SampleInput,
        theta: &OnlineParams,
        target: Option<&ObjectMotion>,
    ) -> (Prediction, Option<(Loss, [f64; 3])>) {
        let theta = theta.clamped();
        let o = theta.com_offset;
        let Some(contact) = self.contact(input) else {
            let prediction = Prediction {
                motion: ObjectMotion::default(),
                contact: None,
                contact_motion: None,
            };
            let loss =
                target.map(|t| (Loss::of(&prediction.motion, t, &self.loss_scale), [0.0; 3]));
            return (prediction, loss);
        };
        let c = [contact.point[0] - o[0], contact.point[1] - o[1]];
        let u = input.robot_motion_in_object;
        let com = lynch(c, u, theta.h);
        let centre = centre_motion(&com, o);
        let prediction = Prediction {
            motion: ObjectMotion {
                translation: centre,
                rotation: com.rotation,
            },
            contact: Some(contact.point),
            contact_motion: Some(u),
        };
        let gradient = target.map(|t| {
            let loss = Loss::of(&prediction.motion, t, &self.loss_scale);
            let s = &self.loss_scale;
            let d_centre = [
                2.0 * (centre[0] - t.translation[0]) / s.sigma_pos[0].powi(2),
                2.0 * (centre[1] - t.translation[1]) / s.sigma_pos[1].powi(2),
            ];
            let d_rot = 2.0 * (com.rotation - t.rotation) / s.sigma_rot.powi(2);
            let (d_com, mut d_o) = centre_motion_backward(&com, o, d_centre, d_rot);
            let d_lynch = lynch_backward(c, u, theta.h, &d_com);
            // c = contact − o.
            d_o[0] -= d_lynch.contact[0];
            d_o[1] -= d_lynch.contact[1];
            (loss, [d_o[0], d_o[1], d_lynch.h])
        });
        (prediction, gradient)
    }

    /// The loss of one sample and its gradient with respect to `θ_online`.
    pub fn loss_and_gradient(
        &self,
        sample: &Sample,
        theta: &OnlineParams,
    ) -> (Prediction, Loss, [f64; 3]) {
        let (prediction, lg) =
            self.predict_with_gradient(&sample.input, theta, Some(&sample.target));
        let (loss, gradient) = lg.unwrap_or_default();
        (prediction, loss, gradient)
    }
}
