//! Which layers the scene draws. Plain data, persisted between runs.

use serde::{Deserialize, Serialize};

/// Scene layers the user can switch on and off (the legend doubles as the toggles).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Layers {
    pub robot_path: bool,
    pub trails: bool,
    pub true_now: bool,
    pub true_target: bool,
    pub predicted_online: bool,
    pub predicted_fixed: bool,
    pub predicted_pure_nn: bool,
    pub predicted_physics: bool,
    pub com_estimated: bool,
    pub com_true: bool,
    /// The COM of the best θ for the whole push, once the Steer tab found it (a ring).
    pub com_best: bool,
    /// The 95 % ellipse of the estimated COM (the posterior of `θ_online`).
    pub com_ellipse: bool,
    /// What-if rollouts: the model's own predictions fed back for k steps, as fading ghosts.
    pub what_if: bool,
    /// The COM labelled in the recording's metadata (a draggable diamond).
    pub com_label: bool,
    /// What the controller would do from the frame shown, toward where the push ends (its
    /// planned arc and the pusher's way); off by default: it plans at every frame moved.
    pub controller: bool,
    pub contact: bool,
    /// The best few of the Steer tab's next pushes, as numbered arrows on the object.
    pub next_pushes: bool,
    pub grid: bool,
    /// Target poses are drawn with their motion from the current pose multiplied by this, so that
    /// millimetre-sized per-frame motions and their errors are visible.
    pub motion_gain: f64,
}

impl Default for Layers {
    fn default() -> Self {
        Self {
            robot_path: true,
            trails: true,
            true_now: true,
            true_target: true,
            predicted_online: true,
            predicted_fixed: true,
            predicted_pure_nn: false,
            predicted_physics: false,
            com_estimated: true,
            com_true: true,
            com_best: true,
            com_ellipse: true,
            what_if: true,
            com_label: true,
            controller: false,
            contact: true,
            next_pushes: true,
            grid: true,
            motion_gain: 10.0,
        }
    }
}

/// A layer's switch in [`Layers`].
type Switch = fn(&mut Layers) -> &mut bool;

/// Each layer's short name (what `pushlab render --layers` takes) and its switch, in the legend's
/// order: one table for the parser and its message.
pub const NAMED: [(&str, Switch); 18] = [
    ("true-now", |l| &mut l.true_now),
    ("true-target", |l| &mut l.true_target),
    ("online", |l| &mut l.predicted_online),
    ("fixed", |l| &mut l.predicted_fixed),
    ("physics", |l| &mut l.predicted_physics),
    ("pure-nn", |l| &mut l.predicted_pure_nn),
    ("what-if", |l| &mut l.what_if),
    ("controller", |l| &mut l.controller),
    ("com", |l| &mut l.com_estimated),
    ("ellipse", |l| &mut l.com_ellipse),
    ("true-com", |l| &mut l.com_true),
    ("best-com", |l| &mut l.com_best),
    ("com-label", |l| &mut l.com_label),
    ("contact", |l| &mut l.contact),
    ("next-pushes", |l| &mut l.next_pushes),
    ("robot-path", |l| &mut l.robot_path),
    ("trails", |l| &mut l.trails),
    ("grid", |l| &mut l.grid),
];

impl Layers {
    /// Only the layers named (comma-separated short names of [`NAMED`]), the motion gain kept; an
    /// unknown name is an error listing the names.
    pub fn only(&self, names: &str) -> Result<Self, String> {
        let mut only = self.clone();
        for (_, switch) in NAMED {
            *switch(&mut only) = false;
        }
        for name in names.split(',').map(str::trim).filter(|n| !n.is_empty()) {
            let Some((_, switch)) = NAMED.iter().find(|(n, _)| *n == name) else {
                let names: Vec<&str> = NAMED.iter().map(|(n, _)| *n).collect();
                return Err(format!(
                    "no layer `{name}`: the layers are {}",
                    names.join(", ")
                ));
            };
            *switch(&mut only) = true;
        }
        Ok(only)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_layers_named_are_on_and_a_wrong_name_lists_them() {
        let only = Layers::default().only("online, com,grid").expect("names");
        assert!(only.predicted_online && only.com_estimated && only.grid);
        assert!(!only.trails && !only.true_now && !only.com_ellipse && !only.predicted_fixed);
        assert_eq!(only.motion_gain, Layers::default().motion_gain);
        let error = Layers::default()
            .only("online,comm")
            .expect_err("a wrong name");
        assert!(
            error.starts_with("no layer `comm`: the layers are true-now, true-target, online"),
            "{error}"
        );
        // Every switch has a name: with every named one off, no layer is on.
        let mut all = Layers::default();
        for (_, switch) in NAMED {
            *switch(&mut all) = false;
        }
        let fields = serde_json::to_value(&all).expect("JSON");
        for (field, value) in fields.as_object().expect("an object") {
            assert_ne!(value, &serde_json::Value::Bool(true), "{field} has no name");
        }
    }
}
