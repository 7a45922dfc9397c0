//! Drive, in the Connect form and the timeline's live strip: the form's section (the command topic,
//! the goal, the speed and rate, what the controller plans with) and the strip's buttons (Arm,
//! Pause, Disarm) with what the gate is doing. Reads the state's live session and sends
//! `LiveCommand::Drive`; the goal and the plan are drawn in the scene (`scene::plan`).

use eframe::egui::{self, RichText};
use pushlab_core::control::PlanWith;

use crate::app::state::sources::live::{DriveChoice, DriveCommand, LiveCommand, Running};
use crate::app::state::{AppState, Command};

/// The form's Drive section: edits `drive` in place.
pub fn form_section(ui: &mut egui::Ui, drive: &mut DriveChoice) {
    ui.checkbox(&mut drive.on, "Drive the robot to a goal")
        .on_hover_text(
            "the controller plans with the model as it learns and sends the pusher's target by \
             client publish; nothing is sent until you press Arm",
        );
    if !drive.on {
        return;
    }
    egui::Grid::new("live-drive-form")
        .num_columns(2)
        .show(ui, |ui| {
            ui.label("Command topic");
            ui.text_edit_singleline(&mut drive.command)
                .on_hover_text("geometry_msgs/msg/PoseStamped: the pusher's target");
            ui.end_row();
            ui.label("Frame id");
            ui.text_edit_singleline(&mut drive.frame)
                .on_hover_text("the targets' header.frame_id: the pose streams' frame");
            ui.end_row();
            ui.label("Goal x, y (m), yaw (°)");
            ui.horizontal(|ui| {
                ui.add(
                    egui::DragValue::new(&mut drive.goal[0])
                        .speed(0.005)
                        .suffix(" m"),
                );
                ui.add(
                    egui::DragValue::new(&mut drive.goal[1])
                        .speed(0.005)
                        .suffix(" m"),
                );
                let mut degrees = drive.goal[2].to_degrees();
                if ui
                    .add(egui::DragValue::new(&mut degrees).speed(1.0).suffix("°"))
                    .changed()
                {
                    drive.goal[2] = degrees.to_radians();
                }
            });
            ui.end_row();
            ui.label("Top speed, control rate");
            ui.horizontal(|ui| {
                ui.add(
                    egui::DragValue::new(&mut drive.speed)
                        .speed(0.001)
                        .range(0.001..=0.5)
                        .suffix(" m/s"),
                );
                ui.add(
                    egui::DragValue::new(&mut drive.control_hz)
                        .speed(0.5)
                        .range(1.0..=100.0)
                        .suffix(" Hz"),
                );
            });
            ui.end_row();
            ui.label("Plans with");
            egui::ComboBox::from_id_salt("live-drive-plan-with")
                .selected_text(drive.plan_with.name())
                .show_ui(ui, |ui| {
                    for with in PlanWith::ALL {
                        ui.selectable_value(&mut drive.plan_with, with, with.name())
                            .on_hover_text(with.description());
                    }
                });
            ui.end_row();
        });
}

/// The drive's part of the live strip, when the session drives: the gate's state and its buttons.
pub fn strip(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let Some(running) = state.live().running() else {
        return;
    };
    if running.drive.is_none() {
        if let Some(why) = (running.latest.drive.as_ref()).and_then(|d| d.refused.as_ref()) {
            ui.colored_label(ui.visuals().warn_fg_color, "NOT DRIVING")
                .on_hover_text(why);
        }
        return;
    }
    let status = running.latest.drive.clone().unwrap_or_default();
    if let Some(why) = &status.refused {
        ui.colored_label(ui.visuals().warn_fg_color, "NOT DRIVING")
            .on_hover_text(why);
        return;
    }
    // One word in the strip, so that the timeline's buttons after it keep their room; why it
    // holds is in the tooltip (and was said on the status line).
    let (badge, color) = match (status.armed, status.halted) {
        (_, Some(_)) => ("HELD", ui.visuals().warn_fg_color),
        (true, None) => ("ARMED", ui.visuals().error_fg_color),
        (false, None) => ("NOT ARMED", ui.visuals().weak_text_color()),
    };
    let mut hover = describe(running, &status);
    if let Some(why) = status.halted {
        hover = format!("held: {}; {hover}", why.describe());
    }
    ui.label(RichText::new(badge).strong().color(color))
        .on_hover_text(hover);
    let live = state.live().is_live();
    let mut send = |c| commands.push(Command::Live(LiveCommand::Drive(c)));
    if !status.armed || status.halted.is_some() {
        if ui
            .add_enabled(live, egui::Button::new("Arm"))
            .on_hover_text("send the controller's targets to the robot from the next step on")
            .clicked()
        {
            send(DriveCommand::Arm);
        }
    } else {
        if ui
            .button("Pause")
            .on_hover_text("hold the pusher where it is; planning goes on")
            .clicked()
        {
            send(DriveCommand::Pause);
        }
        if ui
            .button("Disarm")
            .on_hover_text("hold the pusher and send nothing more")
            .clicked()
        {
            send(DriveCommand::Disarm);
        }
    }
    ui.separator();
}

/// The drive in a sentence.
fn describe(running: &Running, status: &crate::app::state::sources::live::DriveStatus) -> String {
    let choice = &running.choice.drive;
    let mut text = format!(
        "driving {} to ({:.3} m, {:.3} m, {:.0}°) at up to {} m/s, {} Hz, planned with {}; {} target(s) sent",
        choice.command,
        choice.goal[0],
        choice.goal[1],
        choice.goal[2].to_degrees(),
        choice.speed,
        choice.control_hz,
        choice.plan_with.description(),
        status.sent
    );
    if let Some(w) = status.workspace {
        text += &format!(
            "; workspace x {:.3} to {:.3} m, y {:.3} to {:.3} m",
            w.min[0], w.max[0], w.min[1], w.max[1]
        );
    }
    text
}
