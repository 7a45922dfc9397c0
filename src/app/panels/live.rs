//! File → Connect to a live robot…: the form (server, topics, the object's setting, the file to
//! record to), and the timeline's live strip (the connection, messages, how late the poses come,
//! Back to live, Disconnect). Reads the state's `live` and sends `LiveCommand`s.

use pushlab_core::live::Lag;
use std::path::PathBuf;

use eframe::egui::{self, RichText};

use crate::app::colors;
use crate::app::state::sources::live::{Link, LiveCommand, Running};
use crate::app::state::{AppState, Command};

/// Draws the Connect form when it is open.
pub fn window(ctx: &egui::Context, state: &AppState, commands: &mut Vec<Command>) {
    let Some(form) = state.live().form() else {
        return;
    };
    let mut send = |c| commands.push(Command::Live(c));
    let mut choice = form.choice.clone();
    let mut open = true;
    egui::Window::new("Connect to a live robot")
        .open(&mut open)
        .collapsible(false)
        .default_width(520.0)
        .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
        .show(ctx, |ui| {
            ui.label(
                "A Foxglove WebSocket server: foxglove_bridge (ROS 1 and 2) or the Foxglove SDK's. \
                 The push grows as the frames arrive and θ is learned as they do.",
            );
            if let Some(error) = &form.error {
                ui.colored_label(ui.visuals().error_fg_color, error);
            }
            let streams = match &form.streams {
                Some(Ok(streams)) => streams.iter().map(ToString::to_string).collect(),
                _ => Vec::new(),
            };
            egui::Grid::new("live-form").num_columns(2).show(ui, |ui| {
                ui.label("Server");
                ui.horizontal(|ui| {
                    ui.text_edit_singleline(&mut choice.url).on_hover_text(
                        "ws://HOST:PORT (foxglove_bridge and the SDK listen on 8765)",
                    );
                    if state.live().is_listing() {
                        ui.spinner();
                    } else if ui
                        .button("List topics")
                        .on_hover_text(
                            "connect for a moment and offer the server's pose streams, \
                             pre-selected by name as for a bag",
                        )
                        .clicked()
                    {
                        send(LiveCommand::ListTopics);
                    }
                });
                ui.end_row();
                match &form.streams {
                    Some(Err(why)) => {
                        ui.label("");
                        ui.colored_label(ui.visuals().error_fg_color, why);
                        ui.end_row();
                    }
                    // Listed, and nothing to follow: said, so the click is not taken for nothing.
                    Some(Ok(streams)) if streams.is_empty() => {
                        ui.label("");
                        ui.colored_label(
                            ui.visuals().warn_fg_color,
                            "the server offers no pose stream (PoseStamped, TFMessage, Odometry, \
                             Pose2D, a JSON pose or foxglove.PoseInFrame): is its node running?",
                        );
                        ui.end_row();
                    }
                    _ => {}
                }
                for (label, id, value) in [
                    ("Pusher topic", "live-pusher", &mut choice.pusher),
                    ("Object topic", "live-object", &mut choice.object),
                ] {
                    ui.label(label);
                    ui.horizontal(|ui| {
                        ui.text_edit_singleline(value).on_hover_text(
                            "TOPIC, or TOPIC:CHILD_FRAME for a TF topic such as /tf",
                        );
                        if !streams.is_empty() {
                            egui::ComboBox::from_id_salt(id)
                                .selected_text("choose")
                                .show_ui(ui, |ui| {
                                    for stream in &streams {
                                        ui.selectable_value(value, stream.clone(), stream);
                                    }
                                });
                        }
                    });
                    ui.end_row();
                }
                ui.label("Object's setting.json");
                path_edit(ui, &mut choice.setting);
                ui.end_row();
                ui.label("Record to (.mcap)");
                path_edit(ui, &mut choice.record).on_hover_text(
                    "a new MCAP file every message received is written to as it arrives; \
                     empty: not recorded",
                );
                ui.end_row();
                ui.label("Grid rate (Hz)");
                let mut rate = choice.rate_hz.map(|r| r.to_string()).unwrap_or_default();
                if ui
                    .text_edit_singleline(&mut rate)
                    .on_hover_text("empty: the rate the model was trained at")
                    .changed()
                {
                    choice.rate_hz = rate.trim().parse().ok();
                }
                ui.end_row();
            });
            ui.separator();
            super::live_drive::form_section(ui, &mut choice.drive);
            ui.horizontal(|ui| {
                if ui.button("Connect").clicked() {
                    send(LiveCommand::Connect);
                }
                if ui.button("Cancel").clicked() {
                    send(LiveCommand::CloseForm);
                }
            });
        });
    if choice != form.choice {
        send(LiveCommand::Edit(choice));
    }
    if !open {
        send(LiveCommand::CloseForm);
    }
}

