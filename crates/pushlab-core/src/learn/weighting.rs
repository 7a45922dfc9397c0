//! Weighing the combined model against Lynch's model alone, online: a Bayesian model average with
//! forgetting.
//!
//! Why: only `θ_online = (COM offset, h)` is learned online, so a network that is wrong for an
//! object it never saw stays wrong for the whole push, and there the combined model can predict
//! worse than physics alone (MIT ellip1 held out). Both models learn their own θ beside each other;
//! at each frame the prediction is `w · combined + (1 − w) · physics`, `w` the posterior
//! probability that the combined model is the one predicting this object, from how well each
//! predicted the frames just seen. The translation and the rotation have a weight each: on MuJoCo
//! pushes the combined model predicts the translation better and physics alone the rotation, and
//! one weight for both lost a few per cent on one of them wherever that happened
//! (`experiments/weighting`).
//!
//! The evidence for one frame is the log-likelihood ratio of the two predictions under the loss's
//! Gaussian (`(ℓ_physics − ℓ_combined) / 2`, the losses normalised by the offline σ, eq. 8;
//! `ℓ_pos,x + ℓ_pos,y` for the translation, `ℓ_rot` for the rotation), counted
//! per tenth of a second rather than per frame so that a 250 Hz push is not 25 times surer than a
//! 10 Hz one, and forgotten with a half-life in seconds so that the weight follows the push as it
//! changes. Both count the time of the frames taken in: where θ was held over frames (labelled
//! bad, or a controller's pusher away from the object), nothing was seen, so nothing is learned or
//! forgotten over them. Counted over the gap, the first frame after a controller went round the
//! object stood for the whole time away and pinned the weight to one model (2026-12-04: measured
//! in `docs/src/control.md`). The log-odds start at the prior and are kept within
//! ±[`MAX_LOG_ODDS`] so that the losing model can come back within a few half-lives. The blended prediction's squared error is
//! never above the weighted mean of the two models' (it is convex), which is what keeps the
//! average near the better of the two.
//!
//! The weight at frame k uses only the losses of frames before k — what θ at frame k was learned
//! from — so it is as online as θ is. The weights are a pure function of the two runs' frames
//! (`OnlineRun::weigh_against` takes them in), so a rewound run recomputes its weights from the
//! frames that stay.

use crate::math;
use serde::{Deserialize, Serialize};

use crate::model::{FrameLoss, Loss, ObjectMotion};

/// The log-odds are kept within ± this (a weight between 0.0025 and 0.9975).
pub const MAX_LOG_ODDS: f64 = 6.0;

/// The time one frame's evidence is counted per, seconds.
const EVIDENCE_UNIT_S: f64 = 0.1;

/// When a frame taken in was, and the frame before it in its trajectory (`None`: not known, or
/// the first): the frame's evidence counts, and the evidence before it is forgotten, over its own
/// interval only, not over frames before it that were not taken in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameTime {
    pub time: f64,
    pub previous: Option<f64>,
}

impl From<f64> for FrameTime {
    /// A frame of a trajectory whose every frame is taken in: its interval is the time since the
    /// last one.
    fn from(time: f64) -> Self {
        Self {
            time,
            previous: None,
        }
    }
}

/// How the two models are weighed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct WeightConfig {
    /// Evidence this old counts half, seconds.
    pub half_life_s: f64,
    /// The weight of the combined model before any frame is seen.
    pub prior: f64,
}

/// Chosen on the second draw of MuJoCo pushes (`experiments/weighting/run`): of half-lives 0.25–4 s
/// and priors 0.5 and 0.8, the lowest worst ratio of weighted to the better of the two models.
/// A prior of 0.5 lost 3–6 % in translation to the combined model alone, in the first frames,
/// before the evidence that the network predicts well came in.
impl Default for WeightConfig {
    fn default() -> Self {
        Self {
            half_life_s: 2.0,
            prior: 0.8,
        }
    }
}

/// The combined model's weights, one for the translation and one for the rotation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Weights {
    pub pos: f64,
    pub rot: f64,
}

impl Weights {
    /// The weighted prediction: the combined model's and the physics-only model's motions mixed
    /// by these weights. What the weighting scores, and what a controller plans with.
    pub fn blend(&self, combined: &ObjectMotion, physics: &ObjectMotion) -> ObjectMotion {
        let mix = |w: f64, c: f64, p: f64| w * c + (1.0 - w) * p;
        ObjectMotion {
            translation: [
                mix(self.pos, combined.translation[0], physics.translation[0]),
                mix(self.pos, combined.translation[1], physics.translation[1]),
            ],
            rotation: mix(self.rot, combined.rotation, physics.rotation),
        }
    }
}

/// One frame of the weighted run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct WeightedFrame {
    /// The recording's frame.
    pub frame: usize,
    /// The combined model's weights used to predict this frame's sample.
    pub weight: Weights,
    /// The blended prediction's losses.
    pub loss: FrameLoss,
}

