//! The `θ_online` that fits a whole push best: the least mean loss over every frame at once, kept
//! physical — what no online learner with this model can beat on that push.
//!
//! Why: online learning sees one frame at a time and ends wherever its steps left `θ`; when its COM
//! ends far from the truth, that is either the learner (too slow, too noisy) or the model (no `θ`
//! makes it predict the push well near the true COM). The best fit tells them apart: if even the
//! best `θ` for the whole push is far from the true COM, no online step size, optimiser or
//! uncertainty will bring the learned one nearer, and the limit is the model's misfit on that data.
//!
//! How: the loss over a push is not convex in `θ` (the contact frame switches faces, the network is
//! piecewise affine, the motion cone clips), so a local method from `θ_online(0)` alone can stop in a
//! valley beside the best one. A grid over the physical range (the COM inside the footprint on a
//! 13 × 13 lattice, `h` at six fractions of the largest it can be there) finds the basin; projected
//! Levenberg–Marquardt on the residuals from its best three cells and from `θ_online(0)` finds its
//! floor. The loss is `Σ r²` of the linearisation's residuals, the same `ℓ` as every run's.

use crate::math;
use nalgebra::{Matrix3, Vector3};
use serde::Serialize;

use crate::inspect::landscape::mean_loss;
use crate::learn::Nmse;
use crate::model::{FrameLoss, Loss, OnlineModel, OnlineParams, Sample};

/// COM cells per side of the grid.
const GRID_CELLS: usize = 13;
/// `h` of the grid, as fractions of the largest `h` the footprint allows about the cell's COM (or,
/// without an outline, of twice `θ_online(0)`'s `h`).
const H_FRACTIONS: [f64; 6] = [0.15, 0.25, 0.4, 0.55, 0.7, 0.9];
/// Grid cells refined besides `θ_online(0)`.
const STARTS: usize = 3;
/// Levenberg–Marquardt iterations at most per start.
const ITERATIONS: usize = 60;
/// How many times [`best_fit`] polls `cancelled` when it runs to the end: before each grid row and
/// each refinement (a caller's progress is its polls over this).
pub const POLLS: usize = GRID_CELLS + STARTS + 1;

/// The best `θ_online` for a whole push and how well the model predicts the push with it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BestFit {
    pub theta: OnlineParams,
    /// NMSE over the push's samples with `theta` held fixed.
    pub nmse: Nmse,
    /// The mean total loss `ℓ` with `theta` (what was minimised).
    pub mean_loss: f64,
    /// Samples of the push.
    pub samples: usize,
}

/// The best `θ_online` over every push of one object at once (`pushlab eval --best-fit
/// --carry-theta`): what the pushes together allow the model, beside where carried online learning
/// ended.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectBestFit {
    /// The pushes, as indices of the online recordings, in order.
    pub recordings: Vec<usize>,
    /// `None` without samples.
    pub fit: Option<BestFit>,
}

/// The best fits of several pushes together: their NMSE as the runs' rows weigh it (by samples),
/// and over the pushes with a known COM the mean distance of the best COM from it (as
/// [`ComSummary`](super::ComSummary) gives the online runs').
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BestFitSummary {
    pub pushes: usize,
    pub nmse: Nmse,
    /// Pushes with a known COM.
    pub with_truth: usize,
    /// Mean distance of the best fit's COM from the true one over those, metres.
    pub mean_com_error_m: Option<f64>,
}

impl BestFitSummary {
    /// The summary of `(fit, true COM offset)` pairs; `None` without any.
    pub fn of<'a>(fits: impl IntoIterator<Item = (&'a BestFit, Option<[f64; 2]>)>) -> Option<Self> {
        let (mut pushes, mut samples, mut pos, mut rot) = (0, 0usize, 0.0, 0.0);
        let mut errors = Vec::new();
        for (fit, truth) in fits {
            pushes += 1;
            samples += fit.samples;
            pos += fit.nmse.pos * fit.samples as f64;
            rot += fit.nmse.rot * fit.samples as f64;
            if let Some(truth) = truth {
                errors.push(fit.com_error_m(truth));
            }
        }
        let n = samples.max(1) as f64;
        (pushes > 0).then(|| Self {
            pushes,
            nmse: Nmse {
                pos: pos / n,
                rot: rot / n,
            },
            with_truth: errors.len(),
            mean_com_error_m: (!errors.is_empty())
                .then(|| errors.iter().sum::<f64>() / errors.len() as f64),
        })
    }
}

impl BestFit {
    /// Distance of its COM from `truth` (a COM offset), metres.
    pub fn com_error_m(&self, truth: [f64; 2]) -> f64 {
        math::hypot(
            self.theta.com_offset[0] - truth[0],
            self.theta.com_offset[1] - truth[1],
        )
    }
}

/// The best `θ_online` for `samples` (one push's), kept inside the model's physical bounds (see the
/// module documentation); `None` without samples or when `cancelled` returns true (polled before
/// each grid row and each refinement, [`POLLS`] times in all).
pub fn best_fit<M: OnlineModel + ?Sized>(
    model: &M,
    samples: &[Sample],
    cancelled: &dyn Fn() -> bool,
) -> Option<BestFit> {
    crate::slices::finish(best_fit_in_slices(model, samples, cancelled))
}

