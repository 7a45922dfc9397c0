//! One step of online learning (Algorithm 1): predict with `θ_online(t)`, take the frame into the
//! posterior, and update `θ_online` with the configured optimiser — the paper's gradient descent, done
//! by the model itself, or the Gauss–Newton (recursive least-squares) step built from the posterior's
//! information. A pure function of (model, sample, state, rule): a run that replays it gets the same
//! numbers bit for bit.

use nalgebra::{Matrix3, Vector3};

use super::config::{OnlineConfig, Optimizer};
use super::uncertainty::{Posterior, vector};
use crate::model::{Linearization, Loss, OnlineModel, OnlineParams, OnlineStep, Sample};

/// `θ_online` and what the frames seen so far say about it: what online learning carries from frame
/// to frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OnlineState {
    pub theta: OnlineParams,
    pub posterior: Posterior,
}

impl OnlineState {
    /// The start of a trajectory learned with `optimizer`: `θ_online(0)` and the prior, with the
    /// model's COM misfit for that optimiser (`model::ComMisfit`, per `θ_online(0)`'s `h`).
    pub fn start<M: OnlineModel + ?Sized>(model: &M, optimizer: Optimizer) -> Self {
        Self::believing(model, optimizer, model.theta0())
    }

    /// [`OnlineState::start`] believing the COM `shift` (object frame, metres) from `θ_online(0)`'s,
    /// kept physical on the object: θ and the prior's centre both there, the prior as wide. Whether
    /// online learning finds a COM it was not given — on real pushes, whose true COM is where
    /// `θ_online(0)` puts it, the one way to see it.
    pub fn start_with_com_shift<M: OnlineModel + ?Sized>(
        model: &M,
        optimizer: Optimizer,
        shift: [f64; 2],
    ) -> Self {
        let theta0 = model.theta0();
        let theta = model.keep_physical(OnlineParams {
            com_offset: [
                theta0.com_offset[0] + shift[0],
                theta0.com_offset[1] + shift[1],
            ],
            ..theta0
        });
        Self::believing(model, optimizer, theta)
    }

    /// θ and the prior centred at it.
    fn believing<M: OnlineModel + ?Sized>(
        model: &M,
        optimizer: Optimizer,
        theta: OnlineParams,
    ) -> Self {
        Self {
            theta,
            posterior: Posterior::prior(&theta, model.horizon())
                .with_com_misfit(com_misfit_m(model, optimizer)),
        }
    }

    /// The start from a given `θ` (a user's steering) with the posterior kept.
    pub fn at(theta: OnlineParams, posterior: Posterior) -> Self {
        let theta = theta.clamped();
        Self {
            theta,
            posterior: posterior.at(&theta),
        }
    }
}

/// The model's COM misfit for `optimizer` in metres: its `per_h` figure times `θ_online(0)`'s `h` on
/// this object. What the posterior adds to the COM's spread (see `model::ComMisfit`).
pub fn com_misfit_m<M: OnlineModel + ?Sized>(model: &M, optimizer: Optimizer) -> f64 {
    let misfit = model.com_misfit();
    let per_h = match optimizer {
        Optimizer::Gd => misfit.gd_per_h,
        Optimizer::GaussNewton => misfit.gauss_newton_per_h,
    };
    per_h * model.theta0().h
}

/// One online step from `state` with the configured optimiser: the prediction with `state.theta`
/// (its loss and gradient), `θ` after the update, and the posterior with this frame taken in. A pure
/// function, like [`OnlineModel::online_step`].
pub fn learn_step<M: OnlineModel + ?Sized>(
    model: &M,
    sample: &Sample,
    state: &OnlineState,
    config: &OnlineConfig,
) -> (OnlineStep, OnlineState) {
    let mut next = *state;
    let step = learn_step_in_place(model, sample, &mut next, config);
    (step, next)
}

/// [`learn_step`] with `state` updated in place: the same numbers, bit for bit, without the copies of
/// the posterior (about 1.4 kB, mostly its score batches) that moving it by value costs every frame.
pub fn learn_step_in_place<M: OnlineModel + ?Sized>(
    model: &M,
    sample: &Sample,
    state: &mut OnlineState,
    config: &OnlineConfig,
) -> OnlineStep {
    let step = learn_step_on(model, sample, state.theta, &mut state.posterior, config);
    state.theta = step.theta_after;
    step
}

/// The step from `theta` with `posterior` (the frames before this one) updated in place to take this
/// frame in and to sit at `θ` after the step, which the returned step holds.
pub(super) fn learn_step_on<M: OnlineModel + ?Sized>(
    model: &M,
    sample: &Sample,
    theta: OnlineParams,
    posterior: &mut Posterior,
    config: &OnlineConfig,
) -> OnlineStep {
    let theta = model.keep_physical(theta);
    // Gradient descent's step does not depend on the posterior: it is taken together with the
    // linearisation, which shares its first forward pass.
    let (linearization, descent_step) = match config.optimizer {
        Optimizer::Gd => {
            let (linearization, step) = model.linearize_and_step(sample, &theta, &config.descent());
            (linearization, Some(step))
        }
        Optimizer::GaussNewton => (model.linearize(sample, &theta), None),
    };
    posterior.take_in(&linearization, &theta);
    let mut step = match descent_step {
        Some(step) => step,
        None => gauss_newton_step(model, sample, &theta, &linearization, posterior, config),
    };
    step.theta_after = model.keep_physical(step.theta_after);
    posterior.move_to(&step.theta_after);
    step
}

/// The Gauss–Newton (recursive least-squares) step: `θ − I⁻¹ Jᵀr / (s² k c)` with `I` the information
/// after this frame, kept inside the bounds of `h` and the COM; a step that is not finite is not
/// taken. With `config.steps == 0` nothing is learned (the fixed model).
fn gauss_newton_step<M: OnlineModel + ?Sized>(
    model: &M,
    sample: &Sample,
    theta: &OnlineParams,
    linearization: &Linearization,
    posterior: &Posterior,
    config: &OnlineConfig,
) -> OnlineStep {
    let j = Matrix3::from_fn(|i, k| linearization.jacobian[i][k]);
    let r = Vector3::from(linearization.residual);
    let jtr = j.transpose() * r;
    let gradient = (2.0 * jtr).into();
    let mut after = *theta;
    let weight = posterior.frame_weight();
    if config.steps > 0
        && let Some(inverse) = posterior.information_at(weight).try_inverse()
    {
        let next = vector(theta) - inverse * jtr * weight;
        if next.iter().all(|t| t.is_finite()) {
            after = OnlineParams {
                com_offset: [next[0], next[1]],
                h: next[2],
            }
            .clamped();
        }
    }
    OnlineStep {
        theta_before: *theta,
        prediction: linearization.prediction,
        loss: Loss::of(
            &linearization.prediction.motion,
            &sample.target,
            &model.loss_scale(),
        ),
        gradient,
        theta_after: after,
    }
}
