//! What a push not yet made would tell about `θ_online`: its frames' information, and the posterior
//! it would leave.
//!
//! The posterior's information is `Σ JᵀJ` over the frames learned, weighed by `1 / (s² k c)`
//! ([`Posterior::frame_weight`]). A push's Jacobians depend on where the pusher touches the object
//! and how it moves, not on what the object then does, so they can be summed *before* the push, along
//! the motion the model predicts for it (`inspect::next_push`). Added to what the posterior knows —
//! forgotten as the push's frames would forget it — they give the covariance the posterior would
//! have after the push if the model is right: the Fisher information of the push, the classical
//! rule for choosing the next experiment (an "optimal design").
//!
//! What it cannot foresee: the noise the push will show (`s²` and `c` are taken as they are now),
//! and how far the estimate will still slide (the path drift of [`Posterior::covariance`]). The
//! model's COM misfit, a bias no push reveals, is kept in: no push is expected to shrink the COM's
//! spread below it.

use nalgebra::Matrix3;

use super::{KEEP, Posterior, com_block};
use crate::model::Linearization;

/// The information of a push's frames about `[com_x, com_y, h]`: `Σ JᵀJ` of their linearisations,
/// the earlier frames forgotten as the posterior forgets them, per square metre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PushInformation {
    jtj: Matrix3<f64>,
    frames: usize,
}

impl Default for PushInformation {
    fn default() -> Self {
        Self::none()
    }
}

impl PushInformation {
    /// No frames: a push that would not touch the object.
    pub fn none() -> Self {
        Self {
            jtj: Matrix3::zeros(),
            frames: 0,
        }
    }

    /// Takes in one more frame (a frame whose Jacobian is not finite is left out, as the posterior
    /// leaves it out).
    pub fn add(&mut self, linearization: &Linearization) {
        let j = Matrix3::from_fn(|i, k| linearization.jacobian[i][k]);
        let jtj = j.transpose() * j;
        if jtj.iter().all(|x| x.is_finite()) {
            self.jtj = self.jtj * KEEP + jtj;
            self.frames += 1;
        }
    }

    /// Frames taken in.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// `Σ JᵀJ`, the frames forgotten as they would be by the push's end.
    pub fn jtj(&self) -> &Matrix3<f64> {
        &self.jtj
    }
}

impl Posterior {
    /// The spread of `[com_x, com_y, h]` about the mode after `push` were learned too, square
    /// metres: `((JᵀJ·keepⁿ + push) / (s² k c) + Λ₀)⁻¹` at today's frame weight, where the
    /// posterior's frames are forgotten over the push's `n` frames. With no push, the spread now.
    pub fn mode_covariance_after(&self, push: &PushInformation) -> Matrix3<f64> {
        let forgotten = KEEP.powi(i32::try_from(push.frames).unwrap_or(i32::MAX));
        let information = (self.jtj * forgotten + push.jtj) * self.frame_weight()
            + Matrix3::from_diagonal(&self.prior_precision.into());
        information.try_inverse().unwrap_or_else(|| {
            Matrix3::from_diagonal(&self.prior_precision.map(|p| 1.0 / p).into())
        })
    }

