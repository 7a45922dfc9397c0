//! Steering `θ_online`: sliders for the COM offset and `h` (the prediction follows instantly), online
//! learning by hand ("Learn this frame") or while playing, reset, and the update rule.

mod controller_here;
mod next_push;

use eframe::egui;
use pushlab_core::learn::{self, OnlineConfig, Optimizer};
use pushlab_core::model::OnlineParams;
use pushlab_core::recording::Recording;

use crate::app::colors;
use crate::app::format;
use crate::app::state::learning::best_fit::BestFitCommand;
use crate::app::state::learning::online::OnlineRun;
use crate::app::state::{AppState, Command, MAX_WHAT_IF_STEPS};
use crate::app::state::{OnlineCommand, TrainingCommand};

/// Whether the model fits the open recordings; if not, why, and the button that trains one that does.
fn model_fit(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let palette = colors::of(ui.ctx());
    let training = &state.training();
    if let Some(mismatch) = state.domain_mismatch() {
        ui.colored_label(palette.warning, format!("Warning: {}", mismatch.message));
    }
    if state.domain_mismatch().is_none() && !training.is_running() {
        return;
    }
    ui.horizontal(|ui| {
        let train = ui
            .add_enabled(
                !training.is_running(),
                egui::Button::new("Train for these recordings"),
            )
            .on_hover_text(
                "Train the Train tab's kind in the background on the recordings labelled offline \
                 (else on all but the one shown); the model is remembered for these folders",
            );
        if train.clicked() {
            commands.push(Command::Training(TrainingCommand::TrainForOpenRecordings));
        }
        if training.is_running() {
            ui.add(
                egui::ProgressBar::new(training.progress())
                    .desired_width(160.0)
                    .text(format!(
                        "{} {:.0} %",
                        training.phase(),
                        training.progress() * 100.0
                    )),
            );
            if ui.button("Cancel").clicked() {
                commands.push(Command::Training(TrainingCommand::Cancel));
            }
        }
    });
}

/// What the COM's spread at the frame shown is made of: why the ellipse is as wide as it is. Always
/// two lines (the prior's spread before anything is learned), so that the controls below do not
/// jump when learning starts or is reset.
fn spread_parts(ui: &mut egui::Ui, run: &learn::OnlineRun, frame: usize) {
    let parts = run.spread_at(frame).com_parts();
    // Past the frontier the spread is the frontier's: nothing after it is learned yet.
    let at = if frame > run.frontier() {
        format!("frame {} (newest learned)", run.frontier())
    } else {
        format!("frame {frame}")
    };
    ui.label(
        egui::RichText::new(format!(
            "COM σ at {at} (mm): frames learned {:.1},\nmodel misfit {:.1}, estimate still moving \
             {:.1}",
            parts.frames_m * 1e3,
            parts.misfit_m * 1e3,
            parts.drift_m * 1e3,
        ))
        .weak(),
    )
    .on_hover_text(
        "The three add in squares to the COM's σ: what the frames learned say (with the prior), \
         the model's COM misfit measured at training on objects left out, and how far the estimate \
         was still sliding when it got here (its path's drift; an estimate still moving one way may \
         be that far again from where it stops)",
    );
}

/// How much the prediction trusts the combined model and physics alone at the frame shown, when
/// physics alone learns beside the run: the two weights and, where physics is trusted, why.
fn model_weights(ui: &mut egui::Ui, run: &learn::OnlineRun, frame: usize) {
    let Some(weight) = run.model_weight() else {
        return;
    };
    ui.add_space(4.0);
    ui.heading("Network or physics alone");
    let w = weight.at(frame);
    for (part, w) in [("translation", w.pos), ("rotation", w.rot)] {
        ui.label(format::trust(part, w, weight.half_life_s()));
    }
    ui.label(
        egui::RichText::new(
            "The prediction blends the two by these weights: each the chance that its model is the \
             one predicting this object, from how well each predicted the frames before this one",
        )
        .weak(),
    );
}

