//! The loss-landscape window's state: which frames it scores, and the landscape of the frame shown,
//! computed by pushlab-core (`inspect::com_landscape`, `h_slice`, `contours`) off the UI thread (a
//! worker thread on the desktop, a slice of each frame in a page: `platform`).
//!
//! The landscape follows the frame shown and `θ` there, but never queues: while one is computed,
//! later frames wait, and when it arrives the newest request starts. During playback the window so
//! shows the landscape of a frame a few frames back, marked as such, rather than falling behind
//! without end. A user's cancel holds until the request changes (another frame, other frames, a new
//! θ or model), so that it is not restarted at once. The UI thread only polls.

use std::sync::Arc;

use pushlab_core::inspect::{
    ComGrid, Contour, DEFAULT_QUANTILES, Landscape, LandscapeFrames, com_landscape_in_slices,
    contour_levels, contours, h_slice, landscape_samples,
};
use pushlab_core::model::OnlineParams;

use crate::app::state::job::{Job, take_ended};
use crate::app::state::learning::online::{OnlineRun, RunIdentity};

/// Cells along each side of the COM grid (the 64 × 64 of the `landscape_64` benchmark).
pub const LANDSCAPE_CELLS: usize = 64;
/// Values of `h` in the slice.
pub const H_SLICE_POINTS: usize = 64;
/// Frames "Last N" scores unless the user chooses otherwise.
pub const DEFAULT_RECENT: usize = 50;

/// A change to the landscape window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LandscapeCommand {
    /// Show or hide the window (hidden, nothing is computed).
    Show(bool),
    /// Score these frames.
    SetFrames(LandscapeFrames),
    /// Stop the landscape being computed.
    Cancel,
    /// Compute the landscape of the frame shown again after a cancel.
    Compute,
}

/// What a landscape is computed for: when any of it changes, the landscape shown is out of date.
#[derive(Clone, Debug, PartialEq)]
pub struct LandscapeRequest {
    /// The run it is for (a new model or recording is a new request).
    run: RunIdentity,
    pub frame: usize,
    pub frames: LandscapeFrames,
    /// θ at the frame: the grid is at its `h`, the slice through its COM offset.
    pub theta: OnlineParams,
    pub grid: ComGrid,
}

/// A computed landscape and what it was computed for.
#[derive(Clone, Debug)]
pub struct LandscapeResult {
    pub request: LandscapeRequest,
    pub landscape: Landscape,
    pub contours: Vec<Contour>,
    /// The slice over `h` at θ's COM offset: `(h, mean loss)`, metres.
    pub h_slice: Vec<(f64, f64)>,
    /// Samples scored (0: nothing to score at this frame; the landscape is all `NaN`).
    pub samples: usize,
    /// Counts results, so that a view can tell a new one from the one it drew.
    pub generation: u64,
}

/// The landscape window's state.
pub struct LandscapeState {
    pub open: bool,
    pub frames: LandscapeFrames,
    result: Option<LandscapeResult>,
    /// The landscape being computed, with its request.
    job: Option<(LandscapeRequest, Job<LandscapeResult>)>,
    /// The request the user cancelled, not started again while it stays the newest.
    cancelled: Option<LandscapeRequest>,
    generation: u64,
}

impl Default for LandscapeState {
    fn default() -> Self {
        Self {
            open: false,
            frames: LandscapeFrames::Recent(DEFAULT_RECENT),
            result: None,
            job: None,
            cancelled: None,
            generation: 0,
        }
    }
}

impl LandscapeState {
    /// The last landscape computed (perhaps for an earlier frame: compare its request).
    pub fn result(&self) -> Option<&LandscapeResult> {
        self.result.as_ref()
    }

    /// The fraction of the running landscape's rows begun, or `None` when none runs.
    pub fn progress(&self) -> Option<f32> {
        self.job.as_ref().map(|(_, job)| job.progress())
    }

    /// Whether a landscape is being computed.
    pub fn is_running(&self) -> bool {
        self.job.is_some()
    }

    /// Whether the user cancelled the landscape of the current request.
    pub fn was_cancelled(&self) -> bool {
        self.cancelled.is_some()
    }

