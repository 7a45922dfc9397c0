//! Losses and metrics: the paper's normalised squared errors (eqs. 5–8) and the series statistics used
//! to plot and compare them.

use serde::{Deserialize, Serialize};

use crate::model::normalization::{Stats1, Stats2};
use crate::model::{ObjectMotion, Sample};

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

/// NMSE over a set of samples (eq. 7): positional and rotational.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Nmse {
    pub pos: f64,
    pub rot: f64,
}

impl Nmse {
    /// The mean of per-sample losses; zero for none.
    pub fn of<'a>(losses: impl IntoIterator<Item = &'a Loss>) -> Self {
        let (mut n, mut pos, mut rot) = (0usize, 0.0, 0.0);
        for l in losses {
            n += 1;
            pos += l.pos();
            rot += l.rot;
        }
        if n == 0 {
            Self::default()
        } else {
            Self {
                pos: pos / n as f64,
                rot: rot / n as f64,
            }
        }
    }
}

/// Trailing moving average over `window` values (the paper smooths its curves over 10 steps). The first
/// values average over what is available so far, so the output has the input's length.
pub fn moving_average(series: &[f64], window: usize) -> Vec<f64> {
    let window = window.max(1);
    let mut out = Vec::with_capacity(series.len());
    let mut sum = 0.0;
    for (i, v) in series.iter().enumerate() {
        sum += v;
        if i >= window {
            sum -= series[i - window];
        }
        out.push(sum / (i + 1).min(window) as f64);
    }
    out
}

/// Mean and standard deviation across several series, step by step. Series may differ in length: at
/// each step only the series that reach it count, and the output is as long as the longest series.
pub fn mean_std_across(series: &[Vec<f64>]) -> (Vec<f64>, Vec<f64>) {
    let len = series.iter().map(Vec::len).max().unwrap_or(0);
    let mut mean = Vec::with_capacity(len);
    let mut std = Vec::with_capacity(len);
    for t in 0..len {
        let values: Vec<f64> = series.iter().filter_map(|s| s.get(t).copied()).collect();
        let stats = Stats1::of(values.iter().copied());
        mean.push(stats.mean);
        std.push(if values.len() < 2 { 0.0 } else { stats.std });
    }
    (mean, std)
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
    }

    #[test]
    fn nmse_of_predicting_the_mean_is_one() {
        // Predicting the mean of the data gives NMSE = variance / σ² = 1 on each axis.
        let targets = [(0.01, -0.002, 0.1), (0.03, 0.004, -0.2), (0.02, 0.001, 0.4)];
        let samples: Vec<Sample> = targets
            .iter()
            .enumerate()
            .map(|(i, &(x, y, r))| Sample {
                input: crate::model::SampleInput {
                    robot_in_object: [0.0; 2],
                    robot_motion_in_object: [0.0; 2],
                },
                target: ObjectMotion {
                    translation: [x, y],
                    rotation: r,
                },
                frame: i,
            })
            .collect();
        let scale = LossScale::from_samples(&samples);
        let mean = ObjectMotion {
            translation: [0.02, 0.001],
            rotation: 0.1,
        };
        let losses: Vec<Loss> = samples
            .iter()
            .map(|s| Loss::of(&mean, &s.target, &scale))
            .collect();
        let nmse = Nmse::of(&losses);
        assert!((nmse.pos - 1.0).abs() < 1e-9, "{nmse:?}");
        assert!((nmse.rot - 1.0).abs() < 1e-9, "{nmse:?}");
    }

    #[test]
    fn moving_average_and_band() {
        let ma = moving_average(&[1.0, 2.0, 3.0, 4.0, 5.0], 2);
        assert_eq!(ma, vec![1.0, 1.5, 2.5, 3.5, 4.5]);
        let (mean, std) = mean_std_across(&[vec![1.0, 2.0, 3.0], vec![3.0, 4.0]]);
        assert_eq!(mean, vec![2.0, 3.0, 3.0]);
        assert_eq!(std, vec![1.0, 1.0, 0.0]);
    }
}
