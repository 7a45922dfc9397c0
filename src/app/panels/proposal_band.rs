//! The proposals band under the label bands: what `labels::propose` proposes for the selected
//! recording and the user has not decided on yet, one row per exclusive group, each segment in its
//! label's colour but hatched and outlined (a label band is solid). Click a proposed segment to
//! accept it, right-click to reject it; hover it for its confidence; click elsewhere to jump there.
//! Its menu, in the timeline's top row, accepts every proposal of one label or restores rejected
//! ones.

use eframe::egui::{self, Color32, Pos2, Rect, Sense, Stroke, Vec2};
use pushlab_core::labels::LabelSchema;

use super::label_bands::color;
use crate::app::colors;
use crate::app::state::labels::proposals::{Pending, ProposalAction, Status};
use crate::app::state::playback::timeline::TimelineCommand;
use crate::app::state::{AppState, Command};

/// Height of one row, points (as a label band).
const ROW_HEIGHT: f32 = 9.0;

/// Draws the band over `width` points (the label bands' width, so frames line up), and its menu.
pub fn ui(ui: &mut egui::Ui, state: &AppState, width: f32, commands: &mut Vec<Command>) {
    let (Some(recording), Some(target)) = (state.recording(), state.label_target()) else {
        return;
    };
    let default_schema = LabelSchema::default();
    let schema = state.labels().schema_of(&target).unwrap_or(&default_schema);
    let pending = state.pending_proposals();
    // Rows from every proposal, decided or not, so that they stay put while the user decides.
    let proposed: Vec<&str> = state
        .proposals()
        .of(&recording.source)
        .map(|p| p.segments.iter().map(|s| s.label).collect())
        .unwrap_or_default();
    let rows = rows_of(schema, &proposed);
    let rejected = state.proposals().rejected_count(&recording.source);
    let note = match state.proposals().status(&recording.source) {
        Status::None => Some(String::new()),
        Status::Running(done) => Some(format!("proposing labels… {:.0} %", 100.0 * done)),
        Status::Failed(reason) => Some(reason.to_owned()),
        Status::Ready(_) if pending.is_empty() && rejected > 0 => Some(format!(
            "no proposals left ({rejected} rejected: the Proposals menu restores them)"
        )),
        Status::Ready(_) if pending.is_empty() => {
            Some("no proposals left: every proposed frame is labelled".to_owned())
        }
        Status::Ready(_) => None,
    };
    band(ui, state, width, &pending, &rows, note, commands);
}

/// The rows: one per exclusive group of a proposed label (a label without a group is its own), in
/// schema order.
fn rows_of(schema: &LabelSchema, proposed: &[&str]) -> Vec<String> {
    let row_of = |label: &str| {
        schema
            .group_of(label)
            .map_or_else(|| label.to_owned(), str::to_owned)
    };
    let mut rows: Vec<String> = Vec::new();
    let names = schema.labels.iter().map(|l| l.name.as_str());
    // Proposed labels the schema lacks (renamed or removed) still get a row, last.
    for name in names.chain(proposed.iter().copied()) {
        let row = row_of(name);
        if proposed.iter().any(|p| row_of(p) == row) && !rows.contains(&row) {
            rows.push(row);
        }
    }
    rows
}

