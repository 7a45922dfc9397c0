//! Live plots: per-step losses (online vs fixed, positional and rotational, with moving averages) and
//! `θ_online(t)` with the true values dashed. All share the x axis (seconds): zooming one zooms all,
//! the current frame is a vertical cursor, and clicking a plot seeks there.
//!
//! Each series is drawn as its min/max envelope per pixel column over the visible time (the run's
//! `plot_points`), so a million-frame recording draws about as many points as a short one.

use eframe::egui::{self, Id};
use egui_plot::{HLine, Legend, Line, LineStyle, Plot, PlotPoints, PlotUi, VLine};
use pushlab_core::recording::Recording;

use super::axes;
use crate::app::colors::{self, Palette};
use crate::app::state::learning::online::OnlineRun;
use crate::app::state::learning::run_plots::{LossPart, MOVING_AVERAGE, Series};
use crate::app::state::playback::timeline::TimelineCommand;
use crate::app::state::{AppState, Command};

/// Draws the plots.
pub fn ui(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let palette = colors::of(ui.ctx());
    let (Some(run), Some(recording)) = (&state.run(), state.recording()) else {
        ui.centered_and_justified(|ui| ui.weak("Plots appear when a recording is selected"));
        return;
    };
    let frames = &recording.trajectory.frames;
    let t0 = frames.first().map_or(0.0, |f| f.time);
    let now = frames.get(state.frame()).map_or(0.0, |f| f.time - t0);
    // Per recording, so that a new selection starts with its whole duration in view.
    let group = Id::unique(("pushlab-plots", state.session().selected));
    let duration = recording.trajectory.duration().max(1e-3);
    // A live push grows: its plots keep all of it in view while the timeline follows its newest
    // frame.
    let follow = state.growing_following();

    // Two rows with a little room to spare; the rest is claimed below, so that the content is exactly
    // as tall as the panel. (The panel takes its content's height: content a few points shorter
    // shrank it every frame, a few points taller grew it.)
    let row_height = ((ui.available_height() - 12.0) / 2.0).max(80.0);
    let shared = Shared {
        group,
        row_height,
        duration,
        follow,
        now,
    };
    let mut seek = ui.columns(2, |cols| loss_plots(cols, run, palette, &shared));
    ui.add_space(4.0);
    // With physics alone weighed beside the run, a fourth plot: the network's weights.
    let weights = run.model_weight().is_some();
    ui.columns(if weights { 4 } else { 3 }, |cols| {
        if weights && let Some(col) = cols.get_mut(3) {
            seek = seek.or(weight_plot(col, run, frames, t0, palette, &shared));
        }
        seek = seek.or(theta_plots(cols, state, run, recording, palette, &shared));
    });
    ui.allocate_space(egui::vec2(0.0, ui.available_height().max(0.0)));

    if let Some(t) = seek {
        let k = nearest_frame(frames, t0 + t);
        commands.push(Command::Timeline(TimelineCommand::SeekTo(k)));
    }
}

/// What every plot of the panel shares.
struct Shared {
    /// Links the plots' x axes and cursors (per recording).
    group: Id,
    row_height: f32,
    /// The push's duration, seconds: the x axis's span at first.
    duration: f64,
    /// Whether the plots follow a live push, keeping all of it in view.
    follow: bool,
    /// The time shown, seconds since the first frame: the cursor.
    now: f64,
}

/// The loss plots (position, rotation), fixed and online, raw and averaged; returns a click's time.
fn loss_plots(
    cols: &mut [egui::Ui],
    run: &OnlineRun,
    palette: &Palette,
    shared: &Shared,
) -> Option<f64> {
    let mut seek: Option<f64> = None;
    for (col, (title, part)) in cols.iter_mut().zip([
        ("Position loss", LossPart::Pos),
        ("Rotation loss", LossPart::Rot),
    ]) {
        let plot = base_plot(title, shared).legend(
            Legend::default()
                .position(egui_plot::Corner::LeftTop)
                .background_alpha(0.5)
                .text_style(egui::TextStyle::Small),
        );
        let response = plot.show(col, |plot_ui| {
            let (visible, columns) = visible(plot_ui, shared.duration, shared.follow);
            for (name, raw, average, color) in [
                (
                    "Fixed",
                    Series::Fixed(part),
                    Series::FixedAverage(part),
                    palette.fixed,
                ),
                (
                    "Online",
                    Series::Online(part),
                    Series::OnlineAverage(part),
                    palette.online,
                ),
            ] {
                plot_ui.line(
                    Line::new(
                        format!("{name} (per step)"),
                        points(run, raw, visible, columns),
                    )
                    .color(color.gamma_multiply(0.35))
                    .width(1.0),
                );
                plot_ui.line(
                    Line::new(
                        format!("{name} (moving avg {MOVING_AVERAGE})"),
                        points(run, average, visible, columns),
                    )
                    .color(color)
                    .width(2.0),
                );
            }
            cursor(plot_ui, shared.now);
            clicked_x(plot_ui)
        });
        seek = seek.or(response.inner);
    }
    seek
}

