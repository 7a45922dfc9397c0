//! The options `train` and `eval` share, and the parsers of their values.

use clap::Args;
use pushlab_core::model::ModelKind;

/// Options shared by `train` and `eval`.
#[derive(Clone, Debug, Args)]
pub struct TrainingArgs {
    /// Prediction horizon in frames: each sample predicts the motion from frame t to t+K
    /// [default: 1, or the horizon of --model].
    #[arg(long, value_name = "K", value_parser = positive)]
    pub horizon: Option<usize>,
    /// Most epochs of offline training (it stops early when the validation loss stops improving).
    #[arg(long, value_name = "N", default_value_t = 100, value_parser = positive)]
    pub epochs: usize,
    /// Seeds the weights, the validation split and the shuffling: same seed, same model.
    #[arg(long, value_name = "S", default_value_t = 0)]
    pub seed: u64,
    /// Stop after this many epochs without a better validation loss; 0 never stops early.
    #[arg(long, value_name = "N", default_value_t = 15)]
    pub patience: usize,
    /// Adam's learning rate in offline training (the paper: 0.005), as the app's Train tab sets it.
    #[arg(long, value_name = "LR", default_value_t = 0.005, value_parser = positive_real)]
    pub adam_lr: f64,
    /// Take from the given paths only the recordings whose split (in their folder's labels file, or
    /// else in setting.json) matches the role: offline for --data and --offline, online for --online.
    #[arg(long)]
    pub split_from_labels: bool,
    /// Which combined model: `contact` (the push seen in a frame at the contact, correcting a
    /// friction-cone prior; carries over to other faces, objects and real data) or `paper` (the
    /// paper's Fig. 4 exactly) [default: contact, or the kind of --model].
    #[arg(long, value_name = "KIND", value_parser = model_kind)]
    pub model_kind: Option<ModelKind>,
    /// Skip measuring the COM misfit. By default, when the recordings span two or more objects and
    /// know their COM, a model is also trained without each object in turn and learns online on
    /// it: how far its COM lands from the truth widens the COM ellipse of the model saved (one
    /// extra training per object).
    #[arg(long)]
    pub no_com_calibration: bool,
}

/// A model kind by name.
pub fn model_kind(text: &str) -> Result<ModelKind, String> {
    ModelKind::from_name(text.trim()).ok_or_else(|| {
        let names: Vec<&str> = ModelKind::ALL.iter().map(|k| k.name()).collect();
        format!(
            "unknown model kind {text:?}; expected one of {}",
            names.join(", ")
        )
    })
}

/// A whole number of at least 1.
pub fn positive(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        Ok(_) => Err("must be at least 1".into()),
        Err(_) => Err(format!(
            "expected a whole number of at least 1, got {text:?}"
        )),
    }
}

/// An online optimiser by name: `gd` or `gauss-newton`.
pub fn optimizer(text: &str) -> Result<pushlab_core::learn::Optimizer, String> {
    pushlab_core::learn::Optimizer::from_name(text.trim())
        .ok_or_else(|| format!("expected gd or gauss-newton, got {text:?}"))
}

/// An offset in the plane, `X,Y` in metres (e.g. `0.02,-0.01`).
pub fn offset_xy(text: &str) -> Result<[f64; 2], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let [x, y] = parts.as_slice() else {
        return Err(format!(
            "expected X,Y in metres (e.g. 0.02,0), got {text:?}"
        ));
    };
    let number = |t: &str| match t.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!(
            "expected X,Y in metres (e.g. 0.02,0), got {text:?}: {t:?} is not a number"
        )),
    };
    Ok([number(x)?, number(y)?])
}

/// A finite number above 0.
pub fn positive_real(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        Ok(_) => Err(format!("must be a finite number above 0, got {text:?}")),
        Err(_) => Err(format!("expected a number, got {text:?}")),
    }
}

/// A weight from 0 to 1.
pub fn unit_interval(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(x) if (0.0..=1.0).contains(&x) => Ok(x),
        Ok(_) => Err(format!("must be from 0 to 1, got {text:?}")),
        Err(_) => Err(format!("expected a number, got {text:?}")),
    }
}

/// How θ_online learns along a push: `pushlab eval`'s and `pushlab live`'s options, one definition.
#[derive(Debug, Args)]
pub struct OnlineArgs {
    /// Gradient-descent steps on θ_online per online time step (the paper: 5).
    #[arg(long, value_name = "N", default_value_t = 5)]
    pub steps: usize,
    /// Online learning rate on θ_online / s (the paper: 0.005).
    #[arg(long, value_name = "LR", default_value_t = 0.005, value_parser = positive_real)]
    pub lr: f64,
    /// How θ_online learns: `gd` (the paper's gradient descent, --steps and --lr) or `gauss-newton`
    /// (one Gauss–Newton step per frame weighed against the frames before; --steps 0 still fixes θ).
    #[arg(long, value_name = "OPTIMIZER", default_value = "gd", value_parser = optimizer)]
    pub optimizer: pushlab_core::learn::Optimizer,
}

impl OnlineArgs {
    /// The core's rule from the options.
    pub fn config(&self) -> pushlab_core::learn::OnlineConfig {
        pushlab_core::learn::OnlineConfig {
            steps: self.steps,
            lr: self.lr,
            optimizer: self.optimizer,
        }
    }
}
