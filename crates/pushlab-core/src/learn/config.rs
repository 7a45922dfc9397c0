//! The rule online learning follows: the paper's gradient descent (steps and learning rate, eq. 13)
//! or one Gauss–Newton step per frame. Saved with the app's settings and in reports.

use serde::{Deserialize, Serialize};

use crate::model::Descent;

/// How online learning updates `θ_online` after each observed step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct OnlineConfig {
    /// Gradient-descent steps per observed step (the paper: 5). Zero gives the "fixed" model.
    pub steps: usize,
    /// Learning rate on `θ_online` divided component-wise by the model's scales (the paper: 0.005).
    pub lr: f64,
    /// Gradient descent (the paper's) or Gauss–Newton (`learn::step`).
    #[serde(default)]
    pub optimizer: Optimizer,
}

impl Default for OnlineConfig {
    fn default() -> Self {
        Self {
            steps: 5,
            lr: 0.005,
            optimizer: Optimizer::Gd,
        }
    }
}

impl OnlineConfig {
    /// Its gradient-descent part, as the models take it (Gauss–Newton does not use it).
    pub fn descent(&self) -> Descent {
        Descent {
            steps: self.steps,
            lr: self.lr,
        }
    }

    /// The "fixed" model of the paper's figures: predicts, never updates.
    pub fn fixed() -> Self {
        Self {
            steps: 0,
            lr: 0.0,
            optimizer: Optimizer::Gd,
        }
    }
}

/// How online learning updates `θ_online` from each observed frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Optimizer {
    /// The paper's: `steps` gradient-descent steps with learning rate `lr` on this frame's loss.
    #[default]
    Gd,
    /// One Gauss–Newton step weighing this frame against the information of every frame before
    /// (`steps` and `lr` are not used).
    GaussNewton,
}

impl Optimizer {
    /// Both, the paper's first.
    pub const ALL: [Optimizer; 2] = [Optimizer::Gd, Optimizer::GaussNewton];

    /// The name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Optimizer::Gd => "gd",
            Optimizer::GaussNewton => "gauss-newton",
        }
    }

    /// The optimiser called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|o| o.name() == name)
    }
}
