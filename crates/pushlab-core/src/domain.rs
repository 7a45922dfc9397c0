//! The domain a model was trained on — object sizes, pusher radii, frame rates, pushing speeds and the
//! horizon — recorded in its model file, and the one check, shared by the CLI and the app, of whether
//! recordings lie inside it.
//!
//! Why: a model trained on 0.3 m boxes pushed by a 175 mm disc at 10 Hz says nothing useful about a
//! 0.1 m object pushed by a 5 mm rod at 250 Hz, and online learning on such data drives `θ_online`
//! to nonsense (a COM 18 cm off a 10 cm object). Saying so plainly is cheaper than letting a user
//! guess. The network's own input range is recorded in the model itself (the contact kind's clamp
//! range, the paper kind's normalisation); this is the physical side a user can read.
//!
//! A recording is outside when one of its quantities lies beyond the trained range by more than
//! [`SLACK`] (a factor): the sample data's two boxes (0.40 and 0.55 m) are one domain, a 0.1 m MIT
//! object is not.

use serde::{Deserialize, Serialize};

use crate::recording::Recording;

/// How far beyond the trained range (as a factor either way) a quantity may lie and still count as
/// inside.
pub const SLACK: f64 = 1.5;

/// The ranges a model was trained on; each `[smallest, largest]` over its training recordings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Domain {
    /// Largest extent of the object's footprint, metres.
    pub object_size: [f64; 2],
    /// Radius of the pusher disc, metres.
    pub pusher_radius: [f64; 2],
    /// Frame rate, Hz (each recording's mean).
    pub sample_rate_hz: [f64; 2],
    /// The pusher's speed over a recording ([`crate::trajectory::Trajectory::pusher_speed`]: net displacement over
    /// one-second windows), m/s. `None` when read from a model file older than version 3: those
    /// summed frame-to-frame steps, which counts tracking noise as motion (a 0.05 m/s push at 50 Hz
    /// with 2 mm noise read 0.18 m/s), so their speeds cannot be compared with today's and are not
    /// (nor can they be re-derived: the file keeps the range, not the recordings).
    #[serde(default)]
    pub pusher_speed: Option<[f64; 2]>,
    /// Prediction horizon, frames.
    pub horizon: usize,
}

/// What one recording measures, for [`Domain`].
#[derive(Clone, Copy, Debug, PartialEq)]
struct Measures {
    object_size: Option<f64>,
    pusher_radius: f64,
    sample_rate_hz: f64,
    pusher_speed: f64,
}

impl Measures {
    fn of(recording: &Recording) -> Self {
        Self {
            object_size: recording.setting.object.outline().ok().map(|o| o.size()),
            pusher_radius: recording.setting.pusher_radius,
            sample_rate_hz: recording.trajectory.mean_rate_hz(),
            pusher_speed: recording.trajectory.pusher_speed().unwrap_or(0.0),
        }
    }
}

/// Whether a recording measured the quantity: a frame rate or speed of 0 is a push too short to
/// measure (fewer than two frames), not a push at 0 Hz.
fn is_measured(value: f64) -> bool {
    value.is_finite() && value > 0.0
}

/// Smallest and largest of the measured values.
fn range(values: impl Iterator<Item = f64>) -> Option<[f64; 2]> {
    values
        .filter(|v| is_measured(*v))
        .fold(None, |acc, v| match acc {
            None => Some([v, v]),
            Some([lo, hi]) => Some([lo.min(v), hi.max(v)]),
        })
}

impl Domain {
    /// The one frame rate the model was trained at, Hz, rounded to a thousandth (each recording's
    /// mean rate is measured from its frames' times), when every recording had it: the grid a live
    /// session is put on. `None` when the rates differ by more than that.
    pub fn single_rate_hz(&self) -> Option<f64> {
        let [lo, hi] = self.sample_rate_hz.map(|r| (r * 1e3).round() / 1e3);
        (lo == hi && lo > 0.0).then_some(lo)
    }

