//! The online run the app plays: pushlab-core's [`learn::OnlineRun`] (the one the CLI's `eval` and
//! `suite` run too, so the app's θ and losses are theirs to the bit) with the plots' series kept
//! beside it.
//!
//! Reading goes straight to the core's run (through `Deref`); every change goes through this type,
//! which lets the plots follow what the run dropped and added ([`RunPlots::follow`]). There is no
//! `DerefMut`, so the two cannot drift apart.

use std::ops::Deref;
use std::sync::{Arc, Weak};

use pushlab_core::experiment::evaluate::start_state;
use pushlab_core::learn::{self, ModelWeight, OnlineConfig, OnlineState, WeightConfig};
use pushlab_core::model::{
    OnlineModel, OnlineParams, OnlineStep, PhysicsOnlyModel, SharedOnlineModel,
};
use pushlab_core::recording::Recording;
use pushlab_core::trajectory::{Frame, Trajectory};

use crate::app::state::learning::run_plots::{RunPlots, Series};

/// Where a run that went on from an earlier push started: θ and the posterior, physics alone's
/// beside it and the weight, and the push before by name.
#[derive(Clone, Debug)]
pub struct Carried {
    pub from: String,
    pub start: OnlineState,
    pub beside: Option<(OnlineState, ModelWeight)>,
}

/// Online learning along the selected recording, and what the plots draw of it.
pub struct OnlineRun {
    run: learn::OnlineRun,
    plots: RunPlots,
    /// The recording learned along (shared data; kept to tell whether the next one pushes the same
    /// object).
    recording: Recording,
    /// The recording whose run this one went on from ("Carry θ to the next push"), by name.
    continued_from: Option<String>,
}

impl OnlineRun {
    /// A run on `recording` at frame 0 with θ = `θ_online(0)` of the model, or going on from where
    /// the run on `from`'s recording ended (the same object, see [`learn::OnlineRun::continuing`]).
    pub fn new(
        model: SharedOnlineModel,
        recording: &Recording,
        horizon: usize,
        config: OnlineConfig,
        from: Option<&OnlineRun>,
    ) -> Self {
        Self::starting(model, recording, (horizon, config), from, None, None)
    }

    /// [`OnlineRun::new`], a run not carried on starting believing the COM `start_com_shift` from
    /// `θ_online(0)`'s — where `pushlab eval --start-com-shift` starts (the core's `start_state`) —
    /// and with `physics`, the physics-only model learning beside it and weighed against it
    /// (starting as `pushlab eval --physics` starts its physics-only run, and carried on with it).
    pub fn starting(
        model: SharedOnlineModel,
        recording: &Recording,
        (horizon, config): (usize, OnlineConfig),
        from: Option<&OnlineRun>,
        start_com_shift: Option<[f64; 2]>,
        physics: Option<PhysicsOnlyModel>,
    ) -> Self {
        let start_of = |model: SharedOnlineModel, from: Option<&OnlineState>| {
            let trajectory = Arc::clone(&recording.trajectory);
            match start_state(model.as_ref(), &config, from, start_com_shift) {
                Some(start) => {
                    learn::OnlineRun::continuing(model, trajectory, horizon, config, &start)
                }
                None => learn::OnlineRun::new(model, trajectory, horizon, config),
            }
        };
        let from_state = from.map(OnlineRun::end_state);
        let mut run = start_of(model, from_state.as_ref());
        if let Some(physics) = physics {
            let carried = from.and_then(|f| f.run.beside_end());
            let physics_run = start_of(Arc::new(physics), carried.as_ref().map(|(state, _)| state));
            let weight = carried.map_or_else(
                || ModelWeight::new(WeightConfig::default()),
                |(_, weight)| weight,
            );
            run = run.with_physics_beside(physics_run, weight);
        }
        let plots = RunPlots::new(&mut run);
        Self {
            run,
            plots,
            recording: recording.clone(),
            continued_from: from.map(|f| f.recording.name.clone()),
        }
    }

