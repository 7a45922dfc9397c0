//! What survives a restart (eframe persistence): the settings a user chose, kept as they were
//! saved, every field defaulted when an older save lacks it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

use pushlab_core::learn::OnlineConfig;
use serde::{Deserialize, Serialize};

use super::DEFAULT_WHAT_IF_STEPS;
use super::playback::layers::Layers;
use super::recordings::browser::BrowserView;
use super::sources::live::LiveChoice;

/// What survives a restart (eframe persistence).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Persisted {
    /// Most recently opened paths, newest first.
    pub recent: Vec<PathBuf>,
    pub layers: Layers,
    pub speed: f64,
    pub looping: bool,
    pub learn_while_playing: bool,
    pub online: OnlineConfig,
    /// Whether selecting another push of the same object goes on from what the one shown learned
    /// (θ and its posterior) instead of from `θ_online(0)`.
    pub carry_theta: bool,
    /// A push not carried on starts believing the COM this far from `θ_online(0)`'s (object frame,
    /// metres), as `pushlab eval --start-com-shift`; `pushlab render` sets it, the window does not.
    pub start_com_shift: Option<[f64; 2]>,
    /// Whether the physics-only model learns its own θ beside the run and the two are weighed
    /// online (`learn::ModelWeight`), as `pushlab eval --physics` reports them.
    pub weigh_physics: bool,
    /// The model trained for each folder of recordings ("Train for these recordings").
    pub folder_models: BTreeMap<PathBuf, PathBuf>,
    /// The browser's filter and sort.
    pub browser: BrowserView,
    /// Steps of the what-if rollouts.
    pub what_if_steps: usize,
    /// Camera streams the user hid, by name.
    pub hidden_cameras: BTreeSet<String>,
    /// The Connect form's choice for each live server connected to, by address.
    pub live_choices: BTreeMap<String, LiveChoice>,
    /// The live server connected to last.
    pub live_url: Option<String>,
}

impl Default for Persisted {
    fn default() -> Self {
        Self {
            recent: Vec::new(),
            layers: Layers::default(),
            speed: 1.0,
            looping: false,
            learn_while_playing: true,
            online: OnlineConfig::default(),
            carry_theta: false,
            start_com_shift: None,
            weigh_physics: true,
            folder_models: BTreeMap::new(),
            browser: BrowserView::default(),
            what_if_steps: DEFAULT_WHAT_IF_STEPS,
            hidden_cameras: BTreeSet::new(),
            live_choices: BTreeMap::new(),
            live_url: None,
        }
    }
}
