//! Where `θ_online` can physically be for one object: the COM inside the footprint, and `h` no
//! larger than the footprint allows.
//!
//! Without these bounds online learning takes whatever `θ` fits the frames best, and where the
//! model misses real contact systematically that is not a physical one: on the real MIT pushes of a
//! 90 mm square held out of training, Gauss–Newton walked the COM to 134 mm from the centre, outside
//! the object. The generic bounds of [`OnlineParams::clamped`] (±2 m) only keep the numbers finite.
//!
//! `h` is the mean distance of the support pressure from the COM (Lynch's ratio of the largest
//! friction torque to the largest friction force, `uniform_pressure_h`), so for any pressure over
//! the footprint it lies between 0 (all of it under the COM) and the distance from the COM to the
//! footprint's farthest point (a vertex) — that farthest distance is the bound.
//!
//! Every optimiser's step and every steering of `θ` is kept inside by [`PhysicalBounds::keep`]
//! (`learn::step`, `learn::run`), so the app and the CLI learn inside the same bounds.

use nalgebra::{Point2, Vector2};

use super::params::{H_MIN, OnlineParams};
use crate::geometry::Outline;

/// The physical range of `θ_online` on one object (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct PhysicalBounds {
    /// The footprint, object frame: its inside test and nearest boundary point are the outline's own.
    outline: Outline,
    /// Its geometric centre, where a COM offset of zero lies.
    centre: Point2<f64>,
    /// A COM offset shorter than this is inside for sure: the distance from the centre to the
    /// nearest edge (0 when the centre is outside a non-convex footprint).
    inner_radius: f64,
    /// The distance from the centre to the farthest vertex.
    outer_radius: f64,
}

impl PhysicalBounds {
    /// The bounds of an object with this footprint.
    pub fn of(outline: &Outline) -> Self {
        let centre = outline.centroid();
        let inner_radius = if outline.contains(centre) {
            outline.closest_boundary_point(centre).signed_distance.abs()
        } else {
            0.0
        };
        let outer_radius = outline
            .vertices()
            .iter()
            .map(|v| (v - centre).norm())
            .fold(0.0, f64::max);
        Self {
            outline: outline.clone(),
            centre,
            inner_radius,
            outer_radius,
        }
    }

    /// `θ` kept physical: a COM offset outside the footprint moved to the nearest point of its
    /// boundary, then `h` kept within [`H_MIN`] and the distance from that COM to the farthest vertex.
    /// Inside the bounds `θ` passes through unchanged (after [`OnlineParams::clamped`]).
    pub fn keep(&self, theta: OnlineParams) -> OnlineParams {
        let theta = theta.clamped();
        let mut com = Vector2::from(theta.com_offset);
        if com.norm() > self.inner_radius && !self.outline.contains(self.centre + com) {
            com = self.outline.closest_boundary_point(self.centre + com).point - self.centre;
        }
        // Every vertex is at least `outer_radius − |com|` from the COM: below that, no need to
        // look for the farthest (the common case, and the step's hot path).
        let h = if theta.h <= self.outer_radius - com.norm() {
            theta.h
        } else {
            theta.h.min(self.h_max(com)).max(H_MIN)
        };
        OnlineParams {
            com_offset: [com.x, com.y],
            h,
        }
    }

    /// Whether a COM offset lies inside the footprint or on its boundary (within 1e-12 m, where a
    /// projection lands and the crossing rule of a non-convex outline is undecided).
    pub fn com_inside(&self, com_offset: [f64; 2]) -> bool {
        let p = self.centre + Vector2::from(com_offset);
        self.outline.contains(p)
            || self.outline.closest_boundary_point(p).signed_distance.abs() <= 1e-12
    }

    /// The largest `h` a pressure over the footprint can have about a COM at `com_offset`: the
    /// distance to the farthest vertex.
    pub fn h_max(&self, com_offset: Vector2<f64>) -> f64 {
        let com = self.centre + com_offset;
        self.outline
            .vertices()
            .iter()
            .map(|v| (v - com).norm())
            .fold(0.0, f64::max)
    }

