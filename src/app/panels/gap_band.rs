//! The gaps band over the scrub slider, shown while the selected push is a live session that lost
//! its connection: each span the connection was away, in red, its frames being interpolated
//! between the poses before and after. Hover a span for what happened; click it to jump to its
//! first frame.

use eframe::egui::{self, Color32, Pos2, Rect, Sense, Stroke, Vec2};

use crate::app::colors;
use crate::app::state::playback::timeline::TimelineCommand;
use crate::app::state::sources::live::Gap;
use crate::app::state::{AppState, Command};

/// Height of the band, points (as a label band's row).
const HEIGHT: f32 = 9.0;

/// Draws the band over `width` points (the label bands' width, so frames line up); nothing when
/// the push shown has no gap.
pub fn ui(ui: &mut egui::Ui, state: &AppState, width: f32, commands: &mut Vec<Command>) {
    let gaps = state.live_gaps();
    if gaps.is_empty() {
        return;
    }
    let (rect, response) = ui.allocate_exact_size(Vec2::new(width, HEIGHT + 4.0), Sense::click());
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "Gaps band"));
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, colors::of(ui.ctx()).band);
    let frames = state.timeline().last_frame() + 1;
    let x_of = |frame: usize| rect.left() + rect.width() * frame as f32 / frames as f32;
    let hover = response.hover_pos();
    let mut under_pointer: Option<&Gap> = None;
    for gap in gaps {
        let piece = Rect::from_min_max(
            Pos2::new(x_of(gap.frames.start), rect.top() + 2.0),
            Pos2::new(
                x_of(gap.frames.end).max(x_of(gap.frames.start) + 2.0),
                rect.bottom() - 2.0,
            ),
        );
        painter.rect_filled(piece, 1.0, Color32::from_rgb(200, 70, 60));
        if hover.is_some_and(|h| piece.expand2(Vec2::new(3.0, 0.0)).contains(h)) {
            under_pointer = Some(gap);
        }
    }
    let x = x_of(state.frame()) + 0.5;
    painter.line_segment(
        [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
        Stroke::new(1.5, colors::of(ui.ctx()).cursor),
    );
    let Some(gap) = under_pointer else {
        return;
    };
    if response.clicked() {
        commands.push(Command::Timeline(TimelineCommand::SeekTo(gap.frames.start)));
    }
    response.on_hover_text(describe(gap));
}

/// A gap in a sentence: what the hover says.
pub fn describe(gap: &Gap) -> String {
    format!(
        "connection lost for {:.1} s: frames {}–{} are interpolated across it (click to jump there)",
        gap.away_s,
        gap.frames.start,
        gap.frames.end.saturating_sub(1)
    )
}
