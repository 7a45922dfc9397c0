//! A grid of pushes laid out on the object, as candidates for the ranking when no recorded push
//! says where to push next: every side given × contact offset × angle, each a straight push of one
//! length at the recordings' own pusher speed and frame rate (so its frames weigh as theirs do).
//!
//! Each grid push is a recording whose object rests at the origin and whose pusher follows the
//! simulator's plan of that push (`sim::PushPlan`: the same face point and approach as
//! `pushlab simulate`); the ranking never reads the object's recorded motion, so a resting object
//! is all it needs. The pushes keep the object's setting and folder, so they are the same object.

use std::sync::Arc;

use crate::geometry::{OutlineError, Pose2};
use crate::recording::{PushSide, Recording};
use crate::sim::PushPlan;
use crate::sim::path::contact_offsets;
use crate::trajectory::{Frame, Trajectory};

/// Where each grid push starts: this far before the pusher's disc touches the face, metres.
pub const APPROACH_M: f64 = 0.01;

/// A grid of pushes.
#[derive(Clone, Debug, PartialEq)]
pub struct PushGrid {
    /// The sides pushed.
    pub sides: Vec<PushSide>,
    /// Contact offsets as fractions of each face's half length, in (−1, 1).
    pub offsets: Vec<f64>,
    /// Push angles from the face's normal, degrees, counter-clockwise positive.
    pub angles_deg: Vec<f64>,
    /// How far the pusher goes once it touches, metres.
    pub length_m: f64,
}

impl Default for PushGrid {
    /// Every side, at −0.6, 0 and 0.6 of each face's half length, straight in and 20° either way,
    /// 10 cm long: 36 pushes, what `pushlab suggest --grid` and the app's Steer tab lay out unless
    /// told otherwise.
    fn default() -> Self {
        Self {
            sides: PushSide::ALL.to_vec(),
            offsets: vec![-0.6, 0.0, 0.6],
            angles_deg: vec![-20.0, 0.0, 20.0],
            length_m: 0.1,
        }
    }
}

/// The grid's pushes, and those of its points that cannot be pushed (off the face, blocked), each
/// a sentence.
#[derive(Clone, Debug)]
pub struct GridPushes {
    pub pushes: Vec<Recording>,
    pub skipped: Vec<String>,
    /// The frame rate the pushes are sampled at, Hz: the recording's (10 Hz if it has none).
    pub rate_hz: f64,
    /// The pusher's speed, m/s: the recording's (3 cm/s if it has none).
    pub speed: f64,
}

impl PushGrid {
    /// The grid's pushes on the object of `like` (a recording of it), at `like`'s frame rate and
    /// pusher speed.
    pub fn pushes(&self, like: &Recording) -> Result<GridPushes, OutlineError> {
        let outline = like.setting.object.outline()?;
        let rate_hz = positive(like.trajectory.mean_rate_hz()).unwrap_or(10.0);
        let speed = like
            .trajectory
            .pusher_speed()
            .and_then(positive)
            .unwrap_or(0.03);
        let at_rest = Pose2::new(0.0, 0.0, 0.0);
        let frames = ((APPROACH_M + self.length_m) / speed * rate_hz).ceil() as usize + 1;
        let mut grid = GridPushes {
            pushes: Vec::new(),
            skipped: Vec::new(),
            rate_hz,
            speed,
        };
        for &side in &self.sides {
            let offsets = contact_offsets(&outline, side, &self.offsets);
            for (&fraction, &offset) in self.offsets.iter().zip(&offsets) {
                for &angle in &self.angles_deg {
                    let name = format!("{} {:+.1} cm {:+.0}°", side.name(), offset * 1e2, angle);
                    let plan = PushPlan {
                        side,
                        contact_offset: offset,
                        push_angle_deg: angle,
                        speed,
                        curvature: 0.0,
                        approach: APPROACH_M,
                    };
                    let path = match plan.path(&outline, &at_rest, like.setting.pusher_radius) {
                        Ok(path) => path,
                        Err(e) => {
                            grid.skipped
                                .push(format!("{name} (offset {fraction}): {e}"));
                            continue;
                        }
                    };
                    let trajectory = Trajectory::new(
                        (0..frames)
                            .map(|k| {
                                let time = k as f64 / rate_hz;
                                Frame {
                                    time,
                                    robot: path.position(time),
                                    object: at_rest,
                                }
                            })
                            .collect(),
                    );
                    grid.pushes.push(Recording {
                        source: like.source.with_file_name(&name),
                        name,
                        setting: Arc::clone(&like.setting),
                        entry: None,
                        trajectory: Arc::new(trajectory),
                        warnings: Vec::new(),
                        notes: Vec::new(),
                        cameras: Vec::new(),
                    });
                }
            }
        }
        Ok(grid)
    }
}

