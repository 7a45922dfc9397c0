//! The contact-frame combined model: the paper's structure (network → Lynch → eq. 15, `θ_online =
//! (COM offset, h)`), but the network sees the push in a local frame at the outline point the pusher
//! touches or is nearest to, and corrects a physical prior instead of predicting from scratch.
//!
//! Why: the paper's network sees the pusher's absolute position in the object frame, so another face or
//! another object is a region of input space it never saw, and `θ_online` cannot rotate or rescale
//! that input. Here a push on any face of any outline (convex or not) looks the same:
//! - the **frame** ([`frame`]): first axis the inward normal at the nearest outline point `q`, second
//!   the tangent, handedness chosen so that a push and its mirror image coincide;
//! - the network's **inputs**, all dimensionless and clamped to the range seen offline (a network
//!   evaluated outside it extrapolates linearly; clamped, it keeps the nearest behaviour it knows):
//!   `g / h` where `g = q − COM` in the frame (the lever of the push: this is where `θ_online` enters),
//!   the rim's gap to the outline and the pusher's offset along the tangent (non-zero at corners), both
//!   per length of the pusher's motion, and the direction of that motion;
//! - the **prior** ([`prior`]): the pusher's motion swept from the moment it reaches the outline and
//!   clipped to the motion cone of a friction coefficient `μ` learned offline;
//! - the network's **outputs**, mapped back to the object frame: a correction of the contact point
//!   (in units of `h`) and of the contact motion (in units of the pusher's motion);
//! - `θ_online(0)` is per object: COM at the centre, `h` of a uniform pressure over its outline; the
//!   online step sizes are stored per unit of that `h`, so they carry over to other object sizes.

mod batch;
pub mod frame;
mod pass;
pub(crate) mod prior;

use serde::{Deserialize, Serialize};

pub(crate) use self::batch::{BatchPass, TrainingSample};
pub use self::frame::ContactGeometry;
pub(crate) use self::pass::Features;
use super::kernel::theta_real;
use super::mlp::Network;
use super::params::OnlineParams;
use super::{Prediction, SampleInput};
use crate::model::{ComMisfit, LossScale};
use crate::real::Real;

/// Inputs of the contact-frame network: `g_n / h`, `g_t / h`, gap and tangential offset per motion
/// length, and the motion's direction (normal, tangent).
pub const CONTACT_INPUTS: usize = 6;

/// How the contact-frame network's inputs are formed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactInputs {
    /// Each input is clamped into `[low, high]`: the range seen in the offline data.
    pub low: [f64; CONTACT_INPUTS],
    pub high: [f64; CONTACT_INPUTS],
    /// Added to the pusher's motion length before dividing by it, metres: a tenth of the mean motion
    /// length offline, so that a pusher standing still does not blow the gap up.
    pub motion_floor: f64,
}

/// Which parts of the contact-frame model are used: both in the model `train` makes; the others are
/// ablations that measure what each part buys (`pushlab suite` variants `contact-no-prior` and
/// `contact-prior-only`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct ContactOptions {
    /// The network corrects the physical prior (sweep + motion cone); without it, the raw pusher
    /// motion.
    pub prior: bool,
    /// The network is used at all; without it, the prior alone predicts (only `μ` is trained).
    pub network: bool,
}

impl Default for ContactOptions {
    fn default() -> Self {
        Self {
            prior: true,
            network: true,
        }
    }
}

/// The trained contact-frame model. `θ_online` is an argument of every prediction; the object's
/// geometry is too (a [`ContactGeometry`] per recording).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(bound = "", from = "ContactModelData<T>")]
pub struct ContactModel<T: Real = f32> {
    pub(crate) network: Network<T, CONTACT_INPUTS>,
    pub(crate) inputs: ContactInputs,
    /// The prior's friction coefficient `μ` between pusher and object, learned offline.
    pub(crate) friction: f64,
    /// The prior counts the pusher as touching while its rim is within this of the outline, metres:
    /// the 90th percentile of the gap while the object moves in the offline data (tracking noise and
    /// calibration offsets of the outline).
    pub(crate) contact_tolerance: f64,
    pub(crate) loss_scale: LossScale,
    pub(crate) horizon: usize,
    /// Online gradient descent's step scales per metre of the object's `θ_online(0)` `h`.
    pub(crate) relative_theta_scales: [f64; 3],
    /// Which parts are used (every part, unless an ablation).
    #[serde(default)]
    pub(crate) options: ContactOptions,
    /// How far its learned COM lands from the truth on objects it did not train on.
    #[serde(default)]
    pub(crate) com_misfit: ComMisfit,
    #[serde(skip)]
    constants: Constants<T>,
}

