//! Every keyboard shortcut of the app. The fixed bindings are one table that both the handler and the
//! shortcut cheat-sheet read, so the sheet cannot drift from what the keys do; label hotkeys come
//! from the labels file's schema.
//!
//! Nothing fires while a text field has the keyboard: typing "1" into the notes is not a paint stroke.

use eframe::egui::{self, Key, KeyboardShortcut, Modifiers};
use pushlab_core::labels::{LabelKind, LabelSchema};

use crate::app::camera_mode::CameraMode;
use crate::app::state::labels::labeling::{ERASE_HOTKEY, LabelAction};
use crate::app::state::labels::proposals::ProposalAction;
use crate::app::state::learning::landscape::LandscapeCommand;
use crate::app::state::playback::timeline::TimelineCommand;
use crate::app::state::sources::sandbox::SandboxCommand;
use crate::app::state::{AppState, Command};

/// What a fixed binding does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum KeyAction {
    Timeline(TimelineCommand),
    JumpToLabel {
        forward: bool,
    },
    SetInPoint,
    PaintFromInPoint,
    Undo,
    Redo,
    SaveLabels,
    /// Accept the label proposals at the playhead.
    AcceptProposals,
    /// Reject the label proposals at the playhead.
    RejectProposals,
    ToggleCheatSheet,
    /// Show or hide the loss-landscape window.
    ToggleLandscape,
    /// Switch to or from the presentation layout (view state).
    TogglePresentation,
    /// Show or hide the menu bar (view state): a classroom link may hide it (`hide=menu`).
    ToggleMenuBar,
    /// How the scene's camera moves (view state).
    Camera(CameraMode),
}

/// One fixed key binding.
#[derive(Clone, Copy, Debug)]
pub struct Binding {
    pub shortcut: KeyboardShortcut,
    pub action: KeyAction,
    /// What the cheat-sheet says it does.
    pub help: &'static str,
}

const fn bind(modifiers: Modifiers, key: Key, action: KeyAction, help: &'static str) -> Binding {
    Binding {
        shortcut: KeyboardShortcut::new(modifiers, key),
        action,
        help,
    }
}

const NONE: Modifiers = Modifiers::NONE;
const SHIFT: Modifiers = Modifiers::SHIFT;
const COMMAND: Modifiers = Modifiers::COMMAND;

/// The fixed bindings, most specific first (egui matches Shift loosely, so Shift+→ must be tried
/// before →, and Ctrl+Shift+Z before Ctrl+Z).
pub const BINDINGS: [Binding; 23] = [
    bind(
        NONE,
        Key::Space,
        KeyAction::Timeline(TimelineCommand::TogglePlay),
        "play / pause",
    ),
    bind(
        SHIFT,
        Key::ArrowRight,
        KeyAction::Timeline(TimelineCommand::Step(10)),
        "forward 10 frames",
    ),
    bind(
        SHIFT,
        Key::ArrowLeft,
        KeyAction::Timeline(TimelineCommand::Step(-10)),
        "back 10 frames",
    ),
    bind(
        NONE,
        Key::ArrowRight,
        KeyAction::Timeline(TimelineCommand::Step(1)),
        "forward 1 frame",
    ),
    bind(
        NONE,
        Key::ArrowLeft,
        KeyAction::Timeline(TimelineCommand::Step(-1)),
        "back 1 frame",
    ),
    bind(
        NONE,
        Key::Home,
        KeyAction::Timeline(TimelineCommand::JumpStart),
        "first frame",
    ),
    bind(
        NONE,
        Key::End,
        KeyAction::Timeline(TimelineCommand::JumpEnd),
        "last frame",
    ),
    bind(
        NONE,
        Key::CloseBracket,
        KeyAction::JumpToLabel { forward: true },
        "next label start/end or event",
    ),
    bind(
        NONE,
        Key::OpenBracket,
        KeyAction::JumpToLabel { forward: false },
        "previous label start/end or event",
    ),
    bind(NONE, Key::I, KeyAction::SetInPoint, "set the in point here"),
    bind(
        NONE,
        Key::O,
        KeyAction::PaintFromInPoint,
        "paint the chosen label from the in point to here",
    ),
    bind(
        COMMAND.plus(SHIFT),
        Key::Z,
        KeyAction::Redo,
        "redo a label edit",
    ),
    bind(COMMAND, Key::Z, KeyAction::Undo, "undo a label edit"),
    bind(COMMAND, Key::Y, KeyAction::Redo, "redo a label edit"),
    bind(
        COMMAND,
        Key::S,
        KeyAction::SaveLabels,
        "save labels now (they also save by themselves)",
    ),
    bind(
        NONE,
        Key::Enter,
        KeyAction::AcceptProposals,
        "accept the label proposals at this frame (one undo step)",
    ),
    bind(
        NONE,
        Key::Backspace,
        KeyAction::RejectProposals,
        "reject the label proposals at this frame",
    ),
    bind(
        NONE,
        Key::F1,
        KeyAction::ToggleCheatSheet,
        "show / hide this sheet (also ?)",
    ),
    bind(
        NONE,
        Key::F2,
        KeyAction::ToggleLandscape,
        "show / hide the loss landscape",
    ),
    bind(
        NONE,
        Key::F5,
        KeyAction::TogglePresentation,
        "presentation layout on / off (demo mode)",
    ),
    bind(
        NONE,
        Key::F10,
        KeyAction::ToggleMenuBar,
        "show / hide the menu bar",
    ),
    bind(
        NONE,
        Key::F,
        KeyAction::Camera(CameraMode::Follow),
        "camera: follow the object",
    ),
    bind(
        NONE,
        Key::A,
        KeyAction::Camera(CameraMode::FitAll),
        "camera: fit the whole push",
    ),
];

