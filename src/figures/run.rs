//! One online run as the app's plots panel shows it, for a file (File → Export plots as SVG or PDF…): the
//! position and rotation losses per step — the fixed model's and online learning's, each with its
//! trailing moving average over the last [`MOVING_AVERAGE`] steps — and `θ_online` (COM offset x, y
//! and h, in mm) with its ±2σ band and the true value dashed when the setting knows it. x is
//! seconds since the push's first frame, as in the app.
//!
//! A series of more points than twice the panel's pixel columns is drawn as each column's first,
//! lowest, highest and last point (as the app's envelopes do), so a 67-minute push is a file of a
//! few hundred kilobytes that looks like the full series at any zoom a viewer allows.

use plotters::coord::Shift;
use plotters::prelude::*;
use pushlab_core::learn::{Spread, moving_average};
use pushlab_core::model::{FrameLoss, OnlineParams};

use super::{Chart, Drawing, FIXED, FONT, ONLINE, legend, plot_error, register};

/// The figure's size, pixels.
pub const WIDTH: u32 = 1500;
pub const HEIGHT: u32 = 800;
/// The app's moving average (`state::learning::run_plots`).
pub const MOVING_AVERAGE: usize = 25;

/// What the figure shows: one run, one value per sample (per frame learned for θ).
pub struct RunFigure<'a> {
    /// Printed above the panels: the recording and the model.
    pub title: String,
    /// Seconds since the first frame, one per frame.
    pub times: Vec<f64>,
    /// The fixed model's loss at each sample.
    pub fixed: &'a [FrameLoss],
    /// Online learning's loss at each sample learned (`None`: held).
    pub learned: &'a [Option<FrameLoss>],
    /// θ at each frame up to where the run learned.
    pub theta: &'a [OnlineParams],
    pub spreads: &'a [Spread],
    /// COM offset x, y and h, metres, where the setting knows them.
    pub truth: [Option<f64>; 3],
}

impl Drawing for RunFigure<'_> {
    fn size(&self) -> (u32, u32) {
        (WIDTH, HEIGHT)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        register()?;
        root.fill(&WHITE).map_err(plot_error)?;
        let body = root.titled(&self.title, (FONT, 22)).map_err(plot_error)?;
        let (losses, thetas) = body.split_vertically(HEIGHT / 2 - 10);
        let loss_areas = losses.split_evenly((1, 2));
        for (area, (title, pick)) in loss_areas.iter().zip([
            (
                "Position loss",
                (|l: &FrameLoss| l.pos) as fn(&FrameLoss) -> f64,
            ),
            ("Rotation loss", |l: &FrameLoss| l.rot),
        ]) {
            self.draw_loss(area, title, pick)?;
        }
        let theta_areas = thetas.split_evenly((1, 3));
        for (component, area) in theta_areas.iter().enumerate() {
            self.draw_theta(area, component)?;
        }
        root.present().map_err(plot_error)
    }
}

