//! The rules behind label proposals, each a pure function of per-frame series: the tracking noise
//! estimated from the recording itself, the pusher's gap to the outline, the pusher's drift over the
//! object while in contact, pose jumps the pusher cannot explain, and the model's residual spikes.
//!
//! Every threshold is a number of standard deviations of a noise estimated from the data (never the
//! simulator's truth), so that the same rules serve a 10 Hz camera with 2 mm noise and a 250 Hz
//! motion-capture system with a tenth of a millimetre.

use crate::math;
use nalgebra::{Point2, Vector2};

use crate::geometry::{Outline, wrap_angle};
use crate::trajectory::Trajectory;

/// The smallest noise the rules assume, metres and radians: a noise-free simulation would otherwise
/// make every tolerance zero and every rounding error significant.
pub(super) const MIN_POSITION_SD: f64 = 1e-5;
pub(super) const MIN_YAW_SD: f64 = 1e-5;

/// MAD → standard deviation for Gaussian data.
const MAD_TO_SD: f64 = 1.482_6;

/// The median of `values` (reordered); `None` when empty.
pub(super) fn median(values: &mut [f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mid = values.len() / 2;
    let (_, m, _) = values.select_nth_unstable_by(mid, f64::total_cmp);
    Some(*m)
}

/// The `q` quantile of `values` (the nearest rank); `None` when empty.
pub(super) fn quantile(values: &[f64], q: f64) -> Option<f64> {
    let mut work = values.to_vec();
    let last = work.len().checked_sub(1)?;
    let rank = ((q.clamp(0.0, 1.0) * last as f64).round() as usize).min(last);
    let (_, v, _) = work.select_nth_unstable_by(rank, f64::total_cmp);
    Some(*v)
}

/// A robust standard deviation: the median absolute deviation from the median, scaled for Gaussian
/// data; with the median. `None` when empty.
pub(super) fn robust_spread(values: &[f64]) -> Option<(f64, f64)> {
    let mut work = values.to_vec();
    let centre = median(&mut work)?;
    for v in &mut work {
        *v = (*v - centre).abs();
    }
    Some((centre, MAD_TO_SD * median(&mut work)?))
}

/// The noise of a series from its second differences: for a smooth motion sampled with independent
/// Gaussian errors of σ, `x[k+1] − 2x[k] + x[k−1]` has a standard deviation of √6 σ, and a robust
/// estimate ignores the few frames where the motion itself changes (contact made, a turn).
pub(super) fn second_difference_sd(series: &[&[f64]]) -> f64 {
    let mut d2: Vec<f64> = series
        .iter()
        .flat_map(|s| s.windows(3).map(|w| (w[2] - 2.0 * w[1] + w[0]).abs()))
        .collect();
    median(&mut d2).map_or(0.0, |m| MAD_TO_SD * m / 6f64.sqrt())
}

/// The tracking noise of a recording, estimated from the recording alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseEstimate {
    /// Of the pusher's recorded x and y, metres.
    pub robot_sd: f64,
    /// Of the object's recorded x and y, metres.
    pub object_sd: f64,
    /// Of the object's recorded yaw, radians.
    pub yaw_sd: f64,
}

impl NoiseEstimate {
    /// Estimates the noise of every recorded coordinate from its second differences.
    pub fn of(trajectory: &Trajectory) -> Self {
        let column = |f: &dyn Fn(&crate::trajectory::Frame) -> f64| -> Vec<f64> {
            trajectory.frames.iter().map(f).collect()
        };
        let (rx, ry) = (column(&|f| f.robot.x), column(&|f| f.robot.y));
        let (ox, oy) = (
            column(&|f| f.object.position.x),
            column(&|f| f.object.position.y),
        );
        let yaw = column(&|f| f.object.yaw);
        Self {
            robot_sd: second_difference_sd(&[&rx, &ry]).max(MIN_POSITION_SD),
            object_sd: second_difference_sd(&[&ox, &oy]).max(MIN_POSITION_SD),
            yaw_sd: second_difference_sd(&[&yaw]).max(MIN_YAW_SD),
        }
    }

    /// The noise of the pusher's position seen from the object at `distance` from the object's
    /// origin: both positions' noise, and the yaw's noise turning the arm.
    pub fn relative_sd(&self, distance: f64) -> f64 {
        (self.robot_sd.powi(2) + self.object_sd.powi(2) + (self.yaw_sd * distance).powi(2)).sqrt()
    }
}

/// Per frame, what the pusher's place on the object says: its centre in the object frame, the
/// outward normal of the outline nearest to it, and the gap between its rim and the outline
/// (negative: overlap), metres.
pub(super) struct PusherOnObject {
    pub centre: Vec<Point2<f64>>,
    pub normal: Vec<Vector2<f64>>,
    pub gap: Vec<f64>,
}