/// The keys that steer the sandbox's pusher while its object is shown (they step the timeline
/// elsewhere), with the direction each pushes toward in the world: read by the handler and the
/// cheat-sheet.
pub const STEER_KEYS: [(Key, [f64; 2]); 4] = [
    (Key::ArrowRight, [1.0, 0.0]),
    (Key::ArrowLeft, [-1.0, 0.0]),
    (Key::ArrowUp, [0.0, 1.0]),
    (Key::ArrowDown, [0.0, -1.0]),
];
/// The cheat-sheet's line for [`STEER_KEYS`].
pub const STEER_HELP: &str = "in Push it yourself: move the pusher (held: it keeps going)";

/// What a key asks of the window's view rather than of the state: the app's shell carries it out
/// (`View::apply_key`), so that this table names no view and no panel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewChange {
    ToggleCheatSheet,
    TogglePresentation,
    ToggleMenuBar,
    Camera(CameraMode),
}

/// Turns this frame's key events into commands, in the order they happened: when a slow frame
/// collects "→, I" the in point lands after the step, and "I, →" before it. Several presses within
/// one frame all count. The cheat-sheet's visibility and the camera are view state, asked for as
/// view changes; everything else goes out as commands.
pub fn handle(
    ctx: &egui::Context,
    state: &AppState,
    view_changes: &mut Vec<ViewChange>,
    commands: &mut Vec<Command>,
) {
    if ctx.egui_wants_keyboard_input() {
        // A widget has the keyboard (typing in the notes, say): no shortcut fires, but a paint key
        // let go must still end its stroke, or the stroke would paint on and swallow the typing.
        if let Some(key) = state.labels().stroke_hotkey().and_then(Key::from_name)
            && !ctx.input(|i| i.key_down(key))
        {
            commands.push(Command::Label(LabelAction::EndStroke));
        }
        return;
    }
    let target = state.label_target();
    let schema = target.as_ref().and_then(|t| state.labels().schema_of(t));
    let steering = state.sandbox_shown();
    ctx.input_mut(|i| {
        if steering {
            steer(i, state, commands);
        }
        let mut held = state.labels().stroke_hotkey().and_then(Key::from_name);
        let mut consumed = vec![false; i.events.len()];
        for (index, event) in i.events.iter().enumerate() {
            let egui::Event::Key {
                key,
                pressed,
                repeat,
                modifiers,
                ..
            } = event
            else {
                continue;
            };
            if steering && STEER_KEYS.iter().any(|(k, _)| k == key) {
                consumed[index] = true;
                continue;
            }
            if !pressed {
                if held == Some(*key) {
                    commands.push(Command::Label(LabelAction::EndStroke));
                    held = None;
                }
                continue;
            }
            // The app's own keys come first: a label whose hotkey is one of them is painted from
            // the Labels tab instead (the cheat-sheet says so).
            if let Some(binding) = binding_for(*key, *modifiers) {
                consumed[index] = true;
                match binding.action {
                    KeyAction::Timeline(c) => commands.push(Command::Timeline(c)),
                    KeyAction::JumpToLabel { forward } => {
                        commands.push(Command::JumpToLabel { forward });
                    }
                    KeyAction::SetInPoint => commands.push(Command::Label(LabelAction::SetInPoint)),
                    KeyAction::PaintFromInPoint => {
                        commands.push(Command::Label(LabelAction::PaintFromInPoint));
                    }
                    KeyAction::Undo => commands.push(Command::Label(LabelAction::Undo)),
                    KeyAction::Redo => commands.push(Command::Label(LabelAction::Redo)),
                    KeyAction::SaveLabels => commands.push(Command::Label(LabelAction::SaveAll)),
                    KeyAction::AcceptProposals => {
                        commands.push(Command::Proposal(ProposalAction::AcceptHere));
                    }
                    KeyAction::RejectProposals => {
                        commands.push(Command::Proposal(ProposalAction::RejectHere));
                    }
                    KeyAction::ToggleCheatSheet => view_changes.push(ViewChange::ToggleCheatSheet),
                    KeyAction::ToggleLandscape => commands.push(Command::Landscape(
                        LandscapeCommand::Show(!state.landscape().open),
                    )),
                    KeyAction::TogglePresentation => {
                        view_changes.push(ViewChange::TogglePresentation);
                    }
                    KeyAction::ToggleMenuBar => view_changes.push(ViewChange::ToggleMenuBar),
                    KeyAction::Camera(mode) => view_changes.push(ViewChange::Camera(mode)),
                }
            } else if *key == Key::Questionmark {
                consumed[index] = true;
                view_changes.push(ViewChange::ToggleCheatSheet);
            } else if let Some(schema) = schema
                && !modifiers.command
                && !modifiers.alt
                && !repeat
                && let Some(command) = label_key(schema, *key, &mut held)
            {
                commands.push(command);
            }
        }
        // A key released while the window had no focus sends no release event.
        if let Some(key) = held
            && !i.key_down(key)
        {
            commands.push(Command::Label(LabelAction::EndStroke));
        }
        let mut index = 0;
        i.events.retain(|_| {
            index += 1;
            !consumed[index - 1]
        });
    });
}

