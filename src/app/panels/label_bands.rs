//! The label overview above the scrub slider: one band per range label used in the recording, a row
//! of event ticks, the in point and the current frame. Click or drag anywhere on it to jump there;
//! hover a band to read its label and frames.

use eframe::egui::{self, Color32, Pos2, Rect, Sense, Stroke, Vec2};
use pushlab_core::labels::{LabelSchema, RecordingLabels, Rgb};

use crate::app::colors;
use crate::app::state::playback::timeline::TimelineCommand;
use crate::app::state::{AppState, Command};

/// Height of one band, points.
const BAND_HEIGHT: f32 = 9.0;

/// Draws the bands over `width` points (the scrub slider's width, so frames line up with it).
pub fn ui(ui: &mut egui::Ui, state: &AppState, width: f32, commands: &mut Vec<Command>) {
    let Some(target) = state.label_target() else {
        return;
    };
    let empty = RecordingLabels::default();
    let labels = state.labels().labels_of(&target).unwrap_or(&empty);
    let default_schema = LabelSchema::default();
    let schema = state.labels().schema_of(&target).unwrap_or(&default_schema);
    let rows: Vec<&str> = schema
        .labels
        .iter()
        .filter(|l| labels.segments.iter().any(|s| s.label == l.name))
        .map(|l| l.name.as_str())
        .collect();
    let band_rows = rows.len() + usize::from(!labels.events.is_empty());
    let height = BAND_HEIGHT * band_rows.max(1) as f32 + 4.0;

    let (rect, response) =
        ui.allocate_exact_size(Vec2::new(width, height), Sense::click_and_drag());
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "Label bands"));
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, colors::of(ui.ctx()).band);
    let frames = target.frames.max(1);
    let x_of = |frame: usize| rect.left() + rect.width() * frame as f32 / frames as f32;
    let frame_at = |x: f32| {
        let t = ((x - rect.left()) / rect.width()).clamp(0.0, 1.0);
        ((t * frames as f32) as usize).min(frames - 1)
    };

    if band_rows == 0 {
        let hint = match state.labels().read_only_reason(&target) {
            Some(_) => "labels are read-only: see the Labels tab",
            None => {
                "no labels yet: hold a label's key (1–5) while stepping, or press ? for all keys"
            }
        };
        painter.text(
            rect.left_center() + Vec2::new(6.0, 0.0),
            egui::Align2::LEFT_CENTER,
            hint,
            egui::FontId::proportional(10.0),
            Color32::GRAY,
        );
    }
    let mut hovered_text = None;
    let hover = response.hover_pos();
    for (row, name) in rows.iter().enumerate() {
        let colour = schema.get(name).map_or(Color32::GRAY, |l| color(l.colour));
        let top = rect.top() + 2.0 + row as f32 * BAND_HEIGHT;
        for segment in labels.segments.iter().filter(|s| s.label == *name) {
            let band = Rect::from_min_max(
                Pos2::new(x_of(segment.start), top),
                Pos2::new(
                    x_of(segment.end).max(x_of(segment.start) + 1.0),
                    top + BAND_HEIGHT - 1.0,
                ),
            );
            painter.rect_filled(band, 1.0, colour);
            if hover.is_some_and(|p| band.contains(p)) {
                hovered_text = Some(format!(
                    "{name}: frames {}–{}",
                    segment.start,
                    segment.last_frame()
                ));
            }
        }
    }
    if !labels.events.is_empty() {
        let top = rect.top() + 2.0 + rows.len() as f32 * BAND_HEIGHT;
        for event in &labels.events {
            let colour = schema
                .get(&event.label)
                .map_or(Color32::GRAY, |l| color(l.colour));
            let x = x_of(event.frame) + 0.5;
            painter.line_segment(
                [Pos2::new(x, top), Pos2::new(x, top + BAND_HEIGHT - 1.0)],
                Stroke::new(2.0, colour),
            );
            if hover.is_some_and(|p| (p.x - x).abs() < 3.0 && p.y >= top) {
                hovered_text = Some(format!("{}: frame {}", event.label, event.frame));
            }
        }
    }
    if let Some(in_point) = state.labels().in_point {
        let x = x_of(in_point);
        painter.line_segment(
            [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
            Stroke::new(2.0, Color32::from_rgb(120, 255, 120)),
        );
    }
    let x = x_of(state.frame()) + 0.5;
    painter.line_segment(
        [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
        Stroke::new(1.5, colors::of(ui.ctx()).cursor),
    );

    if (response.clicked() || response.dragged())
        && let Some(pointer) = response.interact_pointer_pos()
    {
        commands.push(Command::Timeline(TimelineCommand::SeekTo(frame_at(
            pointer.x,
        ))));
    }
    if let Some(text) = hovered_text {
        response.on_hover_text(text);
    } else if let Some(p) = hover {
        response.on_hover_text(format!("click to jump to frame {}", frame_at(p.x)));
    }
}

/// The egui colour of a schema colour.
pub fn color(rgb: Rgb) -> Color32 {
    let [r, g, b] = rgb.0;
    Color32::from_rgb(r, g, b)
}
