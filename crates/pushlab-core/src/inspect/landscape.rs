//! The online loss as a function of `θ_online` over some frames: a grid of COM offsets at one `h`,
//! and a slice over `h` at one COM offset.
//!
//! Each cell is the mean total loss (eq. 8's sum of the three normalised squared errors) of the
//! frames' predictions with that `θ`. Along a push on one face, the loss valley runs along the push:
//! moving the COM along the push direction changes the predicted motion much less than moving it
//! across — the picture that explains why the COM along a front push is poorly determined.
//!
//! A grid costs `cells² × frames` predictions; rows are computed on scoped threads, one per core.

use serde::{Deserialize, Serialize};

use crate::model::{H_MAX, H_MIN, OnlineParams, Sample, sample_at};
use crate::model::{Loss, OnlineModel};
use crate::trajectory::Trajectory;

/// Most samples a landscape scores: a longer span is thinned evenly, so that a grid over a long
/// recording costs what one over a short push does (the loss is a mean; evenly spaced frames keep it).
pub const MAX_LANDSCAPE_SAMPLES: usize = 256;

/// Which frames a landscape scores, counted back from the frame shown. Each frame stands for the
/// sample that predicts from it; the frame shown's is the one the next online step learns from, so
/// the landscape's downhill is where θ is about to move.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LandscapeFrames {
    /// Only the sample that predicts from the frame shown: what one online step sees.
    ThisFrame,
    /// The samples of the last `n` frames up to and including the frame shown.
    Recent(usize),
    /// Every frame from the first to the frame shown: what the posterior has seen, and the next step.
    SoFar,
}

impl LandscapeFrames {
    /// The first frame of the span that ends at `frame`.
    pub fn first(self, frame: usize) -> usize {
        match self {
            Self::ThisFrame => frame,
            Self::Recent(n) => frame.saturating_sub(n.max(1) - 1),
            Self::SoFar => 0,
        }
    }
}

/// The samples a landscape at `frame` scores: those of `frames` that exist (not within the horizon
/// of the end) and that `skipped` does not leave out (frames online learning holds θ over, such as
/// bad tracking), at most [`MAX_LANDSCAPE_SAMPLES`] of them, evenly spaced.
pub fn landscape_samples(
    trajectory: &Trajectory,
    horizon: usize,
    frame: usize,
    frames: LandscapeFrames,
    skipped: &dyn Fn(usize) -> bool,
) -> Vec<Sample> {
    let first = frames.first(frame);
    let span = frame.saturating_sub(first) + 1;
    let stride = span.div_ceil(MAX_LANDSCAPE_SAMPLES).max(1);
    (first..=frame)
        .step_by(stride)
        .filter(|&k| !skipped(k))
        .filter_map(|k| sample_at(trajectory, k, horizon))
        .collect()
}

/// A square grid of COM offsets, object frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ComGrid {
    /// The grid's centre, metres.
    pub centre: [f64; 2],
    /// Half its side, metres.
    pub half_width: f64,
    /// Cells along each side.
    pub cells: usize,
}

impl ComGrid {
    /// A square grid of `cells` × `cells` over the COM `ranges` (`[x, y, …]` as
    /// [`OnlineParams::plausible_ranges`] gives them) with a tenth to spare on each side, so that an
    /// estimate at the edge of the object still shows inside it.
    pub fn covering(ranges: &[(f64, f64)], cells: usize) -> Self {
        let [(x0, x1), (y0, y1)] = [ranges[0], ranges[1]];
        let half = 0.5 * (x1 - x0).abs().max((y1 - y0).abs());
        Self {
            centre: [0.5 * (x0 + x1), 0.5 * (y0 + y1)],
            half_width: 1.1 * half.max(1e-3),
            cells: cells.max(2),
        }
    }

    /// The centre of cell `i` along one axis (`axis` 0 is x, 1 is y), metres.
    pub fn cell_centre(&self, axis: usize, i: usize) -> f64 {
        let size = self.cell_size();
        self.centre[axis] - self.half_width + (i as f64 + 0.5) * size
    }

    /// The side of one cell, metres.
    pub fn cell_size(&self) -> f64 {
        2.0 * self.half_width / self.cells.max(1) as f64
    }
}

/// The mean loss on a [`ComGrid`] at one `h`.
#[derive(Clone, Debug, PartialEq)]
pub struct Landscape {
    pub grid: ComGrid,
    pub h: f64,
    /// Row-major, `y` rows of `x` cells: `loss[iy * cells + ix]`. `NaN` where no frame could be scored.
    pub loss: Vec<f64>,
}