impl RunFigure<'_> {
    fn time(&self, k: usize) -> f64 {
        self.times.get(k).copied().unwrap_or(k as f64)
    }

    fn duration(&self) -> f64 {
        self.times.last().copied().unwrap_or(0.0).max(1e-3)
    }

    fn draw_loss<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        title: &str,
        pick: fn(&FrameLoss) -> f64,
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let fixed: Vec<f64> = self.fixed.iter().map(pick).collect();
        let fixed_average = moving_average(&fixed, MOVING_AVERAGE);
        let online: Vec<f64> = (self.learned.iter())
            .map(|l| l.as_ref().map_or(f64::NAN, pick))
            .collect();
        let online_average = learned_average(&online);
        let columns = (area.dim_in_pixel().0 as usize).max(1);
        let top = fixed
            .iter()
            .chain(&online)
            .copied()
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max);
        let top = if top > 0.0 { top * 1.15 } else { 1.0 };
        let mut chart = chart(area, title, 0.0..self.duration(), 0.0..top)?;
        mesh(&mut chart)?;
        for (values, colour, width, name) in [
            (&fixed, FIXED.mix(0.35), 1, "Fixed (per step)"),
            (&online, ONLINE.mix(0.35), 1, "Online (per step)"),
            (&fixed_average, FIXED.mix(1.0), 3, "Fixed (moving avg 25)"),
            (
                &online_average,
                ONLINE.mix(1.0),
                3,
                "Online (moving avg 25)",
            ),
        ] {
            let style = colour.stroke_width(width);
            for (i, run) in self.runs(values, columns).into_iter().enumerate() {
                let series = chart
                    .draw_series(LineSeries::new(run, style))
                    .map_err(plot_error)?;
                // One legend entry per series, however many stretches a held step breaks it into.
                if i == 0 {
                    series
                        .label(name)
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style));
                }
            }
        }
        legend(&mut chart, 14)
    }

    fn draw_theta<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        component: usize,
    ) -> anyhow::Result<()>
    where
        DB::ErrorType: 'static,
    {
        let mm = |m: f64| m * 1e3;
        let value = |p: &OnlineParams| mm(p.to_array()[component]);
        let theta: Vec<f64> = self.theta.iter().map(value).collect();
        let sigma: Vec<f64> = (self.spreads.iter())
            .map(|s| mm(s.std()[component]))
            .collect();
        let high: Vec<f64> = theta.iter().zip(&sigma).map(|(t, s)| t + 2.0 * s).collect();
        let low: Vec<f64> = theta.iter().zip(&sigma).map(|(t, s)| t - 2.0 * s).collect();
        let truth = self.truth[component].map(mm);
        let finite = |v: &&f64| v.is_finite();
        let shown = theta.iter().chain(&high).chain(&low).chain(&truth);
        let (mut bottom, mut top) = shown
            .filter(finite)
            .fold((f64::MAX, f64::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        if bottom > top {
            (bottom, top) = (-1.0, 1.0);
        }
        // As the app: a COM offset spans at least ±1 mm; h's plot includes 0.
        if component < 2 {
            (bottom, top) = (bottom.min(-1.0), top.max(1.0));
        } else {
            bottom = bottom.min(0.0);
        }
        let pad = (top - bottom) * 0.08;
        let title = ["COM offset x [mm]", "COM offset y [mm]", "h [mm]"][component];
        let mut chart = chart(
            area,
            title,
            0.0..self.duration(),
            (bottom - pad)..(top + pad),
        )?;
        mesh(&mut chart)?;
        let columns = (area.dim_in_pixel().0 as usize).max(1);
        // The ±2σ band: the upper edge forward, the lower back.
        let upper: Vec<(f64, f64)> = self.runs(&high, columns).concat();
        let mut outline = upper;
        outline.extend(self.runs(&low, columns).concat().into_iter().rev());
        if outline.len() >= 3 {
            chart
                .draw_series(std::iter::once(Polygon::new(
                    outline,
                    ONLINE.mix(0.18).filled(),
                )))
                .map_err(plot_error)?
                .label("±2σ")
                .legend(|(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 24, y + 5)], ONLINE.mix(0.18).filled())
                });
        }
        for (i, run) in self.runs(&theta, columns).into_iter().enumerate() {
            let series = chart
                .draw_series(LineSeries::new(run, ONLINE.stroke_width(3)))
                .map_err(plot_error)?;
            if i == 0 {
                series.label("θ_online").legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], ONLINE.stroke_width(3))
                });
            }
        }
        if let Some(truth) = truth {
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(0.0, truth), (self.duration(), truth)],
                    10,
                    6,
                    BLACK.mix(0.6).stroke_width(2),
                ))
                .map_err(plot_error)?
                .label("true")
                .legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], BLACK.mix(0.6).stroke_width(2))
                });
        }
        legend(&mut chart, 14)
    }

    /// The finite stretches of `values` (one per sample) as points at their times, each thinned to
    /// about two points per pixel column.
    fn runs(&self, values: &[f64], columns: usize) -> Vec<Vec<(f64, f64)>> {
        let per_column = (values.len() / columns).max(1);
        let mut runs = Vec::new();
        let mut current: Vec<(f64, f64)> = Vec::new();
        let mut k = 0;
        while k < values.len() {
            let end = (k + per_column).min(values.len());
            let block: Vec<(usize, f64)> = (k..end)
                .filter(|&i| values[i].is_finite())
                .map(|i| (i, values[i]))
                .collect();
            if block.len() < end - k {
                // A gap (a held step): the line breaks here.
                if !current.is_empty() {
                    runs.push(std::mem::take(&mut current));
                }
                if block.is_empty() {
                    k = end;
                    continue;
                }
            }
            if per_column == 1 {
                current.extend(block.iter().map(|&(i, v)| (self.time(i), v)));
            } else {
                // First, lowest, highest, last, in the order they occur.
                let (lo, hi) = (block.iter()).fold((block[0], block[0]), |(lo, hi), &p| {
                    (
                        if p.1 < lo.1 { p } else { lo },
                        if p.1 > hi.1 { p } else { hi },
                    )
                });
                let mut picked = vec![block[0], lo, hi, block[block.len() - 1]];
                picked.sort_by_key(|p| p.0);
                picked.dedup_by_key(|p| p.0);
                current.extend(picked.iter().map(|&(i, v)| (self.time(i), v)));
            }
            k = end;
        }
        if !current.is_empty() {
            runs.push(current);
        }
        runs
    }
}

