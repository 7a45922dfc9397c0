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
    pub contact: bool,
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
            contact: true,
            grid: true,
            motion_gain: 10.0,
        }
    }
}
