//! Cleaning two pose streams and resampling them onto one time grid, shared by the importers whose
//! sources record the pusher and the object as separate, unsynchronised streams (MIT Push Dataset
//! files and ROS 2 bags). One implementation, so that both report the same defects with the same
//! words and align the streams by the same rules.
//!
//! Rows are `[t, x, y, yaw]`, `t` in seconds. The limits every stream obeys are here too, with the
//! one problem of their span, so that each importer's own problems wrap them rather than restate
//! them.

use nalgebra::Point2;

use crate::geometry::{Pose2, unwrap_angles};
use crate::trajectory::Frame;

/// A gap between consecutive samples longer than this is reported, seconds.
pub const GAP_WARN_S: f64 = 0.050;
/// Fewest rows a pusher or object stream must keep after cleaning.
pub const MIN_ROWS: usize = 10;
/// Shortest usable overlap of the pusher and object streams, seconds.
pub const MIN_DURATION_S: f64 = 0.1;
/// Longest accepted push, seconds: a push lasts seconds; more means broken timestamps (and would
/// make the resampled grid enormous).
pub const MAX_DURATION_S: f64 = 600.0;
/// Largest position magnitude accepted, metres from the origin of the recording's frame.
pub const MAX_POSITION_M: f64 = 100.0;

/// Keeps the rows whose timestamp increases, reporting backwards and repeated stamps and long gaps
/// as warnings that start with `key` (a stream must be monotone to be interpolated).
pub(crate) fn clean(key: &str, rows: &[[f64; 4]], warnings: &mut Vec<String>) -> Vec<[f64; 4]> {
    let mut kept: Vec<[f64; 4]> = Vec::with_capacity(rows.len());
    let (mut backwards, mut worst, mut repeated) = (0usize, 0.0f64, 0usize);
    for (i, row) in rows.iter().enumerate() {
        if i > 0 {
            let step = row[0] - rows[i - 1][0];
            if step < 0.0 {
                backwards += 1;
                worst = worst.min(step);
            } else if step == 0.0 {
                repeated += 1;
            }
        }
        if kept.last().is_none_or(|last| row[0] > last[0]) {
            kept.push(*row);
        }
    }
    let dropped = rows.len() - kept.len();
    if backwards > 0 {
        warnings.push(format!(
            "{key}: {backwards} timestamp(s) step backwards (worst {:.1} ms); {dropped} row(s) out of order dropped",
            worst * 1e3
        ));
    } else if repeated > 0 {
        warnings.push(format!(
            "{key}: {repeated} repeated timestamp(s); {dropped} row(s) dropped"
        ));
    }
    let (mut gaps, mut longest) = (0usize, 0.0f64);
    for pair in kept.windows(2) {
        let step = pair[1][0] - pair[0][0];
        if step > GAP_WARN_S {
            gaps += 1;
            longest = longest.max(step);
        }
    }
    if gaps > 0 {
        warnings.push(format!(
            "{key}: {gaps} gap(s) over {:.0} ms (longest {:.1} ms); interpolated across",
            GAP_WARN_S * 1e3,
            longest * 1e3
        ));
    }
    kept
}

/// Unwraps the yaw column (kept in (−π, π] by every source) so that interpolation never swings the
/// long way round; notes how often it wrapped (nothing is lost: a note, not a warning).
pub(crate) fn unwrap_yaw(key: &str, rows: &mut [[f64; 4]], notes: &mut Vec<String>) {
    let mut yaw: Vec<f64> = rows.iter().map(|r| r[3]).collect();
    let wraps = unwrap_angles(&mut yaw);
    if wraps > 0 {
        notes.push(format!("{key} yaw wraps at ±π {wraps} time(s); unwrapped"));
        for (row, y) in rows.iter_mut().zip(&yaw) {
            row[3] = *y;
        }
    }
}

