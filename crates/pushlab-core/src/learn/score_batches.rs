//! How much evidence a push's frames really hold about `θ_online` when their errors are not
//! independent: batch means of the per-frame scores `gₜ(θ) = Jₜᵀ rₜ(θ)`.
//!
//! The frames are cut into consecutive batches; each batch keeps its linearisation sums
//! (`Aᵦ = Σ JᵀJ`, `cᵦ = Σ Jᵀb`), so that its score `Gᵦ(θ) = Aᵦ θ − cᵦ` can be evaluated at the current
//! estimate. If the frames' errors were independent (up to the samples' overlap `k`), each batch
//! score would scatter with covariance `s² k Aᵦ`, and `tr(A⁻¹ Σᵦ (Gᵦ − Ḡ)(Gᵦ − Ḡ)ᵀ) / (B − 1) ≈ 3 s² k`
//! with `A = Σᵦ Aᵦ`. Errors that persist over many frames — a learned model's systematic miss on real
//! contact — make the batch scores scatter far more, and the ratio is the factor by which the
//! frame-by-frame information overstates the evidence (the batch-means estimate of the long-run
//! variance, as in MCMC output analysis and the cluster-robust "sandwich").
//!
//! A fixed number of slots: when all [`SLOTS`] are full, neighbours are merged pairwise and batches
//! become twice as long, so a million-frame run keeps the same few hundred bytes and its batches
//! grow with it. Batches start one horizon long, so that overlapping samples share a batch.

use nalgebra::{Matrix3, Vector3};

/// Batch slots; half of them are full after a merge.
pub const SLOTS: usize = 16;

/// Complete batches needed before their scatter is trusted (fewer: factor 1).
pub const MIN_BATCHES: usize = 4;

/// The largest factor taken as measured.
pub const MAX_FACTOR: f64 = 100.0;

/// The batches' linearisation sums.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScoreBatches {
    /// `Σ JᵀJ` of each batch, its upper triangle: xx, xy, xh, yy, yh, hh.
    jtj: [[f64; 6]; SLOTS],
    /// `Σ Jᵀb` of each batch.
    jtb: [[f64; 3]; SLOTS],
    /// Complete batches; slot `complete` is the one filling.
    complete: usize,
    /// Frames in the filling batch.
    filling: usize,
    /// Frames per batch.
    length: usize,
}

fn upper(m: &Matrix3<f64>) -> [f64; 6] {
    [
        m[(0, 0)],
        m[(0, 1)],
        m[(0, 2)],
        m[(1, 1)],
        m[(1, 2)],
        m[(2, 2)],
    ]
}

fn full(u: &[f64; 6]) -> Matrix3<f64> {
    Matrix3::new(u[0], u[1], u[2], u[1], u[3], u[4], u[2], u[4], u[5])
}

impl ScoreBatches {
    /// No frames yet; batches `horizon` frames long.
    pub fn new(horizon: usize) -> Self {
        Self {
            jtj: [[0.0; 6]; SLOTS],
            jtb: [[0.0; 3]; SLOTS],
            complete: 0,
            filling: 0,
            length: horizon.max(1),
        }
    }

    /// Takes in one frame's `JᵀJ` and `Jᵀb`.
    pub fn push(&mut self, jtj: &Matrix3<f64>, jtb: &Vector3<f64>) {
        let slot = self.complete;
        for (sum, x) in self.jtj[slot].iter_mut().zip(upper(jtj)) {
            *sum += x;
        }
        for (sum, x) in self.jtb[slot].iter_mut().zip(jtb.iter()) {
            *sum += x;
        }
        self.filling += 1;
        if self.filling < self.length {
            return;
        }
        self.filling = 0;
        self.complete += 1;
        if self.complete == SLOTS {
            for i in 0..SLOTS / 2 {
                let (a, b) = (2 * i, 2 * i + 1);
                self.jtj[i] = std::array::from_fn(|k| self.jtj[a][k] + self.jtj[b][k]);
                self.jtb[i] = std::array::from_fn(|k| self.jtb[a][k] + self.jtb[b][k]);
            }
            for i in SLOTS / 2..SLOTS {
                self.jtj[i] = [0.0; 6];
                self.jtb[i] = [0.0; 3];
            }
            self.complete = SLOTS / 2;
            self.length *= 2;
        }
    }

    /// Frames per batch now.
    pub fn batch_length(&self) -> usize {
        self.length
    }

    /// Complete batches.
    pub fn batches(&self) -> usize {
        self.complete
    }

    /// `tr(A⁻¹ S) / 3` with `S` the batch scores' scatter at `theta` (`[com_x, com_y, h]`): the
    /// variance per frame that the batches show, in the units of `s² k`; `None` with fewer than
    /// [`MIN_BATCHES`] complete batches or numbers that are not finite.
    pub fn scatter_per_frame(&self, theta: &Vector3<f64>) -> Option<f64> {
        let n = self.complete;
        if n < MIN_BATCHES {
            return None;
        }
        let scores: Vec<Vector3<f64>> = (0..n)
            .map(|b| full(&self.jtj[b]) * theta - Vector3::from(self.jtb[b]))
            .collect();
        let mean = scores.iter().sum::<Vector3<f64>>() / n as f64;
        let scatter = scores
            .iter()
            .map(|g| (g - mean) * (g - mean).transpose())
            .sum::<Matrix3<f64>>()
            / (n - 1) as f64;
        // The mean batch's JᵀJ: the scatter is that of one batch.
        let a = (0..n).map(|b| full(&self.jtj[b])).sum::<Matrix3<f64>>() / n as f64;
        let value = (a.try_inverse()? * scatter).trace() / 3.0;
        value.is_finite().then_some(value.max(0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(x: f64) -> (Matrix3<f64>, Vector3<f64>) {
        (Matrix3::identity() * x, Vector3::new(x, 2.0 * x, 0.5))
    }

    #[test]
    fn batches_merge_pairwise_when_full_and_keep_every_frame() {
        let mut batches = ScoreBatches::new(2);
        let mut total_jtb = Vector3::zeros();
        for t in 0..100 {
            let (jtj, jtb) = frame(t as f64);
            total_jtb += jtb;
            batches.push(&jtj, &jtb);
        }
        // 2-frame batches fill 16 slots at frame 32 and merge to 8 of 4; 4-frame batches fill 16
        // at frame 64 and merge to 8 of 8; frames 64–95 make 4 more, 96–99 fill the next.
        assert_eq!(batches.batch_length(), 8);
        assert_eq!(batches.batches(), 12);
        let kept: Vector3<f64> = batches.jtb.iter().map(|b| Vector3::from(*b)).sum();
        assert!((kept - total_jtb).norm() < 1e-9);
        // Batch 0 holds frames 0–7.
        assert_eq!(batches.jtj[0][0], (0..8).sum::<i32>() as f64);
    }

    #[test]
    fn too_few_batches_say_nothing() {
        let mut batches = ScoreBatches::new(1);
        for t in 0..3 {
            let (jtj, jtb) = frame(1.0 + t as f64);
            batches.push(&jtj, &jtb);
        }
        assert_eq!(batches.scatter_per_frame(&Vector3::zeros()), None);
    }
}
