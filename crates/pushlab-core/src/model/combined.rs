//! A trained combined model of either kind, as files, the CLI and the app hold it.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::contact::{ContactGeometry, ContactModel};
use super::loss::LossScale;
use super::misfit::ComMisfit;
use super::online::{ContactModelOnObject, SharedOnlineModel};
use super::paper::PaperModel;

/// Which combined model: the paper's, or the contact-frame model that carries over to other faces,
/// objects and real data.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ModelKind {
    /// The paper's Fig. 4 exactly: the network sees the pusher in the object frame.
    Paper,
    /// The network sees the push in a local frame at the contact and corrects a physical prior.
    #[default]
    Contact,
}

impl ModelKind {
    /// Every kind, the default first.
    pub const ALL: [ModelKind; 2] = [ModelKind::Contact, ModelKind::Paper];

    /// The name used in files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            ModelKind::Paper => "paper",
            ModelKind::Contact => "contact",
        }
    }

    /// The kind of a name, if it is one.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// One line for menus and help.
    pub fn description(self) -> &'static str {
        match self {
            ModelKind::Paper => "the paper's model: pusher position in the object frame",
            ModelKind::Contact => {
                "contact frame: the push seen at the contact, correcting a friction-cone prior"
            }
        }
    }
}

impl std::fmt::Display for ModelKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A trained combined model. Shared (`Arc`), so that every recording's learner can use it.
#[derive(Clone, Debug, PartialEq)]
pub enum CombinedModel {
    Paper(Arc<PaperModel>),
    Contact(Arc<ContactModel>),
}

/// Why a model cannot be bound to a recording's object: the contact-frame model needs the object's
/// outline, and the recording's is unusable.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the contact-frame model needs the object's outline, and this recording's is unusable")]
pub struct NoOutline;

impl CombinedModel {
    /// Its kind.
    pub fn kind(&self) -> ModelKind {
        match self {
            CombinedModel::Paper(_) => ModelKind::Paper,
            CombinedModel::Contact(_) => ModelKind::Contact,
        }
    }

    /// The prediction horizon in frames it was trained for.
    pub fn horizon(&self) -> usize {
        match self {
            CombinedModel::Paper(m) => m.horizon(),
            CombinedModel::Contact(m) => m.horizon(),
        }
    }

    /// How far its learned COM lands from the truth on objects it did not train on.
    pub fn com_misfit(&self) -> ComMisfit {
        match self {
            CombinedModel::Paper(m) => m.com_misfit(),
            CombinedModel::Contact(m) => m.com_misfit(),
        }
    }

    /// The same model calibrated with `misfit` (`experiment::calibrate_com_misfit_in_slices`).
    pub fn with_com_misfit(mut self, misfit: ComMisfit) -> Self {
        match &mut self {
            CombinedModel::Paper(m) => Arc::make_mut(m).com_misfit = misfit,
            CombinedModel::Contact(m) => Arc::make_mut(m).com_misfit = misfit,
        }
        self
    }

    /// The σ of its offline data, which normalise every loss reported next to it.
    pub fn loss_scale(&self) -> LossScale {
        match self {
            CombinedModel::Paper(m) => m.loss_scale(),
            CombinedModel::Contact(m) => m.loss_scale(),
        }
    }

    /// The model bound to an object of this geometry (`None` when the recording's outline is
    /// unusable): its `θ_online(0)`, step scales, predictions and online steps on that object. The
    /// paper's model is the same on every object; the contact-frame model needs the outline.
    pub fn on_object(
        &self,
        geometry: Option<&Arc<ContactGeometry>>,
    ) -> Result<SharedOnlineModel, NoOutline> {
        Ok(match self {
            CombinedModel::Paper(m) => m.clone(),
            CombinedModel::Contact(m) => Arc::new(ContactModelOnObject::new(
                m.clone(),
                geometry.ok_or(NoOutline)?.clone(),
            )),
        })
    }
}
