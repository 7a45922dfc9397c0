//! Push it yourself: the menu entries that start a mystery, and the sandbox's window — the mystery
//! (object and seed, the link a class shares), how to push and guess in one line, the model's
//! estimate (hidden in challenge mode), Reveal with its score card, New mystery, Save. Reads the
//! state's sandbox and sends its commands.

use eframe::egui::{self, RichText};
use pushlab_core::sandbox::{MysteryObject, PushReview, ScoreCard};

use crate::app::colors;
use crate::app::dialogs::{DialogRequest, Dialogs};
use crate::app::platform::{SystemTime, UNIX_EPOCH};
use crate::app::state::sources::sandbox::{SandboxCommand, SandboxSession};
use crate::app::state::{AppState, Command};

/// A seed for a new mystery from the clock: four digits, short enough to read out to a class.
fn fresh_seed() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(1, |d| u64::from(d.subsec_micros()) % 10_000)
}

/// The menu entries that start a sandbox: one per object, and the outline of the recording shown.
pub fn start_menu(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let mut start = |object: Option<MysteryObject>| {
        commands.push(Command::Sandbox(SandboxCommand::Start {
            seed: fresh_seed(),
            object,
            noise: false,
            challenge: false,
            com: None,
        }));
    };
    let hover = "an object whose centre of mass is hidden: push it with the mouse and watch the \
                 model find it, then guess and reveal";
    for (label, object) in [
        ("A box", MysteryObject::Box),
        ("The T", MysteryObject::T),
        ("An ellipse", MysteryObject::Ellipse),
    ] {
        if ui.button(label).on_hover_text(hover).clicked() {
            start(Some(object));
            ui.close();
        }
    }
    if ui
        .add_enabled(
            state.recording().is_some(),
            egui::Button::new("The outline of this recording"),
        )
        .on_hover_text(hover)
        .clicked()
    {
        start(None);
        ui.close();
    }
}

/// The sandbox's window, while there is one.
pub fn window(
    ctx: &egui::Context,
    state: &AppState,
    dialogs: &mut Dialogs,
    commands: &mut Vec<Command>,
) {
    let Some(session) = state.sandbox() else {
        return;
    };
    let mystery = session.sandbox().mystery();
    let mut open = true;
    egui::Window::new("Push it yourself")
        .open(&mut open)
        .collapsible(true)
        .default_width(330.0)
        .anchor(egui::Align2::RIGHT_TOP, [-16.0, 48.0])
        .show(ctx, |ui| {
            ui.label(
                RichText::new(format!(
                    "Mystery {} #{}",
                    mystery.object.name(),
                    mystery.seed
                ))
                .strong(),
            );
            ui.label(
                "Drag the yellow pusher into the object, or draw an arrow from its outline. \
                 Drag the ? to where you think its centre of mass is.",
            );
            ui.separator();
            pushes_and_estimate(ui, state, session);
            buttons(ui, session, dialogs, commands);
            ui.separator();
            super::sandbox_goal::section(ui, session, commands);
            if let Some(score) = session.score() {
                ui.separator();
                score_card(ui, score);
            }
        });
    if !open {
        commands.push(Command::Sandbox(SandboxCommand::Close));
    }
}

/// The pushes made, and the model's estimate unless challenge mode hides it.
fn pushes_and_estimate(ui: &mut egui::Ui, state: &AppState, session: &SandboxSession) {
    let made = session.sandbox().made().len();
    let pushing = session.sandbox().is_pushing();
    ui.label(format!(
        "{} made{}",
        crate::app::format::count(made, "push", "pushes"),
        if pushing { ", one being made" } else { "" }
    ));
    if session.hides_estimate() {
        ui.weak("Challenge: the model's estimate is hidden until you reveal.");
    } else if let (Some(theta), Some(run)) = (state.theta(), state.run()) {
        let std = run.spread_at(state.frame()).std();
        ui.label(format!(
            "The model's COM: ({:.1}, {:.1}) ± ({:.1}, {:.1}) mm",
            theta.com_offset[0] * 1e3,
            theta.com_offset[1] * 1e3,
            std[0] * 1e3,
            std[1] * 1e3
        ));
    }
    match session.guess() {
        Some([x, y]) => ui.label(format!("Your guess: ({:.1}, {:.1}) mm", x * 1e3, y * 1e3)),
        None => ui.weak("No guess yet: drag the ?."),
    };
}

