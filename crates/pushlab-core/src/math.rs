//! The functions beyond IEEE 754's exact few that the core computes with, giving the same bits on
//! every target.
//!
//! `f64::sin` and its kin are the platform's: glibc's on Linux, a port of musl's (Rust's
//! compiler-builtins) in a browser's wasm, Apple's on a Mac. Each is within an ulp of the truth,
//! but not the same ulp: a real MIT push learned in the page ended with a COM 8e-10 m from
//! `pushlab eval`'s on the same file, where the sample CSVs, whose poses barely turn, agreed to the
//! bit. Every such call in the core goes through here instead: the `libm` crate's code on every
//! target, so the page, the app and the command line learn the same θ from the same frames.
//! `sqrt`, `mul_add` and `rem_euclid` are exactly rounded by the standard and stay as they are.
//! Clippy refuses the platform's versions in this crate (`clippy.toml`).

use crate::real::Real;

/// Sine of `x` radians.
#[inline]
pub fn sin(x: f64) -> f64 {
    libm::sin(x)
}

/// Cosine of `x` radians.
#[inline]
pub fn cos(x: f64) -> f64 {
    libm::cos(x)
}

/// `(sin x, cos x)` in the model's float ([`Real`]: `f32` or `f64`).
#[inline]
pub fn sin_cos<T: Real>(x: T) -> (T, T) {
    x.sin_cos_everywhere()
}

/// The angle of the vector `(x, y)`, in (−π, π].
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

/// `eˣ`.
#[inline]
pub fn exp(x: f64) -> f64 {
    libm::exp(x)
}

/// The natural logarithm.
#[inline]
pub fn ln(x: f64) -> f64 {
    libm::log(x)
}

/// `xʸ`.
#[inline]
pub fn powf(x: f64, y: f64) -> f64 {
    libm::pow(x, y)
}

/// `√(x² + y²)` without overflow or underflow on the way.
#[inline]
pub fn hypot(x: f64, y: f64) -> f64 {
    libm::hypot(x, y)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Closed forms, and agreement with the platform's own to an ulp or two: these are the same
    /// functions, computed by one known code on every target.
    #[test]
    #[allow(clippy::disallowed_methods)]
    fn agrees_with_closed_forms_and_the_platform() {
        use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
        assert_eq!(sin(0.0), 0.0);
        assert_eq!(cos(0.0), 1.0);
        assert!((sin(FRAC_PI_2) - 1.0).abs() <= f64::EPSILON);
        assert!((atan2(1.0, 1.0) - FRAC_PI_4).abs() <= f64::EPSILON);
        assert_eq!(atan2(0.0, -1.0), PI);
        assert_eq!(exp(0.0), 1.0);
        assert_eq!(ln(1.0), 0.0);
        assert_eq!(powf(2.0, 10.0), 1024.0);
        assert_eq!(hypot(3.0, 4.0), 5.0);
        assert_eq!(hypot(3e300, 4e300), 5e300);
        let (s, c) = sin_cos(0.5_f32);
        assert!(
            (s - 0.5_f32.sin()).abs() <= f32::EPSILON && (c - 0.5_f32.cos()).abs() <= f32::EPSILON
        );
        for k in 0..2000 {
            let x = -20.0 + 0.0201 * f64::from(k);
            let ulp = |a: f64| a.abs().max(1e-300) * f64::EPSILON;
            assert!(
                (sin(x) - x.sin()).abs() <= 2.0 * ulp(x.sin()) + 1e-300,
                "sin {x}"
            );
            assert!(
                (cos(x) - x.cos()).abs() <= 2.0 * ulp(x.cos()) + 1e-300,
                "cos {x}"
            );
            assert!((exp(x) - x.exp()).abs() <= 2.0 * ulp(x.exp()), "exp {x}");
            assert!(
                (atan2(x, 1.5) - x.atan2(1.5)).abs() <= 2.0 * ulp(x.atan2(1.5)),
                "atan2 {x}"
            );
            let (s, c) = sin_cos(x);
            assert_eq!((s, c), (sin(x), cos(x)), "sin_cos {x}");
        }
    }
}