/// Why two streams cannot be put on one grid. Each importer says which streams ("the tip and object
/// streams …").
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum SpanProblem {
    /// They overlap for less than [`MIN_DURATION_S`] (the overlap, ≥ 0).
    #[error("overlap for only {seconds:.3} s, expected at least {MIN_DURATION_S} s")]
    TooShort { seconds: f64 },
    /// They overlap for more than [`MAX_DURATION_S`].
    #[error(
        "span {seconds:.0} s, expected a push shorter than {MAX_DURATION_S} s (broken timestamps?)"
    )]
    TooLong { seconds: f64 },
}

/// The grid over the interval both cleaned, non-empty streams cover: its start time and number of
/// points at `rate_hz`. The grid never reaches past the shorter stream.
pub(crate) fn grid(
    a: &[[f64; 4]],
    b: &[[f64; 4]],
    rate_hz: f64,
) -> Result<(f64, usize), SpanProblem> {
    let (Some(a0), Some(a1), Some(b0), Some(b1)) = (a.first(), a.last(), b.first(), b.last())
    else {
        return Err(SpanProblem::TooShort { seconds: 0.0 });
    };
    let start = a0[0].max(b0[0]);
    let end = a1[0].min(b1[0]);
    let duration = end - start;
    // Written so that a NaN duration is refused too.
    if duration.is_nan() || duration < MIN_DURATION_S {
        return Err(SpanProblem::TooShort {
            seconds: duration.max(0.0),
        });
    }
    if duration > MAX_DURATION_S {
        return Err(SpanProblem::TooLong { seconds: duration });
    }
    // Truncation is intended. Bounded by MAX_DURATION_S × rate.
    Ok((start, (duration * rate_hz).floor() as usize + 1))
}

/// Linear interpolation in a time-sorted stream, for queries at increasing times (a moving cursor
/// makes resampling linear in the number of rows). Queries outside the stream clamp to its ends.
pub(crate) struct Interpolator<'a> {
    rows: &'a [[f64; 4]],
    cursor: usize,
}

impl<'a> Interpolator<'a> {
    /// An interpolator over non-empty, time-sorted rows.
    pub(crate) fn new(rows: &'a [[f64; 4]]) -> Self {
        Self { rows, cursor: 0 }
    }

    /// The row at time `t`.
    pub(crate) fn at(&mut self, t: f64) -> [f64; 4] {
        let rows = self.rows;
        while self.cursor + 2 < rows.len() && rows[self.cursor + 1][0] <= t {
            self.cursor += 1;
        }
        between(
            rows[self.cursor],
            rows[(self.cursor + 1).min(rows.len() - 1)],
            t,
        )
    }
}

/// The row at time `t` on the segment from row `a` to row `b` (clamped to it): the one
/// interpolation of a resampled frame, for a file read whole ([`Interpolator`]) and for a live stream
/// ([`crate::live`]) alike.
pub(crate) fn between(a: [f64; 4], b: [f64; 4], t: f64) -> [f64; 4] {
    let span = b[0] - a[0];
    let w = if span > 0.0 {
        ((t - a[0]) / span).clamp(0.0, 1.0)
    } else {
        0.0
    };
    [
        t,
        a[1] + w * (b[1] - a[1]),
        a[2] + w * (b[2] - a[2]),
        a[3] + w * (b[3] - a[3]),
    ]
}

/// The time of grid point `k` on the streams' clock, for a grid from `start` at `rate_hz`.
pub(crate) fn grid_time(start: f64, k: usize, rate_hz: f64) -> f64 {
    start + k as f64 / rate_hz
}

/// Frame `k` of a grid at `rate_hz` (its time from the grid's start) from the pusher's and the
/// object's rows at its time.
pub(crate) fn grid_frame(k: usize, rate_hz: f64, tip: [f64; 4], obj: [f64; 4]) -> Frame {
    Frame {
        time: k as f64 / rate_hz,
        robot: Point2::new(tip[1], tip[2]),
        object: Pose2::new(obj[1], obj[2], obj[3]),
    }
}
