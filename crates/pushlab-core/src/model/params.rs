//! `θ_online`: the physical parameters learned online.

use serde::{Deserialize, Serialize};

use crate::geometry::Outline;

/// Smallest `h` the model accepts, metres. Lynch's equations divide by `h²`; below a millimetre the
/// predicted rotation of any real object would be absurd.
pub const H_MIN: f64 = 1e-3;
/// Largest `h` the model accepts, metres: far beyond any tabletop or floor object's size.
pub const H_MAX: f64 = 2.0;

/// Largest magnitude of each COM offset component the model accepts, metres. A COM 2 m from the
/// footprint's centre lies outside any object pushed on a table or floor; without a bound, online
/// learning at a wild learning rate walked it to 10¹⁰ m on real MIT pushes, where the passes overflow
/// single precision and the gradient shown became NaN.
pub const COM_OFFSET_MAX: f64 = 2.0;

/// `θ_online = (COM offset, h)` in physical units.
///
/// The COM offset is `COM − geometric centre` in the object frame (the paper's `v` is its negative).
/// `h` is Lynch's limit-surface parameter (ratio of the maximal friction torque to the maximal friction
/// force), kept in [`H_MIN`, `H_MAX`]; each COM offset component is kept in ±[`COM_OFFSET_MAX`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct OnlineParams {
    /// COM − geometric centre, object frame, metres.
    pub com_offset: [f64; 2],
    /// Lynch's `h`, metres.
    pub h: f64,
}

impl OnlineParams {
    /// Parameters with `h` clamped into [`H_MIN`, `H_MAX`] and each COM offset component into
    /// ±[`COM_OFFSET_MAX`] (a non-finite `h` replaced by `H_MIN`, a non-finite component by 0).
    pub fn clamped(self) -> Self {
        let h = if self.h.is_finite() {
            self.h.clamp(H_MIN, H_MAX)
        } else {
            H_MIN
        };
        // Within the bound (every real θ) the value passes through one comparison.
        let bound = |c: f64| {
            if c.abs() <= COM_OFFSET_MAX {
                c
            } else if c.is_nan() {
                0.0
            } else {
                COM_OFFSET_MAX.copysign(c)
            }
        };
        let com_offset = [bound(self.com_offset[0]), bound(self.com_offset[1])];
        Self { com_offset, h }
    }

    /// `θ` as a user gave it (the Python package's `predict(theta=…)`), checked against what the
    /// model accepts — the ranges [`OnlineParams::clamped`] keeps learning in — with an error naming
    /// the component: a θ outside them would be predicted with silently (`h` = 0 divides by zero),
    /// or clamped to another θ than the one asked for.
    pub fn checked(self) -> Result<Self, String> {
        for (name, c) in ["COM offset x", "COM offset y"]
            .into_iter()
            .zip(self.com_offset)
        {
            if !(c.is_finite() && c.abs() <= COM_OFFSET_MAX) {
                return Err(format!(
                    "{name} must be a finite number of metres within ±{COM_OFFSET_MAX}, got {c}"
                ));
            }
        }
        if !(self.h.is_finite() && (H_MIN..=H_MAX).contains(&self.h)) {
            return Err(format!(
                "h must be a finite number of metres in [{H_MIN}, {H_MAX}], got {}",
                self.h
            ));
        }
        Ok(self)
    }

    /// A physically motivated starting point for an object whose outline is known: the COM at the
    /// geometric centre and `h` of a uniform pressure over the footprint.
    pub fn for_outline(outline: &Outline) -> Self {
        let centroid = outline.centroid();
        Self {
            com_offset: [0.0, 0.0],
            h: outline.uniform_pressure_h(centroid, 200),
        }
        .clamped()
    }

    /// The plausible range of each component `[com_x, com_y, h]` for an object, metres: the COM
    /// within the outline's bounding box (symmetric about the footprint's centre), `h` up to the
    /// object's size; for an object without an outline, ±0.1 m and `h` up to 0.2 m. Sliders, plots and
    /// the loss landscape's grid all span these, so that they show the same part of θ's space.
    pub fn plausible_ranges(outline: Option<&Outline>) -> [(f64, f64); 3] {
        let (half_x, half_y, size) = match outline {
            Some(outline) => {
                let (min, max) = outline.bounding_box();
                (
                    min.x.abs().max(max.x.abs()),
                    min.y.abs().max(max.y.abs()),
                    outline.size(),
                )
            }
            None => (0.1, 0.1, 0.2),
        };
        [
            (-half_x, half_x),
            (-half_y, half_y),
            (H_MIN, size.clamp(H_MIN, H_MAX)),
        ]
    }

    /// As an array `[com_x, com_y, h]`, the order of gradients.
    pub fn to_array(self) -> [f64; 3] {
        [self.com_offset[0], self.com_offset[1], self.h]
    }

    /// From an array `[com_x, com_y, h]`, clamped.
    pub fn from_array(a: [f64; 3]) -> Self {
        Self {
            com_offset: [a[0], a[1]],
            h: a[2],
        }
        .clamped()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_theta_the_model_does_not_accept_is_refused_naming_its_component() {
        let theta = |x, y, h| OnlineParams {
            com_offset: [x, y],
            h,
        };
        assert_eq!(
            theta(0.01, -0.02, 0.05).checked(),
            Ok(theta(0.01, -0.02, 0.05))
        );
        assert_eq!(
            theta(-2.0, 2.0, H_MAX).checked(),
            Ok(theta(-2.0, 2.0, H_MAX))
        );
        assert_eq!(
            theta(0.0, 0.0, 0.0).checked(),
            Err("h must be a finite number of metres in [0.001, 2], got 0".to_owned())
        );
        assert_eq!(
            theta(f64::NAN, 0.0, 0.05).checked(),
            Err("COM offset x must be a finite number of metres within ±2, got NaN".to_owned())
        );
        assert_eq!(
            theta(0.0, -2.5, 0.05).checked(),
            Err("COM offset y must be a finite number of metres within ±2, got -2.5".to_owned())
        );
        assert!(theta(0.0, 0.0, f64::INFINITY).checked().is_err());
    }
}
