//! Label proposals from physics: what the recording itself says about contact, sticking and slipping
//! and bad tracking, with a confidence and a reason for every frame, for a person to accept or reject.
//!
//! The rules ([`rules`]), all thresholds in standard deviations of the tracking noise that
//! [`NoiseEstimate::of`] measures on the recording itself:
//! - **contact / no contact**: the pusher's rim is within a tolerance of the object's outline. The
//!   tolerance is the gap seen while the object moves (a real setup's calibration offset, 0 in a
//!   simulation) plus [`ProposeOptions::contact_sigmas`] of the gap's noise, the larger of its spread
//!   while moving and what the position and yaw noise make of it — and at least the 98th percentile
//!   of the gaps seen while the object moves. The gap is a running median over 5 frames, so one
//!   noisy reading does not break a contact.
//! - **sticking / slipping** (frames in contact): a sticking contact keeps the contact point fixed
//!   on the object, a slipping one moves it along the outline. The drift is the least-squares
//!   velocity of the contact along the outline in the object frame, the disc's rolling taken out,
//!   over a window in which the pusher travels [`ProposeOptions::window_sigmas`] noise σ; slipping
//!   when it is [`ProposeOptions::slip_sigmas`] standard errors from zero.
//! - **bad tracking**: a step in which the object moves or turns more than the pusher's move could
//!   cause, by [`ProposeOptions::jump_sigmas`]; and, given a model's per-sample residuals, a residual
//!   [`ProposeOptions::residual_sigmas`] robust σ above its neighbours' running median, where both
//!   samples holding one frame spike (that frame is marked).
//!
//! Proposals are not labels: [`Proposals::to_labels`] turns them into a recording's labels for a
//! proposals file (`pushlab labels propose`), and the app paints one only when the user accepts it.

mod rules;
#[cfg(test)]
mod tests;

use std::ops::Range;

use crate::geometry::Outline;
use crate::labels::schema::names::{BAD_TRACKING, CONTACT, NO_CONTACT, SLIPPING, STICKING};
use crate::labels::{RecordingLabels, Segment};
use crate::model::LossScale;
use crate::recording::Recording;
use crate::trajectory::Trajectory;

pub use rules::NoiseEstimate;

/// The thresholds, each in standard deviations of an estimated noise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProposeOptions {
    /// Contact while the gap is within its offset plus this many σ of its noise.
    pub contact_sigmas: f64,
    /// Slipping while the pusher's drift over the object is this many standard errors from zero.
    pub slip_sigmas: f64,
    /// The drift's window: the pusher travels this many σ of the relative position noise over it.
    pub window_sigmas: f64,
    /// Bad tracking where a step exceeds what the pusher explains by this many σ.
    pub jump_sigmas: f64,
    /// Bad tracking where a model's residual is this many robust σ above the median.
    pub residual_sigmas: f64,
}

impl Default for ProposeOptions {
    fn default() -> Self {
        Self {
            contact_sigmas: 3.0,
            slip_sigmas: 3.0,
            window_sigmas: 40.0,
            jump_sigmas: 6.0,
            residual_sigmas: 6.0,
        }
    }
}

/// A model's residuals: the loss of the sample from each frame `t` to `t + horizon`.
#[derive(Clone, Copy, Debug)]
pub struct Residuals<'a> {
    pub losses: &'a [f64],
    pub horizon: usize,
    /// The σ the losses are normalised by: with the tracking noise they say how large a residual
    /// the noise alone makes, below which nothing is a spike (on noise-free data the model's
    /// smallest kink would otherwise be many σ).
    pub scale: LossScale,
}

/// What was measured at one frame (`f32`: a million-frame recording keeps them all).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameEvidence {
    /// The pusher's rim to the outline, running median, metres (negative: overlap).
    pub gap: f32,
    /// The pusher's drift over the object, metres per second; NaN out of contact.
    pub drift: f32,
    /// The drift in standard errors from zero; NaN out of contact.
    pub drift_z: f32,
    /// The pusher's speed over the drift's window, metres per second; NaN out of contact.
    pub pusher_speed: f32,
    /// How many σ the steps into and out of the frame exceed what the pusher explains (0: not).
    pub jump_z: f32,
    /// The largest robust z-score of the residuals of the samples touching the frame; NaN without
    /// residuals.
    pub residual_z: f32,
    /// How sure the contact / no contact proposal is (0.5–1).
    pub contact_confidence: f32,
    /// How sure the sticking / slipping proposal is; 0 out of contact.
    pub mode_confidence: f32,
    /// How sure the bad-tracking proposal is; 0 where none.
    pub bad_confidence: f32,
}