#[derive(Deserialize)]
#[serde(bound = "")]
struct ContactModelData<T: Real> {
    network: Network<T, CONTACT_INPUTS>,
    inputs: ContactInputs,
    friction: f64,
    contact_tolerance: f64,
    loss_scale: LossScale,
    horizon: usize,
    relative_theta_scales: [f64; 3],
    #[serde(default)]
    options: ContactOptions,
    #[serde(default)]
    com_misfit: ComMisfit,
}

impl<T: Real> From<ContactModelData<T>> for ContactModel<T> {
    fn from(d: ContactModelData<T>) -> Self {
        Self {
            constants: Constants::of(&d.inputs, d.friction),
            network: d.network,
            inputs: d.inputs,
            friction: d.friction,
            contact_tolerance: d.contact_tolerance,
            loss_scale: d.loss_scale,
            horizon: d.horizon,
            relative_theta_scales: d.relative_theta_scales,
            options: d.options,
            com_misfit: d.com_misfit,
        }
    }
}

/// The clamp range and `μ` in the model's float type.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Constants<T> {
    low: [T; CONTACT_INPUTS],
    high: [T; CONTACT_INPUTS],
    friction: T,
}

impl<T: Real> Constants<T> {
    fn of(inputs: &ContactInputs, friction: f64) -> Self {
        Self {
            low: inputs.low.map(T::of),
            high: inputs.high.map(T::of),
            friction: T::of(friction),
        }
    }
}

impl<T: Real> ContactModel<T> {
    /// A model from its parts (training).
    pub(crate) fn from_parts(
        network: Network<T, CONTACT_INPUTS>,
        inputs: ContactInputs,
        friction: f64,
        contact_tolerance: f64,
        loss_scale: LossScale,
        horizon: usize,
        options: ContactOptions,
    ) -> Self {
        Self {
            options,
            constants: Constants::of(&inputs, friction),
            network,
            inputs,
            friction,
            contact_tolerance,
            loss_scale,
            horizon,
            relative_theta_scales: [1.0; 3],
            com_misfit: ComMisfit::default(),
        }
    }

    /// The prediction horizon in frames the model was trained for.
    pub fn horizon(&self) -> usize {
        self.horizon
    }

    /// The σ of the offline data that normalise the losses.
    pub fn loss_scale(&self) -> LossScale {
        self.loss_scale
    }

    /// The prior's friction coefficient, learned offline.
    pub fn friction(&self) -> f64 {
        self.friction
    }

    /// The prior's contact tolerance, metres.
    pub fn contact_tolerance(&self) -> f64 {
        self.contact_tolerance
    }

    /// Which parts of the model are used.
    pub fn options(&self) -> ContactOptions {
        self.options
    }

    /// How the network's inputs are formed.
    pub fn inputs(&self) -> &ContactInputs {
        &self.inputs
    }

    /// `θ_online(0)` for an object of this geometry: COM at the centre, `h` of a uniform pressure.
    pub fn theta0(&self, geometry: &ContactGeometry) -> OnlineParams {
        OnlineParams {
            com_offset: [0.0, 0.0],
            h: geometry.uniform_h(),
        }
        .clamped()
    }

    /// Online gradient descent's step scales for an object of this geometry, metres.
    pub fn theta_scales(&self, geometry: &ContactGeometry) -> [f64; 3] {
        let h0 = self.theta0(geometry).h;
        self.relative_theta_scales.map(|k| k * h0)
    }

    pub(crate) fn set_friction(&mut self, friction: f64) {
        self.friction = friction;
        self.constants = Constants::of(&self.inputs, friction);
    }

    /// How far its learned COM lands from the truth on objects it did not train on.
    pub fn com_misfit(&self) -> ComMisfit {
        self.com_misfit
    }

    /// The same model in another float type (`f64` for gradient checks).
    pub fn cast<U: Real>(&self) -> ContactModel<U> {
        ContactModel {
            network: self.network.cast(),
            inputs: self.inputs,
            friction: self.friction,
            contact_tolerance: self.contact_tolerance,
            loss_scale: self.loss_scale,
            horizon: self.horizon,
            relative_theta_scales: self.relative_theta_scales,
            options: self.options,
            com_misfit: self.com_misfit,
            constants: Constants::of(&self.inputs, self.friction),
        }
    }

    /// Predicts the object's motion for one input on an object of this geometry with `θ_online`.
    pub fn predict(
        &self,
        geometry: &ContactGeometry,
        input: &SampleInput,
        theta: &OnlineParams,
    ) -> Prediction {
        self.predict_on(geometry, input, &theta_real(theta))
    }
}
