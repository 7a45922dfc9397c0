//! The figure of `pushlab eval --plot`, laid out like the paper's experiment figures.
//!
//! Left: the total online loss per time step, mean over the online trajectories with a shaded ±1
//! standard deviation band, for the fixed model (blue) and online learning (orange), and the mean
//! offline loss as a black line. Right: the mean positional (solid) and rotational (dashed) losses of
//! both, with the offline means in black. Curves are smoothed with a trailing moving average of 10
//! steps, as in the paper. Text uses the font shipped in `assets/fonts`, so rendering never depends
//! on the fonts installed on the machine. The same drawing code writes a PNG or an SVG
//! ([`write`], by the file's extension; the shared parts are `figures`').

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use pushlab_core::learn::{mean_std_across, moving_average};

use super::{Chart, Drawing, FIXED, FONT, ONLINE, legend, plot_error, register};

/// Size of the figure, pixels: two panels side by side, sized so that at the paper's column width
/// (about 3.4 in) the text is still about 6 pt.
pub const WIDTH: u32 = 1000;
pub const HEIGHT: u32 = 400;
/// The paper smooths its curves over 10 time steps.
pub const SMOOTHING: usize = 10;

/// Losses of one trajectory, one value per online step.
#[derive(Clone, Debug, Default)]
pub struct StepLosses {
    /// ℓ (eq. 8).
    pub total: Vec<f64>,
    /// (ℓ_pos,x + ℓ_pos,y) / 2.
    pub pos: Vec<f64>,
    /// ℓ_rot.
    pub rot: Vec<f64>,
}

/// Mean losses of the combined model on the offline data.
#[derive(Clone, Copy, Debug)]
pub struct OfflineMeans {
    pub total: f64,
    pub pos: f64,
    pub rot: f64,
}

/// What the figure shows.
pub struct Figure<'a> {
    /// Printed above the panels, e.g. "offline: box1-paper-center-front / online: box1-paper-ur-front".
    pub title: String,
    /// Per online trajectory, the fixed model's losses.
    pub fixed: &'a [StepLosses],
    /// Per online trajectory, online learning's losses.
    pub online: &'a [StepLosses],
    /// The black lines; `None` without offline data (`eval --model` alone).
    pub offline: Option<OfflineMeans>,
}

/// Renders the figure and writes it as its name's extension says (PNG or SVG), atomically.
pub fn write(path: &Path, figure: &Figure) -> anyhow::Result<()> {
    super::write(path, figure)
}

impl Drawing for Figure<'_> {
    fn size(&self) -> (u32, u32) {
        (WIDTH, HEIGHT)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        draw(root, self)
    }
}

/// The figure on a drawing area of either backend.
fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, figure: &Figure) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    register()?;
    root.fill(&WHITE).map_err(plot_error)?;
    let body = root.titled(&figure.title, (FONT, 20)).map_err(plot_error)?;
    let (left, right) = body.split_horizontally(WIDTH / 2);
    draw_total(&left, figure)?;
    draw_components(&right, figure)?;
    root.present().map_err(plot_error)
}

/// Mean and standard deviation across trajectories, smoothed.
fn band(series: &[Vec<f64>]) -> (Vec<f64>, Vec<f64>) {
    let (mean, std) = mean_std_across(series);
    (
        moving_average(&mean, SMOOTHING),
        moving_average(&std, SMOOTHING),
    )
}

fn smoothed_mean(series: &[Vec<f64>]) -> Vec<f64> {
    moving_average(&mean_std_across(series).0, SMOOTHING)
}

fn points(values: &[f64]) -> Vec<(f64, f64)> {
    values
        .iter()
        .enumerate()
        .filter(|(_, v)| v.is_finite())
        .map(|(i, &v)| (i as f64, v))
        .collect()
}

/// The x range (time steps) and a y range from 0 to a little above the largest value shown.
fn ranges<'a>(
    lengths: impl Iterator<Item = usize>,
    values: impl Iterator<Item = &'a f64>,
) -> (std::ops::Range<f64>, std::ops::Range<f64>) {
    let steps = lengths.max().unwrap_or(0).max(2);
    let top = values
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    // Head room for the legend in the upper right corner.
    let top = if top > 0.0 { top * 1.35 } else { 1.0 };
    (0.0..(steps - 1) as f64, 0.0..top)
}

