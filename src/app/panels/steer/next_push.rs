//! The Steer tab's "Next push that teaches the most": the object's other open pushes ranked by how
//! much each is expected to shrink the COM's uncertainty after what the run has learned (the state's
//! `next_push`, the core's ranking `pushlab suggest` prints). Reads the ranking and sends one
//! command; the scene draws the best few as arrows.

use eframe::egui;

use crate::app::state::learning::next_push::{ARROWS, Candidates, NextPushCommand, grid};
use crate::app::state::{AppState, Command};

/// Rows of the ranking listed.
const LISTED: usize = 5;

/// The section: a Suggest button (or the ranking's progress and Cancel), then the best pushes.
pub fn ui(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    ui.add_space(8.0);
    ui.heading("Next push that teaches the most");
    let Some(run) = state.run() else {
        return;
    };
    let ranking = state.next_push();
    if let Some(progress) = ranking.progress_for(run) {
        ui.horizontal(|ui| {
            ui.add(
                egui::ProgressBar::new(progress)
                    .desired_width(160.0)
                    .text(format!("ranking {:.0} %", progress * 100.0)),
            );
            if ui.button("Cancel").clicked() {
                commands.push(Command::NextPush(NextPushCommand::Cancel));
            }
        });
        return;
    }
    let candidates = state.other_pushes_of_object().len();
    let among = match candidates {
        0 => format!(
            "a grid of pushes laid out on the object ({}), as no other push of it is open",
            grid()
        ),
        n => format!("the object's {n} other open pushes"),
    };
    let result = ranking.result_for(run);
    let label = if result.is_some() {
        "Suggest again"
    } else {
        "Suggest the next push"
    };
    if ui
        .button(label)
        .on_hover_text(format!(
            "Ranks {among} by how much each is expected to shrink the COM's uncertainty after \
             what the run has learned up to now: each played through the model with today's θ, \
             its frames' information added to the posterior (the Fisher information; its recorded \
             outcome is never read). The best {ARROWS} are drawn on the object as arrows"
        ))
        .clicked()
    {
        commands.push(Command::NextPush(NextPushCommand::Suggest));
    }
    if let Some(problem) = ranking.problem_for(run) {
        ui.colored_label(ui.visuals().warn_fg_color, problem);
    }
    let Some(result) = result else {
        return;
    };
    let r = &result.ranking;
    if let Candidates::Grid { left_out } = &result.candidates {
        ui.label(
            egui::RichText::new(format!(
                "No other push of this object is open: ranked a grid of {} pushes laid out on it",
                r.suggestions.len()
            ))
            .weak(),
        )
        .on_hover_text(match left_out.as_slice() {
            [] => format!("Laid out: {} (pushlab suggest --grid)", grid()),
            left_out => format!(
                "Left out, as they cannot be pushed: {}",
                left_out.join("; ")
            ),
        });
    }
    ui.label(
        egui::RichText::new(format!(
            "After frame {}: COM σ {:.1} mm now; the model's misfit, {:.1} mm, is the floor",
            result.frame,
            r.com_std_now_m * 1e3,
            r.com_misfit_m * 1e3
        ))
        .weak(),
    );
    egui::Grid::new("next_pushes")
        .num_columns(3)
        .striped(true)
        .show(ui, |ui| {
            for (i, s) in r.suggestions.iter().take(LISTED).enumerate() {
                ui.label(format!("{}.", i + 1));
                ui.label(&s.name).on_hover_text(match &s.shape {
                    Some(p) => format!(
                        "face {}, {:+.1} cm left of its middle, {:+.0}° from straight in, {:.0} cm long",
                        p.face,
                        p.offset_m * 1e2,
                        p.angle_rad.to_degrees(),
                        p.length_m * 1e2
                    ),
                    None => "the model expects the pusher to miss the object".to_owned(),
                });
                ui.label(format!("leaves COM σ {:.1} mm", s.com_std_after_m * 1e3));
                ui.end_row();
            }
        });
}
