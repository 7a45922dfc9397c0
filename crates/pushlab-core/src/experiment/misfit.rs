//! Calibrating a model's COM misfit (`model::ComMisfit`) by leaving each of its training objects out
//! in turn: a model trained on the others learns online on the left-out object's pushes whose true
//! COM is known, and the misfit is the smallest isotropic spread that, added to each push's
//! posterior, puts the truth inside the 95 % ellipse of 95 % of those pushes.
//!
//! Why this and not a statistic of the push itself: a model's error on an object it never saw is
//! the same along the whole push, so the frames agree on a wrong COM and the posterior cannot see
//! it (a sandwich covariance and a physical prior were measured and changed nothing; see the trust
//! experiment's README). Left-out objects are the nearest thing to the new object the model will
//! meet that still has a truth to measure against. The models trained for the folds see one object
//! fewer than the model shipped, so the spread errs wide. The spread is measured in units of each
//! push's `θ_online(0)` `h`, so that it carries over to objects of another size.
//!
//! It is measured on the frames' covariance (`Posterior::covariance_from_frames`), before the
//! estimate's path drift is added: the drift covers an estimate that was still sliding, the misfit
//! one that settled on a wrong COM, and each run adds both. Measured with the drift included, the
//! misfit shrank wherever the left-out pushes slid, and the held-out MIT ellip1, whose pushes
//! settle, fell from 13 to 9 of 13 with Gauss–Newton (the trust experiment's README).
//!
//! What it cannot see: what the training data never show. Trained only on pushes with the COM at
//! the centre, the folds measure the misfit of a new shape, not of a moved COM.

use std::sync::atomic::{AtomicBool, Ordering};

use nalgebra::{Matrix2, Vector2};

use super::data::UsedRecording;
use super::evaluate::TrajectoryRun;
use super::train::train_combined_in_slices;
use crate::learn::uncertainty::{CHI2_2DOF_95, com_block};
use crate::learn::{
    OnlineConfig, Optimizer, TrainConfig, TrainError, TrainProgress, TrainStage, Trained,
    TrainingReport,
};
use crate::model::{ComMisfit, CombinedModel, ModelKind};

/// The share of left-out pushes whose 95 % ellipse must hold the truth: the ellipse's own level.
pub const MISFIT_COVERAGE: f64 = 0.95;

/// One left-out push's final COM estimate against the truth, in units of its `θ_online(0)` `h`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LeftOutPush {
    /// Estimate − truth.
    pub error: [f64; 2],
    /// The posterior's COM covariance (`[xx, xy, yy]`).
    pub covariance: [f64; 3],
}

impl LeftOutPush {
    /// The smallest spread `s` for which `error` lies inside the 95 % ellipse of `covariance + s² I`
    /// (0 if it already does). The Mahalanobis distance falls as `s` grows, so a bisection finds it.
    pub fn spread_needed(&self) -> f64 {
        let holds = |s: f64| {
            let [xx, xy, yy] = self.covariance;
            let c = Matrix2::new(xx + s * s, xy, xy, yy + s * s);
            let e = Vector2::from(self.error);
            c.try_inverse()
                .is_some_and(|inverse| (e.transpose() * inverse * e)[(0, 0)] <= CHI2_2DOF_95)
        };
        if holds(0.0) {
            return 0.0;
        }
        // The error's length over the 95 % radius always suffices: the covariance only adds.
        let (mut low, mut high) = (0.0, Vector2::from(self.error).norm() / CHI2_2DOF_95.sqrt());
        while !holds(high) {
            high *= 2.0;
        }
        for _ in 0..60 {
            let mid = 0.5 * (low + high);
            if holds(mid) {
                high = mid;
            } else {
                low = mid;
            }
        }
        high
    }
}