    /// The domain of the recordings a model is trained on, or `None` when none has a usable outline,
    /// motion and frame rate.
    pub fn of<'a>(
        recordings: impl IntoIterator<Item = &'a Recording>,
        horizon: usize,
    ) -> Option<Self> {
        let measures: Vec<Measures> = recordings.into_iter().map(Measures::of).collect();
        Some(Self {
            object_size: range(measures.iter().filter_map(|m| m.object_size))?,
            pusher_radius: range(measures.iter().map(|m| m.pusher_radius))?,
            sample_rate_hz: range(measures.iter().map(|m| m.sample_rate_hz))?,
            pusher_speed: Some(range(measures.iter().map(|m| m.pusher_speed))?),
            horizon,
        })
    }

    /// Whether these recordings lie outside the domain; `None` when all lie inside (or there are
    /// none). The message starts with "the model was trained on" and names every quantity that
    /// differs, the trained range against the recordings' range.
    pub fn mismatch<'a>(
        &self,
        recordings: impl IntoIterator<Item = &'a Recording>,
    ) -> Option<DomainMismatch> {
        let measures: Vec<Measures> = recordings.into_iter().map(Measures::of).collect();
        // A quantity a recording cannot measure yet (the frame rate and speed of a live push of
        // fewer than two frames) says nothing about the domain, as `range` leaves it out: counted
        // as outside, it made a warning that named no quantity ("trained on ; … have ").
        let inside = |value: f64, [lo, hi]: [f64; 2]| {
            !is_measured(value) || (value >= lo / SLACK && value <= hi * SLACK)
        };
        let outside: Vec<&Measures> = measures
            .iter()
            .filter(|m| {
                !(m.object_size.is_none_or(|s| inside(s, self.object_size))
                    && inside(m.pusher_radius, self.pusher_radius)
                    && inside(m.sample_rate_hz, self.sample_rate_hz)
                    && self.pusher_speed.is_none_or(|r| inside(m.pusher_speed, r)))
            })
            .collect();
        if outside.is_empty() {
            return None;
        }
        let mut trained = Vec::new();
        let mut found = Vec::new();
        let mut compare =
            |name: &str, unit: Unit, ours: Option<[f64; 2]>, theirs: Option<[f64; 2]>| {
                let (Some(ours), Some(theirs)) = (ours, theirs) else {
                    return;
                };
                let differs = theirs[0] < ours[0] / SLACK || theirs[1] > ours[1] * SLACK;
                if differs {
                    trained.push(format!("{name} {}", unit.range(ours)));
                    found.push(format!("{name} {}", unit.range(theirs)));
                }
            };
        compare(
            "objects of",
            Unit::Metres,
            Some(self.object_size),
            range(outside.iter().filter_map(|m| m.object_size)),
        );
        compare(
            "a pusher radius of",
            Unit::Millimetres,
            Some(self.pusher_radius),
            range(outside.iter().map(|m| m.pusher_radius)),
        );
        compare(
            "frames at",
            Unit::Hertz,
            Some(self.sample_rate_hz),
            range(outside.iter().map(|m| m.sample_rate_hz)),
        );
        compare(
            "pushes at",
            Unit::MetresPerSecond,
            self.pusher_speed,
            range(outside.iter().map(|m| m.pusher_speed)),
        );
        Some(DomainMismatch {
            outside: outside.len(),
            total: measures.len(),
            message: format!(
                "the model was trained on {}; {} of {} recording(s) here have {}: its predictions there are extrapolations (train a model for them)",
                trained.join(", "),
                outside.len(),
                measures.len(),
                found.join(", ")
            ),
        })
    }
}

/// Recordings outside a model's domain.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DomainMismatch {
    /// How many recordings lie outside, of how many.
    pub outside: usize,
    pub total: usize,
    /// One sentence for a user: "the model was trained on objects of 0.40–0.55 m, …; 4 of 4
    /// recording(s) here have objects of 0.09–0.16 m, …".
    pub message: String,
}

#[derive(Clone, Copy)]
enum Unit {
    Metres,
    Millimetres,
    Hertz,
    MetresPerSecond,
}

