//! Push to goal, in the sandbox's window: place a goal (then drag its ghost in the scene, or its
//! knob to turn it), choose what the controller plans with, push, and see how it went. The pane
//! says which model it plans with, so that a class running the same goal with θ learned and θ
//! fixed sees what the learning changed. Reads the state's sandbox and sends its commands.

use eframe::egui::{self, RichText};
use pushlab_core::control::PlanWith;

use crate::app::state::Command;
use crate::app::state::sources::sandbox::{SandboxCommand, SandboxSession};

/// Where a new goal goes: this far ahead of the object and turned this much, so that it is seen
/// at once and worth a push.
const NEW_GOAL_AHEAD_M: f64 = 0.3;
const NEW_GOAL_TURN_RAD: f64 = 0.35;

/// The section of the sandbox's window.
pub fn section(ui: &mut egui::Ui, session: &SandboxSession, commands: &mut Vec<Command>) {
    ui.label(RichText::new("Push to goal").strong());
    let send = |commands: &mut Vec<Command>, c: SandboxCommand| {
        commands.push(Command::Sandbox(c));
    };
    let driving = session.driving();
    ui.horizontal_wrapped(|ui| {
        let label = if session.goal().is_some() {
            "New goal"
        } else {
            "Set a goal"
        };
        if ui
            .add_enabled(driving.is_none(), egui::Button::new(label))
            .on_hover_text(
                "a ghost of the object where it should go: drag it, or its knob to turn it",
            )
            .clicked()
        {
            let pose = session.sandbox().object_pose();
            let ahead = pose.point_in_world(nalgebra::Point2::new(NEW_GOAL_AHEAD_M, 0.0));
            send(
                commands,
                SandboxCommand::SetGoal([ahead.x, ahead.y, pose.yaw + NEW_GOAL_TURN_RAD]),
            );
        }
        let mut with = session.plan_with();
        egui::ComboBox::from_label("plans with")
            .selected_text(with.name())
            .show_ui(ui, |ui| {
                for option in PlanWith::ALL {
                    ui.selectable_value(&mut with, option, option.name())
                        .on_hover_text(option.description());
                }
            });
        if with != session.plan_with() {
            send(commands, SandboxCommand::SetPlanWith(with));
        }
        if driving.is_some() {
            if ui.button("Stop").clicked() {
                send(commands, SandboxCommand::StopPushToGoal);
            }
        } else if ui
            .add_enabled(
                session.goal().is_some() && !session.sandbox().is_pushing(),
                egui::Button::new(RichText::new("Push to goal").strong()),
            )
            .on_hover_text("the controller pushes the object to the goal, planning with the model")
            .clicked()
        {
            send(commands, SandboxCommand::PushToGoal);
        }
    });
    ui.weak(format!("Plans with {}.", session.plan_with().description()));
    if let (Some(driving), Some(goal)) = (driving, session.goal()) {
        let pose = session.sandbox().object_pose();
        let (offset, yaw) = pose.motion_to(&goal);
        ui.label(format!(
            "{}, {:.1} s: {:.0} mm and {:.1}° from the goal",
            driving.plan().phase.map_or("planning", |p| p.name()),
            driving.time_s(),
            offset.norm() * 1e3,
            yaw.to_degrees()
        ));
    } else if let Some((reached, time_s, with)) = session.last_drive() {
        ui.label(format!(
            "Last run, planned with {}: {} after {time_s:.1} s.",
            with.name(),
            if reached { "reached" } else { "stopped" }
        ));
    }
}
