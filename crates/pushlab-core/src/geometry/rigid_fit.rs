//! The rigid motion that best maps points of a known outline onto where they were seen: the
//! closed-form least-squares fit in the plane (2-D Procrustes without scaling). A dataset that
//! records an object as keypoints (Push-T's eight corners of the T) becomes a pose this way, and the
//! residual says how well the keypoints fit the outline.

use crate::math;
use nalgebra::{Point2, Vector2};

use super::{Pose2, rotate};

/// A pose fitted to keypoints, and how far the keypoints lie from the fitted outline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidFit {
    /// `world_from_local`: where the local frame's origin is and how it is turned.
    pub pose: Pose2,
    /// Root-mean-square distance between the seen points and the fitted ones, in the points' unit.
    pub rms_residual: f64,
}

/// The pose minimising `Σ |pose · local_i − seen_i|²`: the centroids matched, and the angle
/// `atan2(Σ a×b, Σ a·b)` of the centred points. `None` for fewer than two pairs, unequal counts,
/// non-finite values, or local points that all coincide (no direction to fit).
pub fn fit_rigid(local: &[Point2<f64>], seen: &[Point2<f64>]) -> Option<RigidFit> {
    if local.len() != seen.len() || local.len() < 2 {
        return None;
    }
    let n = local.len() as f64;
    let centre = |points: &[Point2<f64>]| points.iter().map(|p| p.coords).sum::<Vector2<f64>>() / n;
    let (local_mean, seen_mean) = (centre(local), centre(seen));
    let (mut dot, mut cross) = (0.0, 0.0);
    for (p, q) in local.iter().zip(seen) {
        let (a, b) = (p.coords - local_mean, q.coords - seen_mean);
        dot += a.dot(&b);
        cross += a.x * b.y - a.y * b.x;
    }
    if !(dot.is_finite() && cross.is_finite()) || (dot == 0.0 && cross == 0.0) {
        return None;
    }
    let yaw = math::atan2(cross, dot);
    let origin = seen_mean - rotate(local_mean, yaw);
    let pose = Pose2::new(origin.x, origin.y, yaw);
    let squared: f64 = (local.iter().zip(seen))
        .map(|(p, q)| (pose.point_in_world(*p) - q).norm_squared())
        .sum();
    Some(RigidFit {
        pose,
        rms_residual: (squared / n).sqrt(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_known_pose_is_found_exactly_and_noise_shows_in_the_residual() {
        let local: Vec<Point2<f64>> = [[-60.0, 0.0], [60.0, 0.0], [60.0, 30.0], [15.0, 120.0]]
            .iter()
            .map(|&p| Point2::from(p))
            .collect();
        let truth = Pose2::new(250.0, -40.0, 2.9);
        let seen: Vec<_> = local.iter().map(|p| truth.point_in_world(*p)).collect();
        let fit = fit_rigid(&local, &seen).expect("fits");
        assert!(
            (fit.pose.position - truth.position).norm() < 1e-9,
            "{fit:?}"
        );
        assert!((fit.pose.yaw - 2.9).abs() < 1e-12 && fit.rms_residual < 1e-9);
        // One point moved by 4 px: the residual is 4 px spread over the fit, RMS below 4/√4.
        let mut moved = seen.clone();
        moved[3].x += 4.0;
        let fit = fit_rigid(&local, &moved).expect("fits");
        assert!(fit.rms_residual > 1.0 && fit.rms_residual < 2.0, "{fit:?}");
        assert!(fit_rigid(&local[..1], &seen[..1]).is_none());
        assert!(fit_rigid(&[Point2::origin(); 3], &seen[..3]).is_none());
    }
}