/// A path typed in as text.
fn path_edit(ui: &mut egui::Ui, path: &mut PathBuf) -> egui::Response {
    let mut text = path.display().to_string();
    let response = ui.text_edit_singleline(&mut text);
    if response.changed() {
        *path = PathBuf::from(text);
    }
    response
}

/// The live session's strip in the timeline bar, when there is one: what the connection is doing,
/// messages and lateness, Back to live, Disconnect.
pub fn strip(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let palette = colors::of(ui.ctx());
    let Some(running) = state.live().running() else {
        return;
    };
    let live = state.live().is_live();
    let (badge, color) = match &running.latest.link {
        Link::Connecting => ("CONNECTING", ui.visuals().warn_fg_color),
        Link::Connected { .. } => ("LIVE", palette.live),
        Link::Lost { .. } => ("RECONNECTING", ui.visuals().warn_fg_color),
        Link::Ended { .. } => ("ENDED", ui.visuals().weak_text_color()),
    };
    ui.label(RichText::new(badge).strong().color(color))
        .on_hover_text(describe(
            running,
            state.growing().map_or(1, |g| g.every_nth),
        ));
    if live {
        // Always there (greyed at the edge), so that the buttons after it never move under the
        // pointer when the user scrubs back.
        let following = state.growing().is_some_and(|g| g.following);
        let at_edge = following && state.frame() == state.timeline().last_frame();
        if ui
            .add_enabled(!at_edge, egui::Button::new("Back to live"))
            .on_hover_text("show the newest frame and follow it")
            .on_disabled_hover_text("following the newest frame")
            .clicked()
        {
            commands.push(Command::Live(LiveCommand::BackToLive));
        }
        if ui
            .button("Disconnect")
            .on_hover_text(
                "end the session; the recording is closed cleanly and the push stays open",
            )
            .clicked()
        {
            commands.push(Command::Live(LiveCommand::Disconnect));
        }
    }
    ui.separator();
}

/// The session in a sentence.
fn describe(running: &Running, every_nth: usize) -> String {
    let latest = &running.latest;
    let lag = |l: Option<Lag>| l.map_or("-".to_owned(), |l| format!("{:.0} ms", l.seconds * 1e3));
    let mut text = format!(
        "{} — {} messages, {} frames; poses arrive late by: pusher {}, object {}",
        running.choice.url,
        latest.messages,
        running.frames,
        lag(latest.lag[0]),
        lag(latest.lag[1]),
    );
    if latest.lag.iter().flatten().any(|l| !l.wall_clock) {
        text += " (later than each stream's first pose: its stamps are not wall-clock time)";
    }
    if every_nth > 1 {
        text += &format!("; learning every {every_nth}th frame to keep up");
    }
    if latest.refused > 0 {
        text += &format!("; {} pose(s) left out", latest.refused);
    }
    if !running.gaps.is_empty() {
        let spans: Vec<String> = (running.gaps.iter())
            .map(|g| format!("{}–{}", g.frames.start, g.frames.end.saturating_sub(1)))
            .collect();
        text += &format!(
            "; {} gap(s), frames {} interpolated",
            running.gaps.len(),
            spans.join(", ")
        );
    }
    match &latest.link {
        Link::Connected { server } => text += &format!("; server: {server}"),
        Link::Lost { why } => text += &format!("; lost: {why}"),
        Link::Ended { error, recorded } => {
            text += &error.as_ref().map_or(String::new(), |e| format!("; {e}"));
            text += &recorded
                .as_ref()
                .map_or(String::new(), |r| format!("; {r}"));
        }
        Link::Connecting => {}
    }
    if !running.choice.record.as_os_str().is_empty() {
        text += &format!("; recording to {}", running.choice.record.display());
    }
    text
}