/// The network's weight against physics alone, translation and rotation; returns a click's time.
fn weight_plot(
    col: &mut egui::Ui,
    run: &OnlineRun,
    frames: &[pushlab_core::trajectory::Frame],
    t0: f64,
    palette: &Palette,
    shared: &Shared,
) -> Option<f64> {
    let plot = base_plot("Network's weight", shared)
        .include_y(0.0)
        .include_y(1.0)
        .legend(
            Legend::default()
                .position(egui_plot::Corner::LeftBottom)
                .background_alpha(0.5)
                .text_style(egui::TextStyle::Small),
        );
    let response = plot.show(col, |plot_ui| {
        let (visible, columns) = visible(plot_ui, shared.duration, shared.follow);
        let [pos, rot] = weight_points(run, frames, t0, visible, columns);
        plot_ui.line(
            Line::new("translation", pos)
                .color(palette.online)
                .width(2.0),
        );
        plot_ui.line(Line::new("rotation", rot).color(palette.physics).width(2.0));
        cursor(plot_ui, shared.now);
        clicked_x(plot_ui)
    });
    response.inner
}

/// The `θ_online(t)` plots (COM x, y, h), with ±2σ bands and the truth; returns a click's time.
fn theta_plots(
    cols: &mut [egui::Ui],
    state: &AppState,
    run: &OnlineRun,
    recording: &Recording,
    palette: &Palette,
    shared: &Shared,
) -> Option<f64> {
    let setting = &recording.setting;
    let truths = [
        setting.com_offset.map(|c| c[0]),
        setting.com_offset.map(|c| c[1]),
        setting.h,
    ];
    let theta_ranges = state.theta_ranges();
    let mut seek: Option<f64> = None;
    for (index, col) in cols.iter_mut().take(3).enumerate() {
        let title = ["COM offset x [mm]", "COM offset y [mm]", "h [mm]"][index];
        // A COM offset plot spans at least ±1 mm: one that stays put (−1e-16 m) would
        // otherwise be drawn at the scale of its rounding noise. (h's plot includes 0.)
        let plot = base_plot(title, shared);
        let plot = if index < 2 {
            plot.include_y(-MIN_COM_HALF_SPAN_MM)
                .include_y(MIN_COM_HALF_SPAN_MM)
        } else {
            plot
        };
        let response = plot.show(col, |plot_ui| {
            let (visible, columns) = visible(plot_ui, shared.duration, shared.follow);
            band(plot_ui, run, index, theta_ranges[index], visible, columns);
            plot_ui.line(
                Line::new(
                    "θ_online",
                    points(run, Series::Theta(index), visible, columns),
                )
                .color(palette.online)
                .width(2.0),
            );
            if let Some(truth) = truths[index] {
                plot_ui.hline(
                    HLine::new("true", truth * 1e3)
                        .color(palette.truth)
                        .style(LineStyle::dashed_loose()),
                );
            }
            cursor(plot_ui, shared.now);
            clicked_x(plot_ui)
        });
        seek = seek.or(response.inner);
    }
    seek
}

/// The frame nearest to `target` (the recording's clock, seconds): where a click in a plot seeks.
fn nearest_frame(frames: &[pushlab_core::trajectory::Frame], target: f64) -> usize {
    let k = frames.partition_point(|f| f.time < target);
    if k > 0 && (k == frames.len() || target - frames[k - 1].time < frames[k].time - target) {
        k - 1
    } else {
        k
    }
}

/// The combined model's weights (translation, rotation) at the frames weighed within `visible`
/// (seconds since `t0`), about two a pixel column of `columns`.
fn weight_points(
    run: &OnlineRun,
    frames: &[pushlab_core::trajectory::Frame],
    t0: f64,
    visible: (f64, f64),
    columns: usize,
) -> [Vec<[f64; 2]>; 2] {
    let Some(weight) = run.model_weight() else {
        return [Vec::new(), Vec::new()];
    };
    let time = |frame: usize| frames.get(frame).map_or(0.0, |f| f.time - t0);
    let taken = weight.frames();
    let first = taken.partition_point(|f| time(f.frame) < visible.0);
    let last = taken.partition_point(|f| time(f.frame) <= visible.1);
    let step = ((last - first) / (2 * columns.max(1))).max(1);
    let mut points = [Vec::new(), Vec::new()];
    for f in taken[first..last].iter().step_by(step) {
        let t = time(f.frame);
        points[0].push([t, f.weight.pos]);
        points[1].push([t, f.weight.rot]);
    }
    points
}

