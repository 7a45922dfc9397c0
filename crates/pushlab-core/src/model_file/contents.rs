//! What a model file holds, in memory: the trained combined model, its pure-network baseline and
//! where they came from. `validate` checks it and the parent module reads and writes it; both name
//! it here, below them.

use serde::{Deserialize, Serialize};

use crate::domain::Domain;
use crate::learn::TrainingReport;
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
