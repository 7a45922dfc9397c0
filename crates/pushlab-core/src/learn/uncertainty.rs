//! How sure online learning is of `θ_online`, and a faster optimiser built from the same numbers.
//!
//! Each learned frame linearises the model at the `θ` it predicted with ([`Linearization`]: the
//! residual `r = (predicted − measured) / σ` and its Jacobian `J`). Summed over the frames seen so
//! far, `JᵀJ` is the Gauss–Newton approximation of the loss's curvature; with the noise variance `s²`
//! estimated from the residuals, the samples' overlap `k` (a model predicting `k` frames ahead from
//! every frame sees each motion `k` times) and a weak Gaussian prior at `θ_online(0)`, the Laplace
//! posterior of `θ_online` has the covariance `(JᵀJ / (s² k c) + Λ₀)⁻¹` ([`Posterior`]; `c` below).
//!
//! The same information matrix gives the Gauss–Newton optimiser ([`Optimizer::GaussNewton`](super::Optimizer::GaussNewton), `learn::step`): after
//! each frame, `θ ← θ − (JᵀJ / (s² k c) + Λ₀)⁻¹ Jₜᵀ rₜ / (s² k c)` — the recursive least-squares (extended
//! Kalman filter without process noise) step, which weighs the new frame against everything seen
//! before instead of taking a fixed learning rate.
//!
//! Frames of one push are not independent: a learned model's errors on real contact are partly
//! systematic, the same for hundreds of frames at 250 Hz, and counting each frame as new evidence
//! made the posterior narrow to a few millimetres while the estimate was centimetres off (the MIT
//! rows of the guide's calibration table, `docs/src/model.md`). So the information is also divided
//! by a factor `c ≥ 1`: how much more the scores of consecutive batches of frames scatter than
//! independent errors would make them (`score_batches`, batch means). Independent errors leave
//! `c ≈ 1`.
//!
//! The posterior forgets: before each frame, the frames before it are weighed down so that it
//! remembers about [`MEMORY_FRAMES`] frames. Gauss–Newton's gain is its information, so a long
//! recording's estimate keeps following a COM or `h` that changes instead of freezing after the
//! first hundred thousand frames.
//!
//! The estimate's own path is evidence too. A model that does not fit the object (a COM it never
//! saw, a shape it never trained on) keeps the estimate sliding through the whole push — gradient
//! descent's five small steps a frame are still closing in when the push ends, Gauss–Newton follows
//! the error from face to face — and the frames' curvature cannot tell how much further it had to
//! go. Steps that keep one direction are the sign: a filter that fits its model moves its estimate
//! by steps in uncorrelated directions (its estimate is a martingale), which scatter the path by
//! about what the steps' lengths predict. The path's scatter beyond that — its drift, `D²/12` for a
//! steady slide of length `D` — says the estimate may still be a slide length from where it ends,
//! in any direction, and [`Posterior::covariance`] adds `D²/2 = 6 × drift` to each COM component
//! ([`Posterior::com_path_variance`]; the path weighed like the frames, forgetting included). Like
//! the misfit it widens the ellipse and changes neither the estimate, nor the mode, nor
//! Gauss–Newton's gain. Measured on MuJoCo pushes with a moved COM and held-out MIT shapes, where
//! the frames' curvature and the COM misfit left the 95 % ellipse holding the truth in 52–78 % of
//! pushes, and checked on a second draw of MuJoCo pushes made after it was chosen (the trust
//! experiment's README).
//!
//! Assumptions left: Gaussian residuals with one variance per normalised output, errors that
//! decorrelate within a batch (batches grow with the push), and the model linear in `θ` near the
//! estimate.

mod expected;

use crate::math;
use nalgebra::{Matrix2, Matrix3, Vector3};
use serde::Serialize;

use super::score_batches::{MAX_FACTOR, ScoreBatches};
use crate::model::{H_MIN, Linearization, OnlineParams};

pub use expected::PushInformation;

/// The prior's standard deviation of every component of `θ_online`, in units of `θ_online(0)`'s `h`
/// (about a third of the object's size): weak, a COM anywhere on the object is plausible.
pub const PRIOR_STD_PER_H: f64 = 2.0;

/// Pseudo-frames of the noise-variance estimate's prior: residuals normalised by the loss's σ have a
/// variance of 1 for a model that predicts nothing, so the first frames start from there.
const NOISE_PRIOR_FRAMES: f64 = 1.0;

