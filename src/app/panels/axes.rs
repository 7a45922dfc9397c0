//! Plot axes that keep their labels: grid steps of 1, 2 and 5 × 10ⁿ, the labelled step far enough
//! apart for egui_plot to print it, and as many decimals as the step needs.
//!
//! egui_plot's default steps are powers of ten, and it prints a step's labels only when they are
//! far enough apart (20–30 points on a value axis, 60–80 across). Between powers of ten that often
//! leaves one label: a 10 s push in a 330-point plot labelled "0 s" alone (1 s steps too close,
//! 10 s past the end), a COM plot of an MIT object (±60 mm in 130 points) and the loss landscape's
//! COM axes (±250 mm in 250 points) "0" alone. Its own formatter also wrote 0.1 for both 0.05 and
//! 0.10.

use egui_plot::{GridInput, Plot, uniform_grid_spacer};

/// How far apart, in points, the labelled steps of an axis across (x) and along (y) are at least.
const X_LABEL_POINTS: f64 = 75.0;
const Y_LABEL_POINTS: f64 = 30.0;

/// `plot` with 1–2–5 value steps and labels on its y axis.
pub fn y_values(plot: Plot<'_>) -> Plot<'_> {
    plot.y_grid_spacer(uniform_grid_spacer(y_steps))
        .y_axis_formatter(|mark, _| label(mark.value, mark.step_size))
}

/// `plot` with 1–2–5 value steps and labels on its x axis, each followed by `unit` (`" s"`, or
/// `""` where the axis's title names it).
pub fn x_values<'a>(plot: Plot<'a>, unit: &'static str) -> Plot<'a> {
    plot.x_grid_spacer(uniform_grid_spacer(x_steps))
        .x_axis_formatter(move |mark, _| format!("{}{unit}", label(mark.value, mark.step_size)))
}

/// Grid steps for an x axis (labels at least 75 points apart), each dividing the next.
#[allow(clippy::needless_pass_by_value)] // the signature egui_plot's `uniform_grid_spacer` calls
fn x_steps(input: GridInput) -> [f64; 3] {
    steps(&input, X_LABEL_POINTS)
}

/// Grid steps for a y axis (labels at least 30 points apart, where egui_plot prints them in full).
#[allow(clippy::needless_pass_by_value)] // the signature egui_plot's `uniform_grid_spacer` calls
fn y_steps(input: GridInput) -> [f64; 3] {
    steps(&input, Y_LABEL_POINTS)
}

/// `value` with the decimals that tell values `step` apart: step 0.05 → "0.05", 50 → "50".
fn label(value: f64, step: f64) -> String {
    format!("{:.*}", decimals_for(step), value)
}

/// 1–2–5 grid steps whose largest, the labelled one, is at least `labelled_points` apart.
fn steps(input: &GridInput, labelled_points: f64) -> [f64; 3] {
    // `base_step_size` is the value spanned by the plot's minimum grid spacing (8 points).
    let per_point = input.base_step_size / 8.0;
    let labelled = nice_step(per_point * labelled_points);
    let medium = finer(labelled);
    [finer(medium), medium, labelled]
}

/// The decimals that tell a step's values apart: 0.05 → 2, 0.1 → 1, 50 → 0.
fn decimals_for(step: f64) -> usize {
    if !(step.is_finite() && step > 0.0) {
        return 0;
    }
    // The nudge keeps 0.1 (0.09999… in binary) at one decimal.
    (-(step.log10() + 1e-9).floor()).max(0.0) as usize
}

/// The next finer 1–2–5 step that divides `step`: 5 → 1, 2 → 1, 1 → 0.5.
fn finer(step: f64) -> f64 {
    let mantissa = step / 10f64.powf(step.log10().floor());
    if (mantissa - 1.0).abs() < 1e-6 || (mantissa - 2.0).abs() < 1e-6 {
        step / 2.0
    } else {
        step / 5.0
    }
}

/// The smallest of 1, 2 or 5 × 10ⁿ that is at least `x`.
fn nice_step(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return 1.0;
    }
    let power = 10f64.powf(x.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * power)
        .find(|&step| step >= x * (1.0 - 1e-9))
        .unwrap_or(10.0 * power)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_steps_follow_one_two_five() {
        let steps: Vec<f64> = [0.09, 0.1, 0.11, 0.3, 0.7, 1.0, 1.5, 3.0, 12.0]
            .into_iter()
            .map(nice_step)
            .collect();
        assert_eq!(steps, [0.1, 0.1, 0.2, 0.5, 1.0, 1.0, 2.0, 5.0, 20.0]);
    }

    #[test]
    fn a_ten_second_push_in_a_330_point_plot_gets_labels_every_five_seconds() {
        // 10 s over 330 points: the minimum grid spacing of 8 points spans 10 / 330 * 8 s.
        let steps = x_steps(GridInput {
            bounds: (0.0, 10.0),
            base_step_size: 10.0 / 330.0 * 8.0,
        });
        assert_eq!(steps, [0.5, 1.0, 5.0]);
        // Zoomed in to 1 s over the same width: labels every 0.5 s.
        let steps = x_steps(GridInput {
            bounds: (3.0, 4.0),
            base_step_size: 1.0 / 330.0 * 8.0,
        });
        assert_eq!(steps, [0.05, 0.1, 0.5]);
    }

    #[test]
    fn a_com_plot_of_an_mit_object_gets_values_labelled_every_50_mm() {
        // ±60 mm over 130 points.
        let steps = y_steps(GridInput {
            bounds: (-60.0, 60.0),
            base_step_size: 120.0 / 130.0 * 8.0,
        });
        assert_eq!(steps, [5.0, 10.0, 50.0]);
    }

    #[test]
    fn the_landscapes_com_axis_gets_labels_every_200_mm() {
        // ±250 mm across 250 points.
        let steps = x_steps(GridInput {
            bounds: (-250.0, 250.0),
            base_step_size: 500.0 / 250.0 * 8.0,
        });
        assert_eq!(steps, [50.0, 100.0, 200.0]);
    }

    #[test]
    fn labels_have_the_decimals_their_step_needs() {
        let labels = |step: f64| {
            (0..4)
                .map(|k| label(k as f64 * step, step))
                .collect::<Vec<_>>()
        };
        assert_eq!(labels(50.0), ["0", "50", "100", "150"]);
        assert_eq!(labels(0.05), ["0.00", "0.05", "0.10", "0.15"]);
        assert_eq!(labels(0.1), ["0.0", "0.1", "0.2", "0.3"]);
        assert_eq!(labels(0.002), ["0.000", "0.002", "0.004", "0.006"]);
    }
}