/// Half the smallest span of a COM offset plot's y axis, millimetres.
const MIN_COM_HALF_SPAN_MM: f64 = 1.0;

/// The posterior's ±2σ band around a component of `θ_online(t)`, shaded, kept within the range the
/// component can take on this object (`range`, metres): the weak prior's band is far wider than the
/// object and would flatten the curve.
fn band(
    plot_ui: &mut PlotUi<'_>,
    run: &OnlineRun,
    component: usize,
    range: (f64, f64),
    visible: (f64, f64),
    columns: usize,
) {
    let palette = colors::of(plot_ui.ctx());
    let high = run.plot_points(Series::ThetaHigh(component), visible, columns);
    let low = run.plot_points(Series::ThetaLow(component), visible, columns);
    if high.len() < 2 || low.len() < 2 {
        return;
    }
    // Upper edge: the highest value per time; lower: the lowest (the envelopes give both per column).
    let edge = |points: &[[f64; 2]], keep_max: bool| {
        let mut out: Vec<[f64; 2]> = Vec::with_capacity(points.len());
        for p in points {
            match out.last_mut() {
                Some(last) if last[0] == p[0] => {
                    if (keep_max && p[1] > last[1]) || (!keep_max && p[1] < last[1]) {
                        last[1] = p[1];
                    }
                }
                _ => out.push(*p),
            }
        }
        out
    };
    let (high, low) = (edge(&high, true), edge(&low, false));
    let clip = |y: f64| y.clamp(range.0 * 1e3, range.1 * 1e3);
    // One mesh between the edges (egui_plot's `FilledArea`): drawn as a quad per segment, the
    // band's anti-aliased shared edges showed as a seam each, stripes at a frame per pixel.
    let ((xs, lows), highs): ((Vec<f64>, Vec<f64>), Vec<f64>) = (high.iter())
        .zip(&low)
        .map(|(h, l)| ((h[0], clip(l[1])), clip(h[1])))
        .unzip();
    plot_ui.add(
        egui_plot::FilledArea::new("±2σ", &xs, &lows, &highs)
            .fill_color(palette.online.gamma_multiply(0.18)),
    );
}

/// The times the plot showed last frame (its first frame, or following a live push: the whole push)
/// and its width in pixel columns.
fn visible(plot_ui: &mut PlotUi<'_>, duration: f64, follow: bool) -> ((f64, f64), usize) {
    if follow {
        plot_ui.set_plot_bounds_x(0.0..=duration);
    }
    let transform = plot_ui.transform();
    let (min, max) = (transform.bounds().min()[0], transform.bounds().max()[0]);
    let range = if follow {
        (0.0, duration)
    } else if min.is_finite() && max.is_finite() && max > min {
        (min, max)
    } else {
        (0.0, duration)
    };
    let pixels = transform.frame().width() * plot_ui.ctx().pixels_per_point();
    (range, (pixels.max(1.0) as usize).min(8192))
}

fn points(
    run: &OnlineRun,
    series: Series,
    visible: (f64, f64),
    columns: usize,
) -> PlotPoints<'static> {
    run.plot_points(series, visible, columns).into()
}

fn base_plot(title: &str, shared: &Shared) -> Plot<'static> {
    let group = shared.group;
    axes::x_values(axes::y_values(Plot::new((title, group))), " s")
        .height(shared.row_height)
        .link_axis(group, [true, false])
        .link_cursor(group, [true, false])
        .allow_zoom([true, false])
        .allow_scroll([true, false])
        .allow_drag([true, false])
        .allow_boxed_zoom(false)
        .y_axis_label(title.to_owned())
        .y_axis_min_width(36.0)
        .default_x_bounds(0.0, shared.duration)
        .auto_bounds([false, true])
        .include_y(0.0)
}

fn cursor(plot_ui: &mut egui_plot::PlotUi<'_>, now: f64) {
    plot_ui.vline(
        VLine::new("now", now)
            .color(colors::of(plot_ui.ctx()).cursor)
            .width(1.0),
    );
}

fn clicked_x(plot_ui: &egui_plot::PlotUi<'_>) -> Option<f64> {
    if plot_ui.response().clicked() {
        plot_ui.pointer_coordinate().map(|p| p.x)
    } else {
        None
    }
}