/// The weight of the combined model over a push, frame by frame.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelWeight {
    config: WeightConfig,
    /// The evidence for the combined model's translation and rotation, forgotten, in units of
    /// [`EVIDENCE_UNIT_S`].
    evidence: [f64; 2],
    /// The time of the last frame taken in, seconds.
    last_time: Option<f64>,
    /// The evidence a push starts with (its own prior, or carried on).
    start_evidence: [f64; 2],
    frames: Vec<WeightedFrame>,
    /// The evidence and time after each frame taken in: where a rewind goes back to.
    after: Vec<([f64; 2], f64)>,
}

impl ModelWeight {
    /// A push starting at `config`'s prior.
    pub fn new(config: WeightConfig) -> Self {
        Self {
            config,
            evidence: [0.0; 2],
            last_time: None,
            start_evidence: [0.0; 2],
            frames: Vec::new(),
            after: Vec::new(),
        }
    }

    /// A push going on from where `from` (an earlier push of the same object) ended: what it
    /// learned of which model predicts this object carries on, as θ does.
    pub fn continuing(from: &ModelWeight) -> Self {
        Self {
            evidence: from.evidence,
            start_evidence: from.evidence,
            ..Self::new(from.config)
        }
    }

    /// A weight starting where this one started (its prior, or what it was carried on from), with
    /// nothing taken in: what the same push weighed again from its start begins with.
    pub fn restarted(&self) -> Self {
        Self {
            evidence: self.start_evidence,
            start_evidence: self.start_evidence,
            ..Self::new(self.config)
        }
    }

    /// The combined model's weights now: what predicts the next frame.
    pub fn weight(&self) -> Weights {
        let prior = self.config.prior.clamp(1e-6, 1.0 - 1e-6);
        let of = |evidence: f64| {
            let log_odds = math::ln(prior / (1.0 - prior)) + evidence;
            1.0 / (1.0 + math::exp(-log_odds.clamp(-MAX_LOG_ODDS, MAX_LOG_ODDS)))
        };
        Weights {
            pos: of(self.evidence[0]),
            rot: of(self.evidence[1]),
        }
    }

    /// The weights in effect at `frame`: those its sample was predicted with, or, at a frame not
    /// taken in (θ held there, or not learned yet), those the next frame taken in is predicted with.
    pub fn at(&self, frame: usize) -> Weights {
        let next = self.frames.partition_point(|f| f.frame < frame);
        self.frames
            .get(next)
            .map_or_else(|| self.weight(), |f| f.weight)
    }

    /// The half-life of the evidence, seconds.
    pub fn half_life_s(&self) -> f64 {
        self.config.half_life_s
    }

    /// The frames taken in, in order.
    pub fn frames(&self) -> &[WeightedFrame] {
        &self.frames
    }

    /// Takes in the sample of `frame` at `when` (seconds): predicts it with the weight now, then
    /// weighs the two models by how each predicted it. `combined` and `physics` are the two
    /// models' predictions, `truth` the motion measured, each model's loss normalised as the runs'.
    pub fn take(
        &mut self,
        frame: usize,
        when: impl Into<FrameTime>,
        combined: &ObjectMotion,
        physics: &ObjectMotion,
        truth: &ObjectMotion,
        scale: &crate::model::LossScale,
    ) -> WeightedFrame {
        let weight = self.weight();
        let blended = weight.blend(combined, physics);
        let loss = FrameLoss::of(&Loss::of(&blended, truth, scale));
        let FrameTime { time, previous } = when.into();
        let dt = self
            .last_time
            .map_or(EVIDENCE_UNIT_S, |t| (time - t).max(0.0));
        // The frame's own interval: after frames not taken in, `dt` spans them too.
        let counted = previous.map_or(dt, |p| dt.min((time - p).max(0.0)));
        let forget = math::powf(0.5f64, counted / self.config.half_life_s.max(1e-9));
        let (c, p) = (
            Loss::of(combined, truth, scale),
            Loss::of(physics, truth, scale),
        );
        let ratios = [
            (p.pos_x + p.pos_y - c.pos_x - c.pos_y) / 2.0,
            (p.rot - c.rot) / 2.0,
        ];
        let limit = MAX_LOG_ODDS * 2.0;
        for (evidence, ratio) in self.evidence.iter_mut().zip(ratios) {
            *evidence =
                (forget * *evidence + ratio * counted / EVIDENCE_UNIT_S).clamp(-limit, limit);
        }
        self.last_time = Some(time);
        let taken = WeightedFrame {
            frame,
            weight,
            loss,
        };
        self.frames.push(taken);
        self.after.push((self.evidence, time));
        taken
    }

    /// The frames from `frame` on forgotten, as when a run is rewound there: the weight is what it
    /// was before `frame` was taken in.
    pub fn rewind_to(&mut self, frame: usize) {
        let keep = self.frames.partition_point(|f| f.frame < frame);
        self.frames.truncate(keep);
        self.after.truncate(keep);
        (self.evidence, self.last_time) = match self.after.last() {
            Some(&(evidence, time)) => (evidence, Some(time)),
            None => (self.start_evidence, None),
        };
    }
}

#[cfg(test)]
mod tests;