fn draw_total<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    figure: &Figure,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let totals = |s: &[StepLosses]| s.iter().map(|l| l.total.clone()).collect::<Vec<_>>();
    let (fixed_mean, fixed_std) = band(&totals(figure.fixed));
    let (online_mean, online_std) = band(&totals(figure.online));
    let upper = |m: &[f64], s: &[f64]| m.iter().zip(s).map(|(m, s)| m + s).collect::<Vec<_>>();
    let fixed_top = upper(&fixed_mean, &fixed_std);
    let online_top = upper(&online_mean, &online_std);
    let (x, y) = ranges(
        [fixed_mean.len(), online_mean.len()].into_iter(),
        fixed_top
            .iter()
            .chain(&online_top)
            .chain(figure.offline.as_ref().map(|o| &o.total)),
    );
    let (x_end, y_top) = (x.end, y.end);
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .caption("total loss (mean ± 1 std)", (FONT, 22))
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d(x, y)
        .map_err(plot_error)?;
    configure(&mut chart, y_top)?;
    for (mean, std, colour, name) in [
        (&fixed_mean, &fixed_std, FIXED, "Fixed"),
        (&online_mean, &online_std, ONLINE, "Online"),
    ] {
        let mut outline: Vec<(f64, f64)> = mean
            .iter()
            .zip(std.iter())
            .enumerate()
            .filter(|(_, (m, s))| m.is_finite() && s.is_finite())
            .map(|(i, (m, s))| (i as f64, m + s))
            .collect();
        let lower: Vec<(f64, f64)> = mean
            .iter()
            .zip(std.iter())
            .enumerate()
            .filter(|(_, (m, s))| m.is_finite() && s.is_finite())
            .map(|(i, (m, s))| (i as f64, (m - s).max(0.0)))
            .rev()
            .collect();
        outline.extend(lower);
        if outline.len() >= 3 {
            chart
                .draw_series(std::iter::once(Polygon::new(
                    outline,
                    colour.mix(0.2).filled(),
                )))
                .map_err(plot_error)?;
        }
        chart
            .draw_series(LineSeries::new(points(mean), colour.stroke_width(3)))
            .map_err(plot_error)?
            .label(name)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
            });
    }
    if let Some(offline) = &figure.offline {
        chart
            .draw_series(LineSeries::new(
                vec![(0.0, offline.total), (x_end, offline.total)],
                BLACK.stroke_width(2),
            ))
            .map_err(plot_error)?
            .label("Offline")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], BLACK.stroke_width(2)));
    }
    legend(&mut chart, 16)
}

fn draw_components<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    figure: &Figure,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let pick = |s: &[StepLosses], f: fn(&StepLosses) -> &Vec<f64>| {
        s.iter().map(|l| f(l).clone()).collect::<Vec<_>>()
    };
    let curves = [
        (
            smoothed_mean(&pick(figure.fixed, |l| &l.pos)),
            FIXED,
            false,
            "Fixed",
        ),
        (
            smoothed_mean(&pick(figure.fixed, |l| &l.rot)),
            FIXED,
            true,
            "Fixed",
        ),
        (
            smoothed_mean(&pick(figure.online, |l| &l.pos)),
            ONLINE,
            false,
            "Online",
        ),
        (
            smoothed_mean(&pick(figure.online, |l| &l.rot)),
            ONLINE,
            true,
            "Online",
        ),
    ];
    let (x, y) = ranges(
        curves.iter().map(|c| c.0.len()),
        curves
            .iter()
            .flat_map(|c| c.0.iter())
            .chain(figure.offline.iter().flat_map(|o| [&o.pos, &o.rot])),
    );
    let (x_end, y_top) = (x.end, y.end);
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .caption("mean loss: pos (solid), rot (dashed)", (FONT, 22))
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d(x, y)
        .map_err(plot_error)?;
    configure(&mut chart, y_top)?;
    for (values, colour, dashed, name) in &curves {
        let style = colour.stroke_width(3);
        let colour = *colour;
        let drawn = if *dashed {
            chart.draw_series(DashedLineSeries::new(points(values), 10, 6, style))
        } else {
            chart.draw_series(LineSeries::new(points(values), style))
        }
        .map_err(plot_error)?;
        // One legend entry per colour; the caption says which line style is which loss.
        if !*dashed {
            drawn.label(*name).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
            });
        }
    }
    if let Some(offline) = &figure.offline {
        chart
            .draw_series(LineSeries::new(
                vec![(0.0, offline.pos), (x_end, offline.pos)],
                BLACK.stroke_width(2),
            ))
            .map_err(plot_error)?
            .label("Offline")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], BLACK.stroke_width(2)));
        chart
            .draw_series(DashedLineSeries::new(
                vec![(0.0, offline.rot), (x_end, offline.rot)],
                10,
                6,
                BLACK.stroke_width(2),
            ))
            .map_err(plot_error)?;
    }
    legend(&mut chart, 16)
}

fn configure<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
    y_top: f64,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    // Enough decimals to tell the ticks apart, no more.
    let decimals = if y_top >= 10.0 {
        0
    } else if y_top >= 1.0 {
        1
    } else {
        2
    };
    let y_label = move |y: &f64| format!("{y:.decimals$}");
    chart
        .configure_mesh()
        .light_line_style(WHITE)
        .bold_line_style(BLACK.mix(0.08))
        .x_desc("time step")
        .y_desc("online loss")
        .label_style((FONT, 18))
        .axis_desc_style((FONT, 20))
        .x_labels(6)
        .y_labels(6)
        .x_label_formatter(&|x| format!("{x:.0}"))
        .y_label_formatter(&y_label)
        .draw()
        .map_err(plot_error)
}