    /// The COM's covariance after `push` were learned too, if the model is right: the block of
    /// [`Posterior::mode_covariance_after`] plus the model's COM misfit on each component, square
    /// metres. What a suggested push is ranked by.
    pub fn com_covariance_after(&self, push: &PushInformation) -> [[f64; 2]; 2] {
        let mut c = com_block(&self.mode_covariance_after(push));
        c[0][0] += self.com_misfit_var;
        c[1][1] += self.com_misfit_var;
        c
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::model::{ObjectMotion, OnlineParams, Prediction};
    use crate::rng::SplitMix64;

    fn frame(jacobian: [[f64; 3]; 3]) -> Linearization {
        Linearization {
            prediction: Prediction {
                motion: ObjectMotion::default(),
                contact: None,
                contact_motion: None,
            },
            residual: [0.0; 3],
            jacobian,
        }
    }

    fn theta() -> OnlineParams {
        OnlineParams {
            com_offset: [0.0, 0.0],
            h: 0.05,
        }
    }

    #[test]
    fn a_push_expected_holds_the_frames_the_posterior_would_learn() {
        // The push's frames summed ahead, with the posterior's frames forgotten over them, are the
        // information the posterior holds once it learned them: the forecast differs from the
        // posterior after only by the frame weight (the noise the push will show), taken as now.
        let mut rng = SplitMix64::new(7);
        let mut frame_at = |i: usize| {
            let a = 0.3 * i as f64;
            Linearization {
                residual: [rng.normal(), rng.normal(), rng.normal()],
                ..frame([
                    [40.0 * a.cos(), 40.0 * a.sin(), 3.0],
                    [-10.0, 25.0, 0.0],
                    [0.0, 5.0 * a.sin(), 30.0],
                ])
            }
        };
        let before = (0..200).fold(Posterior::prior(&theta(), 1), |p, i| {
            p.with(&frame_at(i % 3), &theta())
        });
        let mut push = PushInformation::none();
        let mut after = before;
        for i in 0..400 {
            let f = frame_at(i);
            push.add(&f);
            after = after.with(&f, &theta());
        }
        assert_eq!(push.frames(), 400);
        let forecast = before.jtj * KEEP.powi(400) + push.jtj;
        for (f, l) in forecast.iter().zip(after.jtj.iter()) {
            assert!((f - l).abs() <= 1e-12 * l.abs().max(1.0), "{f} vs {l}");
        }
        // At the frame weight the posterior then has, the forecast is its spread.
        let at_weight = |w: f64| {
            (forecast * w + Matrix3::from_diagonal(&before.prior_precision.into()))
                .try_inverse()
                .unwrap()
        };
        let learned = after.mode_covariance();
        let expected = at_weight(after.frame_weight());
        assert!((expected - learned).norm() <= 1e-9 * learned.norm());
        let now = before.mode_covariance_after(&PushInformation::none());
        assert!((now - before.mode_covariance()).norm() <= 1e-12 * now.norm());
        let forecast_now = before.mode_covariance_after(&push);
        assert!((forecast_now - at_weight(before.frame_weight())).norm() <= 1e-12 * now.norm());
        assert!(now.norm() > 2.0 * forecast_now.norm());
    }

    #[test]
    fn a_push_that_sees_the_unseen_direction_shrinks_the_com_more_than_one_that_repeats() {
        // Frames that only ever saw com_x: another such push barely helps, one that sees com_y does.
        let sees_x = frame([[30.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 20.0]]);
        let sees_y = frame([[0.0, 0.0, 0.0], [0.0, 30.0, 0.0], [0.0, 0.0, 20.0]]);
        let now = (0..100).fold(Posterior::prior(&theta(), 1), |p, _| {
            p.with(&sees_x, &theta())
        });
        let push_of = |f: &Linearization| {
            let mut push = PushInformation::none();
            (0..100).for_each(|_| push.add(f));
            push
        };
        let trace = |c: [[f64; 2]; 2]| c[0][0] + c[1][1];
        let repeat = trace(now.com_covariance_after(&push_of(&sees_x)));
        let new = trace(now.com_covariance_after(&push_of(&sees_y)));
        let nothing = trace(now.com_covariance_after(&PushInformation::none()));
        assert!(
            repeat < nothing && new < repeat / 10.0,
            "{nothing} {repeat} {new}"
        );
    }

    #[test]
    fn no_push_shrinks_the_com_below_the_models_misfit() {
        let sees_all = frame([[300.0, 0.0, 0.0], [0.0, 300.0, 0.0], [0.0, 0.0, 200.0]]);
        let now = Posterior::prior(&theta(), 1).with_com_misfit(0.004);
        let mut push = PushInformation::none();
        (0..1000).for_each(|_| push.add(&sees_all));
        let c = now.com_covariance_after(&push);
        assert!(c[0][0] >= 0.004 * 0.004 && c[0][0] < 0.004 * 0.004 * 1.01);
    }

    #[test]
    fn a_frame_that_is_not_finite_is_left_out() {
        let mut push = PushInformation::none();
        push.add(&frame([[f64::NAN, 0.0, 0.0], [0.0; 3], [0.0; 3]]));
        assert_eq!(push, PushInformation::none());
    }
}
