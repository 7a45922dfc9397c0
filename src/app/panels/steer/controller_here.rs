//! The Steer tab's "What would the controller do here": the controller's step from the frame
//! shown, toward where the push ends, said in words beside the scene's drawing of it (the state's
//! `controller_here`, the core's `control::replay`). A checkbox switches the scene's layer; the
//! rest reads state.

use eframe::egui;
use pushlab_core::control::Phase;

use crate::app::state::{AppState, Command};

/// The section: the layer's switch, then what the controller would do, in words.
pub fn ui(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    ui.add_space(8.0);
    ui.heading("What would the controller do here");
    let mut layers = state.settings().layers.clone();
    let switched = ui
        .checkbox(&mut layers.controller, "Show it in the scene")
        .on_hover_text(
            "The push-to-goal controller's next step from this frame, planned with the model and \
             θ as learned here, toward where this push ends: the object's arc along the push it \
             would make, and the pusher's way round to it (dashed)",
        )
        .changed();
    if switched {
        commands.push(Command::SetLayers(layers.clone()));
    }
    if !layers.controller {
        return;
    }
    let Some((goal, plan)) = state.controller_here() else {
        ui.weak("Nothing to plan here: the push is too short to give its pusher's speed.");
        return;
    };
    let away = goal.distance(&object_now(state).unwrap_or(goal.pose));
    let text = match (plan.phase, &plan.push) {
        (Some(Phase::Holding) | None, _) => {
            format!(
                "Hold: the object is within tolerance of where the push ends ({:.0} mm off).",
                away * 1e3
            )
        }
        (Some(phase), Some(push)) => format!(
            "{}: a push of {:.0} mm at {:+.0}° from straight in, which the model expects to leave \
             the object {:.0} mm from where the push ends (it is {:.0} mm away now){}.",
            match phase {
                Phase::Moving => "Go round",
                _ => "Push",
            },
            push.length_m * 1e3,
            push.angle.to_degrees(),
            push.expected_distance_m * 1e3,
            away * 1e3,
            match phase {
                Phase::Moving => format!(
                    ", after {:.0} mm of the pusher's way to it",
                    push.way_m * 1e3
                ),
                _ => String::new(),
            }
        ),
        (Some(_), None) => "No push brings the object nearer from here.".to_owned(),
    };
    ui.label(text);
}

/// The object's pose at the frame shown.
fn object_now(state: &AppState) -> Option<pushlab_core::geometry::Pose2> {
    let recording = state.recording()?;
    recording
        .trajectory
        .frames
        .get(state.frame())
        .map(|f| f.object)
}
