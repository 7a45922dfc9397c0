//! The per-sample losses of the paper (eqs. 5–6, 8) and the σ that normalise them: what every model
//! reports for a prediction, so they sit with the models; the metrics over many samples (eq. 7) are
//! `learn::metrics`.

use serde::{Deserialize, Serialize};

use super::normalization::{Stats1, Stats2};
use super::{ObjectMotion, Sample};

/// The standard deviations that normalise the errors, taken from the offline data.
///
/// Each axis of the translation has its own σ, like every output of the network has its own
/// normalisation: for a push along the object's x axis the sideways motion is much smaller than the
/// forward motion, and one pooled σ would let sideways errors vanish from the loss.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LossScale {
    /// σ of `Δp_o` along the object's x and y axes, metres.
    pub sigma_pos: [f64; 2],
    /// σ of `Δω_o`, radians.
    pub sigma_rot: f64,
}

impl LossScale {
    /// The scale of a set of samples (the offline data).
    pub fn from_samples<'a>(samples: impl IntoIterator<Item = &'a Sample> + Clone) -> Self {
        let pos = Stats2::of(samples.clone().into_iter().map(|s| s.target.translation));
        let rot = Stats1::of(samples.into_iter().map(|s| s.target.rotation));
        Self {
            sigma_pos: pos.std,
            sigma_rot: rot.std,
        }
    }
}

/// The per-sample losses of one prediction (eqs. 5–6).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Loss {
    /// `ℓ_pos,x`.
    pub pos_x: f64,
    /// `ℓ_pos,y`.
    pub pos_y: f64,
    /// `ℓ_rot`.
    pub rot: f64,
}

impl Loss {
    /// The losses of `predicted` against `truth`.
    pub fn of(predicted: &ObjectMotion, truth: &ObjectMotion, scale: &LossScale) -> Self {
        let sq = |a: f64, b: f64, s: f64| ((a - b) / s).powi(2);
        Self {
            pos_x: sq(
                predicted.translation[0],
                truth.translation[0],
                scale.sigma_pos[0],
            ),
            pos_y: sq(
                predicted.translation[1],
                truth.translation[1],
                scale.sigma_pos[1],
            ),
            rot: sq(predicted.rotation, truth.rotation, scale.sigma_rot),
        }
    }

    /// The overall loss `ℓ` (eq. 8).
    pub fn total(&self) -> f64 {
        self.pos_x + self.pos_y + self.rot
    }

    /// The positional loss of one sample as NMSE_pos averages it: `(ℓ_pos,x + ℓ_pos,y) / 2` (eq. 7).
    pub fn pos(&self) -> f64 {
        (self.pos_x + self.pos_y) / 2.0
    }
}

/// The losses of one prediction as runs keep them for every frame: `ℓ_pos = (ℓ_pos,x + ℓ_pos,y) / 2`
/// and `ℓ_rot`, exactly the two numbers NMSE averages (eq. 7). The overall loss is
/// `2 ℓ_pos + ℓ_rot`, equal to [`Loss::total`] to the bit (halving and doubling are exact).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FrameLoss {
    pub pos: f64,
    pub rot: f64,
}

impl FrameLoss {
    /// The two numbers of a loss.
    pub fn of(loss: &Loss) -> Self {
        Self {
            pos: loss.pos(),
            rot: loss.rot,
        }
    }

    /// The overall loss `ℓ` (eq. 8).
    pub fn total(&self) -> f64 {
        2.0 * self.pos + self.rot
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loss_is_squared_error_over_sigma_squared() {
        let scale = LossScale {
            sigma_pos: [0.01, 0.002],
            sigma_rot: 0.05,
        };
        let p = ObjectMotion {
            translation: [0.012, 0.001],
            rotation: 0.1,
        };
        let t = ObjectMotion {
            translation: [0.010, 0.0],
            rotation: 0.0,
        };
        let l = Loss::of(&p, &t, &scale);
        assert!((l.pos_x - 0.04).abs() < 1e-12);
        assert!((l.pos_y - 0.25).abs() < 1e-12);
        assert!((l.rot - 4.0).abs() < 1e-12);
        assert!((l.total() - 4.29).abs() < 1e-12);
        assert!((l.pos() - 0.145).abs() < 1e-12);
        let kept = FrameLoss::of(&l);
        assert_eq!((kept.pos, kept.rot), (l.pos(), l.rot));
        assert_eq!(kept.total().to_bits(), l.total().to_bits());
    }
}