/// Frames the posterior remembers: before each frame is taken in, the frames before are weighed
/// down by `1 − 1/2000` ([`Posterior::forget`]). Gauss–Newton's gain is this posterior's
/// information: without forgetting it falls as `1/frames`, and after 100,000 frames of a long
/// recording one frame barely moves `θ` — a COM that shifts half-way would take another 100,000
/// frames to follow. 2000 frames is 8 s of the MIT dataset at 250 Hz and 200 s at 10 Hz; a push of
/// 300 frames keeps 86 % of its first frame's weight.
pub const MEMORY_FRAMES: f64 = 2000.0;

const KEEP: f64 = 1.0 - 1.0 / MEMORY_FRAMES;

/// The COM variance, per component, added per unit of the estimate's path drift: a steady slide of
/// length `D` drifts by `D²/12`, and an estimate that may still be `D` from where it ends, in any
/// direction, has `D²/2` in each component.
pub const PATH_DRIFT_SCALE: f64 = 6.0;

/// χ² with two degrees of freedom at 95 %: the squared Mahalanobis radius of the COM's 95 % ellipse.
pub const CHI2_2DOF_95: f64 = 5.991_464_547_107_979;

/// The Laplace posterior of `θ_online` given the frames learned so far.
///
/// Each frame's residual is kept as its linearisation `r(θ) ≈ J θ − b` (with `b = J θₜ − rₜ` at the
/// `θₜ` it was linearised at), so that the sum of squared residuals can be evaluated at the current
/// estimate — exactly for a model linear in `θ` — and the noise variance is that of the fit, not of
/// the early predictions made far from it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Posterior {
    /// `Σ JᵀJ` over the frames, per square metre.
    jtj: Matrix3<f64>,
    /// `Σ Jᵀb`.
    jtb: Vector3<f64>,
    /// `Σ |b|²`.
    btb: f64,
    frames: usize,
    /// The frames' total weight: `frames`, less what forgetting took away (`Posterior::forget`).
    weight: f64,
    /// `Λ₀`: the prior's precision of each component, per square metre.
    prior_precision: [f64; 3],
    /// The estimate the noise variance is evaluated at.
    estimate: Vector3<f64>,
    /// The prior's mean, `θ_online(0)`.
    prior_mean: Vector3<f64>,
    /// Samples per independent sample: a model predicting `k` frames ahead from every frame sees
    /// each frame's motion in `k` overlapping samples, whose residuals are not independent.
    overlap: f64,
    /// The frames' linearisation sums in batches, for the correlation factor.
    batches: ScoreBatches,
    /// The model's COM misfit (`model::ComMisfit`) as a variance added to each COM component of the
    /// estimate's error, square metres: the bias no frame can reveal.
    com_misfit_var: f64,
    /// The COM estimates the frames were learned at, for their drift
    /// ([`Posterior::com_path_variance`]), as offsets from the prior's mean (so that the squares
    /// stay small against the sums), weighed like the frames.
    path: PathMoments,
}

/// The COM estimate's path, as weighted moments: enough to give its scatter and the part of that
/// scatter its steps would make in random directions, without keeping the path.
///
/// With points `xⱼ` of weight `wⱼ` (total `W`) and steps `Δₖ = xₖ − xₖ₋₁`, a step moves the points
/// after it, of weight `Aₖ`, against those before; steps in uncorrelated directions would scatter
/// the points by `Σₖ |Δₖ|² (Aₖ/W)(1 − Aₖ/W)` on average. Kept as `S₁ = Σ |Δₖ|² Aₖ`,
/// `S₂ = Σ |Δₖ|² Aₖ²` and `V = Σ |Δₖ|²`: a new point adds 1 to every `Aₖ`, forgetting scales them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct PathMoments {
    weight: f64,
    sum: [f64; 2],
    squares: f64,
    last: Option<[f64; 2]>,
    steps_by_after: f64,
    steps_by_after_squared: f64,
    steps: f64,
}

impl PathMoments {
    fn add(&mut self, x: [f64; 2]) {
        // Every step so far has one more point after it.
        self.steps_by_after_squared += 2.0 * self.steps_by_after + self.steps;
        self.steps_by_after += self.steps;
        if let Some(last) = self.last {
            let step = (x[0] - last[0]).powi(2) + (x[1] - last[1]).powi(2);
            self.steps_by_after += step;
            self.steps_by_after_squared += step;
            self.steps += step;
        }
        self.last = Some(x);
        self.weight += 1.0;
        self.sum[0] += x[0];
        self.sum[1] += x[1];
        self.squares += x[0] * x[0] + x[1] * x[1];
    }

