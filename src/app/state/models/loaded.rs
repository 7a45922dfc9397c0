//! The models the app predicts with: a trained combined model of either kind (from a model file or
//! trained in the app) and the optional pure-network baseline. How each learns on a recording, and the
//! physics-only model beside them, are pushlab-core's rules (`experiment::learner_for`,
//! `experiment::physics_model`), shared with the CLI.

use std::sync::Arc;

use pushlab_core::experiment::{geometry_of, loss_scale_for, physics_model};
use pushlab_core::model::{
    CombinedModel, DEFAULT_CONTACT_TOLERANCE, ModelKind, PhysicsOnlyModel, PureNnModel,
};
use pushlab_core::model_file::TrainingMetadata;
use pushlab_core::recording::Recording;

use pushlab_core::experiment::DEFAULT_HORIZON;
use pushlab_core::model::SharedOnlineModel;

/// The trained models currently in use.
#[derive(Clone, Default)]
pub struct Models {
    /// The combined model online learning runs on; `None` falls back to physics only.
    pub combined: Option<CombinedModel>,
    /// The pure-network baseline, drawn as an optional layer.
    pub pure_nn: Option<Arc<PureNnModel>>,
    /// Where the models came from, for the status bar ("assets/default-model.json", "trained in app").
    pub source: Option<String>,
    /// How the combined model was trained, kept when it is saved again.
    pub training: TrainingMetadata,
}

impl Models {
    /// The prediction horizon in frames: the trained model's, or the physics-only default.
    pub fn horizon(&self) -> usize {
        self.combined
            .as_ref()
            .map_or(DEFAULT_HORIZON, CombinedModel::horizon)
    }

    /// The model online learning uses on `recording` and its horizon in frames.
    ///
    /// Without a trained model, the physics-only model of the recording's outline learns instead, so
    /// that the app still shows and steers something meaningful.
    pub fn learner_for(&self, recording: &Recording) -> Result<(SharedOnlineModel, usize), String> {
        let unusable = |e: &dyn std::fmt::Display| {
            format!(
                "{}: the object outline in setting.json is unusable: {e}",
                recording.source.display()
            )
        };
        if let Some(model) = &self.combined {
            let geometry = geometry_of(&recording.setting);
            let learner = model
                .on_object(geometry.as_ref().ok())
                .map_err(|e| match &geometry {
                    Err(outline) => unusable(outline),
                    Ok(_) => format!("{}: {e}", recording.source.display()),
                })?;
            return Ok((learner, model.horizon()));
        }
        let physics = self.physics_for(recording)?;
        Ok((Arc::new(physics), DEFAULT_HORIZON))
    }

    /// The physics-only model of `recording`, its losses normalised like the combined model's (or,
    /// without one, by the recording's own motion).
    pub fn physics_for(&self, recording: &Recording) -> Result<PhysicsOnlyModel, String> {
        let scale = loss_scale_for(self.combined.as_ref(), recording, self.horizon());
        physics_model(recording, scale, DEFAULT_CONTACT_TOLERANCE).map_err(|e| {
            format!(
                "{}: the object outline in setting.json is unusable: {e}",
                recording.source.display()
            )
        })
    }

    /// The kind of the combined model, if one is loaded.
    pub fn kind(&self) -> Option<ModelKind> {
        self.combined.as_ref().map(CombinedModel::kind)
    }

    /// A short name of the model online learning uses.
    pub fn learner_name(&self) -> String {
        match self.kind() {
            Some(kind) => format!("combined model ({kind})"),
            None => "physics only (no trained model loaded)".to_owned(),
        }
    }
}
