//! Demo mode: the paper's experiments on the sample data, one click each, for a lecture.
//!
//! The presets are the experiments of `experiments/sample-data.json` (read by the core's
//! [`SuiteSpec`], so there is one list): a demo opens the experiment's recordings, shows its first
//! online recording, and uses a model for its offline recordings — the one remembered for their
//! folders if there is one (the model store, see `model_in_use`), else one trained in the background with the
//! suite's settings, on the recordings the suite's split rule puts offline. Fixed against Online is
//! what the loss plots show; [`narration`] says in plain words what the online run has done.

use std::path::{Path, PathBuf};

use pushlab_core::experiment::suite::SuiteSpec;
use pushlab_core::learn::{MeanLosses, Weights};

use crate::app::format;
use crate::app::state::recordings::session::RecordingId;

/// What the Demos menu asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DemoCommand {
    /// Start the suite's experiment with this index.
    Start(usize),
}

/// The demo suite and the demo running.
pub struct Demos {
    /// The suite and the folder its paths are relative to, or why it could not be read.
    pub suite: Result<(SuiteSpec, PathBuf), String>,
    /// The demo started last.
    pub active: Option<ActiveDemo>,
}

impl Default for Demos {
    fn default() -> Self {
        Self {
            suite: Err("no demo suite loaded".to_owned()),
            active: None,
        }
    }
}

impl Demos {
    /// The demos of the suite file at `path` (paths in it are relative to its folder).
    pub fn load(path: &Path) -> Self {
        let base = path.parent().unwrap_or(Path::new(".")).to_path_buf();
        Self {
            suite: SuiteSpec::load(path)
                .map(|spec| (spec, base))
                .map_err(|e| e.to_string()),
            active: None,
        }
    }

    /// The presets' names, in the suite's order.
    pub fn names(&self) -> Vec<&str> {
        match &self.suite {
            Ok((spec, _)) => spec.experiments.iter().map(|e| e.name.as_str()).collect(),
            Err(_) => Vec::new(),
        }
    }
}

/// A demo that was started.
#[derive(Clone, Debug, PartialEq)]
pub struct ActiveDemo {
    pub name: String,
    /// The recordings its offline model is (or was) trained on.
    pub offline: Vec<RecordingId>,
    /// Its online recordings; the first is shown.
    pub online: Vec<RecordingId>,
    /// Where its model came from, in words.
    pub model: String,
}

/// The numbers the narration speaks about.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NarrationNumbers {
    /// The estimated COM offset at the start of the run and at the frame shown, metres.
    pub com_start: [f64; 2],
    pub com_now: [f64; 2],
    /// The recording's true COM offset, when its setting gives it.
    pub com_true: Option<[f64; 2]>,
    /// Mean losses over the frames learned so far (`None`: nothing learned yet).
    pub losses: Option<MeanLosses>,
    /// The combined model's weights against physics alone at the frame learned last, and their
    /// evidence's half-life in seconds, when the run weighs the two.
    pub trust: Option<(Weights, f64)>,
}

/// One plain sentence on what online learning has done so far.
pub fn narration(n: &NarrationNumbers) -> String {
    let Some(losses) = n.losses else {
        return "Nothing learned yet: press Step or Play, and the model adapts its guess of the \
                centre of mass to this push, frame by frame."
            .to_owned();
    };
    let mm = |a: [f64; 2], b: [f64; 2]| 1000.0 * (a[0] - b[0]).hypot(a[1] - b[1]);
    let moved = mm(n.com_now, n.com_start);
    let com = match n.com_true {
        Some(truth) => {
            let (before, now) = (mm(n.com_start, truth), mm(n.com_now, truth));
            if moved < 0.5 {
                format!("the estimated COM has hardly moved ({now:.0} mm from the true one)")
            } else if now < before - 0.5 {
                format!(
                    "the estimated COM moved {moved:.0} mm toward the true one (now {now:.0} mm from it)"
                )
            } else if now > before + 0.5 {
                format!(
                    "the estimated COM moved {moved:.0} mm away from the true one (now {now:.0} mm \
                     from it, {before:.0} mm at the start)"
                )
            } else {
                format!(
                    "the estimated COM moved {moved:.0} mm but is no closer to the true one \
                     ({now:.0} mm from it)"
                )
            }
        }
        None if moved < 0.5 => {
            "the estimated COM has hardly moved (the true COM is not known)".to_owned()
        }
        None => format!("the estimated COM moved {moved:.0} mm (the true COM is not known)"),
    };
    let online = losses.online_pos + losses.online_rot;
    let fixed = losses.fixed_pos + losses.fixed_rot;
    let loss = compare(online, fixed);
    let frames = match losses.frames {
        1 => "1 frame".to_owned(),
        k => format!("{k} frames"),
    };
    let mut text = format!("After {frames} learned, {com}; {loss}.");
    // Only where physics is trusted: that is what a class should see happen.
    if let Some((weights, half_life_s)) = n.trust {
        for (part, w) in [("translation", weights.pos), ("rotation", weights.rot)] {
            if w < 0.5 {
                text += &format!(" {}.", format::trust(part, w, half_life_s));
            }
        }
    }
    text
}

