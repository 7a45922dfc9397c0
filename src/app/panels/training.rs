//! Offline training from the app: choose recordings, train on a worker thread with a progress bar and
//! a loss curve, cancel, and save or load model files.

use eframe::egui;
use egui_plot::{Legend, Line, Plot, PlotPoints, VLine};
use pushlab_core::model::ModelKind;

use crate::app::colors;
use crate::app::dialogs::{DialogRequest, Dialogs};
use crate::app::state::TrainingCommand;
use crate::app::state::models::training::{RunEnd, TrainingChoice, why_it_ended};
use crate::app::state::{AppState, Command};

/// Draws the training panel.
pub fn ui(ui: &mut egui::Ui, state: &AppState, dialogs: &mut Dialogs, commands: &mut Vec<Command>) {
    ui.heading("Train a combined model");
    let running = state.training().is_running();
    model_kind(ui, state, running, commands);
    quick_choices(ui, state, commands);
    recording_checkboxes(ui, state, commands);
    training_config(ui, state, running, commands);
    start_or_cancel(ui, state, running, commands);
    if running || !state.training().history.is_empty() || state.training().last_end().is_some() {
        run_progress(ui, state, running);
    }
    ui.separator();
    model_files(ui, state, dialogs);
}

/// The model in use, and the kind of model training makes (not changed while a run goes on).
fn model_kind(ui: &mut egui::Ui, state: &AppState, running: bool, commands: &mut Vec<Command>) {
    ui.label(match state.models().kind() {
        Some(kind) => format!("In use: the {kind} model ({})", kind.description()),
        None => "In use: physics only (no trained model)".to_owned(),
    });
    ui.add_enabled_ui(!running, |ui| {
        ui.horizontal(|ui| {
            let label = ui.label("Model kind");
            egui::ComboBox::from_id_salt("model-kind")
                .selected_text(state.training().kind.name())
                .show_ui(ui, |ui| {
                    for kind in ModelKind::ALL {
                        let chosen = state.training().kind == kind;
                        if ui
                            .selectable_label(chosen, kind.name())
                            .on_hover_text(kind.description())
                            .clicked()
                            && !chosen
                        {
                            commands.push(Command::Training(TrainingCommand::SetKind(kind)));
                        }
                    }
                })
                .response
                .labelled_by(label.id);
        });
    });
}

/// Which recordings to train on, at a click (all, none, offline, shown), and how many are chosen.
fn quick_choices(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    ui.label("Recordings to train on (frames labelled bad tracking are left out):");
    // Wrapped: the four buttons are wider than a narrow Tools panel.
    ui.horizontal_wrapped(|ui| {
        if ui.small_button("All").clicked() {
            commands.push(Command::Training(TrainingCommand::Choose(
                TrainingChoice::All,
            )));
        }
        if ui.small_button("None").clicked() {
            commands.push(Command::Training(TrainingCommand::Choose(
                TrainingChoice::None,
            )));
        }
        if ui
            .small_button("Labelled offline")
            .on_hover_text("the recordings whose split is offline (Labels tab or setting.json)")
            .clicked()
        {
            commands.push(Command::Training(TrainingCommand::ChooseOfflineLabelled));
        }
        if ui
            .small_button("Shown in the browser")
            .on_hover_text(
                "the recordings the Recordings list shows under its filter (type a shape, a \
                 setting or a split there, e.g. \"hex\" or \"ellip1 offline\"), in place of the choice",
            )
            .clicked()
        {
            commands.push(Command::Training(TrainingCommand::Choose(
                TrainingChoice::ShownInBrowser,
            )));
        }
    });
    ui.label(
        egui::RichText::new(format!(
            "{} of {} chosen",
            state.training().chosen.len(),
            state.session().recording_count()
        ))
        .weak(),
    );
}

/// A checkbox per recording open, to choose the recordings to train on one by one.
fn recording_checkboxes(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    // Only the rows in view are laid out: with 5,000 recordings open, laying out every checkbox
    // took 6.5 ms of each frame.
    let row_height = ui.spacing().interact_size.y;
    egui::ScrollArea::vertical()
        .id_salt("train-choice")
        .max_height(140.0)
        .show_rows(
            ui,
            row_height,
            state.session().recording_count(),
            |ui, shown| {
                let in_view = (state.session().recordings())
                    .skip(shown.start)
                    .take(shown.len());
                for (id, recording) in in_view {
                    let label = format!(
                        "{} / {}",
                        state.session().sets[id.set].setting.name,
                        recording.name
                    );
                    let mut on = state.training().chosen.contains(&id);
                    if ui.checkbox(&mut on, label).changed() {
                        commands.push(Command::Training(TrainingCommand::Choose(
                            TrainingChoice::Set(id, on),
                        )));
                    }
                }
            },
        );
}