/// The sandbox's pusher steered by the arrow keys held now; let go when none is held any more.
fn steer(input: &egui::InputState, state: &AppState, commands: &mut Vec<Command>) {
    let mut direction = [0.0, 0.0];
    for (key, [dx, dy]) in STEER_KEYS {
        if input.key_down(key) {
            direction[0] += dx;
            direction[1] += dy;
        }
    }
    let steering_now = state.sandbox().is_some_and(|s| s.steering());
    if direction != [0.0, 0.0] || steering_now {
        commands.push(Command::Sandbox(SandboxCommand::Steer(direction)));
    }
}

/// The fixed binding a key press triggers, if any.
fn binding_for(key: Key, modifiers: Modifiers) -> Option<&'static Binding> {
    BINDINGS.iter().find(|b| {
        b.shortcut.logical_key == key && modifiers.matches_logically(b.shortcut.modifiers)
    })
}

/// Whether `key` (unmodified) is taken by the app, so a label cannot use it as its hotkey.
pub fn is_app_key(key: Key) -> bool {
    key == Key::Questionmark
        || Key::from_name(ERASE_HOTKEY) == Some(key)
        || binding_for(key, Modifiers::NONE).is_some()
}

/// What a plain key press does to labels: a range label's hotkey starts a paint stroke (ignored
/// while another stroke is held), an event label's hotkey toggles its event, and Delete starts an
/// erase stroke. `held` is the key of the stroke in progress.
fn label_key(schema: &LabelSchema, key: Key, held: &mut Option<Key>) -> Option<Command> {
    if Key::from_name(ERASE_HOTKEY) == Some(key) {
        if held.is_some() {
            return None;
        }
        *held = Some(key);
        return Some(Command::Label(LabelAction::StartErase));
    }
    let label = schema
        .labels
        .iter()
        .find(|l| l.hotkey.as_deref().and_then(Key::from_name) == Some(key));
    match label {
        Some(label) if label.kind == LabelKind::Event => {
            Some(Command::Label(LabelAction::Hotkey(label.name.clone())))
        }
        Some(label) if held.is_none() => {
            *held = Some(key);
            Some(Command::Label(LabelAction::Hotkey(label.name.clone())))
        }
        Some(_) | None => None,
    }
}

/// The label hotkeys of a schema for the cheat-sheet: (key, label name, what the key does).
pub fn label_hotkey_rows(
    schema: &pushlab_core::labels::LabelSchema,
) -> Vec<(String, String, &'static str)> {
    let mut rows: Vec<_> = schema
        .labels
        .iter()
        .filter_map(|l| {
            let key = l.hotkey.clone()?;
            let taken = Key::from_name(&key).is_some_and(is_app_key);
            let what = match (taken, l.kind) {
                (true, _) => "taken by the app's own keys: use the Labels tab",
                (false, LabelKind::Range) => "hold to paint while stepping or playing",
                (false, LabelKind::Event) => "place or remove the event here",
            };
            Some((key, l.name.clone(), what))
        })
        .collect();
    rows.push((
        ERASE_HOTKEY.to_owned(),
        "all range labels".to_owned(),
        "hold to erase while stepping or playing",
    ));
    rows
}

#[cfg(test)]
mod tests {
    use pushlab_core::labels::{LabelDef, Rgb};

    use super::*;

    #[test]
    fn the_cheat_sheet_marks_label_keys_the_app_already_uses() {
        let mut schema = LabelSchema::default();
        for (name, key) in [("pushed", "I"), ("wobble", "Delete"), ("fine", "8")] {
            let mut label = LabelDef::range(name, Rgb::new(1, 2, 3));
            label.hotkey = Some(key.to_owned());
            schema.labels.push(label);
        }
        let rows = label_hotkey_rows(&schema);
        let what = |name: &str| {
            rows.iter()
                .find(|(_, label, _)| label == name)
                .map(|(_, _, what)| *what)
                .unwrap_or_default()
        };
        assert!(what("pushed").contains("taken by the app"));
        assert!(what("wobble").contains("taken by the app"));
        assert_eq!(what("fine"), "hold to paint while stepping or playing");
        assert_eq!(what("contact"), "hold to paint while stepping or playing");
    }
}