/// The grid in words, as the app says what it ranked: "every side, at -0.6, 0 and 0.6 of each
/// face's half length, straight in and 20° either way, 10 cm long".
impl std::fmt::Display for PushGrid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let every_side = PushSide::ALL.iter().all(|s| self.sides.contains(s));
        let sides = if every_side {
            "every side".to_owned()
        } else {
            let names: Vec<&str> = self.sides.iter().map(|s| s.name()).collect();
            let plural = if names.len() == 1 { "side" } else { "sides" };
            format!("the {} {plural}", listed(&names))
        };
        let offsets: Vec<String> = self.offsets.iter().map(|&x| number(x)).collect();
        let mut angles = self.angles_deg.clone();
        angles.sort_by(f64::total_cmp);
        let angles = match angles.as_slice() {
            [zero] if *zero == 0.0 => "straight in".to_owned(),
            [low, zero, high] if *zero == 0.0 && *high > 0.0 && *low == -*high => {
                format!("straight in and {}° either way", number(*high))
            }
            _ => {
                let each: Vec<String> = self.angles_deg.iter().map(|&a| number(a)).collect();
                format!("at {}° from straight in", listed(&each))
            }
        };
        write!(
            f,
            "{sides}, at {} of each face's half length, {angles}, {} cm long",
            listed(&offsets),
            number(self.length_m * 1e2)
        )
    }
}

/// "a", "a and b", "a, b and c".
fn listed<S: AsRef<str>>(items: &[S]) -> String {
    match items {
        [] => String::new(),
        [one] => one.as_ref().to_owned(),
        [rest @ .., last] => {
            let rest: Vec<&str> = rest.iter().map(AsRef::as_ref).collect();
            format!("{} and {}", rest.join(", "), last.as_ref())
        }
    }
}

/// `x` with at most two decimals and no trailing zeros ("0.6", "10", "-20"; no "-0").
fn number(x: f64) -> String {
    let text = format!("{:.2}", x + 0.0);
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".to_owned()
    } else {
        text.to_owned()
    }
}

fn positive(x: f64) -> Option<f64> {
    (x.is_finite() && x > 0.0).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_grid_says_what_it_lays_out() {
        assert_eq!(
            PushGrid::default().to_string(),
            "every side, at -0.6, 0 and 0.6 of each face's half length, straight in and 20° \
             either way, 10 cm long"
        );
        let grid = PushGrid {
            sides: vec![PushSide::Left],
            offsets: vec![0.0],
            angles_deg: vec![0.0],
            length_m: 0.05,
        };
        assert_eq!(
            grid.to_string(),
            "the left side, at 0 of each face's half length, straight in, 5 cm long"
        );
        let grid = PushGrid {
            sides: vec![PushSide::Front, PushSide::Back],
            offsets: vec![-0.25, 0.5],
            angles_deg: vec![10.0, -5.0],
            length_m: 0.125,
        };
        assert_eq!(
            grid.to_string(),
            "the front and back sides, at -0.25 and 0.5 of each face's half length, at 10 and -5° \
             from straight in, 12.5 cm long"
        );
    }
}
