//! The prediction models: the paper's combined model and the two baselines, and what they share —
//! the per-sample loss (`loss`) and what online learning needs of a model (`online`), so that
//! `learn` sits strictly above this module.
//!
//! - [`PaperModel`]: COM correction → MLP → Lynch → motion correction (the paper's model).
//! - [`ContactModel`]: the same structure, with the network seeing the push in a local frame at the
//!   contact and correcting a friction-cone prior (carries over to other faces and objects).
//! - [`CombinedModel`]: a trained model of either [`ModelKind`].
//! - [`PureNnModel`]: the MLP alone (the paper's "Offline NN").
//! - [`PhysicsOnlyModel`]: geometry and Lynch, no network.

mod bounds;
mod combined;
pub mod contact;
pub(crate) mod kernel;
mod loss;
mod misfit;
pub(crate) mod mlp;
pub mod normalization;
mod online;
pub mod paper;
mod params;
mod physics;
mod physics_only;
mod pure_nn;
mod sample;
pub(crate) mod tail;

pub use bounds::PhysicalBounds;
pub use combined::{CombinedModel, ModelKind, NoOutline};
pub use contact::{ContactGeometry, ContactModel};
pub use kernel::Linearization;
pub(crate) use kernel::{RealSample, loss_weights, theta_real};
pub use loss::{FrameLoss, Loss, LossScale};
pub use misfit::ComMisfit;
pub use mlp::{HIDDEN, INPUTS, Mlp, Network, OUTPUTS, PARAMETER_COUNT, parameter_count};
pub use online::{ContactModelOnObject, Descent, OnlineModel, OnlineStep, SharedOnlineModel};
pub use paper::PaperModel;
pub use params::{COM_OFFSET_MAX, H_MAX, H_MIN, OnlineParams};
pub use physics::{
    ComMotion, LynchGradient, centre_motion, centre_motion_backward, lynch, lynch_backward,
};
pub use physics_only::{DEFAULT_CONTACT_TOLERANCE, PhysicsOnlyModel};
pub use pure_nn::{OutputNormalization, PureNnModel};
pub use sample::{
    ObjectMotion, Sample, SampleInput, sample_at, sample_count, sample_is_skipped,
    samples_from_trajectory, samples_kept,
};

use serde::{Deserialize, Serialize};

/// What a model predicts for one sample, with the intermediate quantities a user may want to see.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Prediction {
    /// The predicted motion of the object's geometric centre and its rotation.
    pub motion: ObjectMotion,
    /// The contact point `c`, object frame, relative to the geometric centre (the model computes it
    /// relative to the estimated COM; it is shifted back for drawing). `None` for models without one.
    pub contact: Option<[f64; 2]>,
    /// The contact motion `u_c`, object frame. `None` for models without one.
    pub contact_motion: Option<[f64; 2]>,
}