    /// The same run again from its start, which went on from an earlier push (another run's
    /// [`OnlineRun::carried`]); with `physics`, physics alone beside it from where it started there.
    pub fn again_from(
        model: SharedOnlineModel,
        recording: &Recording,
        (horizon, config): (usize, OnlineConfig),
        carried: Carried,
        physics: Option<PhysicsOnlyModel>,
    ) -> Self {
        let start_of = |model: SharedOnlineModel, start: &OnlineState| {
            let trajectory = Arc::clone(&recording.trajectory);
            learn::OnlineRun::continuing(model, trajectory, horizon, config, start)
        };
        let mut run = start_of(model, &carried.start);
        if let (Some(physics), Some((start, weight))) = (physics, carried.beside) {
            run = run.with_physics_beside(start_of(Arc::new(physics), &start), weight);
        }
        let plots = RunPlots::new(&mut run);
        Self {
            run,
            plots,
            recording: recording.clone(),
            continued_from: Some(carried.from),
        }
    }

    /// Where this run started, beside it too, and the push it went on from, when it carried θ on
    /// from one.
    pub fn carried(&self) -> Option<Carried> {
        Some(Carried {
            from: self.continued_from.clone()?,
            start: *self.run.start_state(),
            beside: self.run.beside_start(),
        })
    }

    /// Whether a run on `next` may go on from this one: another recording of the same object.
    pub fn carries_to(&self, next: &Recording) -> bool {
        self.recording.source != next.source && self.recording.same_object_as(next)
    }

    /// The recording this run went on from, by name, when it did.
    pub fn continued_from(&self) -> Option<&str> {
        self.continued_from.as_deref()
    }

    /// θ and the posterior where this run has learned to: what the next push goes on from.
    pub fn end_state(&self) -> OnlineState {
        self.run.end_state()
    }

    /// The recording learned along.
    pub fn recording(&self) -> &Recording {
        &self.recording
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

    /// Appends frames that arrived (a live push's); returns the trajectory, shared, for the
    /// recording to hold. It grows in place when the caller let go of the recording's share first:
    /// this run's is let go of here, so a long push is not copied for each batch.
    pub fn extend(&mut self, frames: Vec<Frame>) -> Arc<Trajectory> {
        self.recording.trajectory = Arc::new(Trajectory::new(Vec::new()));
        self.run.extend(frames);
        self.plots.follow(&mut self.run);
        self.recording.trajectory = Arc::clone(self.run.shared_trajectory());
        Arc::clone(&self.recording.trajectory)
    }

    /// Takes `learned` in place of the core run: a copy of it that learned further on a worker
    /// while this one was left alone (`learning_ahead`); the plots follow what the copy added.
    pub fn take_learned_ahead(&mut self, learned: learn::OnlineRun) {
        self.run = learned;
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

    /// Back to the run's start at frame 0 (`θ_online(0)`, or where the push it went on from
    /// ended), forgetting all learning along this recording.
    pub fn reset(&mut self) {
        self.run.reset();
        self.plots.follow(&mut self.run);
    }
}

/// Which run a piece of work was done for: its model and its recording's trajectory. Work keyed to a
/// run (the best θ, the loss landscape) is stale once either changes — another model loaded or
/// trained, another recording selected — even at the same frame and `θ`.
///
/// Held as weak references, compared by address: a weak reference keeps its allocation, so a model
/// or trajectory made after the old one was dropped cannot take its address and pass for it (raw
/// addresses could, and a stale result would show for the new model).
#[derive(Clone, Debug)]
pub struct RunIdentity {
    model: Weak<dyn OnlineModel + Send + Sync>,
    trajectory: Weak<Trajectory>,
}

impl PartialEq for RunIdentity {
    fn eq(&self, other: &Self) -> bool {
        Weak::ptr_eq(&self.model, &other.model) && Weak::ptr_eq(&self.trajectory, &other.trajectory)
    }
}

impl Eq for RunIdentity {}

impl OnlineRun {
    /// This run's identity (see [`RunIdentity`]).
    pub fn identity(&self) -> RunIdentity {
        RunIdentity {
            model: Arc::downgrade(self.run.model()),
            trajectory: Arc::downgrade(&self.recording.trajectory),
        }
    }
}

impl Deref for OnlineRun {
    type Target = learn::OnlineRun;

    fn deref(&self) -> &learn::OnlineRun {
        &self.run
    }
}
