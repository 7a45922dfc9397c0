//! The floating-point type the model computes in.
//!
//! The model runs in `f32` (half the memory traffic, twice the SIMD lanes: the online step and offline
//! training are dominated by the 16-wide layers) and is checked in `f64` (finite-difference gradient
//! checks need the precision). Everything numeric is generic over [`Real`]; public values are `f64`.

use std::fmt::Debug;

use num_traits::Float;

/// A float the model can compute in: `f32` or `f64`.
pub trait Real: Float + Default + Debug + Send + Sync + 'static {
    /// Converts from `f64` (rounding for `f32`).
    fn of(x: f64) -> Self;
    /// Converts to `f64` (exact).
    fn as_f64(self) -> f64;
    /// `(sin, cos)` with the same bits on every target (`crate::math::sin_cos`).
    fn sin_cos_everywhere(self) -> (Self, Self);
}

impl Real for f32 {
    #[inline(always)]
    fn of(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn as_f64(self) -> f64 {
        f64::from(self)
    }
    #[inline]
    fn sin_cos_everywhere(self) -> (Self, Self) {
        libm::sincosf(self)
    }
}

impl Real for f64 {
    #[inline(always)]
    fn of(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn as_f64(self) -> f64 {
        self
    }
    #[inline]
    fn sin_cos_everywhere(self) -> (Self, Self) {
        libm::sincos(self)
    }
}
