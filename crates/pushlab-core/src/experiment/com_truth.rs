//! How well online learning found the COM, where the recording knows the true one (simulated sets):
//! the final error, how many frames it took to come within [`NEAR_M`] and stay there, and whether
//! the 95 % ellipse of the posterior holds the truth. The calibration and optimiser table of the
//! guide (`docs/src/model.md`) is these numbers, from `pushlab eval`.

use crate::math;
use serde::Serialize;

use crate::learn::{OnlineRun, Posterior};

/// "Found": within 5 mm of the true COM offset, as the optimiser comparison counts it.
pub const NEAR_M: f64 = 0.005;

/// One push's COM estimate against the truth.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ComTruth {
    /// Distance of the learned COM offset from the true one after the last frame, metres.
    pub error_m: f64,
    /// Whether the final posterior's 95 % ellipse holds the true COM offset.
    pub within_95: bool,
    /// Frames learned before the estimate came within [`NEAR_M`] and stayed there to the end, or
    /// `None` if it never settled there.
    pub frames_to_near: Option<usize>,
}

impl ComTruth {
    /// The measures of an online run, over the frames it learned from, against `truth`: the rule of
    /// the combined and the physics-only model alike.
    pub fn of_run(run: &OnlineRun, truth: [f64; 2]) -> Option<Self> {
        let after: Vec<[f64; 2]> = run
            .learned_steps()
            .map(|(_, _, theta)| theta.com_offset)
            .collect();
        Self::of(&after, run.posterior(), truth)
    }

    /// The measures of one online pass (the COM offset after each frame learned from, and the final
    /// posterior) against `truth`.
    pub fn of(com_after: &[[f64; 2]], posterior: &Posterior, truth: [f64; 2]) -> Option<Self> {
        let end = *com_after.last()?;
        let distance = |com: [f64; 2]| math::hypot(com[0] - truth[0], com[1] - truth[1]);
        let error_m = distance(end);
        // Walk back from the end while the estimate after each frame is near.
        let settled_from = com_after
            .iter()
            .rposition(|&com| distance(com) > NEAR_M)
            .map_or(0, |i| i + 1);
        Some(Self {
            error_m,
            within_95: posterior.com_within_95(end, truth),
            frames_to_near: (error_m <= NEAR_M).then_some(settled_from + 1),
        })
    }
}

/// The pushes of an evaluation with a known COM, summarised.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ComSummary {
    /// Pushes with a known COM.
    pub pushes: usize,
    /// Of these, how many 95 % ellipses hold the true COM.
    pub within_95: usize,
    /// Mean final COM error, metres.
    pub mean_error_m: f64,
    /// Pushes whose estimate settled within [`NEAR_M`].
    pub settled: usize,
    /// Median frames to settle, over the pushes that settled.
    pub median_frames_to_near: Option<usize>,
}

impl ComSummary {
    /// The summary of some pushes' measures, or `None` when none has a known COM.
    pub fn of<'a>(pushes: impl IntoIterator<Item = &'a ComTruth>) -> Option<Self> {
        let pushes: Vec<&ComTruth> = pushes.into_iter().collect();
        if pushes.is_empty() {
            return None;
        }
        let mut frames: Vec<usize> = pushes.iter().filter_map(|p| p.frames_to_near).collect();
        frames.sort_unstable();
        Some(Self {
            pushes: pushes.len(),
            within_95: pushes.iter().filter(|p| p.within_95).count(),
            mean_error_m: pushes.iter().map(|p| p.error_m).sum::<f64>() / pushes.len() as f64,
            settled: frames.len(),
            median_frames_to_near: frames.get(frames.len() / 2).copied(),
        })
    }

    /// The fraction of pushes whose 95 % ellipse holds the truth.
    pub fn coverage(&self) -> f64 {
        self.within_95 as f64 / self.pushes.max(1) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::OnlineParams;

    #[test]
    fn frames_to_near_counts_until_the_estimate_stays_within_5_mm() {
        let prior = Posterior::prior(
            &OnlineParams {
                com_offset: [0.0, 0.0],
                h: 0.1,
            },
            1,
        );
        // Near at frame 2, away at 3, near from frame 4 (the 5th frame learned) on.
        let path = [0.02, 0.01, 0.004, 0.008, 0.003, 0.001];
        let steps: Vec<[f64; 2]> = path.iter().map(|&x| [x, 0.0]).collect();
        let truth = ComTruth::of(&steps, &prior, [0.0, 0.0]).expect("steps");
        assert_eq!(truth.frames_to_near, Some(5));
        assert!((truth.error_m - 0.001).abs() < 1e-12);
        assert!(truth.within_95, "the wide prior holds a COM 1 mm away");

        let away = [[0.001, 0.0], [0.02, 0.0]];
        assert_eq!(
            ComTruth::of(&away, &prior, [0.0, 0.0])
                .expect("steps")
                .frames_to_near,
            None
        );
        let summary = ComSummary::of([&truth]).expect("one push");
        assert_eq!(
            (summary.pushes, summary.within_95, summary.settled),
            (1, 1, 1)
        );
        assert_eq!(summary.median_frames_to_near, Some(5));
        assert!(ComSummary::of([]).is_none());
    }
}