/// Where the pusher is on the object at every frame; `None` when `progress` asks to stop.
pub(super) async fn pusher_on_object(
    trajectory: &Trajectory,
    outline: &Outline,
    pusher_radius: f64,
    progress: &mut dyn FnMut(usize) -> bool,
) -> Option<PusherOnObject> {
    let n = trajectory.len();
    let mut out = PusherOnObject {
        centre: Vec::with_capacity(n),
        normal: Vec::with_capacity(n),
        gap: Vec::with_capacity(n),
    };
    for (k, frame) in trajectory.frames.iter().enumerate() {
        if k % 4096 == 0 {
            if !progress(k) {
                return None;
            }
            crate::slices::pause().await;
        }
        let p = frame.object.point_in_object(frame.robot);
        let nearest = outline.closest_boundary_point(p);
        out.gap.push(nearest.signed_distance - pusher_radius);
        out.normal.push(nearest.normal);
        out.centre.push(p);
    }
    Some(out)
}

/// Whether the object visibly moves on both sides of each frame: its position or yaw changes over
/// the `half` frames before it and over the `half` frames after it by more than `sigmas` standard
/// deviations of the difference of two noisy readings. Both sides, so that frames just before the
/// pusher arrives (still apart) do not count as seen pushing.
pub(super) fn object_moves(
    trajectory: &Trajectory,
    noise: &NoiseEstimate,
    half: usize,
    sigmas: f64,
) -> Vec<bool> {
    let frames = &trajectory.frames;
    let n = frames.len();
    let (position_limit, yaw_limit) = (
        sigmas * noise.object_sd * 2f64.sqrt(),
        sigmas * noise.yaw_sd * 2f64.sqrt(),
    );
    let moved = |a: usize, b: usize| {
        let (a, b) = (&frames[a], &frames[b]);
        (b.object.position - a.object.position).norm() > position_limit
            || wrap_angle(b.object.yaw - a.object.yaw).abs() > yaw_limit
    };
    (0..n)
        .map(|k| moved(k.saturating_sub(half), k) && moved(k, (k + half).min(n - 1)))
        .collect()
}

/// A running median over `±half` frames (shorter at the ends): it keeps a step (contact made) where
/// it is and removes single noisy readings.
pub(super) fn running_median(values: &[f64], half: usize) -> Vec<f64> {
    let n = values.len();
    let mut window = Vec::with_capacity(2 * half + 1);
    (0..n)
        .map(|k| {
            window.clear();
            window.extend_from_slice(&values[k.saturating_sub(half)..(k + half + 1).min(n)]);
            median(&mut window).unwrap_or(values[k])
        })
        .collect()
}

/// The contact's slip around one frame: a least-squares velocity of the contact along the outline,
/// and how many standard errors from zero it is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Drift {
    /// Metres per second, positive counter-clockwise along the outline.
    pub speed: f64,
    /// `|speed|` over its standard error (0 when fewer than two frames).
    pub z: f64,
    /// The pusher's own speed in the world over the same frames, metres per second.
    pub pusher_speed: f64,
}

/// The slip at every frame in `run` (a run of frames in contact), over `±half` frames clipped to the
/// run, from the pusher's centre on the object (`on`), the object's yaw and the pusher's radius.
///
/// A disc that does not turn, pressed on a face that does, rolls over the face: even while sticking
/// its centre moves along the face at `ω r` in the object frame (4 mm/s for a 0.175 m pusher and an
/// object turning 1.3°/s). The slip is what remains when that rolling is taken out: the tangential
/// velocity of `centre + r · Δyaw · t`, with `t` the outline's counter-clockwise tangent.
/// `position_sd` is the noise of one coordinate of the pusher's centre on the object.
pub(super) fn drift_in_run(
    trajectory: &Trajectory,
    on: &PusherOnObject,
    pusher_radius: f64,
    run: std::ops::Range<usize>,
    half: usize,
    position_sd: f64,
    yaw_sd: f64,
) -> Vec<Drift> {
    let frames = &trajectory.frames;
    let sd = math::hypot(position_sd, pusher_radius * yaw_sd);
    run.clone()
        .map(|k| {
            let window = k.saturating_sub(half).max(run.start)..(k + half + 1).min(run.end);
            if window.len() < 2 {
                return Drift::default();
            }
            let n = on.normal[k];
            let tangent = Vector2::new(-n.y, n.x);
            let slip_coordinate = |j: usize| {
                let turned = wrap_angle(frames[j].object.yaw - frames[k].object.yaw);
                on.centre[j].coords.dot(&tangent) + pusher_radius * turned
            };
            let count = window.len() as f64;
            let t0 = frames[window.start].time;
            let mean_t = window.clone().map(|j| frames[j].time - t0).sum::<f64>() / count;
            let mean_s = window.clone().map(slip_coordinate).sum::<f64>() / count;
            let (mut stt, mut sts) = (0.0, 0.0);
            for j in window.clone() {
                let dt = frames[j].time - t0 - mean_t;
                stt += dt * dt;
                sts += (slip_coordinate(j) - mean_s) * dt;
            }
            if stt <= 0.0 {
                return Drift::default();
            }
            let speed = sts / stt;
            let standard_error = sd / stt.sqrt();
            let (first, last) = (&frames[window.start], &frames[window.end - 1]);
            let span = last.time - first.time;
            Drift {
                speed,
                z: speed.abs() / standard_error,
                pusher_speed: if span > 0.0 {
                    (last.robot - first.robot).norm() / span
                } else {
                    0.0
                },
            }
        })
        .collect()
}

