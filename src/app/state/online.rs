//! The online run the app plays: pushlab-core's [`learn::OnlineRun`] (the one the CLI's `eval` and
//! `suite` run too, so the app's θ and losses are theirs to the bit) with the plots' series kept
//! beside it.
//!
//! Reading goes straight to the core's run (through `Deref`); every change goes through this type,
//! which lets the plots follow what the run dropped and added ([`RunPlots::follow`]). There is no
//! `DerefMut`, so the two cannot drift apart.

use std::ops::Deref;
use std::sync::Arc;

use pushlab_core::learn::{self, OnlineConfig};
use pushlab_core::model::{OnlineParams, OnlineStep, SharedOnlineModel};
use pushlab_core::trajectory::Trajectory;

use super::run_plots::{RunPlots, Series};

/// Online learning along the selected recording, and what the plots draw of it.
pub struct OnlineRun {
    run: learn::OnlineRun,
    plots: RunPlots,
}

impl OnlineRun {
    /// A run at frame 0 with θ = `θ_online(0)` of the model.
    pub fn new(
        model: SharedOnlineModel,
        trajectory: Arc<Trajectory>,
        horizon: usize,
        config: OnlineConfig,
    ) -> Self {
        let mut run = learn::OnlineRun::new(model, trajectory, horizon, config);
        let plots = RunPlots::new(&mut run);
        Self { run, plots }
    }

    /// The plots' derived series.
    pub fn plots(&self) -> &RunPlots {
        &self.plots
    }

    /// The points to draw of `series` for the times `(x_min, x_max)` (seconds since the first frame)
    /// in a plot `columns` pixels wide: about two per column.
    pub fn plot_points(
        &self,
        series: Series,
        visible: (f64, f64),
        columns: usize,
    ) -> Vec<[f64; 2]> {
        self.plots.points(&self.run, series, visible, columns)
    }

    /// Learns from every frame in `from..to` (see [`learn::OnlineRun::learn_through`]).
    pub fn learn_through(&mut self, from: usize, to: usize, skip_frames: &[bool]) {
        self.run.learn_through(from, to, skip_frames);
        self.plots.follow(&mut self.run);
    }

    /// Sets θ at `frame` (a user's steering), forgetting everything learned after it.
    pub fn set_theta_at(&mut self, frame: usize, theta: OnlineParams) {
        self.run.set_theta_at(frame, theta);
        self.plots.follow(&mut self.run);
    }

    /// A new update rule from `frame` on; the steps after it are learned again.
    pub fn set_config_at(&mut self, frame: usize, config: OnlineConfig) {
        self.run.set_config_at(frame, config);
        self.plots.follow(&mut self.run);
    }

    /// One online update from the sample at `frame` ("Learn this frame").
    pub fn learn_this_frame(&mut self, frame: usize) -> Option<OnlineStep> {
        let step = self.run.learn_this_frame(frame);
        self.plots.follow(&mut self.run);
        step
    }

    /// Back to `θ_online(0)` at frame 0, forgetting all learning.
    pub fn reset(&mut self) {
        self.run.reset();
        self.plots.follow(&mut self.run);
    }
}

impl Deref for OnlineRun {
    type Target = learn::OnlineRun;

    fn deref(&self) -> &learn::OnlineRun {
        &self.run
    }
}
