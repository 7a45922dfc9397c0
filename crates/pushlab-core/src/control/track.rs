//! A filter on the poses a controller plans from: tracking noise (a camera's or a motion-capture
//! system's millimetres) moves the object's pose from one control step to the next, and the
//! planner's choices that hinge on millimetres (whether the pusher is on its push's line, whether
//! the object is within the goal's tolerance) flip with it. The sandbox's 2 mm and 0.5° took the
//! controller from 95 of 100 goals to about a third (`docs/src/control.md`).
//!
//! An alpha–beta filter per coordinate, in units of one control step: a pose and its rate, the
//! pose predicted a step on by the rate and pulled toward the measurement by `alpha`, the rate by
//! `beta`. It follows a steady push with no lag once its rate has settled, so it only smooths; yaw's
//! residual is taken the short way round. Learning never sees it: the online run learns from the
//! poses as they were measured, as the paper does. Off unless asked ([`TrackConfig`]).

use nalgebra::Point2;

use crate::geometry::Pose2;
use crate::math;

/// How strongly the filter follows each measurement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackConfig {
    /// The share of each residual taken into the pose, in (0, 1]: 1 takes the measurement as is.
    pub alpha: f64,
    /// The share of each residual taken into the rate, per step, in [0, 1).
    pub beta: f64,
}

impl TrackConfig {
    /// The filter following `alpha` of each residual into the pose and `beta` into its rate, or
    /// what is wrong with them (the one rule the CLI's `--track` and Python's `track=` check).
    pub fn new(alpha: f64, beta: f64) -> Result<Self, String> {
        if !(alpha > 0.0 && alpha <= 1.0 && (0.0..1.0).contains(&beta)) {
            return Err("expected 0 < ALPHA ≤ 1 and 0 ≤ BETA < 1".to_owned());
        }
        Ok(Self { alpha, beta })
    }

    /// `ALPHA,BETA`, or what is wrong with it.
    pub fn parse(text: &str) -> Result<Self, String> {
        let values: Vec<f64> = (text.split(','))
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|e| format!("'{text}': {e}; expected ALPHA,BETA"))?;
        let [alpha, beta] = values.as_slice() else {
            return Err(format!("'{text}': expected ALPHA,BETA, two numbers"));
        };
        Self::new(*alpha, *beta).map_err(|e| format!("'{text}': {e}"))
    }
}

/// The object's pose and the pusher's position, and their rates per step.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Tracked {
    value: [f64; 5],
    rate: [f64; 5],
}

/// The filter (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct PoseTrack {
    config: TrackConfig,
    state: Option<Tracked>,
}

impl PoseTrack {
    pub fn new(config: TrackConfig) -> Self {
        Self {
            config,
            state: None,
        }
    }

    /// Takes a control step's measured poses in: the filtered ones to plan from.
    pub fn update(&mut self, object: &Pose2, pusher: Point2<f64>) -> (Pose2, Point2<f64>) {
        let measured = [
            object.position.x,
            object.position.y,
            object.yaw,
            pusher.x,
            pusher.y,
        ];
        let TrackConfig { alpha, beta } = self.config;
        let tracked = match self.state {
            None => Tracked {
                value: measured,
                rate: [0.0; 5],
            },
            Some(Tracked { value, rate }) => {
                let mut next = Tracked { value, rate };
                for k in 0..5 {
                    let predicted = value[k] + rate[k];
                    let mut residual = measured[k] - predicted;
                    if k == 2 {
                        residual = math::atan2(math::sin(residual), math::cos(residual));
                    }
                    next.value[k] = predicted + alpha * residual;
                    next.rate[k] = rate[k] + beta * residual;
                }
                next.value[2] = math::atan2(math::sin(next.value[2]), math::cos(next.value[2]));
                next
            }
        };
        self.state = Some(tracked);
        let v = tracked.value;
        (Pose2::new(v[0], v[1], v[2]), Point2::new(v[3], v[4]))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    /// The filter chosen on the bench's tuning pairs with tracking noise.
    const SMOOTH: TrackConfig = TrackConfig {
        alpha: 0.5,
        beta: 0.1,
    };

    #[test]
    fn a_steady_push_is_followed_with_no_lag_once_settled() {
        let mut track = PoseTrack::new(SMOOTH);
        let mut out = (Pose2::new(0.0, 0.0, 0.0), Point2::origin());
        for k in 0..200 {
            let t = f64::from(k);
            let object = Pose2::new(0.004 * t, -0.001 * t, 3.1 + 0.002 * t);
            out = track.update(&object, Point2::new(0.004 * t - 0.2, -0.001 * t));
        }
        let t = 199.0;
        assert!((out.0.position.x - 0.004 * t).abs() < 1e-9, "{out:?}");
        assert!((out.0.position.y + 0.001 * t).abs() < 1e-9, "{out:?}");
        // Yaw went past π on the way: followed the short way round, no jump of 2π.
        let yaw = 3.1 + 0.002 * t;
        let wrapped = yaw.sin().atan2(yaw.cos());
        assert!(
            (out.0.yaw - wrapped).abs() < 1e-9,
            "{} vs {wrapped}",
            out.0.yaw
        );
        assert!((out.1.x - (0.004 * t - 0.2)).abs() < 1e-9, "{out:?}");
    }

    #[test]
    fn noise_on_a_steady_push_is_cut_by_a_third_or_more() {
        let mut track = PoseTrack::new(SMOOTH);
        // A fixed sequence of errors of ±2 mm (a linear congruential draw: no rng needed).
        let mut draw = 12_345u64;
        let mut noise = || {
            draw = draw.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            ((draw >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.004
        };
        let (mut raw, mut filtered) = (0.0, 0.0);
        for k in 0..2000 {
            let x = 0.004 * f64::from(k);
            let measured = x + noise();
            let (object, _) = track.update(&Pose2::new(measured, 0.0, 0.0), Point2::new(0.0, 0.0));
            if k >= 100 {
                raw += (measured - x).powi(2);
                filtered += (object.position.x - x).powi(2);
            }
        }
        let ratio = (filtered / raw).sqrt();
        assert!(ratio < 0.67, "the filtered error is {ratio} of the raw");
    }

    #[test]
    fn a_filter_that_follows_nothing_or_runs_away_is_refused() {
        assert_eq!(
            TrackConfig::parse("0.4, 0.05").unwrap(),
            TrackConfig {
                alpha: 0.4,
                beta: 0.05
            }
        );
        for bad in ["0,0.1", "1.5,0.1", "0.4,1", "0.4", "a,b"] {
            let why = TrackConfig::parse(bad).unwrap_err();
            assert!(why.contains("ALPHA"), "{bad}: {why}");
        }
    }
}
