//! The simulator's tracking noise: the crate's SplitMix64 with Box–Muller normals.
//!
//! Written here rather than taken from a crate so that a seed gives the same sample data on every
//! platform and every future version: the bundled `sample-data/` must be reproducible bit for bit.

use crate::math;

/// The crate's SplitMix64 ([`crate::rng::SplitMix64`]) with a Box–Muller generator that hands out both
/// values of each pair: the sample data's noise stream, kept exactly as it was generated. Its own
/// name, not SplitMix64's: its normals are not the crate generator's (which uses one value of each
/// pair), so the two streams differ for one seed.
#[derive(Clone, Debug)]
pub struct NoiseStream {
    bits: crate::rng::SplitMix64,
    /// The second normal deviate of the last Box–Muller pair, not yet handed out.
    spare_normal: Option<f64>,
}

impl NoiseStream {
    /// A generator from a seed; equal seeds give equal sequences.
    pub fn new(seed: u64) -> Self {
        Self {
            bits: crate::rng::SplitMix64::new(seed),
            spare_normal: None,
        }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.bits.next_u64()
    }

    /// Uniform in [0, 1), with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        self.bits.uniform()
    }

    /// Uniform in [low, high).
    pub fn uniform(&mut self, low: f64, high: f64) -> f64 {
        low + (high - low) * self.next_f64()
    }

    /// A standard normal deviate (Box–Muller, both values of each pair used).
    pub fn normal(&mut self) -> f64 {
        if let Some(z) = self.spare_normal.take() {
            return z;
        }
        // 1 − u lies in (0, 1], so the logarithm is finite.
        let u1 = 1.0 - self.next_f64();
        let u2 = self.next_f64();
        let radius = (-2.0 * math::ln(u1)).sqrt();
        let angle = 2.0 * std::f64::consts::PI * u2;
        self.spare_normal = Some(radius * math::sin(angle));
        radius * math::cos(angle)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_matches_the_reference_sequence() {
        // First outputs of the reference C implementation for seed 1234567.
        let mut rng = NoiseStream::new(1_234_567);
        assert_eq!(rng.next_u64(), 6_457_827_717_110_365_317);
        assert_eq!(rng.next_u64(), 3_203_168_211_198_807_973);
    }

    #[test]
    fn normal_deviates_have_zero_mean_and_unit_variance() {
        let mut rng = NoiseStream::new(42);
        let n = 200_000;
        let samples: Vec<f64> = (0..n).map(|_| rng.normal()).collect();
        let mean = samples.iter().sum::<f64>() / n as f64;
        let var = samples.iter().map(|z| (z - mean).powi(2)).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.01, "mean {mean}");
        assert!((var - 1.0).abs() < 0.01, "variance {var}");
    }

    #[test]
    fn equal_seeds_give_equal_noise() {
        let mut a = NoiseStream::new(9);
        let mut b = NoiseStream::new(9);
        for _ in 0..100 {
            assert_eq!(a.normal().to_bits(), b.normal().to_bits());
        }
    }
}