/// For each step `k − 1 → k` (index `k`, 0 for the first frame): how many standard deviations the
/// object's move or turn exceeds what the pusher's move could cause. In quasi-static pushing the
/// COM moves no farther than the contact point (eqs. 9–11 shrink the contact's motion), so the
/// geometric centre moves at most about twice the pusher's move, and the object turns at most by
/// the pusher's move over a quarter of its size.
pub(super) fn jump_scores(trajectory: &Trajectory, noise: &NoiseEstimate, size: f64) -> Vec<f64> {
    let frames = &trajectory.frames;
    let turn_per_metre = 4.0 / size.max(1e-6);
    let step_sd_position =
        (2.0 * noise.object_sd.powi(2) + 4.0 * 2.0 * noise.robot_sd.powi(2)).sqrt();
    let step_sd_yaw =
        (2.0 * noise.yaw_sd.powi(2) + turn_per_metre.powi(2) * 2.0 * noise.robot_sd.powi(2)).sqrt();
    let mut scores = vec![0.0; frames.len()];
    for k in 1..frames.len() {
        let (a, b) = (&frames[k - 1], &frames[k]);
        let pusher_move = (b.robot - a.robot).norm();
        let object_move = (b.object.position - a.object.position).norm();
        let turn = wrap_angle(b.object.yaw - a.object.yaw).abs();
        let position_z = (object_move - 2.0 * pusher_move) / step_sd_position;
        let yaw_z = (turn - turn_per_metre * pusher_move) / step_sd_yaw;
        scores[k] = position_z.max(yaw_z).max(0.0);
    }
    scores
}

/// For each frame: how many standard deviations its object pose lies off the line through its two
/// neighbours, beyond what the pusher explains. A pushed object's velocity follows the pusher's: it
/// bends where the pusher's path bends (up to twice as much, as for a step) and changes by at most
/// the pusher's step where the object starts or stops; a glitch of one frame does neither. Far more
/// sensitive than a step's size at a low frame rate, where the pusher's step is large.
pub(super) fn glitch_scores(trajectory: &Trajectory, noise: &NoiseEstimate, size: f64) -> Vec<f64> {
    let frames = &trajectory.frames;
    let turn_per_metre = 4.0 / size.max(1e-6);
    // A midpoint deviation `x_k − (x_{k−1} + x_{k+1}) / 2` of independent noise has σ √1.5.
    let dev_sd_position = (1.5f64).sqrt() * noise.object_sd;
    let dev_sd_yaw = (1.5f64).sqrt() * noise.yaw_sd;
    // The pusher's bend counts only where it is real: beyond three σ of its own noise (otherwise the
    // pusher's noise would excuse every glitch of the object's size).
    let pusher_bend_noise = 3.0 * (1.5f64).sqrt() * noise.robot_sd;
    let mut scores = vec![0.0; frames.len()];
    for k in 1..frames.len().saturating_sub(1) {
        let (a, b, c) = (&frames[k - 1], &frames[k], &frames[k + 1]);
        let pusher_bend = (b.robot - nalgebra::center(&a.robot, &c.robot)).norm();
        let pusher_step = (b.robot - a.robot).norm().max((c.robot - b.robot).norm());
        let allowed = 2.0 * (pusher_bend - pusher_bend_noise).max(0.0) + 0.5 * pusher_step;
        let midpoint = nalgebra::center(&a.object.position, &c.object.position);
        let position_z = ((b.object.position - midpoint).norm() - allowed) / dev_sd_position;
        let bend =
            0.5 * wrap_angle(b.object.yaw - a.object.yaw - wrap_angle(c.object.yaw - b.object.yaw));
        let yaw_z = (bend.abs() - turn_per_metre * allowed) / dev_sd_yaw;
        scores[k] = position_z.max(yaw_z).max(0.0);
    }
    scores
}