/// One proposed segment.
#[derive(Clone, Debug, PartialEq)]
pub struct Proposal {
    /// A label of the default schema.
    pub label: &'static str,
    /// Half-open, like a segment.
    pub frames: Range<usize>,
    /// Mean confidence over its frames (0.5–1).
    pub confidence: f32,
}

/// Everything proposed for one recording, with the numbers behind it.
#[derive(Clone, Debug, PartialEq)]
pub struct Proposals {
    /// The tracking noise estimated on the recording.
    pub noise: NoiseEstimate,
    /// The gap while the object moves (median), metres.
    pub gap_offset: f64,
    /// The gap's noise, metres.
    pub gap_sd: f64,
    /// Contact while the gap is at most this, metres.
    pub contact_tolerance: f64,
    /// Half-width of the drift's window, frames.
    pub window: usize,
    /// The residuals' horizon, when residuals were given.
    pub residual_horizon: Option<usize>,
    /// The thresholds used.
    pub options: ProposeOptions,
    /// One per frame.
    pub evidence: Vec<FrameEvidence>,
    /// Sorted by start, then label.
    pub segments: Vec<Proposal>,
}

/// Why no proposals could be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProposeError {
    #[error(
        "{recording}: the object's outline is unusable ({reason}), so contact cannot be judged"
    )]
    Outline { recording: String, reason: String },
    #[error("stopped before the proposals were done")]
    Cancelled,
}

/// Proposes labels for a loaded recording, with its setting's outline and pusher.
pub fn propose_for(
    recording: &Recording,
    residuals: Option<Residuals<'_>>,
    options: &ProposeOptions,
    progress: &mut dyn FnMut(f32) -> bool,
) -> Result<Proposals, ProposeError> {
    crate::slices::finish(propose_for_in_slices(
        recording, residuals, options, progress,
    ))
}

/// [`propose_for`] in slices (`crate::slices`): it pauses every 4,096 frames of its costliest pass
/// and between its stages.
pub async fn propose_for_in_slices(
    recording: &Recording,
    residuals: Option<Residuals<'_>>,
    options: &ProposeOptions,
    progress: &mut dyn FnMut(f32) -> bool,
) -> Result<Proposals, ProposeError> {
    let outline = recording
        .setting
        .object
        .outline()
        .map_err(|e| ProposeError::Outline {
            recording: recording.source.display().to_string(),
            reason: e.to_string(),
        })?;
    propose_in_slices(
        &recording.trajectory,
        &outline,
        recording.setting.pusher_radius,
        residuals,
        options,
        progress,
    )
    .await
}

