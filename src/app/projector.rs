//! Projector mode: a lecture hall's projector washes out thin grey lines and small text, so the
//! whole window goes to a light theme with black text, thicker strokes and 1.4× zoom.

use eframe::egui;

/// How much larger everything is drawn on a projector.
pub const ZOOM: f32 = 1.4;

/// Sets the style for projector mode `on` (or back), only when it changes.
pub fn apply(ctx: &egui::Context, on: bool) {
    let id = egui::Id::unique("pushlab-projector");
    let was: bool = ctx.data(|d| d.get_temp(id).unwrap_or(false));
    if was == on {
        return;
    }
    ctx.data_mut(|d| d.insert_temp(id, on));
    if on {
        let mut visuals = egui::Visuals::light();
        visuals.override_text_color = Some(egui::Color32::BLACK);
        for widget in [
            &mut visuals.widgets.noninteractive,
            &mut visuals.widgets.inactive,
            &mut visuals.widgets.hovered,
            &mut visuals.widgets.active,
        ] {
            widget.fg_stroke.width = widget.fg_stroke.width.max(1.5);
            widget.bg_stroke.width = widget.bg_stroke.width.max(1.0);
            widget.bg_stroke.color = egui::Color32::BLACK;
        }
        ctx.set_visuals(visuals);
        ctx.set_zoom_factor(ZOOM);
    } else {
        ctx.set_visuals(egui::Visuals::dark());
        ctx.set_zoom_factor(1.0);
    }
}
