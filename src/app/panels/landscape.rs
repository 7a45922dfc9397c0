//! The loss-landscape window: the online loss of the frames chosen over a grid of COM offsets at θ's
//! `h` (a heatmap, log scale, with contour lines), θ's path over the push so far, θ now, the lowest
//! cell and the true COM where the recording knows it; below, the slice over `h` through θ's COM.
//!
//! Everything drawn is computed by pushlab-core on a worker thread (`state::learning::landscape`); this panel
//! only maps it to the screen, in millimetres.

use eframe::egui::{self, Stroke};
use egui_plot::{Heatmap, Legend, Line, MarkerShape, Plot, PlotPoint, PlotPoints, Points, VLine};
use pushlab_core::inspect::LandscapeFrames;

use super::axes;
use crate::app::colors;
use crate::app::state::learning::landscape::{DEFAULT_RECENT, LandscapeCommand, LandscapeResult};
use crate::app::state::{AppState, Command};

/// Most points of θ's path drawn (a long run's path is thinned evenly).
const MAX_PATH_POINTS: usize = 1000;

/// Draws the window when it is open (first over the browser, which matters least while one push is
/// inspected); closing it sends the command that stops its work.
pub fn window(ctx: &egui::Context, state: &AppState, commands: &mut Vec<Command>) {
    if !state.landscape().open {
        return;
    }
    let mut open = true;
    egui::Window::new("Loss landscape")
        .open(&mut open)
        .default_size([420.0, 640.0])
        .default_pos([12.0, 60.0])
        .resizable(true)
        .show(ctx, |ui| contents(ui, state, commands));
    if !open {
        commands.push(Command::Landscape(LandscapeCommand::Show(false)));
    }
}

fn contents(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    frames_choice(ui, state, commands);
    let landscape = &state.landscape();
    if let Some(progress) = landscape.progress() {
        ui.horizontal(|ui| {
            ui.add(
                egui::ProgressBar::new(progress)
                    .desired_width(240.0)
                    .text("computing the landscape…"),
            );
            if ui.button("Cancel").clicked() {
                commands.push(Command::Landscape(LandscapeCommand::Cancel));
            }
        });
    } else if landscape.was_cancelled() {
        ui.horizontal(|ui| {
            ui.weak("cancelled");
            if ui.button("Compute").clicked() {
                commands.push(Command::Landscape(LandscapeCommand::Compute));
            }
        });
    }
    let Some(result) = landscape.result() else {
        if state.run().is_none() {
            ui.weak("The landscape appears when a recording is selected and a model is in use.");
        }
        return;
    };
    describe(ui, state, result);
    if result.samples == 0 {
        ui.weak("No sample to score here: the frame is within the model's horizon of the end.");
        return;
    }
    let side = ui
        .available_width()
        .min(ui.available_height() - 190.0)
        .max(160.0);
    com_plot(ui, state, result, side);
    ui.label("Colour: log₁₀ of the mean loss (eq. 8), dark is low; lines: where the lowest 2, 5, 10, 20, 35, 55 and 80 % of cells end.");
    h_plot(ui, result);
}

fn frames_choice(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let current = state.landscape().frames;
    ui.horizontal(|ui| {
        ui.label("Frames:");
        let mut choose =
            |frames| commands.push(Command::Landscape(LandscapeCommand::SetFrames(frames)));
        if ui
            .selectable_label(current == LandscapeFrames::ThisFrame, "this one")
            .on_hover_text("what one online step sees")
            .clicked()
        {
            choose(LandscapeFrames::ThisFrame);
        }
        let recent = match current {
            LandscapeFrames::Recent(n) => Some(n),
            _ => None,
        };
        if ui
            .selectable_label(recent.is_some(), "last")
            .on_hover_text("the frames up to this one")
            .clicked()
        {
            choose(LandscapeFrames::Recent(DEFAULT_RECENT));
        }
        let mut n = recent.unwrap_or(DEFAULT_RECENT);
        if ui
            .add_enabled(
                recent.is_some(),
                egui::DragValue::new(&mut n).range(2..=100_000),
            )
            .changed()
        {
            choose(LandscapeFrames::Recent(n));
        }
        if ui
            .selectable_label(current == LandscapeFrames::SoFar, "all so far")
            .on_hover_text("every frame from the first: what the posterior has seen")
            .clicked()
        {
            choose(LandscapeFrames::SoFar);
        }
    });
}

fn describe(ui: &mut egui::Ui, state: &AppState, result: &LandscapeResult) {
    let request = &result.request;
    let first = request.frames.first(request.frame);
    let theta = request.theta;
    let samples = match result.samples {
        1 => "1 sample".to_owned(),
        n => format!("{n} samples"),
    };
    let frames = if first == request.frame {
        format!("frame {first}")
    } else {
        format!("frames {first}–{}", request.frame)
    };
    ui.label(format!(
        "{samples} from {frames} at h = {:.1} mm",
        theta.h * 1e3
    ));
    if request.frame != state.frame() {
        ui.weak(format!(
            "(computed at frame {}; catching up)",
            request.frame
        ));
    }
    let [x, y] = theta.com_offset.map(|c| c * 1e3);
    ui.label(format!(
        "θ at frame {}: COM x = {x:.1} mm, y = {y:.1} mm",
        request.frame
    ));
    if let Some(([lx, ly], _)) = result.landscape.minimum() {
        ui.label(format!(
            "lowest cell: x = {:.1} mm, y = {:.1} mm",
            lx * 1e3,
            ly * 1e3
        ));
    }
    if let Some([tx, ty]) = state.recording().and_then(|r| r.setting.com_offset) {
        ui.label(format!(
            "true COM: x = {:.1} mm, y = {:.1} mm",
            tx * 1e3,
            ty * 1e3
        ));
    }
}