/// Proposes labels for `trajectory` of an object with `outline`, pushed by a disc of
/// `pusher_radius`. `progress` is told the fraction done now and then and stops the work by
/// returning `false`. In slices (`crate::slices`): it pauses every 4,096 frames of its gap pass
/// and between its stages.
pub async fn propose_in_slices(
    trajectory: &Trajectory,
    outline: &Outline,
    pusher_radius: f64,
    residuals: Option<Residuals<'_>>,
    options: &ProposeOptions,
    progress: &mut dyn FnMut(f32) -> bool,
) -> Result<Proposals, ProposeError> {
    let n = trajectory.len();
    let noise = NoiseEstimate::of(trajectory);
    let on = rules::pusher_on_object(trajectory, outline, pusher_radius, &mut |k| {
        progress(0.6 * k as f32 / n.max(1) as f32)
    })
    .await
    .ok_or(ProposeError::Cancelled)?;
    let raw_gap = &on.gap;

    // The drift's window: the pusher travels `window_sigmas` of the relative noise over it.
    let mut distances: Vec<f64> = on.centre.iter().map(|p| p.coords.norm()).collect();
    let arm = rules::median(&mut distances).unwrap_or(0.0);
    let relative_sd = noise.relative_sd(arm);
    let mut steps: Vec<f64> = trajectory
        .frames
        .windows(2)
        .map(|w| (w[1].robot - w[0].robot).norm())
        .collect();
    let step = rules::median(&mut steps).unwrap_or(0.0).max(1e-9);
    let window = ((options.window_sigmas * relative_sd / step / 2.0).ceil() as usize).clamp(2, 50);

    // Contact: the gap while the object moves says where contact is (and a calibration offset).
    let moving = rules::object_moves(trajectory, &noise, window, 5.0);
    let moving_gaps: Vec<f64> = raw_gap
        .iter()
        .zip(&moving)
        .filter(|(_, m)| **m)
        .map(|(g, _)| *g)
        .collect();
    let (gap_offset, spread) = if moving_gaps.len() >= 5 {
        rules::robust_spread(&moving_gaps).unwrap_or((0.0, 0.0))
    } else {
        (0.0, 0.0)
    };
    let gap_sd = spread.max(relative_sd);
    // On a real setup the gap drifts along a push (the pusher presses into the edge, the outline
    // is not exact: 0.4 mm over an MIT push, 3 MAD σ being 0.15 mm): a gap at which the object was
    // seen moving under the pusher is contact, whatever the noise says.
    let seen_pushing = rules::quantile(&moving_gaps, 0.98).unwrap_or(f64::NEG_INFINITY);
    let contact_tolerance = (gap_offset + options.contact_sigmas * gap_sd).max(seen_pushing);
    const GAP_HALF: usize = 2;
    let gap = rules::running_median(raw_gap, GAP_HALF);
    let smoothed_sd = gap_sd * 1.2533 / ((2 * GAP_HALF + 1) as f64).sqrt();
    let in_contact: Vec<bool> = gap.iter().map(|g| *g <= contact_tolerance).collect();
    if !progress(0.7) {
        return Err(ProposeError::Cancelled);
    }
    crate::slices::pause().await;

    let mut evidence: Vec<FrameEvidence> = gap
        .iter()
        .map(|&g| FrameEvidence {
            gap: g as f32,
            drift: f32::NAN,
            drift_z: f32::NAN,
            pusher_speed: f32::NAN,
            residual_z: f32::NAN,
            contact_confidence: rules::confidence((contact_tolerance - g) / smoothed_sd),
            ..FrameEvidence::default()
        })
        .collect();

    // Sticking or slipping, run of contact by run of contact.
    let mut slipping = vec![false; n];
    for run in runs_of(&in_contact, true) {
        let drifts = rules::drift_in_run(
            trajectory,
            &on,
            pusher_radius,
            run.clone(),
            window,
            relative_sd,
            noise.yaw_sd,
        );
        for (k, drift) in run.zip(drifts) {
            let e = &mut evidence[k];
            e.drift = drift.speed.abs() as f32;
            e.drift_z = drift.z as f32;
            e.pusher_speed = drift.pusher_speed as f32;
            slipping[k] = drift.z >= options.slip_sigmas;
            e.mode_confidence = rules::confidence(drift.z - options.slip_sigmas);
        }
    }
    if !progress(0.85) {
        return Err(ProposeError::Cancelled);
    }
    crate::slices::pause().await;

    // Bad tracking: jumps, and the model's residual spikes.
    let steps = rules::jump_scores(trajectory, &noise, outline.size());
    let glitches = rules::glitch_scores(trajectory, &noise, outline.size());
    let mut bad = rules::jump_frames(&steps, options.jump_sigmas);
    for (k, glitch) in rules::glitch_frames(&glitches, options.jump_sigmas)
        .into_iter()
        .enumerate()
    {
        bad[k] |= glitch;
    }
    for k in 0..n {
        let after = steps.get(k + 1).copied().unwrap_or(0.0);
        evidence[k].jump_z = steps[k].max(after).max(glitches[k]) as f32;
    }
    if let Some(residuals) = residuals {
        let [sx, sy] = residuals.scale.sigma_pos;
        let noise_error = (2.0 * noise.object_sd.powi(2) * (sx.powi(-2) + sy.powi(-2))
            + 2.0 * (noise.yaw_sd / residuals.scale.sigma_rot).powi(2))
        .sqrt();
        let scores = rules::residual_scores(residuals.losses, noise_error);
        let flagged =
            rules::residual_frames(&scores, residuals.horizon, n, options.residual_sigmas);
        for k in 0..n {
            bad[k] |= flagged[k];
            let touching = [Some(k), k.checked_sub(residuals.horizon.max(1))];
            let z = touching
                .into_iter()
                .flatten()
                .filter_map(|t| scores.get(t))
                .fold(f64::NAN, |a, &b| a.max(b));
            evidence[k].residual_z = z as f32;
        }
    }
    for k in (0..n).filter(|&k| bad[k]) {
        let e = &mut evidence[k];
        let jump = f64::from(e.jump_z) - options.jump_sigmas;
        let residual = f64::from(e.residual_z) - options.residual_sigmas;
        e.bad_confidence = rules::confidence(jump.max(if residual.is_nan() {
            f64::NEG_INFINITY
        } else {
            residual
        }));
    }

    let mut segments = Vec::new();
    let contact_of = |k: usize| if in_contact[k] { CONTACT } else { NO_CONTACT };
    push_runs(
        &mut segments,
        n,
        |k| Some(contact_of(k)),
        |e| e.contact_confidence,
        &evidence,
    );
    push_runs(
        &mut segments,
        n,
        |k| in_contact[k].then_some(if slipping[k] { SLIPPING } else { STICKING }),
        |e| e.mode_confidence,
        &evidence,
    );
    push_runs(
        &mut segments,
        n,
        |k| bad[k].then_some(BAD_TRACKING),
        |e| e.bad_confidence,
        &evidence,
    );
    segments.sort_by(|a, b| (a.frames.start, a.label).cmp(&(b.frames.start, b.label)));
    progress(1.0);
    Ok(Proposals {
        noise,
        gap_offset,
        gap_sd,
        contact_tolerance,
        window,
        residual_horizon: residuals.map(|r| r.horizon),
        options: *options,
        evidence,
        segments,
    })
}