fn band(
    ui: &mut egui::Ui,
    state: &AppState,
    width: f32,
    pending: &[Pending<'_>],
    rows: &[String],
    note: Option<String>,
    commands: &mut Vec<Command>,
) {
    let Some(target) = state.label_target() else {
        return;
    };
    let default_schema = LabelSchema::default();
    let schema = state.labels().schema_of(&target).unwrap_or(&default_schema);
    let height = ROW_HEIGHT * rows.len().max(1) as f32 + 4.0;
    let (rect, response) = ui.allocate_exact_size(Vec2::new(width, height), Sense::click());
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "Proposals band"));
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, colors::of(ui.ctx()).band);
    let frames = target.frames.max(1);
    let x_of = |frame: usize| rect.left() + rect.width() * frame as f32 / frames as f32;
    let frame_at = |x: f32| {
        let t = ((x - rect.left()) / rect.width()).clamp(0.0, 1.0);
        ((t * frames as f32) as usize).min(frames - 1)
    };
    if let Some(note) = note {
        painter.text(
            rect.left_center() + Vec2::new(6.0, 0.0),
            egui::Align2::LEFT_CENTER,
            note,
            egui::FontId::proportional(10.0),
            Color32::GRAY,
        );
    }
    let hover = response.hover_pos();
    let mut under_pointer: Option<&Pending<'_>> = None;
    for p in pending {
        let row_name = schema
            .group_of(p.proposal.label)
            .unwrap_or(p.proposal.label);
        let row = rows.iter().position(|r| r == row_name).unwrap_or(0);
        let top = rect.top() + 2.0 + row as f32 * ROW_HEIGHT;
        let colour = schema
            .get(p.proposal.label)
            .map_or(Color32::GRAY, |l| color(l.colour));
        for frames in &p.open {
            let piece = Rect::from_min_max(
                Pos2::new(x_of(frames.start), top),
                Pos2::new(
                    x_of(frames.end).max(x_of(frames.start) + 1.0),
                    top + ROW_HEIGHT - 1.0,
                ),
            );
            hatched(&painter, piece, colour);
            if hover.is_some_and(|h| piece.contains(h)) {
                under_pointer = Some(p);
            }
        }
    }
    let x = x_of(state.frame()) + 0.5;
    painter.line_segment(
        [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
        Stroke::new(1.5, colors::of(ui.ctx()).cursor),
    );

    match under_pointer {
        Some(p) if response.clicked() => {
            commands.push(Command::Proposal(ProposalAction::Accept(p.index)));
        }
        Some(p) if response.secondary_clicked() => {
            commands.push(Command::Proposal(ProposalAction::Reject(p.index)));
        }
        None if response.clicked() => {
            if let Some(pointer) = response.interact_pointer_pos() {
                commands.push(Command::Timeline(TimelineCommand::SeekTo(frame_at(
                    pointer.x,
                ))));
            }
        }
        _ => {}
    }
    if let Some(p) = under_pointer {
        response.on_hover_text(format!(
            "proposed {}: frames {}–{}, {:.0} % sure\nclick to accept (Enter at the playhead), right-click to reject (Backspace)",
            p.proposal.label,
            p.proposal.frames.start,
            p.proposal.frames.end.saturating_sub(1),
            100.0 * p.proposal.confidence
        ));
    } else if let Some(h) = hover {
        response.on_hover_text(format!("click to jump to frame {}", frame_at(h.x)));
    }
}

/// A proposed piece: translucent, outlined and hatched in its label's colour.
fn hatched(painter: &egui::Painter, piece: Rect, colour: Color32) {
    let [r, g, b, _] = colour.to_array();
    painter.rect_filled(piece, 1.0, Color32::from_rgba_unmultiplied(r, g, b, 60));
    let clipped = painter.with_clip_rect(piece.intersect(painter.clip_rect()));
    let line = Stroke::new(1.0, Color32::from_rgba_unmultiplied(r, g, b, 200));
    let mut x = piece.left() - piece.height();
    while x < piece.right() {
        clipped.line_segment(
            [
                Pos2::new(x, piece.bottom()),
                Pos2::new(x + piece.height(), piece.top()),
            ],
            line,
        );
        x += 4.0;
    }
    painter.rect_stroke(
        piece,
        1.0,
        Stroke::new(1.0, colour),
        egui::StrokeKind::Inside,
    );
}

/// The Proposals menu (in the timeline's top row): accept every proposal of one label, act at the
/// playhead, restore rejected proposals.
pub fn menu(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    let (Some(recording), Some(target)) = (state.recording(), state.label_target()) else {
        return;
    };
    let default_schema = LabelSchema::default();
    let schema = state.labels().schema_of(&target).unwrap_or(&default_schema);
    let pending = state.pending_proposals();
    let rejected = state.proposals().rejected_count(&recording.source);
    let mut send = |action| commands.push(Command::Proposal(action));
    ui.menu_button(format!("Proposals ({})", pending.len()), |ui| {
        for label in &schema.labels {
            let n = pending
                .iter()
                .filter(|p| p.proposal.label == label.name)
                .count();
            if n > 0
                && ui
                    .button(format!("Accept all {} ({n})", label.name))
                    .on_hover_text("one undo step; frames you labelled in its group are kept")
                    .clicked()
            {
                send(ProposalAction::AcceptAll(label.name.clone()));
            }
        }
        ui.separator();
        if ui.button("Accept at the playhead (Enter)").clicked() {
            send(ProposalAction::AcceptHere);
        }
        if ui.button("Reject at the playhead (Backspace)").clicked() {
            send(ProposalAction::RejectHere);
        }
        if ui
            .add_enabled(
                rejected > 0,
                egui::Button::new(format!("Restore rejected ({rejected})")),
            )
            .clicked()
        {
            send(ProposalAction::RestoreRejected);
        }
    });
}