/// The spread that puts [`MISFIT_COVERAGE`] of the pushes inside their ellipses: that quantile of
/// what each needs (0 without pushes).
pub fn misfit_for(pushes: &[LeftOutPush]) -> f64 {
    let mut needed: Vec<f64> = pushes.iter().map(LeftOutPush::spread_needed).collect();
    if needed.is_empty() {
        return 0.0;
    }
    needed.sort_by(f64::total_cmp);
    let rank = (MISFIT_COVERAGE * needed.len() as f64).ceil() as usize;
    needed[rank.clamp(1, needed.len()) - 1]
}

/// The objects of the recordings, each with the indices of its recordings (an object is its
/// setting's outline: box, polygon or preset).
fn objects(used: &[UsedRecording]) -> Vec<Vec<usize>> {
    let mut objects: Vec<Vec<usize>> = Vec::new();
    for (i, u) in used.iter().enumerate() {
        let object = &u.recording.setting.object;
        match (objects.iter_mut()).find(|o| used[o[0]].recording.setting.object == *object) {
            Some(o) => o.push(i),
            None => objects.push(vec![i]),
        }
    }
    objects
}

/// Measures the COM misfit of a model of `kind` trained with `config` on `used` (see the module
/// documentation): per object whose recordings know their COM, a model trained on every other
/// object, online on that object's recordings with each optimiser (the default online rule
/// otherwise). Uncalibrated (all zero) with fewer than two objects or no known COM; stops early,
/// uncalibrated, when `cancel` is set. `progress` sees each fold's training, its stage saying which
/// fold. In slices (`crate::slices`): it pauses after each left-out push and within each fold's
/// training.
pub async fn calibrate_com_misfit_in_slices(
    kind: ModelKind,
    used: &[UsedRecording],
    config: &TrainConfig,
    progress: &mut dyn FnMut(&TrainProgress),
    cancel: &AtomicBool,
) -> Result<ComMisfit, TrainError> {
    let objects = objects(used);
    let known = |i: &usize| used[*i].recording.setting.com_offset.is_some();
    let folds: Vec<&Vec<usize>> = objects.iter().filter(|o| o.iter().any(known)).collect();
    if objects.len() < 2 || folds.is_empty() {
        return Ok(ComMisfit::default());
    }
    let mut left_out = [Vec::new(), Vec::new()];
    for (k, fold) in folds.iter().enumerate() {
        let rest: Vec<UsedRecording> = (used.iter().enumerate())
            .filter(|(i, _)| !fold.contains(i))
            .map(|(_, u)| u.clone())
            .collect();
        let stage = TrainStage::MisfitFold {
            fold: k + 1,
            folds: folds.len(),
        };
        let mut fold_progress = |p: &TrainProgress| progress(&TrainProgress { stage, ..*p });
        let Trained { model, report } =
            train_combined_in_slices(kind, &rest, config, &mut fold_progress, cancel).await?;
        if report.cancelled || cancel.load(Ordering::Relaxed) {
            return Ok(ComMisfit::default());
        }
        for &i in fold.iter().filter(|i| known(i)) {
            for (pushes, optimizer) in left_out.iter_mut().zip(OPTIMIZERS) {
                pushes.extend(left_out_push(&model, &used[i], optimizer));
                crate::slices::pause().await;
            }
        }
    }
    let [gd, gauss_newton] = &left_out;
    Ok(ComMisfit {
        gd_per_h: misfit_for(gd),
        gauss_newton_per_h: misfit_for(gauss_newton),
        pushes: gd.len(),
        objects: folds.len(),
    })
}

const OPTIMIZERS: [Optimizer; 2] = [Optimizer::Gd, Optimizer::GaussNewton];