/// The maximal runs of frames whose flag is `value`.
fn runs_of(flags: &[bool], value: bool) -> Vec<Range<usize>> {
    let mut out: Vec<Range<usize>> = Vec::new();
    for (k, &f) in flags.iter().enumerate() {
        if f != value {
            continue;
        }
        match out.last_mut() {
            Some(run) if run.end == k => run.end = k + 1,
            _ => out.push(k..k + 1),
        }
    }
    out
}

/// Appends the runs of equal labels (`None`: nothing proposed) with their mean confidence.
fn push_runs(
    out: &mut Vec<Proposal>,
    n: usize,
    label: impl Fn(usize) -> Option<&'static str>,
    confidence: impl Fn(&FrameEvidence) -> f32,
    evidence: &[FrameEvidence],
) {
    let mut k = 0;
    while k < n {
        let Some(name) = label(k) else {
            k += 1;
            continue;
        };
        let start = k;
        while k < n && label(k) == Some(name) {
            k += 1;
        }
        let sum: f64 = evidence[start..k]
            .iter()
            .map(|e| f64::from(confidence(e)))
            .sum();
        out.push(Proposal {
            label: name,
            frames: start..k,
            confidence: (sum / (k - start) as f64) as f32,
        });
    }
}

impl Proposals {
    /// The proposals covering `frame`.
    pub fn at(&self, frame: usize) -> impl Iterator<Item = &Proposal> {
        self.segments
            .iter()
            .filter(move |p| p.frames.contains(&frame))
    }

    /// The proposals as a recording's labels, leaving out segments less sure than `min_confidence`.
    pub fn to_labels(&self, min_confidence: f32) -> RecordingLabels {
        RecordingLabels {
            segments: self
                .segments
                .iter()
                .filter(|p| p.confidence >= min_confidence)
                .map(|p| Segment::new(p.label, p.frames.clone()))
                .collect(),
            ..RecordingLabels::default()
        }
    }

    /// One sentence per proposal at `frame`: the label, the numbers that decided it and how sure it
    /// is — what the app's inspector shows and what a person checks before accepting.
    pub fn why(&self, frame: usize) -> Vec<String> {
        let Some(e) = self.evidence.get(frame) else {
            return Vec::new();
        };
        let mm = |m: f64| format!("{:.1} mm", m * 1e3);
        let sure = |c: f32| format!("{:.0} % sure", 100.0 * c);
        let mut out = Vec::new();
        for proposal in self.at(frame) {
            let line = match proposal.label {
                CONTACT | NO_CONTACT => format!(
                    "{}: the pusher's rim is {} from the outline (contact within {}: {} offset + {} × {} noise); {}",
                    proposal.label,
                    mm(f64::from(e.gap)),
                    mm(self.contact_tolerance),
                    mm(self.gap_offset),
                    self.options.contact_sigmas,
                    mm(self.gap_sd),
                    sure(e.contact_confidence)
                ),
                STICKING | SLIPPING => {
                    let share = if e.pusher_speed > 0.0 {
                        format!(", {:.0} % of its speed", 100.0 * e.drift / e.pusher_speed)
                    } else {
                        String::new()
                    };
                    format!(
                        "{}: the pusher drifts {:.1} mm/s over the object{share} ({:.1} σ; slipping from {} σ); {}",
                        proposal.label,
                        e.drift * 1e3,
                        e.drift_z,
                        self.options.slip_sigmas,
                        sure(e.mode_confidence)
                    )
                }
                _ => {
                    let mut reasons = Vec::new();
                    if f64::from(e.jump_z) >= self.options.jump_sigmas {
                        reasons.push(format!(
                            "the object jumped {:.1} σ beyond what the pusher's move explains",
                            e.jump_z
                        ));
                    }
                    if f64::from(e.residual_z) >= self.options.residual_sigmas {
                        reasons.push(format!(
                            "the model's residual is {:.1} σ above its median",
                            e.residual_z
                        ));
                    }
                    if reasons.is_empty() {
                        reasons.push("a neighbouring sample's residual spikes".to_owned());
                    }
                    format!(
                        "{}: {}; {}",
                        proposal.label,
                        reasons.join(", and "),
                        sure(e.bad_confidence)
                    )
                }
            };
            out.push(line);
        }
        out
    }
}
