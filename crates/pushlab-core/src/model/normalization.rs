//! Zero-mean, unit-variance scaling of the network's inputs and outputs (paper, Sec. IV).

use serde::{Deserialize, Serialize};

/// Mean and standard deviation of a planar quantity, per component.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stats2 {
    pub mean: [f64; 2],
    pub std: [f64; 2],
}

/// Mean and standard deviation of a scalar quantity.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stats1 {
    pub mean: f64,
    pub std: f64,
}

impl Stats2 {
    /// Statistics of a set of planar values. A component that barely varies gets a standard deviation
    /// floored at a thousandth of the other's (and at 1e-12), so that normalising never divides by zero
    /// nor blows measurement noise up into the network's range.
    pub fn of(values: impl IntoIterator<Item = [f64; 2]>) -> Self {
        let (mut n, mut sum, mut sq) = (0usize, [0.0; 2], [0.0; 2]);
        let values: Vec<[f64; 2]> = values.into_iter().collect();
        for v in &values {
            n += 1;
            sum[0] += v[0];
            sum[1] += v[1];
        }
        if n == 0 {
            return Self {
                mean: [0.0; 2],
                std: [1.0; 2],
            };
        }
        let mean = [sum[0] / n as f64, sum[1] / n as f64];
        for v in &values {
            sq[0] += (v[0] - mean[0]).powi(2);
            sq[1] += (v[1] - mean[1]).powi(2);
        }
        let std = [(sq[0] / n as f64).sqrt(), (sq[1] / n as f64).sqrt()];
        let floor = (1e-3 * std[0].max(std[1])).max(1e-12);
        Self {
            mean,
            std: [std[0].max(floor), std[1].max(floor)],
        }
    }

    /// The root-mean-square of the two standard deviations: one length for both axes.
    pub fn scale(&self) -> f64 {
        ((self.std[0].powi(2) + self.std[1].powi(2)) / 2.0).sqrt()
    }

    /// The same statistics with both axes scaled by [`Stats2::scale`]: a normalisation that keeps
    /// distances, so that a displacement means the same in every direction.
    pub fn isotropic(self) -> Self {
        let scale = self.scale();
        Self {
            mean: self.mean,
            std: [scale, scale],
        }
    }
}

impl Stats1 {
    /// Statistics of a set of scalars; the standard deviation is floored at 1e-12.
    pub fn of(values: impl IntoIterator<Item = f64>) -> Self {
        let values: Vec<f64> = values.into_iter().collect();
        if values.is_empty() {
            return Self {
                mean: 0.0,
                std: 1.0,
            };
        }
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
        Self {
            mean,
            std: var.sqrt().max(1e-12),
        }
    }
}

/// How the network's inputs are scaled, and how the combined model's network outputs are scaled back.
///
/// For the combined model both are isotropic (one scale for x and y, see [`Stats2::isotropic`]). The
/// paper normalises every variable separately, but the COM correction shifts the network's position
/// input by a physical displacement: in pushes on one face the pusher's position along the push barely
/// varies (σ ≈ 1.4 mm against 77 mm across it in the sample data), so per-axis scaling made the network
/// fifty times more sensitive to the COM offset along the push than across it, and online learning
/// oscillated by centimetres instead of converging.
///
/// The combined model's network outputs a contact point (a position relative to the COM, like its
/// input) and a contact motion (a motion, like its input), so its outputs are de-normalised with the
/// input statistics: an untrained network then already predicts contacts near the pusher and contact
/// motions near the pusher motion.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct InputNormalization {
    /// Pusher centre relative to the COM (at `θ_online(0)`), object frame.
    pub position: Stats2,
    /// Pusher motion, object frame.
    pub motion: Stats2,
}