    /// The distance from the geometric centre to the farthest vertex, metres.
    pub fn outer_radius(&self) -> f64 {
        self.outer_radius
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> PhysicalBounds {
        // 90 mm square like MIT's rect1, centred away from the origin to check the centring.
        let outline = Outline::new(
            [[0.1, 0.2], [0.19, 0.2], [0.19, 0.29], [0.1, 0.29]]
                .into_iter()
                .map(Point2::from)
                .collect(),
        )
        .expect("valid square");
        PhysicalBounds::of(&outline)
    }

    #[test]
    fn a_com_inside_passes_through_and_one_outside_lands_on_the_nearest_edge() {
        let bounds = square();
        let inside = OnlineParams {
            com_offset: [0.03, -0.04],
            h: 0.03,
        };
        assert_eq!(bounds.keep(inside), inside);
        // The MIT Gauss–Newton case: 134 mm out, beyond the left edge and above the top.
        let kept = bounds.keep(OnlineParams {
            com_offset: [-0.123, 0.052],
            h: 0.03,
        });
        assert!((kept.com_offset[0] + 0.045).abs() < 1e-12);
        assert!((kept.com_offset[1] - 0.045).abs() < 1e-12);
        let beside = bounds.keep(OnlineParams {
            com_offset: [0.02, -0.08],
            h: 0.03,
        });
        assert!((beside.com_offset[0] - 0.02).abs() < 1e-12);
        assert!((beside.com_offset[1] + 0.045).abs() < 1e-12);
    }

    #[test]
    fn h_is_kept_below_the_distance_to_the_farthest_corner() {
        let bounds = square();
        let half_diagonal = 0.045 * 2f64.sqrt();
        assert!((bounds.outer_radius() - half_diagonal).abs() < 1e-12);
        let wide = bounds.keep(OnlineParams {
            com_offset: [0.0, 0.0],
            h: 0.5,
        });
        assert!((wide.h - half_diagonal).abs() < 1e-12);
        // From a COM at one corner the farthest corner is the whole diagonal away.
        let cornered = bounds.keep(OnlineParams {
            com_offset: [0.045, 0.045],
            h: 0.5,
        });
        assert!((cornered.h - 2.0 * half_diagonal).abs() < 1e-12);
        // A uniform pressure's h (the mean distance) is always within the bound.
        let outline = Outline::rectangle(0.09, 0.09).expect("valid");
        let uniform = outline.uniform_pressure_h(outline.centroid(), 200);
        assert!(uniform < bounds.h_max(Vector2::zeros()));
    }

    #[test]
    fn a_notch_of_a_non_convex_outline_is_outside() {
        // A U: the notch between the arms is outside the footprint.
        let outline = Outline::new(
            [
                [0.0, 0.0],
                [0.3, 0.0],
                [0.3, 0.2],
                [0.2, 0.2],
                [0.2, 0.05],
                [0.1, 0.05],
                [0.1, 0.2],
                [0.0, 0.2],
            ]
            .into_iter()
            .map(Point2::from)
            .collect(),
        )
        .expect("valid U");
        let bounds = PhysicalBounds::of(&outline);
        let centre = outline.centroid();
        let in_notch = [0.15 - centre.x, 0.15 - centre.y];
        assert!(!bounds.com_inside(in_notch));
        let kept = bounds.keep(OnlineParams {
            com_offset: in_notch,
            h: 0.05,
        });
        assert!(bounds.com_inside(kept.com_offset));
        // From the notch's middle the arms' inner faces are 0.05 m aside, its floor 0.1 m down.
        let moved = (kept.com_offset[0] - in_notch[0]).hypot(kept.com_offset[1] - in_notch[1]);
        assert!((moved - 0.05).abs() < 1e-12);
    }
}
