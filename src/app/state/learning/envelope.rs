//! Min/max envelopes of long per-frame series, so that a plot draws one vertical stroke per pixel
//! column instead of every point (as rerun's time-series view does).
//!
//! A recording of a million frames has a million losses per series; handing them all to the plot
//! made egui tessellate a 280 MB vertex buffer (more than wgpu allows) and cost tens of milliseconds
//! per frame. An [`Envelope`] is a pyramid of (min, max) pairs over blocks of [`LEAF`]·2ᵏ values of a
//! series that lives elsewhere (the online run's losses, `θ_online(t)`): any range's min and max come
//! from O(log n) blocks plus at most 2·[`LEAF`] raw values at its ends, and a series that grows at its
//! end (online learning) or is cut back (steering) is followed in O(1) amortised per value.
//!
//! Values are `f32`: envelopes are for drawing, a pixel is far coarser than an `f32`'s precision.
//! NaN marks a frame without a value (a frame not learned) and is skipped.

/// Values per block at the pyramid's finest level. Ranges shorter than this read the series itself;
/// it keeps the pyramid at an eighth of the series' size.
pub const LEAF: usize = 16;

/// The smallest and largest value of a range; empty (`min > max`) when it has no value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MinMax {
    pub min: f32,
    pub max: f32,
}

impl MinMax {
    /// No value yet.
    pub const EMPTY: Self = Self {
        min: f32::INFINITY,
        max: f32::NEG_INFINITY,
    };

    /// Whether no value was seen.
    pub fn is_empty(&self) -> bool {
        self.min > self.max
    }

    /// Takes `value` in; NaN (no value) is skipped.
    fn add(&mut self, value: f32) {
        if !value.is_nan() {
            self.min = self.min.min(value);
            self.max = self.max.max(value);
        }
    }

    fn merge(&mut self, other: MinMax) {
        self.min = self.min.min(other.min);
        self.max = self.max.max(other.max);
    }
}

/// A min/max pyramid over the first [`Envelope::len`] values of a series held elsewhere: level k
/// summarises blocks of `LEAF·2ᵏ` values. Only whole blocks are kept; the rest is read from the series.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Envelope {
    levels: Vec<Vec<MinMax>>,
}

impl Envelope {
    /// How many leading values of the series the pyramid summarises (a multiple of [`LEAF`]).
    pub fn len(&self) -> usize {
        self.levels.first().map_or(0, Vec::len) * LEAF
    }

    /// Whether nothing is summarised yet.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Summarises every whole block of the first `len` values of `series` not summarised yet. Call
    /// [`Envelope::truncate`] first when values already summarised changed.
    pub fn extend(&mut self, series: impl Fn(usize) -> f32, len: usize) {
        if self.levels.is_empty() {
            self.levels.push(Vec::new());
        }
        let leaves = &mut self.levels[0];
        while (leaves.len() + 1) * LEAF <= len {
            let start = leaves.len() * LEAF;
            let mut block = MinMax::EMPTY;
            for i in start..start + LEAF {
                block.add(series(i));
            }
            leaves.push(block);
        }
        let mut level = 0;
        while self.levels[level].len() >= 2 {
            if self.levels.len() == level + 1 {
                self.levels.push(Vec::new());
            }
            let (lower, upper) = self.levels.split_at_mut(level + 1);
            let (lower, upper) = (&lower[level], &mut upper[0]);
            while (upper.len() + 1) * 2 <= lower.len() {
                let i = upper.len() * 2;
                let mut block = lower[i];
                block.merge(lower[i + 1]);
                upper.push(block);
            }
            level += 1;
        }
    }

    /// Forgets every block that reaches past the first `len` values (they changed or are gone).
    pub fn truncate(&mut self, len: usize) {
        let mut blocks = len / LEAF;
        for level in &mut self.levels {
            level.truncate(blocks);
            blocks /= 2;
        }
    }

    /// The min and max of `series[from..to]`; `to` must not pass the series' end.
    pub fn range(&self, series: impl Fn(usize) -> f32, from: usize, to: usize) -> MinMax {
        let mut result = MinMax::EMPTY;
        // Past the summarised blocks the series is read as it is.
        let summarised = to.min(self.len());
        for i in from.max(summarised)..to {
            result.add(series(i));
        }
        let (mut a, mut b) = (from, summarised);
        while a < b && a % LEAF != 0 {
            result.add(series(a));
            a += 1;
        }
        while b > a && b % LEAF != 0 {
            b -= 1;
            result.add(series(b));
        }
        // Whole leaves [a, b): climb the pyramid taking the odd blocks at each end.
        let (mut lo, mut hi) = (a / LEAF, b / LEAF);
        let mut level = 0;
        while lo < hi {
            let blocks = &self.levels[level];
            if lo % 2 == 1 {
                result.merge(blocks[lo]);
                lo += 1;
            }
            if hi % 2 == 1 {
                hi -= 1;
                result.merge(blocks[hi]);
            }
            lo /= 2;
            hi /= 2;
            level += 1;
        }
        result
    }
}

