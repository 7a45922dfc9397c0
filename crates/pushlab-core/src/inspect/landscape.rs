//! The online loss as a function of `θ_online` over some frames: a grid of COM offsets at one `h`,
//! and a slice over `h` at one COM offset.
//!
//! Each cell is the mean total loss (eq. 8's sum of the three normalised squared errors) of the
//! frames' predictions with that `θ`. Along a push on one face, the loss valley runs along the push:
//! moving the COM along the push direction changes the predicted motion much less than moving it
//! across — the picture that explains why the COM along a front push is poorly determined.
//!
//! A grid costs `cells² × frames` predictions; rows are computed on scoped threads, one per core.

use crate::learn::{Loss, OnlineModel};
use crate::model::{H_MAX, H_MIN, OnlineParams, Sample};

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

/// The mean loss of `samples` over `grid` at `h`. `cancelled` is polled once per row; a cancelled
/// landscape is `None`.
pub fn com_landscape<M: OnlineModel + Sync + ?Sized>(
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
        (0..cells).map(row).collect()
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