/// The best θ for the whole push shown (`pushlab eval --best-fit`'s): found on request in the
/// background, then shown beside the online run's with a button that steers θ to it here.
fn best_theta(
    ui: &mut egui::Ui,
    state: &AppState,
    recording: &Recording,
    commands: &mut Vec<Command>,
) {
    ui.add_space(8.0);
    ui.heading("Best θ for this push");
    let search = state.best_fit();
    let Some(run) = state.run() else {
        return;
    };
    if let Some(progress) = search.progress_for(run) {
        ui.horizontal(|ui| {
            ui.add(
                egui::ProgressBar::new(progress)
                    .desired_width(160.0)
                    .text(format!("finding {:.0} %", progress * 100.0)),
            );
            if ui.button("Cancel").clicked() {
                commands.push(Command::BestFit(BestFitCommand::Cancel));
            }
        });
        return;
    }
    match search.result_for(run).map(|r| r.fit) {
        None => {
            if ui
                .button("Find the best θ")
                .on_hover_text(
                    "The θ that fits this whole push best, held fixed over it (a grid over the \
                     object, then Levenberg–Marquardt; frames labelled bad tracking left out): no \
                     online learner with this model does better on this push. A learned COM as \
                     far from the truth as the best one is the model's limit, not the learner's",
                )
                .clicked()
            {
                commands.push(Command::BestFit(BestFitCommand::Find));
            }
        }
        Some(None) => {
            ui.weak("This push has no sample to fit.");
        }
        Some(Some(fit)) => {
            let t = fit.theta;
            let truth = recording
                .setting
                .com_offset
                .map(|c| format!("; {:.1} mm from the true COM", fit.com_error_m(c) * 1e3));
            ui.label(format!(
                "COM ({:.2}, {:.2}) mm, h {:.2} mm{}",
                t.com_offset[0] * 1e3,
                t.com_offset[1] * 1e3,
                t.h * 1e3,
                truth.unwrap_or_default()
            ));
            let online = run.mean_losses();
            ui.label(
                egui::RichText::new(format!(
                    "NMSE over the push {:.3} pos / {:.3} rot{}",
                    fit.nmse.pos,
                    fit.nmse.rot,
                    online
                        .map(|m| format!(
                            " (online so far {:.3} / {:.3})",
                            m.online_pos, m.online_rot
                        ))
                        .unwrap_or_default()
                ))
                .weak(),
            );
            ui.horizontal(|ui| {
                if ui
                    .button("Use it here")
                    .on_hover_text("Steer θ at this frame to the best θ")
                    .clicked()
                {
                    commands.push(Command::Online(OnlineCommand::SetTheta(t)));
                }
                if ui.small_button("Find again").clicked() {
                    commands.push(Command::BestFit(BestFitCommand::Find));
                }
            });
        }
    }
}

/// Draws the steering controls.
pub fn ui(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let (Some(theta), Some(recording), Some(run)) =
        (state.theta(), state.recording(), &state.run())
    else {
        ui.weak("Select a recording to steer the model.");
        return;
    };
    ui.label(format!("Learning with: {}", state.models().learner_name()));
    model_fit(ui, state, commands);
    theta_sliders(ui, state, theta, run, commands);
    spread_parts(ui, run, state.frame());
    model_weights(ui, run, state.frame());
    truth(ui, recording);
    ui.weak("Or drag the orange COM marker in the scene.");

    online_learning(ui, state, run, commands);
    optimiser(ui, run, commands);
    learning_ahead(ui, state, run, commands);

    best_theta(ui, state, recording, commands);
    next_push::ui(ui, state, commands);
    what_if(ui, state, recording, commands);
    controller_here::ui(ui, state, commands);
}

/// The θ_online sliders at the frame shown, each with its ±σ: moving one steers θ here.
fn theta_sliders(
    ui: &mut egui::Ui,
    state: &AppState,
    theta: OnlineParams,
    run: &OnlineRun,
    commands: &mut Vec<Command>,
) {
    ui.add_space(4.0);
    ui.heading("θ_online at this frame");
    // Slider ranges follow the object: the COM stays within its bounding box, h within its size.
    let theta_ranges = state.theta_ranges();
    let range = |i: usize| {
        let (low, high) = theta_ranges[i];
        low * 1e3..=high * 1e3
    };
    let mut mm = [
        theta.com_offset[0] * 1e3,
        theta.com_offset[1] * 1e3,
        theta.h * 1e3,
    ];
    let mut changed = false;
    let ranges = [
        ("COM offset x", range(0)),
        ("COM offset y", range(1)),
        ("h", range(2)),
    ];
    // The slider takes what its row leaves, so that the value, the name and the ± beside it stay in
    // view in a narrow Tools panel (they take about 230 points).
    ui.spacing_mut().slider_width = (ui.available_width() - 230.0).clamp(60.0, 150.0);
    let std = run.spread_at(state.frame()).std();
    let misfit = match run.com_misfit_m() {
        m if m > 0.0 => format!(
            "; here ± {:.1} mm, measured on {} objects left out of training",
            m * 1e3,
            run.model().com_misfit().objects
        ),
        _ => "; this model's training measured none".to_owned(),
    };
    for (((label, range), value), std) in ranges.into_iter().zip(mm.iter_mut()).zip(std) {
        ui.horizontal(|ui| {
            changed |= ui
                .add(
                    egui::Slider::new(value, range)
                        .text(label)
                        .suffix(" mm")
                        .fixed_decimals(2)
                        .clamping(egui::SliderClamping::Never),
                )
                .changed();
            ui.label(egui::RichText::new(format!("± {:.1}", std * 1e3)).weak())
                .on_hover_text(format!(
                    "One standard deviation of the posterior of θ_online given the frames learned \
                     so far (Gauss–Newton/Laplace), the COM's widened by the model's COM misfit{misfit}, \
                     and by how far the estimate was still sliding (its path's drift: an estimate \
                     still moving one way may be that far again from where it stops); the scene's \
                     ellipse holds the COM with 95 %",
                ));
        });
    }
    if changed {
        commands.push(Command::Online(OnlineCommand::SetTheta(OnlineParams {
            com_offset: [mm[0] * 1e-3, mm[1] * 1e-3],
            h: mm[2] * 1e-3,
        })));
    }
}