/// The points a plot draws for the frames whose times fall in `[x_min, x_max]` of a series, at most
/// about two per pixel column: each of `columns` columns gets its range's min and max (one point
/// when they are equal, none when it has no value). Where the range has no more frames than twice
/// the columns, every point is returned as it is, so zooming in shows the exact series.
///
/// `time_of(i)` is frame i's time, increasing; `frames` the number of frames with a value slot.
pub fn envelope_points(
    envelope: &Envelope,
    series: impl Fn(usize) -> f32,
    time_of: impl Fn(usize) -> f64,
    frames: usize,
    (x_min, x_max): (f64, f64),
    columns: usize,
) -> Vec<[f64; 2]> {
    let first_at_or_after = |x: f64| partition_point(frames, |i| time_of(i) < x);
    let (from, to) = (
        first_at_or_after(x_min),
        partition_point(frames, |i| time_of(i) <= x_max),
    );
    // One frame either side, so the line runs on to the plot's edges.
    let (from, to) = (from.saturating_sub(1), (to + 1).min(frames));
    let columns = columns.max(1);
    if to <= from {
        return Vec::new();
    }
    if to - from <= 2 * columns {
        return (from..to)
            .map(|i| [time_of(i), f64::from(series(i))])
            .filter(|p| !p[1].is_nan())
            .collect();
    }
    let width = (x_max - x_min) / columns as f64;
    let mut points = Vec::with_capacity(2 * columns + 2);
    let mut start = from;
    for column in 0..columns {
        let end = if column + 1 == columns {
            to
        } else {
            first_at_or_after(x_min + width * (column + 1) as f64).clamp(start, to)
        };
        if end > start {
            let MinMax { min, max } = envelope.range(&series, start, end);
            if min <= max {
                let x = x_min + width * (column as f64 + 0.5);
                points.push([x, f64::from(min)]);
                if max > min {
                    points.push([x, f64::from(max)]);
                }
            }
        }
        start = end;
    }
    points
}

/// The first index in `0..len` where `before(i)` is false (`before` true then false, as
/// `slice::partition_point`).
fn partition_point(len: usize, before: impl Fn(usize) -> bool) -> usize {
    let (mut lo, mut hi) = (0, len);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if before(mid) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    lo
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic wiggly series with NaN holes.
    fn series(n: usize) -> Vec<f32> {
        (0..n)
            .map(|i| {
                if i % 37 == 5 {
                    f32::NAN
                } else {
                    ((i as f32) * 0.37).sin() * (1.0 + (i % 101) as f32)
                }
            })
            .collect()
    }

    fn brute(values: &[f32], from: usize, to: usize) -> MinMax {
        let mut m = MinMax::EMPTY;
        for &v in &values[from..to] {
            m.add(v);
        }
        m
    }

    #[test]
    fn every_range_equals_the_brute_force_min_and_max() {
        let values = series(1000);
        let mut envelope = Envelope::default();
        envelope.extend(|i| values[i], values.len());
        assert_eq!(envelope.len(), 992, "whole leaves only");
        for from in (0..1000).step_by(7) {
            for to in (from..=1000).step_by(13) {
                assert_eq!(
                    envelope.range(|i| values[i], from, to),
                    brute(&values, from, to),
                    "{from}..{to}"
                );
            }
        }
        assert!(
            envelope.range(|i| values[i], 5, 6).is_empty(),
            "a NaN alone"
        );
    }

    #[test]
    fn growing_and_cutting_back_gives_the_pyramid_of_the_new_series() {
        let mut values = series(3000);
        let mut grown = Envelope::default();
        // Grow in uneven steps, as learning while playing does.
        let mut len = 0;
        for step in [1, 15, 16, 17, 100, 1000, 851] {
            len += step;
            grown.extend(|i| values[i], len);
        }
        let mut fresh = Envelope::default();
        fresh.extend(|i| values[i], len);
        assert_eq!(grown, fresh);

        // Steering at frame 1234 changes everything after it.
        grown.truncate(1234);
        for v in &mut values[1234..] {
            *v += 50.0;
        }
        grown.extend(|i| values[i], 3000);
        let mut fresh = Envelope::default();
        fresh.extend(|i| values[i], 3000);
        assert_eq!(grown, fresh);
        assert_eq!(
            grown.range(|i| values[i], 1200, 1300),
            brute(&values, 1200, 1300)
        );
    }

    #[test]
    fn a_million_points_become_about_two_per_column_with_the_true_extremes() {
        let n = 1_000_000;
        let values: Vec<f32> = (0..n).map(|i| ((i % 1000) as f32) / 1000.0).collect();
        let mut envelope = Envelope::default();
        envelope.extend(|i| values[i], n);
        let time = |i: usize| i as f64 * 0.004;
        let points = envelope_points(&envelope, |i| values[i], time, n, (0.0, 4000.0), 600);
        assert!(points.len() <= 1200, "{} points", points.len());
        let min = points.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        let max = points
            .iter()
            .map(|p| p[1])
            .fold(f64::NEG_INFINITY, f64::max);
        assert_eq!((min, max), (0.0, f64::from(values[999])));
        // Every point lies within its column and on a value the series has.
        assert!(points.iter().all(|p| (0.0..=4000.0).contains(&p[0])));
    }

    #[test]
    fn zoomed_in_the_series_is_drawn_point_by_point() {
        let values = series(10_000);
        let mut envelope = Envelope::default();
        envelope.extend(|i| values[i], values.len());
        let time = |i: usize| i as f64 * 0.01;
        // 1 s = 100 frames in 600 columns: every point, plus one either side.
        let points = envelope_points(&envelope, |i| values[i], time, 10_000, (20.0, 21.0), 600);
        let expected: Vec<[f64; 2]> = (1999..=2101)
            .filter(|&i| !values[i].is_nan())
            .map(|i| [time(i), f64::from(values[i])])
            .collect();
        assert_eq!(points, expected);
        assert!(
            envelope_points(&envelope, |i| values[i], time, 0, (0.0, 1.0), 10).is_empty(),
            "no frames, no points"
        );
    }
}
