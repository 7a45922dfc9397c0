//! What the scene draws of a whole recording at once: the pusher's path, thinned to a bounded number
//! of points, and the box that holds the robot's and the object's paths (what "Fit all" shows).
//!
//! Computed once per selected recording: a million-frame push drawn point by point every frame cost
//! milliseconds of tessellation for a line no screen can resolve.

use nalgebra::Point2;
use pushlab_core::trajectory::Trajectory;

/// Most points of the drawn robot path.
pub const MAX_PATH_POINTS: usize = 4000;

/// The recording as a whole.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PathOverview {
    /// The pusher's path: the first and last frame, and between them every point at least a
    /// tolerance from the one kept before (the tolerance grows until at most [`MAX_PATH_POINTS`]).
    pub robot_path: Vec<Point2<f64>>,
    /// Corners of the box around every robot and object position, metres; `None` without frames.
    pub bounds: Option<(Point2<f64>, Point2<f64>)>,
}

impl PathOverview {
    /// The overview of a trajectory.
    pub fn of(trajectory: &Trajectory) -> Self {
        let frames = &trajectory.frames;
        let mut bounds: Option<(Point2<f64>, Point2<f64>)> = None;
        for p in frames.iter().flat_map(|f| [f.robot, f.object.position]) {
            if !(p.x.is_finite() && p.y.is_finite()) {
                continue;
            }
            bounds = Some(match bounds {
                None => (p, p),
                Some((lo, hi)) => (lo.inf(&p), hi.sup(&p)),
            });
        }
        let diagonal = bounds.map_or(0.0, |(lo, hi)| (hi - lo).norm());
        let mut tolerance = diagonal / 2000.0;
        let robot_path = loop {
            let path = thinned(frames.iter().map(|f| f.robot), tolerance);
            if path.len() <= MAX_PATH_POINTS || tolerance <= 0.0 || !tolerance.is_finite() {
                break path;
            }
            tolerance *= 2.0;
        };
        Self { robot_path, bounds }
    }
}

/// The points at least `tolerance` from the point kept before them, with the first and the last.
fn thinned(points: impl Iterator<Item = Point2<f64>>, tolerance: f64) -> Vec<Point2<f64>> {
    let mut kept: Vec<Point2<f64>> = Vec::new();
    let mut last = None;
    for p in points {
        last = Some(p);
        if kept.last().is_none_or(|k| (p - k).norm() > tolerance) {
            kept.push(p);
        }
    }
    if let Some(last) = last
        && kept.last() != Some(&last)
    {
        kept.push(last);
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;
    use pushlab_core::geometry::Pose2;
    use pushlab_core::trajectory::Frame;

    #[test]
    fn a_million_frames_of_circles_give_a_bounded_path_within_the_tolerance() {
        // 4000 s at 250 Hz around a 0.5 m circle, twenty times round.
        let frames: Vec<Frame> = (0..1_000_001)
            .map(|i| {
                let t = i as f64 * 0.004;
                let a = t * std::f64::consts::TAU * 20.0 / 4000.0;
                let robot = Point2::new(0.5 * a.cos(), 0.5 * a.sin());
                Frame {
                    time: t,
                    robot,
                    object: Pose2::new(0.45 * a.cos(), 0.45 * a.sin(), a),
                }
            })
            .collect();
        let overview = PathOverview::of(&Trajectory::new(frames.clone()));
        let path = &overview.robot_path;
        assert!(path.len() <= MAX_PATH_POINTS, "{} points", path.len());
        assert!(
            path.len() > 500,
            "a circle needs more than {} points",
            path.len()
        );
        assert_eq!(path.first(), Some(&frames[0].robot));
        assert_eq!(path.last(), Some(&frames[1_000_000].robot));
        // Every frame lies near a kept point: the drawn path is the recorded one to within the
        // tolerance (here a few millimetres on a 1 m circle).
        for f in frames.iter().step_by(997) {
            let nearest = path
                .iter()
                .map(|p| (p - f.robot).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(nearest < 0.005, "{nearest} m from the drawn path");
        }
        let (lo, hi) = overview.bounds.expect("frames");
        assert!((lo.x + 0.5).abs() < 1e-6 && (hi.y - 0.5).abs() < 1e-6);
    }

    #[test]
    fn short_and_empty_recordings() {
        assert_eq!(
            PathOverview::of(&Trajectory::default()),
            PathOverview::default()
        );
        let still = Frame {
            time: 0.0,
            robot: Point2::new(1.0, 2.0),
            object: Pose2::new(0.0, 0.0, 0.0),
        };
        let overview = PathOverview::of(&Trajectory::new(vec![still; 3]));
        assert_eq!(overview.robot_path, vec![still.robot]);
    }
}