/// The glitches among `scores` (from [`glitch_scores`]): frames at or above `sigmas` that score
/// higher than both neighbours (a glitch bends its neighbours' lines by half as much).
pub(super) fn glitch_frames(scores: &[f64], sigmas: f64) -> Vec<bool> {
    let at = |k: usize| scores.get(k).copied().unwrap_or(0.0);
    (0..scores.len())
        .map(|k| {
            let z = at(k);
            z >= sigmas && z > at(k + 1) && (k == 0 || z > at(k - 1))
        })
        .collect()
}

/// The frames a tracking jump spoiled, from the scores of the steps: a frame whose steps in and out
/// both jump is a glitch (it alone is marked); a jump on its own (tracking re-acquired elsewhere)
/// marks the frame it lands on.
pub(super) fn jump_frames(step_scores: &[f64], sigmas: f64) -> Vec<bool> {
    let n = step_scores.len();
    let jumps = |k: usize| k < n && step_scores[k] >= sigmas;
    let mut bad = vec![false; n];
    let mut explained = vec![false; n];
    for k in 1..n {
        if jumps(k) && jumps(k + 1) && !explained[k] {
            bad[k] = true;
            explained[k] = true;
            explained[k + 1] = true;
        }
    }
    for k in 1..n {
        if jumps(k) && !explained[k] {
            bad[k] = true;
        }
    }
    bad
}

/// Samples on either side whose running median a residual is compared with.
pub(super) const RESIDUAL_HALF: usize = 5;

/// Robust z-scores of a model's residuals (the loss of each sample, by its start frame): the
/// residual's square root (an error, not a squared one) less the running median of its neighbours
/// (±[`RESIDUAL_HALF`] samples), against the median absolute value of those differences. A model's
/// own error changes slowly (a contact made, a slip) and is taken out by the running median; a
/// tracking glitch changes one or two samples and stands out. The spread is at least `noise_error`,
/// the error the tracking noise alone makes.
pub(super) fn residual_scores(losses: &[f64], noise_error: f64) -> Vec<f64> {
    let errors: Vec<f64> = losses
        .iter()
        .map(|&l| {
            if l.is_finite() {
                l.max(0.0).sqrt()
            } else {
                0.0
            }
        })
        .collect();
    let local = running_median(&errors, RESIDUAL_HALF);
    let excess: Vec<f64> = errors.iter().zip(&local).map(|(e, m)| e - m).collect();
    let mut absolute: Vec<f64> = excess.iter().map(|d| d.abs()).collect();
    let Some(mad) = median(&mut absolute) else {
        return Vec::new();
    };
    let spread = (MAD_TO_SD * mad).max(noise_error).max(1e-12);
    excess.iter().map(|d| d / spread).collect()
}

/// The frames behind residual spikes. A sample from `t` to `t + horizon` is made of those two frames;
/// a bad frame `j` spoils both samples that contain it, the one starting at `j` and the one at
/// `j − horizon`, so only spikes in such pairs point at a frame (their common one). A spike alone is
/// the model's error, not the tracking's — unless its partner sample does not exist (the ends of the
/// recording), where it marks its frame at that end.
pub(super) fn residual_frames(
    scores: &[f64],
    horizon: usize,
    frames: usize,
    sigmas: f64,
) -> Vec<bool> {
    let horizon = horizon.max(1);
    let samples = scores.len();
    let spikes = |t: usize| scores.get(t).is_some_and(|&z| z >= sigmas);
    let mut bad = vec![false; frames];
    for t in (0..samples).filter(|&t| spikes(t)) {
        let end = t + horizon;
        let explained_before = t >= horizon && spikes(t - horizon);
        if end < frames && (spikes(end) || (end >= samples && !explained_before)) {
            bad[end] = true;
        }
        if t < horizon && !spikes(end) {
            bad[t] = true;
        }
    }
    bad
}

/// The standard normal distribution function, for turning a z-score into a confidence
/// (Abramowitz & Stegun 7.1.26, error below 1.5e-7).
pub(super) fn normal_cdf(z: f64) -> f64 {
    let x = z.abs() / std::f64::consts::SQRT_2;
    let t = 1.0 / (1.0 + 0.327_591_1 * x);
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    let erf = 1.0 - poly * math::exp(-x * x);
    if z >= 0.0 {
        0.5 * (1.0 + erf)
    } else {
        0.5 * (1.0 - erf)
    }
}

/// How sure a decision at `margin` standard deviations from its threshold is: 0.5 on the threshold,
/// 0.84 one σ away, 0.9987 three σ away.
pub(super) fn confidence(margin: f64) -> f32 {
    if margin.is_finite() {
        normal_cdf(margin.abs()) as f32
    } else {
        1.0
    }
}
