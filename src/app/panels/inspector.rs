//! The frame inspector: for the frame shown, the model's inputs, the network's outputs `c` and `u_c`,
//! predicted vs true motion, the losses and the gradient on `θ_online` — what an engineer needs to
//! debug one frame — and why labels were proposed there.

use eframe::egui::{self, RichText};

use std::path::Path;

use crate::app::colors;
use crate::app::format;
use crate::app::state::AppState;
use crate::app::state::labels::proposals::Status;

/// Draws the inspector.
pub fn ui(ui: &mut egui::Ui, state: &AppState) {
    let palette = colors::of(ui.ctx());
    let frame = state.frame();
    let (Some(_), Some(recording)) = (&state.run(), state.recording()) else {
        ui.weak("Select a recording to inspect its frames.");
        return;
    };
    let Some(predictions) = state.predictions() else {
        ui.label(format!(
            "Frame {frame} has no sample: it is within the prediction horizon of the end."
        ));
        proposals_section(ui, state, &recording.source, frame);
        return;
    };
    let (sample, step, fixed) = (predictions.sample, predictions.online, predictions.fixed);
    let mm = |v: f64| format!("{:+.3} mm", v * 1e3);
    let mm2 = |v: [f64; 2]| format!("({:+.3}, {:+.3}) mm", v[0] * 1e3, v[1] * 1e3);
    let deg = |v: f64| format!("{:+.3}°", v.to_degrees());

    let time = recording
        .trajectory
        .frames
        .get(frame)
        .map_or(0.0, |f| f.time);
    ui.label(format!("Frame {frame}, t = {time:.3} s"));
    ui.add_space(4.0);
    proposals_section(ui, state, &recording.source, frame);
    section(ui, "Inputs (object frame at t)", |ui| {
        row(ui, "robot position", mm2(sample.input.robot_in_object));
        row(ui, "robot motion", mm2(sample.input.robot_motion_in_object));
    });
    section(ui, "θ_online at this frame", |ui| {
        row(ui, "COM offset", mm2(step.theta_before.com_offset));
        row(ui, "h", mm(step.theta_before.h));
    });
    section(ui, "Network outputs", |ui| {
        row(
            ui,
            "contact c",
            step.prediction.contact.map_or("—".to_owned(), mm2),
        );
        row(
            ui,
            "contact motion u_c",
            step.prediction.contact_motion.map_or("—".to_owned(), mm2),
        );
    });
    section(ui, "Motion: predicted vs true", |ui| {
        let p = &step.prediction.motion;
        let t = &sample.target;
        let f = &fixed.prediction.motion;
        row_colored(ui, "online Δx, Δy", mm2(p.translation), palette.online);
        row_colored(ui, "online Δθ", deg(p.rotation), palette.online);
        row_colored(ui, "fixed Δx, Δy", mm2(f.translation), palette.fixed);
        row_colored(ui, "fixed Δθ", deg(f.rotation), palette.fixed);
        row_colored(ui, "true Δx, Δy", mm2(t.translation), palette.truth);
        row_colored(ui, "true Δθ", deg(t.rotation), palette.truth);
    });
    section(ui, "Losses (normalised)", |ui| {
        let l = &step.loss;
        row_colored(
            ui,
            "online: pos x, pos y, rot",
            [l.pos_x, l.pos_y, l.rot]
                .map(|v| format::loss(v, 4))
                .join(", "),
            palette.online,
        );
        row_colored(
            ui,
            "online: total",
            format::loss(l.total(), 4),
            palette.online,
        );
        row_colored(
            ui,
            "fixed: total",
            format::loss(fixed.loss.total(), 4),
            palette.fixed,
        );
    });
    section(ui, "Gradient of the loss on θ_online", |ui| {
        let g = step.gradient;
        row(ui, "d loss / d COM x", format!("{:+.4e} /m", g[0]));
        row(ui, "d loss / d COM y", format!("{:+.4e} /m", g[1]));
        row(ui, "d loss / d h", format!("{:+.4e} /m", g[2]));
    });
    if let Some(rollout) = state.what_if()
        && let Some((&(last, _), (offset, yaw))) = rollout
            .poses
            .last()
            .zip(rollout.final_error(&recording.trajectory))
    {
        section(ui, "What if: rolled ahead with θ at this frame", |ui| {
            row(
                ui,
                "steps (k chosen in Steer)",
                format!(
                    "{} of {}",
                    rollout.poses.len(),
                    state.settings().what_if_steps
                ),
            );
            row(ui, "last predicted frame", last.to_string());
            row(
                ui,
                "final position error",
                format!("{:.3} mm", offset * 1e3),
            );
            row(ui, "final yaw error", deg(yaw));
        });
    }
}

/// Why labels were proposed at `frame`: the gap against the contact tolerance, the drift in σ, the
/// residual in σ and how sure each proposal is, and whether it is still to be decided.
fn proposals_section(ui: &mut egui::Ui, state: &AppState, source: &Path, frame: usize) {
    ui.label(RichText::new("Label proposals at this frame").strong());
    match state.proposals().status(source) {
        Status::Ready(proposals) => {
            let pending = state.pending_proposals();
            let lines = proposals.why(frame);
            if lines.is_empty() {
                ui.weak("nothing proposed here");
            }
            for (proposal, line) in proposals.at(frame).zip(lines) {
                let decided = if state.proposals().is_rejected(source, proposal) {
                    " (rejected)"
                } else if pending.iter().any(|p| std::ptr::eq(p.proposal, proposal)) {
                    ""
                } else {
                    " (labelled)"
                };
                ui.label(format!("{line}{decided}"));
            }
            if let Some(e) = proposals.evidence.get(frame)
                && e.residual_z.is_finite()
            {
                ui.label(format!(
                    "model residual: {:.1} σ above its running median (bad tracking from {} σ)",
                    e.residual_z, proposals.options.residual_sigmas
                ));
            }
        }
        Status::Running(done) => {
            ui.weak(format!("proposing labels… {:.0} %", 100.0 * done));
        }
        Status::Failed(reason) => {
            ui.weak(reason);
        }
        Status::None => {}
    }
    ui.add_space(6.0);
}

fn section(ui: &mut egui::Ui, title: &str, body: impl FnOnce(&mut egui::Ui)) {
    ui.label(RichText::new(title).strong());
    egui::Grid::new(title)
        .num_columns(2)
        .spacing([12.0, 2.0])
        .show(ui, body);
    ui.add_space(6.0);
}

fn row(ui: &mut egui::Ui, name: &str, value: String) {
    ui.label(name);
    ui.monospace(value);
    ui.end_row();
}

fn row_colored(ui: &mut egui::Ui, name: &str, value: String, color: egui::Color32) {
    ui.colored_label(color, name);
    ui.monospace(value);
    ui.end_row();
}