/// The run's settings: epochs, learning rate, horizon and seed (not changed while a run goes on).
fn training_config(
    ui: &mut egui::Ui,
    state: &AppState,
    running: bool,
    commands: &mut Vec<Command>,
) {
    let mut config = state.training().config;
    ui.add_enabled_ui(!running, |ui| {
        egui::Grid::new("train-config")
            .num_columns(2)
            .show(ui, |ui| {
                let config = &mut config;
                let label = ui.label("Epochs");
                ui.add(egui::DragValue::new(&mut config.epochs).range(1..=10_000))
                    .labelled_by(label.id);
                ui.end_row();
                let label = ui.label("Adam learning rate");
                ui.add(
                    egui::DragValue::new(&mut config.learning_rate)
                        .range(1e-6..=1.0)
                        .speed(0.0005)
                        .max_decimals(5),
                )
                .labelled_by(label.id);
                ui.end_row();
                let label = ui.label("Horizon (frames)");
                ui.add(egui::DragValue::new(&mut config.horizon).range(1..=100))
                    .labelled_by(label.id);
                ui.end_row();
                let label = ui.label("Seed");
                ui.add(egui::DragValue::new(&mut config.seed))
                    .labelled_by(label.id);
                ui.end_row();
            });
    });
    if config != state.training().config {
        commands.push(Command::Training(TrainingCommand::SetConfig(config)));
    }
}

/// Train, or while a run goes on, Cancel training.
fn start_or_cancel(
    ui: &mut egui::Ui,
    state: &AppState,
    running: bool,
    commands: &mut Vec<Command>,
) {
    ui.horizontal(|ui| {
        if running {
            if ui.button("Cancel training").clicked() {
                commands.push(Command::Training(TrainingCommand::Cancel));
            }
            ui.spinner();
        } else if ui
            .add_enabled(
                !state.training().chosen.is_empty(),
                egui::Button::new("Train"),
            )
            .clicked()
        {
            commands.push(Command::Training(TrainingCommand::Start));
        }
    });
}

/// How far the run got, or how it ended, and its loss curves (the epoch kept marked).
fn run_progress(ui: &mut egui::Ui, state: &AppState, running: bool) {
    let palette = colors::of(ui.ctx());
    let last = state.training().history.last();
    let ended = state.training().last_end().filter(|_| !running);
    let (progress, text) = match ended {
        Some(end) => (1.0, how_it_ended(end)),
        None => (
            state.training().progress(),
            last.map_or("starting…".to_owned(), |p| {
                format!(
                    "epoch {} / {}, train loss {:.4}",
                    p.epoch, p.epochs, p.train_loss
                )
            }),
        ),
    };
    ui.add(egui::ProgressBar::new(progress).text(text));
    let train: PlotPoints = state
        .training()
        .history
        .iter()
        .map(|p| [p.epoch as f64, p.train_loss])
        .collect();
    let validation: PlotPoints = state
        .training()
        .history
        .iter()
        .filter_map(|p| p.validation_loss.map(|v| [p.epoch as f64, v]))
        .collect();
    Plot::new("training-loss")
        .height(150.0)
        .legend(Legend::default())
        .x_axis_label("epoch")
        .show(ui, |plot_ui| {
            plot_ui.line(Line::new("train", train).color(palette.online));
            plot_ui.line(Line::new("validation", validation).color(palette.fixed));
            if let Some(RunEnd::Trained { report }) = ended {
                plot_ui.vline(VLine::new("kept", report.best_epoch as f64).color(palette.truth));
            }
        });
}

/// Loading a model file, or saving the one in use.
fn model_files(ui: &mut egui::Ui, state: &AppState, dialogs: &mut Dialogs) {
    ui.horizontal(|ui| {
        if ui.button("Load model…").clicked() {
            dialogs.open(DialogRequest::LoadModel);
        }
        if ui
            .add_enabled(
                state.models().combined.is_some(),
                egui::Button::new("Save model…"),
            )
            .clicked()
        {
            dialogs.open(DialogRequest::SaveModel);
        }
    });
}

/// The progress bar's words once a run ended: why it stopped and which epoch's weights the model
/// has — the one with the best validation loss, often well before the last (early stopping waits
/// `patience` epochs for a better one). Its losses are in the status line and the plot's line.
fn how_it_ended(end: &RunEnd) -> String {
    match end {
        RunEnd::Trained { report } => format!(
            "{} after {} of {} epochs; kept epoch {}",
            why_it_ended(report),
            report.epochs_run,
            report.config.epochs,
            report.best_epoch
        ),
        RunEnd::Failed(why) => why.clone(),
    }
}