    fn scale(&mut self, keep: f64) {
        self.weight *= keep;
        self.sum = self.sum.map(|s| s * keep);
        self.squares *= keep;
        self.steps_by_after *= keep;
        self.steps_by_after_squared *= keep * keep;
    }

    /// The weighted mean squared distance of the points from their mean (0 before any point).
    fn scatter(&self) -> f64 {
        if self.weight <= 0.0 {
            return 0.0;
        }
        let mean = self.sum.map(|s| s / self.weight);
        (self.squares / self.weight - mean[0] * mean[0] - mean[1] * mean[1]).max(0.0)
    }

    /// What the same steps in uncorrelated directions would scatter the points by, on average.
    fn jitter(&self) -> f64 {
        if self.weight <= 0.0 {
            return 0.0;
        }
        let w = self.weight;
        (self.steps_by_after / w - self.steps_by_after_squared / (w * w)).max(0.0)
    }

    /// The scatter the steps' persistence made: a path that slid steadily by `D` scatters by
    /// `D²/12` and jitters by almost nothing; one that only jittered, by about its jitter.
    fn drift(&self) -> f64 {
        (self.scatter() - self.jitter()).max(0.0)
    }
}

impl Posterior {
    /// Nothing seen yet: the prior centred at `theta0`, `PRIOR_STD_PER_H × h` wide, for samples
    /// `horizon` frames long taken from every frame.
    pub fn prior(theta0: &OnlineParams, horizon: usize) -> Self {
        let std = PRIOR_STD_PER_H * theta0.h.max(H_MIN);
        Self {
            jtj: Matrix3::zeros(),
            jtb: Vector3::zeros(),
            btb: 0.0,
            frames: 0,
            weight: 0.0,
            prior_precision: [1.0 / (std * std); 3],
            estimate: vector(theta0),
            prior_mean: vector(theta0),
            overlap: horizon.max(1) as f64,
            batches: ScoreBatches::new(horizon),
            com_misfit_var: 0.0,
            path: PathMoments::default(),
        }
    }

    /// The same posterior with the model's COM misfit, a standard deviation in metres, added to
    /// each COM component's spread ([`Posterior::covariance`]). It widens the ellipse; it does not
    /// change the mode or Gauss–Newton's gain, which weigh what the frames say.
    pub fn with_com_misfit(mut self, std_m: f64) -> Self {
        self.com_misfit_var = if std_m.is_finite() {
            std_m * std_m
        } else {
            0.0
        };
        self
    }

    /// Takes in one frame's linearisation at `theta` (a frame whose numbers are not finite is left
    /// out).
    pub fn with(mut self, linearization: &Linearization, theta: &OnlineParams) -> Self {
        self.take_in(linearization, theta);
        self
    }

    /// [`Posterior::with`] in place. The posterior is about 1.4 kB (mostly its score batches): an
    /// online step that moved it by value copied it several times per frame, a tenth of the step's
    /// time.
    pub(super) fn take_in(&mut self, linearization: &Linearization, theta: &OnlineParams) {
        let j = Matrix3::from_fn(|i, k| linearization.jacobian[i][k]);
        let b = j * vector(theta) - Vector3::from(linearization.residual);
        let jtj = j.transpose() * j;
        let jtb = j.transpose() * b;
        if jtj.iter().chain(jtb.iter()).all(|x| x.is_finite()) && b.norm_squared().is_finite() {
            self.forget(KEEP);
            self.jtj += jtj;
            self.jtb += jtb;
            self.btb += b.norm_squared();
            self.frames += 1;
            self.weight += 1.0;
            self.batches.push(&jtj, &jtb);
            self.path.add([
                theta.com_offset[0] - self.prior_mean[0],
                theta.com_offset[1] - self.prior_mean[1],
            ]);
        }
    }

