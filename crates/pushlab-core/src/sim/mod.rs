//! A quasi-static pusher–slider simulator: the source of truth with a known COM offset and `h`.
//!
//! Model (Lynch & Mason): an object of any simple outline (convex or not) slides on a floor with
//! Coulomb friction; its limit surface is the ellipsoid centred at the COM whose torque axis is scaled
//! by `h` = max friction torque / max friction force, computed from a pressure distribution over the
//! footprint's own region ([`pressure`]). A disc pusher follows its commanded path exactly (position
//! control). While it presses on the object, the contact point sticks when the push lies inside the
//! motion cone and slides along the edge on the cone's boundary otherwise ([`contact`]); the object
//! never moves without contact and the pusher never penetrates ([`world`], which also says what
//! happens in a concave corner, where the disc touches two faces). Inertia is ignored: the object
//! stops the instant the pusher stops pressing.
//!
//! The pieces, from small to large: [`contact::pusher_slider_step`] (one step of the physics),
//! [`world::PushWorld`] (contact detection and integration in substeps), [`record::simulate_push`]
//! (sampling at a fixed rate with tracking noise), [`spec::generate_set`] (a whole recording set with
//! its `setting.json`); [`truth`] turns what the contact did per frame into a labels file.

pub mod contact;
pub mod noise;
pub mod path;
pub mod pressure;
pub mod record;
pub mod spec;
pub mod stepper;
pub mod truth;
pub mod world;

pub use contact::{ContactMode, ObjectStep, lynch_sticking, motion_cone, pusher_slider_step};
pub use noise::NoiseStream;
pub use path::{PlanError, PushPlan, PusherPath};
pub use pressure::{PressureDistribution, PressureError, PressureModel, UnknownPressure, lynch_h};
pub use record::{
    FrameContact, Sampling, SamplingError, SimulatedPush, TrackingNoise, simulate_push,
};
pub use spec::{
    GeneratedSet, NoiseSpec, PushSpec, SampleSpec, SetSpec, SpecError, SpecFileError, generate_set,
    push_noise_seed, read_sample_spec,
};
pub use truth::{TRUTH_LABELS_FILE, truth_labels};
pub use world::{PushWorld, SimObject, WorldError};

use crate::geometry::OutlineError;

/// Why a simulation could not run, naming the parameter at fault.
///
/// Each message already contains its cause's, so no variant reports a separate `source()` (which would
/// print the cause twice in an error chain).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    #[error("object outline: {0}")]
    Outline(OutlineError),
    #[error("pressure distribution: {0}")]
    Pressure(PressureError),
    #[error("push {index}: {problem}")]
    Push { index: usize, problem: PlanError },
    #[error("{0}")]
    World(WorldError),
    #[error("sampling: {0}")]
    Sampling(SamplingError),
}

impl From<OutlineError> for SimError {
    fn from(e: OutlineError) -> Self {
        SimError::Outline(e)
    }
}

impl From<PressureError> for SimError {
    fn from(e: PressureError) -> Self {
        SimError::Pressure(e)
    }
}

impl From<WorldError> for SimError {
    fn from(e: WorldError) -> Self {
        SimError::World(e)
    }
}

impl From<SamplingError> for SimError {
    fn from(e: SamplingError) -> Self {
        SimError::Sampling(e)
    }
}