/// One recording's final COM against its truth after online learning with `optimizer`, in units
/// of its `θ_online(0)` `h`; `None` without a truth, an outline the model needs, or a learned frame.
fn left_out_push(
    model: &CombinedModel,
    used: &UsedRecording,
    optimizer: Optimizer,
) -> Option<LeftOutPush> {
    let truth = used.recording.setting.com_offset?;
    let config = OnlineConfig {
        optimizer,
        ..OnlineConfig::default()
    };
    let run = TrajectoryRun::learn(model, used, 0, &config).ok()?.run;
    run.learned_steps().next()?;
    // θ at frame 0 is the model's θ_online(0) on this object.
    let h0 = run.theta_at(0).h;
    let estimate = run.theta_at(run.frontier()).com_offset;
    // Before the path's drift (see the module documentation).
    let c = com_block(&run.posterior().covariance_from_frames());
    let h2 = h0 * h0;
    Some(LeftOutPush {
        error: [(estimate[0] - truth[0]) / h0, (estimate[1] - truth[1]) / h0],
        covariance: [c[0][0] / h2, c[0][1] / h2, c[1][1] / h2],
    })
}

/// Trains a combined model ([`train_combined`]) and calibrates its COM misfit
/// ([`calibrate_com_misfit_in_slices`]) when `calibrate`: what `pushlab train`, the app's Train tab and
/// Python's `Model.train` make. A cancelled training is returned uncalibrated.
pub fn train_calibrated(
    kind: ModelKind,
    used: &[UsedRecording],
    config: &TrainConfig,
    calibrate: bool,
    progress: &mut dyn FnMut(&TrainProgress),
    cancel: &AtomicBool,
) -> Result<Trained<CombinedModel>, TrainError> {
    crate::slices::finish(train_calibrated_in_slices(
        kind, used, config, calibrate, progress, cancel,
    ))
}

/// [`train_calibrated`] in slices (`crate::slices`): what a browser tab polls a slice of each frame.
pub async fn train_calibrated_in_slices(
    kind: ModelKind,
    used: &[UsedRecording],
    config: &TrainConfig,
    calibrate: bool,
    progress: &mut dyn FnMut(&TrainProgress),
    cancel: &AtomicBool,
) -> Result<Trained<CombinedModel>, TrainError> {
    let trained = train_combined_in_slices(kind, used, config, progress, cancel).await?;
    if !calibrate || trained.report.cancelled {
        return Ok(trained);
    }
    let misfit = calibrate_com_misfit_in_slices(kind, used, config, progress, cancel).await?;
    // A cancel that cut the calibration short is the run's: its report says cancelled, so that
    // nothing trains after it (a baseline) and the user is told the model has no misfit.
    let cut_short = cancel.load(Ordering::Relaxed) && !misfit.is_calibrated();
    Ok(Trained {
        model: trained.model.with_com_misfit(misfit),
        report: TrainingReport {
            cancelled: cut_short,
            ..trained.report
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spread_needed_puts_the_truth_on_the_ellipse() {
        // Isotropic: |e|² / (σ² + s²) = χ² at the boundary.
        let push = LeftOutPush {
            error: [0.3, 0.4],
            covariance: [0.01, 0.0, 0.01],
        };
        let s = push.spread_needed();
        let expected = (0.25 / CHI2_2DOF_95 - 0.01).sqrt();
        assert!((s - expected).abs() < 1e-12, "{s} vs {expected}");
        // Already inside: nothing needed.
        let inside = LeftOutPush {
            error: [0.01, 0.0],
            covariance: [0.01, 0.0, 0.01],
        };
        assert_eq!(inside.spread_needed(), 0.0);
    }

    #[test]
    fn the_misfit_is_the_95th_percentile_of_what_each_push_needs() {
        // Twenty pushes needing 0.01, 0.02, ... 0.2 (zero covariance: s = |e| / √χ²).
        let pushes: Vec<LeftOutPush> = (1..=20)
            .map(|k| LeftOutPush {
                error: [0.01 * k as f64 * CHI2_2DOF_95.sqrt(), 0.0],
                covariance: [0.0; 3],
            })
            .collect();
        // 95 % of 20 is 19: the 19th smallest.
        assert!((misfit_for(&pushes) - 0.19).abs() < 1e-9);
        assert_eq!(misfit_for(&[]), 0.0);
    }
}