impl Unit {
    fn range(self, [lo, hi]: [f64; 2]) -> String {
        let (scale, unit, digits) = match self {
            Unit::Metres => (1.0, "m", 2),
            Unit::Millimetres => (1000.0, "mm", 1),
            Unit::Hertz => (1.0, "Hz", 0),
            Unit::MetresPerSecond => (1.0, "m/s", 3),
        };
        let (lo, hi) = (lo * scale, hi * scale);
        let (low, high) = (format!("{lo:.digits$}"), format!("{hi:.digits$}"));
        // One number when the range is narrower than 0.5 % or than the digits shown (0.040 m/s, not
        // 0.040–0.040).
        if (hi - lo).abs() <= 0.005 * hi.abs() || low == high {
            format!("{low} {unit}")
        } else {
            format!("{low}–{high} {unit}")
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use std::sync::Arc;

    use nalgebra::Point2;

    use super::*;
    use crate::geometry::Pose2;
    use crate::recording::{ObjectShape, Setting};
    use crate::trajectory::{Frame, Trajectory};

    /// A straight push of a `size`-metre square by a disc of `radius` at `rate` Hz and `speed` m/s.
    fn recording(size: f64, radius: f64, rate: f64, speed: f64) -> Recording {
        let setting = Setting::of_object(
            "test",
            ObjectShape::Box {
                width: size,
                length: size,
            },
            radius,
        );
        let frames = (0..50)
            .map(|i| {
                let t = i as f64 / rate;
                Frame {
                    time: t,
                    robot: Point2::new(-size / 2.0 - radius + speed * t, 0.0),
                    object: Pose2::new(speed * t, 0.0, 0.0),
                }
            })
            .collect();
        Recording {
            source: "push.csv".into(),
            name: "push".into(),
            setting: Arc::new(setting),
            entry: None,
            trajectory: std::sync::Arc::new(Trajectory::new(frames)),
            warnings: Vec::new(),
            notes: Vec::new(),
            cameras: Vec::new(),
        }
    }

    #[test]
    fn the_sample_data_boxes_are_one_domain_and_a_small_fast_rod_push_is_not() {
        let trained = [
            recording(0.40, 0.0875, 10.0, 0.04),
            recording(0.55, 0.0875, 10.0, 0.05),
        ];
        let domain = Domain::of(&trained, 10).unwrap();
        assert_eq!(domain.object_size, [0.40, 0.55]);
        assert_eq!(domain.horizon, 10);
        // Inside: a box between the two, a little slower.
        assert_eq!(domain.mismatch(&[recording(0.5, 0.0875, 10.0, 0.03)]), None);
        // Outside: the MIT Push Dataset's setting.
        let mit = [
            recording(0.10, 0.00475, 250.0, 0.05),
            recording(0.45, 0.0875, 10.0, 0.04),
        ];
        let mismatch = domain.mismatch(&mit).unwrap();
        assert_eq!((mismatch.outside, mismatch.total), (1, 2));
        assert_eq!(
            mismatch.message,
            "the model was trained on objects of 0.40–0.55 m, a pusher radius of 87.5 mm, frames at 10 Hz; \
             1 of 2 recording(s) here have objects of 0.10 m, a pusher radius of 4.8 mm, frames at 250 Hz: \
             its predictions there are extrapolations (train a model for them)"
        );
    }

    #[test]
    fn a_push_too_short_to_measure_is_not_called_outside() {
        let domain = Domain::of(&[recording(0.4, 0.05, 10.0, 0.04)], 1).unwrap();
        let mut live = recording(0.4, 0.05, 10.0, 0.04);
        live.trajectory = Arc::new(Trajectory::new(live.trajectory.frames[..1].to_vec()));
        assert_eq!(live.trajectory.mean_rate_hz(), 0.0);
        assert_eq!(domain.mismatch([&live]), None);
        // Too short to measure, but on a 0.1 m object: outside, for its size alone.
        let mut small = recording(0.1, 0.05, 10.0, 0.04);
        small.trajectory = Arc::new(Trajectory::new(Vec::new()));
        let message = domain.mismatch([&small]).unwrap().message;
        assert!(
            message.starts_with("the model was trained on objects of 0.40 m; 1 of 1 recording(s) here have objects of 0.10 m:"),
            "{message}"
        );
    }

    #[test]
    fn no_recordings_have_no_domain_and_no_mismatch() {
        assert_eq!(Domain::of(&[], 1), None);
        let domain = Domain::of(&[recording(0.4, 0.05, 10.0, 0.04)], 1).unwrap();
        assert_eq!(domain.mismatch(&[]), None);
        let fast = domain.mismatch(&[recording(0.4, 0.05, 10.0, 0.5)]).unwrap();
        assert!(
            fast.message.ends_with(
                "here have pushes at 0.500 m/s: its predictions there are extrapolations (train a model for them)"
            ),
            "{}",
            fast.message
        );
        // A range narrower than the digits shown is one number.
        let steady = Domain::of(
            &[
                recording(0.4, 0.05, 10.0, 0.0398),
                recording(0.4, 0.05, 10.0, 0.0404),
            ],
            1,
        )
        .unwrap();
        let fast = steady.mismatch(&[recording(0.4, 0.05, 10.0, 0.5)]).unwrap();
        assert!(
            fast.message.contains("trained on pushes at 0.040 m/s;"),
            "{}",
            fast.message
        );
        // A domain read from a file before version 3 has no speeds: speed is not compared.
        let unknown_speed = Domain {
            pusher_speed: None,
            ..domain
        };
        assert_eq!(
            unknown_speed.mismatch(&[recording(0.4, 0.05, 10.0, 0.5)]),
            None
        );
    }
}
