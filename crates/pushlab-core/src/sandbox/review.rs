//! The score card a reveal shows: how far the student's guess and the model's estimate are from
//! the hidden COM, how sure the model was, what the pushes cost, and, for each push made, what the
//! next-push ranking (`pushlab suggest --grid`, the app's Steer tab) would have chosen instead from
//! where learning stood when it began — the COM uncertainty its best grid push was expected to
//! leave against the push made, both by the ranking's own rule ([`crate::experiment::suggest`]).

use nalgebra::{Point2, Vector2};
use serde::Serialize;

use crate::experiment::suggest::{Criterion, PushGrid, Suggestion, rank};
use crate::geometry::OutlineError;
use crate::learn::{OnlineState, Posterior, PushInformation};
use crate::model::OnlineModel;
use crate::recording::Recording;

/// How uncertainty is measured on the card: the ranking's default criterion (the COM ellipse's
/// area, as a σ).
pub const CRITERION: Criterion = Criterion::Area;

/// One push made, against the ranking's choice from where learning stood before it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PushReview {
    /// The push's number, from 0.
    pub push: usize,
    /// The COM's uncertainty before it, metres.
    pub com_std_before_m: f64,
    /// The uncertainty the push made was expected to leave (played through the model with θ as it
    /// was, as the ranking plays its candidates), metres.
    pub made_com_std_after_m: f64,
    /// The grid push the ranking would have chosen, and what it was expected to leave; `None`
    /// when no grid push could be laid out on the object.
    pub ranked_best: Option<Suggestion>,
}

/// Reviews a push made: `learner` bound to the object, `state` learning's when the push began,
/// `push` its recording.
pub fn review_push(
    learner: &dyn OnlineModel,
    horizon: usize,
    state: &OnlineState,
    index: usize,
    push: &Recording,
) -> Result<PushReview, OutlineError> {
    let made = rank(learner, horizon, state, &[(0, push)], CRITERION)?;
    let grid = PushGrid::default().pushes(push)?;
    let candidates: Vec<(usize, &Recording)> = grid.pushes.iter().enumerate().collect();
    let ranked = rank(learner, horizon, state, &candidates, CRITERION)?;
    Ok(PushReview {
        push: index,
        com_std_before_m: made.com_std_now_m,
        made_com_std_after_m: made
            .suggestions
            .first()
            .map_or(made.com_std_now_m, |s| s.com_std_after_m),
        ranked_best: ranked.suggestions.into_iter().next(),
    })
}

/// The COM's uncertainty a posterior leaves by the card's criterion, metres.
pub fn com_std(posterior: &Posterior) -> f64 {
    CRITERION.std_of(posterior.com_covariance_after(&PushInformation::none()))
}

/// The score card.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScoreCard {
    /// The hidden COM offset and `h`, metres.
    pub true_com_m: [f64; 2],
    pub true_h_m: f64,
    /// The student's guess of the COM offset, and its distance from the truth; `None` without one.
    pub guess_m: Option<[f64; 2]>,
    pub guess_error_m: Option<f64>,
    /// The model's COM offset and `h` at the end, the COM's distance from the truth, and the
    /// model's own uncertainty of it (the card's criterion), metres.
    pub model_com_m: [f64; 2],
    pub model_h_m: f64,
    pub model_error_m: f64,
    pub model_com_std_m: f64,
    /// How far the model's COM is from the truth in its own σ: about 2 or less is honest.
    pub model_error_in_std: f64,
    pub pushes: usize,
    /// How far the pusher went while it pressed on the object, over every push, metres.
    pub push_length_m: f64,
    pub reviews: Vec<PushReview>,
}

/// What the card is made from.
pub struct Scored<'a> {
    pub true_com_m: [f64; 2],
    pub true_h_m: f64,
    pub guess_m: Option<[f64; 2]>,
    /// Learning's state after the last push.
    pub end: &'a OnlineState,
    pub push_length_m: f64,
    pub reviews: Vec<PushReview>,
}

impl ScoreCard {
    /// The card of a session (see [`Scored`]).
    pub fn of(scored: Scored<'_>) -> Self {
        let truth = Vector2::from(scored.true_com_m);
        let distance = |c: [f64; 2]| (Vector2::from(c) - truth).norm();
        let model = scored.end.theta.com_offset;
        let model_error = distance(model);
        let model_std = com_std(&scored.end.posterior);
        Self {
            true_com_m: scored.true_com_m,
            true_h_m: scored.true_h_m,
            guess_m: scored.guess_m,
            guess_error_m: scored.guess_m.map(distance),
            model_com_m: model,
            model_h_m: scored.end.theta.h,
            model_error_m: model_error,
            model_com_std_m: model_std,
            model_error_in_std: if model_std > 0.0 {
                model_error / model_std
            } else {
                f64::INFINITY
            },
            pushes: scored.reviews.len(),
            push_length_m: scored.push_length_m,
            reviews: scored.reviews,
        }
    }
}

/// How far a pusher went while pressing: the sum of its steps over the frames whose interval it
/// pressed in (`pressing[k]`: the interval from frame k to k + 1).
pub fn pressed_length(path: &[(f64, Point2<f64>)], pressing: &[bool]) -> f64 {
    path.windows(2)
        .zip(pressing)
        .filter(|(_, pressed)| **pressed)
        .map(|(w, _)| (w[1].1 - w[0].1).norm())
        .sum()
}