/// The online loss against the fixed model's, in words.
fn compare(online: f64, fixed: f64) -> String {
    if !(online.is_finite() && fixed.is_finite()) || online.max(fixed) <= 0.0 {
        return "the losses cannot be compared yet".to_owned();
    }
    let times = |r: f64| {
        if r.is_finite() {
            format!("{r:.0}×")
        } else {
            "far".to_owned()
        }
    };
    if online < fixed / 1.05 {
        let ratio = fixed / online;
        if ratio >= 1.95 {
            format!(
                "the online loss is now {} below the fixed model's",
                times(ratio)
            )
        } else {
            let percent = 100.0 * (1.0 - online / fixed);
            format!("the online loss is now {percent:.0} % below the fixed model's")
        }
    } else if online > fixed * 1.05 {
        let ratio = online / fixed;
        let how = if ratio >= 1.95 {
            times(ratio)
        } else {
            format!("{:.0} %", 100.0 * (ratio - 1.0))
        };
        format!(
            "the online loss is {how} above the fixed model's: adapting has not helped on this \
             push so far"
        )
    } else {
        "the online loss is about the same as the fixed model's".to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn losses(frames: usize, online: f64, fixed: f64) -> Option<MeanLosses> {
        Some(MeanLosses {
            frames,
            online_pos: online / 2.0,
            online_rot: online / 2.0,
            fixed_pos: fixed / 2.0,
            fixed_rot: fixed / 2.0,
        })
    }

    fn numbers(now: [f64; 2], truth: Option<[f64; 2]>, losses: Option<MeanLosses>) -> String {
        narration(&NarrationNumbers {
            com_start: [0.0, 0.0],
            com_now: now,
            com_true: truth,
            losses,
            trust: None,
        })
    }

    #[test]
    fn says_how_far_the_com_moved_toward_the_truth_and_how_much_lower_the_loss_is() {
        let text = numbers([0.012, 0.0], Some([0.03, 0.0]), losses(40, 0.1, 0.3));
        assert_eq!(
            text,
            "After 40 frames learned, the estimated COM moved 12 mm toward the true one (now 18 mm \
             from it); the online loss is now 3× below the fixed model's."
        );
    }

    #[test]
    fn says_nothing_was_learned_before_the_first_frame() {
        let text = numbers([0.0, 0.0], Some([0.03, 0.0]), None);
        assert!(text.starts_with("Nothing learned yet"), "{text}");
    }

    #[test]
    fn says_when_the_true_com_is_not_known() {
        let text = numbers([0.0, -0.005], None, losses(1, 0.2, 0.25));
        assert_eq!(
            text,
            "After 1 frame learned, the estimated COM moved 5 mm (the true COM is not known); the \
             online loss is now 20 % below the fixed model's."
        );
    }

    #[test]
    fn says_honestly_when_online_is_worse_than_fixed_and_the_com_moved_away() {
        let text = numbers([-0.01, 0.0], Some([0.02, 0.0]), losses(12, 0.5, 0.2));
        assert_eq!(
            text,
            "After 12 frames learned, the estimated COM moved 10 mm away from the true one (now \
             30 mm from it, 20 mm at the start); the online loss is 2× above the fixed model's: \
             adapting has not helped on this push so far."
        );
        let slightly = numbers([0.0, 0.0], Some([0.0, 0.0]), losses(3, 0.23, 0.2));
        assert!(
            slightly.contains("hardly moved (0 mm from the true one)")
                && slightly.contains("15 % above the fixed model's: adapting has not helped"),
            "{slightly}"
        );
    }

    #[test]
    fn says_where_the_prediction_trusts_physics_and_why() {
        let with = |pos, rot| {
            narration(&NarrationNumbers {
                com_start: [0.0, 0.0],
                com_now: [0.0, 0.0],
                com_true: None,
                losses: losses(30, 0.3, 0.6),
                trust: Some((Weights { pos, rot }, 2.0)),
            })
        };
        assert_eq!(
            with(0.38, 0.7),
            "After 30 frames learned, the estimated COM has hardly moved (the true COM is not \
             known); the online loss is now 2× below the fixed model's. Trusting physics 0.62 for \
             the translation: the network has predicted this object's translation worse than \
             Lynch's model alone over the last 4 s."
        );
        // Where the network is trusted, nothing is added.
        assert!(with(0.8, 0.9).ends_with("below the fixed model's."));
        assert_eq!(with(0.1, 0.2).matches("Trusting physics").count(), 2);
    }

    #[test]
    fn equal_losses_are_about_the_same() {
        let text = numbers([0.0, 0.0], None, losses(5, 0.2, 0.201));
        assert!(
            text.contains("about the same as the fixed model's"),
            "{text}"
        );
    }
}