/// The true COM and h of the recording, where its setting gives them: what θ is compared with.
fn truth(ui: &mut egui::Ui, recording: &Recording) {
    let palette = colors::of(ui.ctx());
    if let (Some(com), h) = (recording.setting.com_offset, recording.setting.h) {
        ui.colored_label(
            palette.truth,
            format!(
                "true: COM ({}, {}) mm{}",
                format::hundredths(com[0] * 1e3),
                format::hundredths(com[1] * 1e3),
                h.map(|h| format!(", h {:.2} mm", h * 1e3))
                    .unwrap_or_default()
            ),
        );
    }
}

/// Online learning: learn this frame or reset; learn while playing, carry θ, weigh against physics.
fn online_learning(
    ui: &mut egui::Ui,
    state: &AppState,
    run: &OnlineRun,
    commands: &mut Vec<Command>,
) {
    ui.add_space(8.0);
    ui.heading("Online learning");
    ui.horizontal(|ui| {
        if ui
            .button("Learn this frame")
            .on_hover_text("One online update from this frame's sample")
            .clicked()
        {
            commands.push(Command::Online(OnlineCommand::LearnThisFrame));
        }
        let reset = match run.continued_from() {
            Some(_) => "Reset to this push's start",
            None => "Reset to θ_online(0)",
        };
        if ui.button(reset).clicked() {
            commands.push(Command::Online(OnlineCommand::ResetTheta));
        }
    });
    if let Some(previous) = run.continued_from() {
        ui.weak(format!(
            "Went on from what {previous} learned (same object): θ and its certainty carried."
        ));
    }
    let mut learn = state.settings().learn_while_playing;
    if ui
        .checkbox(&mut learn, "Learn while playing")
        .on_hover_text("Learn from every frame the timeline moves forward over")
        .changed()
    {
        commands.push(Command::Online(OnlineCommand::SetLearnWhilePlaying(learn)));
    }
    let mut carry = state.settings().carry_theta;
    if ui
        .checkbox(&mut carry, "Carry θ to the next push of this object")
        .on_hover_text(
            "Selecting another recording of the same object (same folder, footprint, material and \
             pusher) goes on from what this one learned, θ and its certainty, as `pushlab eval \
             --carry-theta` does: several pushes on different faces pin the COM down better than \
             one, but a confident θ adapts less to each push",
        )
        .changed()
    {
        commands.push(Command::Online(OnlineCommand::SetCarryTheta(carry)));
    }
    let mut weigh = state.settings().weigh_physics;
    if ui
        .checkbox(&mut weigh, "Weigh against physics alone")
        .on_hover_text(
            "Lynch's model alone learns its own θ beside the network's, and each prediction blends \
             the two by how well each predicted this object lately (`pushlab eval --physics`'s \
             weighted row): a network wrong for an object it never saw is trusted less",
        )
        .changed()
    {
        commands.push(Command::Online(OnlineCommand::SetWeighPhysics(weigh)));
    }
}