/// Reveal, New mystery, challenge mode, Save.
fn buttons(
    ui: &mut egui::Ui,
    session: &SandboxSession,
    dialogs: &mut Dialogs,
    commands: &mut Vec<Command>,
) {
    ui.horizontal_wrapped(|ui| {
        if ui
            .add_enabled(
                !session.revealed(),
                egui::Button::new(RichText::new("Reveal").strong()),
            )
            .on_hover_text("show the hidden centre of mass and h, and how you and the model did")
            .clicked()
        {
            commands.push(Command::Sandbox(SandboxCommand::Reveal));
        }
        if ui
            .button("New mystery")
            .on_hover_text("the next seed: another hidden centre of mass on the same object")
            .clicked()
        {
            commands.push(Command::Sandbox(SandboxCommand::NewMystery));
        }
        let mut challenge = session.challenge();
        if ui
            .checkbox(&mut challenge, "Challenge")
            .on_hover_text("hide the model's estimate until you reveal")
            .changed()
        {
            commands.push(Command::Sandbox(SandboxCommand::SetChallenge(challenge)));
        }
        if ui
            .add_enabled(
                !session.sandbox().made().is_empty(),
                egui::Button::new("Save…"),
            )
            .on_hover_text(
                "the pushes as a recording set with the truth: pushlab eval --carry-theta gives \
                 the θ shown",
            )
            .clicked()
        {
            dialogs.open(DialogRequest::SaveSandbox);
        }
    });
}

/// The score card of the reveal.
fn score_card(ui: &mut egui::Ui, score: &ScoreCard) {
    let palette = colors::of(ui.ctx());
    let mm = |m: f64| format!("{:.1} mm", m * 1e3);
    ui.colored_label(
        palette.truth,
        format!(
            "Hidden: COM ({:.1}, {:.1}) mm, h {}",
            score.true_com_m[0] * 1e3,
            score.true_com_m[1] * 1e3,
            mm(score.true_h_m)
        ),
    );
    egui::Grid::new("sandbox-score")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            ui.label("Your guess");
            ui.label(
                score
                    .guess_error_m
                    .map_or("no guess".to_owned(), |e| format!("{} off", mm(e))),
            );
            ui.end_row();
            ui.label("The model");
            ui.label(format!(
                "{} off, σ {} ({:.1} σ)",
                mm(score.model_error_m),
                mm(score.model_com_std_m),
                score.model_error_in_std
            ));
            ui.end_row();
            ui.label("Pushes");
            ui.label(format!(
                "{}, {} pushed",
                score.pushes,
                mm(score.push_length_m)
            ));
            ui.end_row();
        });
    if !score.reviews.is_empty() {
        ui.label("Each push against the ranking's choice (COM σ it was expected to leave):");
        for review in &score.reviews {
            ui.label(review_line(review));
        }
    }
}

/// "push 1: σ from 24.1 to 12.0 mm; the ranking's best, left +5.0 cm +20°, to 9.8 mm" (words,
/// not arrows: the fonts of a projector's page may lack them).
pub fn review_line(review: &PushReview) -> String {
    let mm = |m: f64| format!("{:.1}", m * 1e3);
    let best = review.ranked_best.as_ref().map_or_else(
        || "no grid push to compare".to_owned(),
        |b| {
            format!(
                "the ranking's best, {}, to {} mm",
                b.name,
                mm(b.com_std_after_m)
            )
        },
    );
    format!(
        "push {}: σ from {} to {} mm; {best}",
        review.push + 1,
        mm(review.com_std_before_m),
        mm(review.made_com_std_after_m)
    )
}