    /// The frames so far weighed down by `keep` (in (0, 1]), as [`Posterior::with`] does before it
    /// takes in the next frame ([`MEMORY_FRAMES`]): exponential forgetting, so that after `1 / (1 − keep)` frames the oldest count for a third
    /// (`1/e`) and a long recording's estimate follows a COM or `h` that changes (a load shifting, a
    /// different floor). The prior is not forgotten; the batches of the correlation factor compare
    /// scatter with information over the whole run, a ratio forgetting leaves alone. The estimate's
    /// path is forgotten with its frames: a long recording's early sliding stops widening the
    /// ellipse.
    fn forget(&mut self, keep: f64) {
        self.jtj *= keep;
        self.jtb *= keep;
        self.btb *= keep;
        self.weight *= keep;
        self.path.scale(keep);
    }

    /// The complete batches of frames the correlation factor compares, and their length in frames.
    pub fn score_batches(&self) -> (usize, usize) {
        (self.batches.batches(), self.batches.batch_length())
    }

    /// `c`: how many frames one frame's evidence is worth, beyond the samples' overlap — the batch
    /// scores' scatter at the estimate over what independent errors give (`s² k` per frame),
    /// within [1, 100]; 1 until there are enough batches.
    pub fn correlation_factor(&self) -> f64 {
        let expected = self.noise_variance() * self.overlap;
        match self.batches.scatter_per_frame(&self.estimate) {
            Some(scatter) if expected > 0.0 => (scatter / expected).clamp(1.0, MAX_FACTOR),
            _ => 1.0,
        }
    }

    /// The same frames, with the noise variance evaluated at `theta` (the estimate after a step).
    pub fn at(mut self, theta: &OnlineParams) -> Self {
        self.move_to(theta);
        self
    }

    /// [`Posterior::at`] in place (see [`Posterior::take_in`]).
    pub(super) fn move_to(&mut self, theta: &OnlineParams) {
        self.estimate = vector(theta);
    }

    /// Frames taken in.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// `Σ |r(θ)|²` at the estimate, by the frames' linearisations.
    pub fn residual_sum_of_squares(&self) -> f64 {
        let t = self.estimate;
        ((t.transpose() * self.jtj * t)[(0, 0)] - 2.0 * t.dot(&self.jtb) + self.btb).max(0.0)
    }

    /// `s²`, the variance of a normalised residual at the estimate: the residual sum of squares over
    /// the frames' three outputs less the three fitted parameters, with one pseudo-frame of
    /// variance 1 (what a model that predicts nothing has) so that the first frames are not
    /// over-confident. Frames count by their weight after forgetting.
    pub fn noise_variance(&self) -> f64 {
        let dof = (3.0 * self.weight - 3.0).max(0.0);
        (self.residual_sum_of_squares() + 3.0 * NOISE_PRIOR_FRAMES)
            / (dof + 3.0 * NOISE_PRIOR_FRAMES)
    }

    /// The weight `1 / (s² k c)` of a frame's squared residuals in the information, with `k` the
    /// samples' overlap (their horizon) and `c` the [`Posterior::correlation_factor`].
    pub fn frame_weight(&self) -> f64 {
        1.0 / (self.noise_variance() * self.overlap * self.correlation_factor())
    }

    /// `JᵀJ / (s² k c) + Λ₀`, per square metre.
    pub fn information(&self) -> Matrix3<f64> {
        self.information_at(self.frame_weight())
    }

    /// [`Posterior::information`] with a given frame weight (computed once by a caller that needs it
    /// twice).
    pub(super) fn information_at(&self, weight: f64) -> Matrix3<f64> {
        self.jtj * weight + Matrix3::from_diagonal(&self.prior_precision.into())
    }

    /// The posterior's spread about its mode, `(JᵀJ / (s² k c) + Λ₀)⁻¹`, square metres.
    pub fn mode_covariance(&self) -> Matrix3<f64> {
        self.mode_covariance_at(self.frame_weight())
    }

    fn mode_covariance_at(&self, weight: f64) -> Matrix3<f64> {
        // Positive definite (the prior's diagonal plus a sum of JᵀJ), so the inverse exists.
        self.information_at(weight)
            .try_inverse()
            .unwrap_or_else(|| {
                Matrix3::from_diagonal(&self.prior_precision.map(|p| 1.0 / p).into())
            })
    }

    /// The mode of the linearised posterior, `[com_x, com_y, h]`: the θ that fits the frames'
    /// linearisations best, given the prior.
    pub fn mode(&self) -> Vector3<f64> {
        let weight = self.frame_weight();
        self.mode_at(weight, &self.mode_covariance_at(weight))
    }

