//! `pushlab eval --best-fit` over an evaluation: each online push's best `θ_online` with the
//! combined and the physics-only model (`best_fit`), and, when θ was carried from push to push of
//! one object, the best `θ` over all of that object's pushes at once — what several pushes on
//! different faces allow the model, beside what carried online learning reached.

use super::best_fit::{BestFit, ObjectBestFit, best_fit};
use super::data::UsedRecording;
use super::evaluate::{EvalOptions, Evaluation, physics_model};
use crate::model::{CombinedModel, DEFAULT_CONTACT_TOLERANCE, OnlineModel, Sample};

impl Evaluation {
    /// Finds, for every online push, the `θ_online` that fits the whole push best with the combined
    /// model and, when the evaluation ran it, the physics-only model (`best_fit`; `online` and
    /// `options` are the evaluation's own): what no online learner with each model can beat on that
    /// push. With θ carried (`options.carry`), also the combined model's best θ over each chain of
    /// pushes that went on from one another (`object_best_fits`). `progress(done, total)` is told
    /// after each fit; `false` when `cancelled` stopped it (the fits done are kept).
    pub fn find_best_fits(
        &mut self,
        model: &CombinedModel,
        online: &[UsedRecording],
        options: &EvalOptions,
        progress: &mut dyn FnMut(usize, usize),
        cancelled: &dyn Fn() -> bool,
    ) -> bool {
        let (horizon, scale) = (model.horizon(), model.loss_scale());
        let chains = if options.carry {
            chains(self)
        } else {
            Vec::new()
        };
        let total = self.trajectories.len() + self.physics_pushes.len() + chains.len();
        let mut done = 0;
        let mut step = |done: &mut usize| {
            *done += 1;
            progress(*done, total);
            !cancelled()
        };
        for run in &mut self.trajectories {
            let used = &online[run.recording];
            run.best_fit = push_best_fit(run.run.model().as_ref(), used, horizon, cancelled);
            if !step(&mut done) {
                return false;
            }
        }
        let tolerance = options.physics.unwrap_or(DEFAULT_CONTACT_TOLERANCE);
        for push in &mut self.physics_pushes {
            let used = &online[push.recording];
            if let Ok(physics) = physics_model(&used.recording, scale, tolerance) {
                push.best_fit = push_best_fit(&physics, used, horizon, cancelled);
            }
            if !step(&mut done) {
                return false;
            }
        }
        self.object_best_fits.clear();
        for chain in chains {
            // Every push of a chain is of one object: the first one's model is all of theirs.
            let learner = self.trajectories[chain[0]].run.model().clone();
            let samples: Vec<Sample> = (chain.iter())
                .flat_map(|&t| online[self.trajectories[t].recording].samples(horizon))
                .collect();
            self.object_best_fits.push(ObjectBestFit {
                recordings: chain
                    .iter()
                    .map(|&t| self.trajectories[t].recording)
                    .collect(),
                fit: best_fit(learner.as_ref(), &samples, cancelled),
            });
            if !step(&mut done) {
                return false;
            }
        }
        true
    }
}

/// The chains of carried pushes, as indices into the evaluation's trajectories: a push that did
/// not go on from another starts one, each that did joins the one before it.
fn chains(evaluation: &Evaluation) -> Vec<Vec<usize>> {
    let mut chains: Vec<Vec<usize>> = Vec::new();
    for (t, run) in evaluation.trajectories.iter().enumerate() {
        match chains.last_mut() {
            Some(chain) if run.continued => chain.push(t),
            _ => chains.push(vec![t]),
        }
    }
    chains
}

/// The best `θ_online` for one recording's push with `learner` (the combined model bound to its
/// object, or its physics-only model) at `horizon`, over the samples its online runs learn from:
/// what `eval --best-fit` and the Python package's `model.best_fit` report.
pub fn push_best_fit(
    learner: &dyn OnlineModel,
    used: &UsedRecording,
    horizon: usize,
    cancelled: &dyn Fn() -> bool,
) -> Option<BestFit> {
    best_fit(learner, &used.samples(horizon), cancelled)
}
