//! Metrics over many predictions: the paper's NMSE (eq. 7) and the series statistics used to plot and
//! compare losses.

use serde::{Deserialize, Serialize};

use crate::model::normalization::Stats1;
use crate::model::{FrameLoss, Loss};

/// NMSE over a set of samples (eq. 7): positional and rotational.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Nmse {
    pub pos: f64,
    pub rot: f64,
}

impl Nmse {
    /// The mean of per-sample losses; zero for none.
    pub fn of<'a>(losses: impl IntoIterator<Item = &'a Loss>) -> Self {
        Self::of_frames(losses.into_iter().map(FrameLoss::of))
    }

    /// The mean of per-sample losses as runs keep them; the same numbers as [`Nmse::of`] to the bit.
    pub fn of_frames(losses: impl IntoIterator<Item = FrameLoss>) -> Self {
        let (mut n, mut pos, mut rot) = (0usize, 0.0, 0.0);
        for l in losses {
            n += 1;
            pos += l.pos;
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
    use crate::model::{LossScale, ObjectMotion, Sample};

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
