//! The models the app predicts with: a trained combined model (from a model file or trained in the
//! app), the optional pure-network baseline, and the physics-only model built per recording.

use std::sync::Arc;

use pushlab_core::learn::LossScale;
use pushlab_core::model::{CombinedModel, PhysicsOnlyModel, PureNnModel, samples_from_trajectory};
use pushlab_core::model_file::TrainingMetadata;
use pushlab_core::recording::Recording;

use super::online::SharedModel;

/// How far the pusher's rim may be from the outline and still count as touching it, metres. Tracked
/// positions are noisy at the millimetre level; a real pusher never sits exactly on the outline.
pub const CONTACT_TOLERANCE: f64 = 0.002;

/// Horizon of the physics-only model when there is no trained model to take it from.
pub const DEFAULT_HORIZON: usize = 1;

/// The trained models currently in use.
#[derive(Clone, Default)]
pub struct Models {
    /// The combined model online learning runs on; `None` falls back to physics only.
    pub combined: Option<Arc<CombinedModel>>,
    /// The pure-network baseline, drawn as an optional layer.
    pub pure_nn: Option<Arc<PureNnModel>>,
    /// Where the models came from, for the status bar ("assets/default-model.json", "trained in app").
    pub source: Option<String>,
    /// How the combined model was trained, kept when it is saved again.
    pub training: TrainingMetadata,
}

impl Models {
    /// The model online learning uses on `recording` and its horizon in frames.
    ///
    /// Without a trained model, the physics-only model of the recording's outline learns instead, so
    /// that the app still shows and steers something meaningful.
    pub fn learner_for(&self, recording: &Recording) -> Result<(SharedModel, usize), String> {
        if let Some(model) = &self.combined {
            let horizon = model.horizon();
            return Ok((model.clone(), horizon));
        }
        let physics = physics_only(recording)?;
        Ok((Arc::new(physics), DEFAULT_HORIZON))
    }

    /// A short name of the model online learning uses.
    pub fn learner_name(&self) -> &'static str {
        if self.combined.is_some() {
            "combined model"
        } else {
            "physics only (no trained model loaded)"
        }
    }
}

/// The physics-only model of a recording's object and pusher; its losses are normalised by the
/// recording's own motion statistics.
pub fn physics_only(recording: &Recording) -> Result<PhysicsOnlyModel, String> {
    let outline = recording.setting.object.outline().map_err(|e| {
        format!(
            "{}: the object outline in setting.json is unusable: {e}",
            recording.source.display()
        )
    })?;
    let samples = samples_from_trajectory(&recording.trajectory, DEFAULT_HORIZON);
    let mut scale = LossScale::from_samples(&samples);
    // A recording without motion on an axis would divide by zero; one millimetre / milliradian keeps
    // the loss finite and still comparable.
    for s in &mut scale.sigma_pos {
        *s = s.max(1e-3);
    }
    scale.sigma_rot = scale.sigma_rot.max(1e-3);
    Ok(PhysicsOnlyModel::new(
        outline,
        recording.setting.pusher_radius,
        CONTACT_TOLERANCE,
        scale,
    ))
}