impl Landscape {
    /// The COM offset of the lowest cell and its loss, or `None` if no cell has a loss.
    pub fn minimum(&self) -> Option<([f64; 2], f64)> {
        let cells = self.grid.cells;
        let (index, loss) = self
            .loss
            .iter()
            .copied()
            .enumerate()
            .filter(|(_, l)| l.is_finite())
            .min_by(|a, b| a.1.total_cmp(&b.1))?;
        let (ix, iy) = (index % cells, index / cells);
        Some((
            [self.grid.cell_centre(0, ix), self.grid.cell_centre(1, iy)],
            loss,
        ))
    }

    /// The loss range of the cells with a loss, for a colour scale.
    pub fn range(&self) -> Option<(f64, f64)> {
        let finite = self.loss.iter().copied().filter(|l| l.is_finite());
        finite.fold(None, |acc, l| match acc {
            None => Some((l, l)),
            Some((lo, hi)) => Some((lo.min(l), hi.max(l))),
        })
    }
}

/// The mean total loss of `samples` with `theta` (`NaN` without samples or with a non-finite loss).
pub fn mean_loss<M: OnlineModel + ?Sized>(
    model: &M,
    samples: &[Sample],
    theta: &OnlineParams,
) -> f64 {
    let scale = model.loss_scale();
    let total: f64 = samples
        .iter()
        .map(|s| Loss::of(&model.predict(&s.input, theta).motion, &s.target, &scale).total())
        .sum();
    if samples.is_empty() {
        f64::NAN
    } else {
        total / samples.len() as f64
    }
}