/// The update rule: the optimiser, its steps and learning rate, and a way back to the paper's.
fn optimiser(ui: &mut egui::Ui, run: &OnlineRun, commands: &mut Vec<Command>) {
    let mut config = run.config();
    let mut config_changed = false;
    // The choices on a line of their own, wrapped: beside the label they ran out of a narrow Tools
    // panel.
    ui.label("Optimiser");
    ui.horizontal_wrapped(|ui| {
        for (optimizer, text, hover) in [
            (
                Optimizer::Gd,
                "Gradient descent (paper)",
                "The paper's: GD steps per frame at the learning rate",
            ),
            (
                Optimizer::GaussNewton,
                "Gauss–Newton",
                "One Gauss–Newton step per frame, weighed against every frame before \
                 (steps and learning rate are not used; 0 steps still fixes θ)",
            ),
        ] {
            config_changed |= ui
                .selectable_value(&mut config.optimizer, optimizer, text)
                .on_hover_text(hover)
                .changed();
        }
    });
    egui::Grid::new("online-config")
        .num_columns(2)
        .show(ui, |ui| {
            let label = ui.label("GD steps per frame");
            config_changed |= ui
                .add(egui::DragValue::new(&mut config.steps).range(0..=100))
                .labelled_by(label.id)
                .changed();
            ui.end_row();
            let label = ui.label("Learning rate");
            config_changed |= ui
                .add(
                    egui::DragValue::new(&mut config.lr)
                        .range(0.0..=1.0)
                        .speed(0.0005)
                        .max_decimals(5),
                )
                .labelled_by(label.id)
                .changed();
            ui.end_row();
        });
    if config_changed {
        commands.push(Command::Online(OnlineCommand::SetConfig(config)));
    }
    if config != OnlineConfig::default()
        && ui
            .small_button("Paper defaults (5 steps, lr 0.005)")
            .clicked()
    {
        commands.push(Command::Online(OnlineCommand::SetConfig(
            OnlineConfig::default(),
        )));
    }
}

/// Learning ahead's progress to the frame shown (with Cancel), or else how far learning got.
fn learning_ahead(
    ui: &mut egui::Ui,
    state: &AppState,
    run: &OnlineRun,
    commands: &mut Vec<Command>,
) {
    match state.learning_ahead() {
        Some((done, to)) => {
            ui.horizontal(|ui| {
                // Room left for Cancel: the text is cut to the bar's width.
                ui.add(
                    egui::ProgressBar::new(done)
                        .desired_width((ui.available_width() - 70.0).max(120.0))
                        .text(format!("learning to frame {to}: {:.0} %", done * 100.0)),
                )
                .on_hover_text(
                    "Every frame up to the one shown is learned, as playing there would; on a \
                     long recording that runs in the background, and θ shows held meanwhile",
                );
                if ui.button("Cancel").clicked() {
                    commands.push(Command::Online(OnlineCommand::StopLearningAhead));
                }
            });
        }
        None => {
            ui.weak(how_far_learned(run));
        }
    }
}

/// What if: the model rolled k steps ahead on its own predictions, and how far off it ends.
fn what_if(
    ui: &mut egui::Ui,
    state: &AppState,
    recording: &Recording,
    commands: &mut Vec<Command>,
) {
    ui.add_space(8.0);
    ui.heading("What if");
    let mut steps = state.settings().what_if_steps;
    ui.horizontal(|ui| {
        let label = ui.label("Roll ahead k steps");
        if ui
            .add(egui::DragValue::new(&mut steps).range(1..=MAX_WHAT_IF_STEPS))
            .labelled_by(label.id)
            .on_hover_text(
                "From this frame, the model is fed its own predicted poses along the recorded \
                 pusher path; the scene draws them as fading ghosts",
            )
            .changed()
        {
            commands.push(Command::Online(OnlineCommand::SetWhatIfSteps(steps)));
        }
    });
    if let Some(rollout) = state.what_if()
        && let Some((offset, yaw)) = rollout.final_error(&recording.trajectory)
    {
        ui.label(format!(
            "After {}: {:.1} mm and {:.2}° from the recorded pose",
            format::count(rollout.poses.len(), "step", "steps"),
            offset * 1e3,
            yaw.to_degrees()
        ));
    }
}

/// How far online learning got. Learning ends `horizon` frames before the recording does (those
/// frames are only targets), so "of N" is said as a frame, not as the timeline's last frame.
fn how_far_learned(run: &learn::OnlineRun) -> String {
    let horizon = run.horizon();
    if run.sample_count() == 0 {
        return format!("Nothing to learn: the recording is too short for horizon {horizon}.");
    }
    let targets = match horizon {
        1 => "the last frame is only a target".to_owned(),
        h => format!("the last {h} frames are only targets at horizon {h}"),
    };
    format!(
        "Learned up to frame {} of {} ({targets}). Scrubbing back restores θ at that frame; \
         playing on re-learns.",
        run.frontier(),
        run.sample_count()
    )
}
