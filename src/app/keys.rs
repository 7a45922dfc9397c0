//! Every keyboard shortcut of the app. The fixed bindings are one table that both the handler and the
//! shortcut cheat-sheet read, so the sheet cannot drift from what the keys do; label hotkeys come
//! from the labels file's schema.
//!
//! Nothing fires while a text field has the keyboard: typing "1" into the notes is not a paint stroke.

use eframe::egui::{self, Key, KeyboardShortcut, Modifiers};

use crate::app::state::labels::{ERASE_HOTKEY, LabelAction};
use crate::app::state::timeline::TimelineCommand;
use crate::app::state::{AppState, Command};

/// What a fixed binding does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum KeyAction {
    Timeline(TimelineCommand),
    JumpToLabel { forward: bool },
    SetInPoint,
    PaintFromInPoint,
    Undo,
    Redo,
    SaveLabels,
    ToggleCheatSheet,
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
pub const BINDINGS: [Binding; 16] = [
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
        Key::F1,
        KeyAction::ToggleCheatSheet,
        "show / hide this sheet (also ?)",
    ),
];

/// Turns this frame's key presses into commands. `cheat_sheet` is the sheet's visibility (view state).
pub fn handle(
    ctx: &egui::Context,
    state: &AppState,
    cheat_sheet: &mut bool,
    commands: &mut Vec<Command>,
) {
    if ctx.egui_wants_keyboard_input() {
        return;
    }
    ctx.input_mut(|i| {
        label_hotkeys(i, state, commands);
        for binding in &BINDINGS {
            // Several presses can arrive within one frame (fast typing, key repeat, a slow frame):
            // each counts, so five quick → are five frames.
            let presses =
                i.count_and_consume_key(binding.shortcut.modifiers, binding.shortcut.logical_key);
            for _ in 0..presses {
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
                    KeyAction::ToggleCheatSheet => *cheat_sheet = !*cheat_sheet,
                }
            }
        }
        if i.consume_key(NONE, Key::Questionmark) {
            *cheat_sheet = !*cheat_sheet;
        }
    });
}

/// A range label's hotkey paints while held; an event label's hotkey toggles its event; Delete held
/// erases. The stroke ends when its key is up, even if it went down and up within one frame.
fn label_hotkeys(i: &egui::InputState, state: &AppState, commands: &mut Vec<Command>) {
    let Some(target) = state.label_target() else {
        return;
    };
    let Some(schema) = state.labels.schema_of(&target) else {
        return;
    };
    let mut held = state.labels.stroke_hotkey().and_then(Key::from_name);
    for label in &schema.labels {
        let Some(key) = label.hotkey.as_deref().and_then(Key::from_name) else {
            continue;
        };
        // Events are placed even during a stroke; a second range key during a stroke is ignored.
        let is_range = label.kind == pushlab_core::labels::LabelKind::Range;
        if fresh_press(i, key) && !(is_range && held.is_some()) {
            commands.push(Command::Label(LabelAction::Hotkey(label.name.clone())));
            if is_range {
                held = Some(key);
            }
        }
    }
    if held.is_none()
        && let Some(erase) = Key::from_name(ERASE_HOTKEY)
        && fresh_press(i, erase)
    {
        commands.push(Command::Label(LabelAction::StartErase));
        held = Some(erase);
    }
    if let Some(key) = held
        && !i.key_down(key)
    {
        commands.push(Command::Label(LabelAction::EndStroke));
    }
}

/// Whether `key` went down this frame without modifiers (key repeats do not count).
fn fresh_press(i: &egui::InputState, key: Key) -> bool {
    i.events.iter().any(|e| {
        matches!(e, egui::Event::Key { key: k, pressed: true, repeat: false, modifiers, .. }
            if *k == key && !modifiers.command && !modifiers.alt)
    })
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
            let what = match l.kind {
                pushlab_core::labels::LabelKind::Range => "hold to paint while stepping or playing",
                pushlab_core::labels::LabelKind::Event => "place or remove the event here",
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