    fn mode_at(&self, weight: f64, mode_covariance: &Matrix3<f64>) -> Vector3<f64> {
        let prior = Vector3::from(self.prior_precision).component_mul(&self.prior_mean);
        mode_covariance * (self.jtb * weight + prior)
    }

    /// What [`Posterior::covariance`] adds to each COM component for an estimate that kept
    /// sliding, square metres: [`PATH_DRIFT_SCALE`] times the drift of the COM estimates the frames
    /// were learned at (their scatter beyond what their steps in uncorrelated directions would
    /// make; 0 before the second frame).
    pub fn com_path_variance(&self) -> f64 {
        PATH_DRIFT_SCALE * self.path.drift()
    }

    /// The covariance of the estimate's error, `[com_x, com_y, h]`, square metres:
    /// [`Posterior::covariance_from_frames`] plus, on each COM component, the drift of the
    /// estimate's path ([`Posterior::com_path_variance`]; see the module documentation). What the
    /// ellipse, the ± and the reports show.
    pub fn covariance(&self) -> Matrix3<f64> {
        let mut covariance = self.covariance_from_frames();
        let path = self.com_path_variance();
        covariance[(0, 0)] += path;
        covariance[(1, 1)] += path;
        covariance
    }

    /// The covariance the frames and the model's calibration give: the spread about the mode plus
    /// the estimate's own offset from it, `Σ + δδᵀ`, plus the model's COM misfit `m²` on each COM
    /// component. Gradient descent's estimate lags behind the mode (five small steps per frame);
    /// Gauss–Newton's sits on it, and `δ ≈ 0`. For a model that fits the object this alone is
    /// calibrated (the linear-Gaussian check in `tests/uncertainty.rs`), and the path's drift
    /// widens [`Posterior::covariance`] only where the estimate slid.
    pub fn covariance_from_frames(&self) -> Matrix3<f64> {
        // The weight (with its correlation factor) and the inverse once, for the mode and the spread.
        let weight = self.frame_weight();
        let mut covariance = self.mode_covariance_at(weight);
        let offset = self.estimate - self.mode_at(weight, &covariance);
        if offset.iter().all(|d| d.is_finite()) {
            covariance += offset * offset.transpose();
        }
        covariance[(0, 0)] += self.com_misfit_var;
        covariance[(1, 1)] += self.com_misfit_var;
        covariance
    }

    /// What the COM's spread is made of (see [`ComSpreadParts`]).
    pub fn com_spread_parts(&self) -> ComSpreadParts {
        let c = self.covariance();
        ComSpreadParts::of(
            (c[(0, 0)] + c[(1, 1)]) / 2.0,
            self.com_misfit_var,
            self.com_path_variance(),
        )
    }

    /// The covariance of the COM offset, object frame, square metres.
    pub fn com_covariance(&self) -> [[f64; 2]; 2] {
        com_block(&self.covariance())
    }

    /// The standard deviations of `[com_x, com_y, h]`, metres.
    pub fn std(&self) -> [f64; 3] {
        std_of(&self.covariance())
    }

    /// Whether `com` lies inside the 95 % ellipse around `estimate` (both object frame, metres).
    pub fn com_within_95(&self, estimate: [f64; 2], com: [f64; 2]) -> bool {
        let c = self.com_covariance();
        let Some(inverse) = Matrix2::new(c[0][0], c[0][1], c[1][0], c[1][1]).try_inverse() else {
            return false;
        };
        let d = nalgebra::Vector2::new(com[0] - estimate[0], com[1] - estimate[1]);
        (d.transpose() * inverse * d)[(0, 0)] <= CHI2_2DOF_95
    }

    /// The 95 % ellipse of the COM offset (see [`ellipse_95`]).
    pub fn com_ellipse_95(&self) -> ([f64; 2], f64) {
        ellipse_95(self.com_covariance())
    }
}

/// What the COM's spread is made of, each as one standard deviation of a COM component (metres,
/// the mean over x and y): what the frames say (the posterior about its mode, the prior, and the
/// estimate's offset from the mode), the model's COM misfit, and the estimate's path drift. Their
/// squares add up to the mean of the two COM variances: why an ellipse is as wide as it is.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ComSpreadParts {
    pub frames_m: f64,
    pub misfit_m: f64,
    pub drift_m: f64,
}