/// The moving average over the last [`MOVING_AVERAGE`] learned steps (NaN where held), as the
/// app's online average.
fn learned_average(values: &[f64]) -> Vec<f64> {
    let mut recent = std::collections::VecDeque::with_capacity(MOVING_AVERAGE);
    values
        .iter()
        .map(|&v| {
            if !v.is_finite() {
                return f64::NAN;
            }
            recent.push_back(v);
            if recent.len() > MOVING_AVERAGE {
                recent.pop_front();
            }
            recent.iter().sum::<f64>() / recent.len() as f64
        })
        .collect()
}

fn chart<'a, DB: DrawingBackend + 'a>(
    area: &'a DrawingArea<DB, Shift>,
    title: &str,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
) -> anyhow::Result<Chart<'a, DB>>
where
    DB::ErrorType: 'static,
{
    ChartBuilder::on(area)
        .margin(10)
        .caption(title, (FONT, 20))
        .x_label_area_size(36)
        .y_label_area_size(60)
        .build_cartesian_2d(x, y)
        .map_err(plot_error)
}

fn mesh<'a, DB: DrawingBackend + 'a>(chart: &mut Chart<'a, DB>) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let x_label = |x: &f64| format!("{x:.0} s");
    chart
        .configure_mesh()
        .light_line_style(WHITE)
        .bold_line_style(BLACK.mix(0.08))
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 16))
        .x_labels(6)
        .y_labels(6)
        .x_label_formatter(&x_label)
        .draw()
        .map_err(plot_error)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figure_of(times: Vec<f64>) -> RunFigure<'static> {
        RunFigure {
            title: String::new(),
            times,
            fixed: &[],
            learned: &[],
            theta: &[],
            spreads: &[],
            truth: [None; 3],
        }
    }

    #[test]
    fn a_long_series_is_thinned_to_its_columns_extremes_and_a_held_step_breaks_it() {
        let n = 100_000;
        let values: Vec<f64> = (0..n).map(|i| ((i * 7919) % 1000) as f64).collect();
        let figure = figure_of((0..n).map(|i| i as f64 * 0.004).collect());
        let runs = figure.runs(&values, 500);
        assert_eq!(runs.len(), 1);
        let points = &runs[0];
        assert!(points.len() <= 4 * 500, "{} points", points.len());
        let ys: Vec<f64> = points.iter().map(|p| p.1).collect();
        assert_eq!(ys.iter().copied().fold(f64::MAX, f64::min), 0.0);
        assert_eq!(ys.iter().copied().fold(f64::MIN, f64::max), 999.0);
        assert!(points.windows(2).all(|w| w[0].0 < w[1].0), "in time order");

        // Short series are drawn point by point; a NaN (a held step) splits the line.
        let short = [1.0, 2.0, f64::NAN, 4.0, 5.0];
        let figure = figure_of((0..5).map(f64::from).collect());
        assert_eq!(
            figure.runs(&short, 500),
            [vec![(0.0, 1.0), (1.0, 2.0)], vec![(3.0, 4.0), (4.0, 5.0)]]
        );
    }
}
