//! What a model file holds, in memory: the trained combined model, its pure-network baseline and
//! where they came from. `validate` checks it and the parent module reads and writes it; both name
//! it here, below them.

use serde::{Deserialize, Serialize};

use crate::domain::Domain;
use crate::learn::{Trained, TrainingReport};
use crate::model::{CombinedModel, PureNnModel};

/// Where a model came from.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TrainingMetadata {
    /// The combined model's training run.
    #[serde(default)]
    pub report: Option<TrainingReport>,
    /// The pure network's training run.
    #[serde(default)]
    pub pure_nn_report: Option<TrainingReport>,
    /// The recordings it was trained on.
    #[serde(default)]
    pub sources: Vec<String>,
    /// The pushlab version that trained it.
    #[serde(default)]
    pub pushlab_version: String,
    /// The objects, pushers, frame rates and speeds it was trained on (`null` in files written before
    /// pushlab recorded it): see [`Domain`].
    #[serde(default)]
    pub domain: Option<Domain>,
}

/// A trained model as saved on disk.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelFile {
    pub combined: CombinedModel,
    pub pure_nn: Option<PureNnModel>,
    pub training: TrainingMetadata,
}

impl ModelFile {
    /// The file of a training run: the combined model, its pure-network baseline if one was trained,
    /// and `metadata` (sources, version, domain: [`crate::experiment::training_metadata`]) with both
    /// runs' reports filled in. `pushlab train`, the app's Train tab and Python's `Model.train` all
    /// save what this makes, so their files say the same things about where a model came from.
    pub fn from_training(
        combined: Trained<CombinedModel>,
        pure_nn: Option<Trained<PureNnModel>>,
        metadata: TrainingMetadata,
    ) -> Self {
        let (pure_nn, pure_nn_report) = match pure_nn {
            Some(t) => (Some(t.model), Some(t.report)),
            None => (None, None),
        };
        Self {
            combined: combined.model,
            pure_nn,
            training: TrainingMetadata {
                report: Some(combined.report),
                pure_nn_report,
                ..metadata
            },
        }
    }
}