/// The heatmap with contours, θ's path, θ now, the lowest cell and the true COM.
fn com_plot(ui: &mut egui::Ui, state: &AppState, result: &LandscapeResult, side: f32) {
    let palette = colors::of(ui.ctx());
    let landscape = &result.landscape;
    let grid = landscape.grid;
    let mm = |v: f64| v * 1e3;
    // log₁₀ of the loss: its range spans decades between the valley and the far corners.
    let logs: Vec<f64> = landscape
        .loss
        .iter()
        .map(|l| l.max(1e-12).log10())
        .collect();
    let (low, high) = landscape.range().map_or((0.0, 1.0), |(lo, hi)| {
        (lo.max(1e-12).log10(), hi.max(1e-12).log10())
    });
    // Cells without a loss get the top of the scale (never the valley's colour).
    let values = logs
        .iter()
        .map(|v| if v.is_finite() { *v } else { high })
        .collect();
    let heatmap = Heatmap::new(values, grid.cells)
        .show_labels(false)
        .palette(&colors::LANDSCAPE_PALETTE)
        .range(low, high.max(low + 1e-9))
        .at(PlotPoint::new(
            mm(grid.centre[0] - grid.half_width),
            mm(grid.centre[1] - grid.half_width),
        ))
        .size(
            mm(2.0 * grid.half_width) as f32,
            mm(2.0 * grid.half_width) as f32,
        )
        .name("mean loss");
    let path = theta_path(state, result.request.frame);
    let theta = result.request.theta.com_offset;
    let minimum = landscape.minimum();
    let truth = state.recording().and_then(|r| r.setting.com_offset);
    let response = axes::x_values(axes::y_values(Plot::new("landscape-com")), "")
        .width(side)
        .height(side)
        .data_aspect(1.0)
        .x_axis_label("COM x (mm)")
        .y_axis_label("COM y (mm)")
        .allow_scroll(false)
        .legend(Legend::default().text_style(egui::TextStyle::Small))
        .show(ui, |plot_ui| {
            plot_ui.heatmap(heatmap);
            plot_ui.line(
                Line::new("θ's path", PlotPoints::new(path))
                    .color(palette.online)
                    .width(1.5),
            );
            plot_ui.points(
                Points::new("θ now", vec![[mm(theta[0]), mm(theta[1])]])
                    .color(palette.online)
                    .shape(MarkerShape::Circle)
                    .filled(true)
                    .radius(5.0),
            );
            if let Some(([x, y], _)) = minimum {
                plot_ui.points(
                    Points::new("lowest cell", vec![[mm(x), mm(y)]])
                        .color(palette.contact)
                        .shape(MarkerShape::Diamond)
                        .radius(5.0),
                );
            }
            if let Some([x, y]) = truth {
                plot_ui.points(
                    Points::new("true COM", vec![[mm(x), mm(y)]])
                        .color(palette.truth)
                        .shape(MarkerShape::Cross)
                        .radius(7.0),
                );
            }
        });
    // Contours over the heatmap, in screen space: hundreds of short segments as plot items would
    // each be a legend-less line of their own.
    let transform = response.transform;
    let painter = ui.painter_at(*transform.frame());
    let stroke = Stroke::new(1.0, palette.contour);
    for contour in &result.contours {
        for [a, b] in &contour.segments {
            let [a, b] =
                [a, b].map(|p| transform.position_from_point(&PlotPoint::new(mm(p[0]), mm(p[1]))));
            painter.line_segment([a, b], stroke);
        }
    }
}

/// θ's COM offset from the first frame to `frame`, millimetres, at most [`MAX_PATH_POINTS`].
fn theta_path(state: &AppState, frame: usize) -> Vec<[f64; 2]> {
    let Some(run) = &state.run() else {
        return Vec::new();
    };
    let checkpoints = run.checkpoints();
    let end = frame.min(checkpoints.len().saturating_sub(1));
    let stride = (end + 1).div_ceil(MAX_PATH_POINTS).max(1);
    let mut path: Vec<[f64; 2]> = checkpoints[..=end]
        .iter()
        .step_by(stride)
        .map(|t| t.com_offset.map(|c| c * 1e3))
        .collect();
    // The path ends where θ is now, however it was thinned.
    path.push(checkpoints[end].com_offset.map(|c| c * 1e3));
    path
}

/// The mean loss over `h` at θ's COM offset, θ's `h` marked.
fn h_plot(ui: &mut egui::Ui, result: &LandscapeResult) {
    let palette = colors::of(ui.ctx());
    let points: Vec<[f64; 2]> = result
        .h_slice
        .iter()
        .filter(|(_, loss)| loss.is_finite())
        .map(|&(h, loss)| [h * 1e3, loss])
        .collect();
    let lowest = points.iter().copied().min_by(|a, b| a[1].total_cmp(&b[1]));
    let h = result.request.theta.h * 1e3;
    if let Some([lh, _]) = lowest {
        ui.label(format!("h slice: lowest at {lh:.1} mm, θ's h = {h:.1} mm"));
    }
    axes::x_values(axes::y_values(Plot::new("landscape-h")), "")
        .height(ui.available_height().clamp(90.0, 160.0))
        .x_axis_label("h (mm)")
        .y_axis_label("mean loss")
        .allow_scroll(false)
        .show(ui, |plot_ui| {
            plot_ui.line(Line::new("loss over h", PlotPoints::new(points)).color(palette.truth));
            plot_ui.vline(VLine::new("θ's h", h).color(palette.online));
            if let Some(point) = lowest {
                plot_ui.points(
                    Points::new("lowest", vec![point])
                        .color(palette.contact)
                        .shape(MarkerShape::Diamond)
                        .radius(4.0),
                );
            }
        });
}