impl ComSpreadParts {
    /// The parts of a spread whose mean COM variance is `com_var`, of which `misfit_var` is the
    /// model's COM misfit and `drift_var` the path's drift (square metres): the frames' part is the
    /// rest. One rule for a posterior and for the [`Spread`] kept at every frame.
    pub fn of(com_var: f64, misfit_var: f64, drift_var: f64) -> Self {
        Self {
            frames_m: (com_var - misfit_var - drift_var).max(0.0).sqrt(),
            misfit_m: misfit_var.max(0.0).sqrt(),
            drift_m: drift_var.max(0.0).sqrt(),
        }
    }
}

/// How sure a run is of `θ_online` at a frame, compactly enough to keep for every frame of a long
/// recording (24 bytes): the COM offset's covariance (m², object frame: xx, xy, yy), the standard
/// deviation of `h` (m) and the parts of each COM variance that are the model's misfit and the
/// path's drift (m²), in `f32` — what the app draws as the ellipse and the ±2σ bands, and what it
/// says the ellipse is made of at the frame shown. (The misfit is kept per frame: an optimiser
/// changed at a frame changes it from there on.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spread {
    pub com_cov: [f32; 3],
    pub h_std: f32,
    /// The posterior's COM misfit, squared.
    pub com_misfit_var: f32,
    /// [`Posterior::com_path_variance`].
    pub com_drift_var: f32,
}

impl Spread {
    /// The spread of a posterior.
    pub fn of(posterior: &Posterior) -> Self {
        // One covariance for both (each takes an inverse and the correlation factor).
        let covariance = posterior.covariance();
        let c = com_block(&covariance);
        Self {
            com_cov: [c[0][0] as f32, c[0][1] as f32, c[1][1] as f32],
            h_std: std_of(&covariance)[2] as f32,
            com_misfit_var: posterior.com_misfit_var as f32,
            com_drift_var: posterior.com_path_variance() as f32,
        }
    }

    /// What the COM's spread is made of (see [`ComSpreadParts`]).
    pub fn com_parts(&self) -> ComSpreadParts {
        let [xx, _, yy] = self.com_cov.map(f64::from);
        ComSpreadParts::of(
            (xx + yy) / 2.0,
            f64::from(self.com_misfit_var),
            f64::from(self.com_drift_var),
        )
    }

    /// Standard deviations of `[com_x, com_y, h]`, metres.
    pub fn std(&self) -> [f64; 3] {
        let [xx, _, yy] = self.com_cov.map(f64::from);
        [
            xx.max(0.0).sqrt(),
            yy.max(0.0).sqrt(),
            f64::from(self.h_std),
        ]
    }

    /// The COM's 95 % ellipse: half-axes (metres, major first) and the major axis's angle in the
    /// object frame.
    pub fn ellipse_95(&self) -> ([f64; 2], f64) {
        let [xx, xy, yy] = self.com_cov.map(f64::from);
        ellipse_95([[xx, xy], [xy, yy]])
    }
}

/// The 95 % ellipse of a 2-D Gaussian with covariance `c`: its half-axes (metres, major first) and
/// the major axis's angle from the x axis (radians).
pub fn ellipse_95(c: [[f64; 2]; 2]) -> ([f64; 2], f64) {
    let (a, b, d) = (c[0][0], c[0][1], c[1][1]);
    let mean = (a + d) / 2.0;
    let spread = (((a - d) / 2.0).powi(2) + b * b).sqrt();
    let (major, minor) = ((mean + spread).max(0.0), (mean - spread).max(0.0));
    let angle = 0.5 * math::atan2(2.0 * b, a - d);
    (
        [(CHI2_2DOF_95 * major).sqrt(), (CHI2_2DOF_95 * minor).sqrt()],
        angle,
    )
}

/// The COM offset's 2 × 2 block of a covariance of `[com_x, com_y, h]`.
pub fn com_block(c: &Matrix3<f64>) -> [[f64; 2]; 2] {
    [[c[(0, 0)], c[(0, 1)]], [c[(1, 0)], c[(1, 1)]]]
}

/// The standard deviations on a covariance's diagonal.
pub fn std_of(c: &Matrix3<f64>) -> [f64; 3] {
    [0, 1, 2].map(|i| c[(i, i)].max(0.0).sqrt())
}

/// `θ_online` as the vector `[com_x, com_y, h]` the posterior works in.
pub(super) fn vector(theta: &OnlineParams) -> Vector3<f64> {
    Vector3::from(theta.to_array())
}

#[cfg(test)]
mod tests;