/// [`best_fit`] in slices (`crate::slices`): it pauses after each grid row and each refinement,
/// where it polls `cancelled`.
pub async fn best_fit_in_slices<M: OnlineModel + ?Sized>(
    model: &M,
    samples: &[Sample],
    cancelled: &dyn Fn() -> bool,
) -> Option<BestFit> {
    if samples.is_empty() {
        return None;
    }
    let theta0 = model.keep_physical(model.theta0());
    let mut cells: Vec<(f64, OnlineParams)> = Vec::new();
    for row in grid(model, &theta0) {
        if cancelled() {
            return None;
        }
        for theta in row {
            let loss = mean_loss(model, samples, &theta);
            if loss.is_finite() {
                cells.push((loss, theta));
            }
        }
        crate::slices::pause().await;
    }
    cells.sort_by(|a, b| a.0.total_cmp(&b.0));
    let starts = std::iter::once(theta0).chain(cells.iter().take(STARTS).map(|c| c.1));
    let mut best: Option<(f64, OnlineParams)> = None;
    for start in starts {
        if cancelled() {
            return None;
        }
        let (loss, theta) = refine(model, samples, start);
        if best.is_none_or(|b| loss < b.0) {
            best = Some((loss, theta));
        }
        crate::slices::pause().await;
    }
    // Every θ predicting a non-finite loss (a model gone wrong): nothing to report.
    let (_, theta) = best.filter(|b| b.0.is_finite())?;
    let losses: Vec<Loss> = samples.iter().map(|s| model.loss_at(s, &theta)).collect();
    let nmse = Nmse::of_frames(losses.iter().map(FrameLoss::of));
    Some(BestFit {
        theta,
        nmse,
        mean_loss: losses.iter().map(Loss::total).sum::<f64>() / losses.len() as f64,
        samples: samples.len(),
    })
}

/// The grid's rows of `θ`: COM offsets on a square lattice over the footprint (cells outside it
/// left out), each with `h` at [`H_FRACTIONS`] of the largest the footprint allows there. Without an
/// outline, around `θ_online(0)`: COM within ±2 h₀, `h` up to 2 h₀.
fn grid<M: OnlineModel + ?Sized>(model: &M, theta0: &OnlineParams) -> Vec<Vec<OnlineParams>> {
    let bounds = model.bounds();
    // With an outline, a COM offset of zero is its geometric centre.
    let (centre, half) = match bounds {
        Some(b) => ([0.0, 0.0], b.outer_radius()),
        None => (theta0.com_offset, 2.0 * theta0.h),
    };
    let at = |i: usize| -half + 2.0 * half * (i as f64 + 0.5) / GRID_CELLS as f64;
    (0..GRID_CELLS)
        .map(|iy| {
            let mut row = Vec::new();
            for ix in 0..GRID_CELLS {
                let com = [centre[0] + at(ix), centre[1] + at(iy)];
                let h_max = match bounds {
                    Some(b) if !b.com_inside(com) => continue,
                    Some(b) => b.h_max(com.into()),
                    None => 2.0 * theta0.h,
                };
                row.extend(H_FRACTIONS.iter().map(|f| OnlineParams {
                    com_offset: com,
                    h: f * h_max,
                }));
            }
            row
        })
        .collect()
}

/// Projected Levenberg–Marquardt on the push's residuals from `start`: each iteration solves
/// `(JᵀJ + λ diag(JᵀJ)) δ = −Jᵀr`, keeps `θ + δ` physical and takes it if the loss fell (then
/// trusts the linearisation more), else tries again with a larger `λ`. The summed loss and `θ` where
/// it stopped.
fn refine<M: OnlineModel + ?Sized>(
    model: &M,
    samples: &[Sample],
    start: OnlineParams,
) -> (f64, OnlineParams) {
    let total = |theta: &OnlineParams| {
        let l = mean_loss(model, samples, theta) * samples.len() as f64;
        if l.is_finite() { l } else { f64::INFINITY }
    };
    let mut theta = model.keep_physical(start);
    let mut loss = total(&theta);
    let mut lambda = 1e-3;
    for _ in 0..ITERATIONS {
        let (mut jtj, mut jtr) = (Matrix3::<f64>::zeros(), Vector3::<f64>::zeros());
        for s in samples {
            let lin = model.linearize(s, &theta);
            for (row, r) in lin.jacobian.iter().zip(lin.residual) {
                let j = Vector3::from(*row);
                jtj += j * j.transpose();
                jtr += j * r;
            }
        }
        let mut improved = None;
        for _ in 0..12 {
            let mut damped = jtj;
            for k in 0..3 {
                damped[(k, k)] += lambda * jtj[(k, k)].max(1e-12);
            }
            let Some(delta) = damped.lu().solve(&(-jtr)) else {
                lambda *= 4.0;
                continue;
            };
            let candidate = model.keep_physical(OnlineParams {
                com_offset: [
                    theta.com_offset[0] + delta[0],
                    theta.com_offset[1] + delta[1],
                ],
                h: theta.h + delta[2],
            });
            let candidate_loss = total(&candidate);
            if candidate_loss < loss {
                improved = Some((candidate_loss, candidate));
                lambda = (lambda / 3.0).max(1e-9);
                break;
            }
            lambda *= 4.0;
        }
        match improved {
            Some((l, t)) => {
                let gain = loss - l;
                (loss, theta) = (l, t);
                if gain <= 1e-12 * loss.max(1e-300) {
                    break;
                }
            }
            None => break,
        }
    }
    (loss, theta)
}

#[cfg(test)]
mod tests;