/// The mean loss of `samples` over `grid` at `h`. `cancelled` is polled once before each row (and
/// only then, so counting its calls counts the rows begun: a caller's progress); a cancelled
/// landscape is `None`.
pub fn com_landscape<M: OnlineModel + Sync + ?Sized>(
    model: &M,
    samples: &[Sample],
    grid: &ComGrid,
    h: f64,
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Option<Landscape> {
    crate::slices::finish(com_landscape_in_slices(model, samples, grid, h, cancelled))
}

/// [`com_landscape`] in slices (`crate::slices`): on one core (a page) the rows are computed one
/// after another with a pause after each; on several they are split across the cores, in one
/// piece.
#[cfg_attr(
    target_arch = "wasm32",
    expect(
        clippy::disallowed_methods,
        reason = "a page has no cores to count (available_parallelism fails): one worker, no spawn"
    )
)]
pub async fn com_landscape_in_slices<M: OnlineModel + Sync + ?Sized>(
    model: &M,
    samples: &[Sample],
    grid: &ComGrid,
    h: f64,
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Option<Landscape> {
    let cells = grid.cells;
    let h = h.clamp(H_MIN, H_MAX);
    let row = |iy: usize| -> Option<Vec<f64>> {
        if cancelled() {
            return None;
        }
        let y = grid.cell_centre(1, iy);
        Some(
            (0..cells)
                .map(|ix| {
                    let theta = OnlineParams {
                        com_offset: [grid.cell_centre(0, ix), y],
                        h,
                    };
                    mean_loss(model, samples, &theta)
                })
                .collect(),
        )
    };
    let workers = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(cells.max(1));
    let rows: Vec<Option<Vec<f64>>> = if workers <= 1 || cells * samples.len() < 4096 {
        let mut rows = Vec::with_capacity(cells);
        for iy in 0..cells {
            let done = row(iy);
            let cancelled = done.is_none();
            rows.push(done);
            if cancelled {
                break;
            }
            crate::slices::pause().await;
        }
        rows
    } else {
        let mut rows = vec![None; cells];
        std::thread::scope(|scope| {
            let row = &row;
            let chunks: Vec<_> = rows
                .chunks_mut(cells.div_ceil(workers))
                .enumerate()
                .map(|(c, chunk)| {
                    let first = c * cells.div_ceil(workers);
                    scope.spawn(move || {
                        for (k, slot) in chunk.iter_mut().enumerate() {
                            *slot = row(first + k);
                        }
                    })
                })
                .collect();
            for chunk in chunks {
                // A worker panics only if the model does; pass it on.
                chunk.join().expect("landscape worker");
            }
        });
        rows
    };
    let mut loss = Vec::with_capacity(cells * cells);
    for r in rows {
        loss.extend(r?);
    }
    Some(Landscape {
        grid: *grid,
        h,
        loss,
    })
}

/// The mean loss of `samples` at `com_offset` for each of `hs`.
pub fn h_slice<M: OnlineModel + ?Sized>(
    model: &M,
    samples: &[Sample],
    com_offset: [f64; 2],
    hs: &[f64],
) -> Vec<f64> {
    hs.iter()
        .map(|&h| {
            let theta = OnlineParams { com_offset, h }.clamped();
            mean_loss(model, samples, &theta)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use nalgebra::Point2;

    use super::*;
    use crate::geometry::{Outline, Pose2};
    use crate::trajectory::Frame;

    /// A straight push: the pusher and the object move 1 mm per frame along x, the pusher drifting
    /// sideways so that every sample differs; frame k's time is k.
    fn push(frames: usize) -> Trajectory {
        Trajectory::new(
            (0..frames)
                .map(|k| {
                    let x = k as f64 * 1e-3;
                    Frame {
                        time: k as f64,
                        robot: Point2::new(x - 0.06, k as f64 * 1e-5),
                        object: Pose2::new(x, 0.0, 0.0),
                    }
                })
                .collect(),
        )
    }

    fn start_frames(samples: &[Sample], trajectory: &Trajectory) -> Vec<usize> {
        // Every sample of the push differs: its start frame is its index among all of them.
        let all: Vec<Sample> = (0..trajectory.len())
            .filter_map(|k| sample_at(trajectory, k, 1))
            .collect();
        samples
            .iter()
            .map(|s| {
                all.iter()
                    .position(|a| a == s)
                    .expect("a sample of the push")
            })
            .collect()
    }

    #[test]
    fn the_frames_of_a_landscape_end_at_the_frame_shown_and_leave_out_skipped_ones() {
        let trajectory = push(50);
        let first = |f: LandscapeFrames, frame| f.first(frame);
        assert_eq!(first(LandscapeFrames::ThisFrame, 20), 20);
        assert_eq!(first(LandscapeFrames::Recent(5), 20), 16);
        assert_eq!(first(LandscapeFrames::Recent(50), 20), 0);
        assert_eq!(first(LandscapeFrames::SoFar, 20), 0);
        let count = |frames, frame, skipped: &dyn Fn(usize) -> bool| {
            landscape_samples(&trajectory, 1, frame, frames, skipped).len()
        };
        let none = |_| false;
        assert_eq!(count(LandscapeFrames::ThisFrame, 20, &none), 1);
        assert_eq!(count(LandscapeFrames::Recent(5), 20, &none), 5);
        assert_eq!(count(LandscapeFrames::SoFar, 20, &none), 21);
        // The last frame has no sample (nothing after it to predict).
        assert_eq!(count(LandscapeFrames::ThisFrame, 49, &none), 0);
        assert_eq!(count(LandscapeFrames::Recent(5), 20, &|k| k == 18), 4);
    }

    #[test]
    fn a_long_span_is_thinned_evenly_to_the_cap() {
        let trajectory = push(2000);
        let samples = landscape_samples(&trajectory, 1, 1500, LandscapeFrames::SoFar, &|_| false);
        assert!(samples.len() <= MAX_LANDSCAPE_SAMPLES);
        assert!(samples.len() > MAX_LANDSCAPE_SAMPLES / 2);
        let starts = start_frames(&samples, &trajectory);
        let gaps: Vec<usize> = starts.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(gaps.iter().all(|&g| g == gaps[0]), "{gaps:?}");
    }

    #[test]
    fn the_grid_covers_the_objects_com_range_with_room_to_spare() {
        let outline = Outline::rectangle(0.2, 0.1).expect("a valid box");
        let ranges = OnlineParams::plausible_ranges(Some(&outline));
        assert_eq!(ranges[0], (-0.1, 0.1));
        assert_eq!(ranges[1], (-0.05, 0.05));
        assert_eq!(ranges[2].0, H_MIN);
        let grid = ComGrid::covering(&ranges, 64);
        assert_eq!(grid.centre, [0.0, 0.0]);
        assert!((grid.half_width - 0.11).abs() < 1e-12);
        assert_eq!(grid.cells, 64);
        // Every corner of the object lies inside the grid's outer cells.
        let low = grid.cell_centre(0, 0) - grid.cell_size() / 2.0;
        assert!(low < -0.1);
    }
}