    fn stop(&mut self) {
        // Dropping the job cancels it.
        if let Some((request, _)) = self.job.take() {
            self.cancelled = Some(request);
        }
    }

    /// Takes a finished landscape; returns whether one arrived or the worker ended.
    fn poll(&mut self) -> bool {
        let Some((request, result)) = take_ended(&mut self.job) else {
            return false;
        };
        match result {
            Some(mut result) => {
                self.generation += 1;
                result.generation = self.generation;
                self.result = Some(result);
            }
            // The worker died (a cancel drops the job before a poll can see it): held like a
            // cancel, so that the same request is not started again on every frame.
            None => self.cancelled = Some(request),
        }
        true
    }
}

/// What the owner hands the landscape: the run of the recording shown, the frame shown, the ranges
/// θ is plotted in and the frames labelled to skip.
pub struct LandscapeSource<'a> {
    pub run: &'a OnlineRun,
    pub frame: usize,
    pub ranges: [(f64, f64); 3],
    pub skip: Arc<[bool]>,
}

impl LandscapeSource<'_> {
    /// What the landscape of this frame is computed for.
    fn request(&self, frames: LandscapeFrames) -> LandscapeRequest {
        LandscapeRequest {
            run: self.run.identity(),
            frame: self.frame,
            frames,
            theta: self.run.theta_at(self.frame),
            grid: ComGrid::covering(&self.ranges, LANDSCAPE_CELLS),
        }
    }
}

impl LandscapeState {
    /// Applies a change to the landscape window (the owner then calls [`LandscapeState::update`]).
    pub fn apply(&mut self, command: LandscapeCommand) {
        match command {
            LandscapeCommand::Show(open) => {
                self.open = open;
                if !open {
                    self.stop();
                }
            }
            LandscapeCommand::SetFrames(frames) => self.frames = frames,
            LandscapeCommand::Cancel => self.stop(),
            LandscapeCommand::Compute => self.cancelled = None,
        }
    }

    /// Takes a finished landscape and, with the window open and no landscape running, starts the
    /// one of `source` (the frame shown) if that is neither the one shown nor the one cancelled.
    /// Returns whether anything is running.
    pub fn update(&mut self, source: Option<LandscapeSource<'_>>) -> bool {
        self.poll();
        if !self.open || self.is_running() {
            return self.is_running();
        }
        let Some(source) = source else {
            return false;
        };
        let request = source.request(self.frames);
        let done = self.result.as_ref().map(|r| &r.request);
        if done == Some(&request) || self.cancelled.as_ref() == Some(&request) {
            return false;
        }
        self.cancelled = None;
        self.start(request, &source);
        true
    }

    fn start(&mut self, request: LandscapeRequest, source: &LandscapeSource<'_>) {
        let run = source.run;
        let samples = landscape_samples(
            run.trajectory(),
            run.horizon(),
            request.frame,
            request.frames,
            &|k| run.is_skipped(k, &source.skip),
        );
        let model = Arc::clone(run.model());
        let for_request = request.clone();
        let (h_low, h_high) = source.ranges[2];
        let hs: Vec<f64> = (0..H_SLICE_POINTS)
            .map(|i| h_low + (h_high - h_low) * i as f64 / (H_SLICE_POINTS - 1) as f64)
            .collect();
        let job = Job::spawn_in_slices(move |context| async move {
            // The landscape checks for a cancel once per row it begins.
            let rows_begun = context.counting_checks(for_request.grid.cells);
            let theta = for_request.theta;
            let landscape = com_landscape_in_slices(
                model.as_ref(),
                &samples,
                &for_request.grid,
                theta.h,
                &rows_begun,
            )
            .await?;
            let levels = contour_levels(&landscape, &DEFAULT_QUANTILES);
            let slice = h_slice(model.as_ref(), &samples, theta.com_offset, &hs);
            Some(LandscapeResult {
                request: for_request,
                contours: contours(&landscape, &levels),
                landscape,
                h_slice: hs.into_iter().zip(slice).collect(),
                samples: samples.len(),
                generation: 0,
            })
        });
        self.job = Some((request, job));
    }
}
