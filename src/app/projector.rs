//! Projector mode: a lecture hall's projector washes out thin grey lines and small text, so the
//! whole window goes to a light theme with black text, thicker strokes and up to 1.4× zoom.
//!
//! Outside projector mode the window is in the dark theme or, asked for (View → Light theme, a
//! link's `light=1`), egui's light one; the scene's colours follow either (`colors::of`).
//!
//! Why the zoom follows the window: many projectors are 1280×800, and at 1.4× that leaves 914
//! points, where the tools pane and the right of the menu bar were cut off. The zoom is as large as
//! leaves the layout [`ROOM`] points across, between 1× and [`ZOOM`].

use eframe::egui;

/// How much larger everything is drawn on a projector wide enough for it.
pub const ZOOM: f32 = 1.4;

/// The width, in points, the panels need side by side without cutting the tools pane.
pub const ROOM: f32 = 1150.0;

/// The zoom for a window `native_width` points wide (at zoom 1).
pub fn zoom_for(native_width: f32) -> f32 {
    (native_width / ROOM).clamp(1.0, ZOOM)
}

/// Sets the style for projector mode `on` (or back to the dark or, with `light`, the light theme)
/// when it changes, and the zoom to the window's width while it is on.
pub fn apply(ctx: &egui::Context, on: bool, light: bool) {
    let id = egui::Id::unique("pushlab-projector");
    let was: (bool, bool) = ctx.data(|d| d.get_temp(id).unwrap_or((false, false)));
    if on {
        let wanted = zoom_for(ctx.content_rect().width() * ctx.zoom_factor());
        if (ctx.zoom_factor() - wanted).abs() > 0.01 {
            ctx.set_zoom_factor(wanted);
        }
    }
    if was == (on, light) {
        return;
    }
    ctx.data_mut(|d| d.insert_temp(id, (on, light)));
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
    } else {
        ctx.set_visuals(if light {
            egui::Visuals::light()
        } else {
            egui::Visuals::dark()
        });
        if was.0 {
            ctx.set_zoom_factor(1.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_zoom_leaves_the_layout_its_room() {
        // A 1280-wide projector: 1.11×, leaving 1,150 points; a 1920-wide one gets the full 1.4×.
        assert!((zoom_for(1280.0) - 1280.0 / ROOM).abs() < 1e-6);
        assert!(1280.0 / zoom_for(1280.0) >= ROOM - 0.01);
        assert_eq!(zoom_for(1920.0), ZOOM);
        // Never smaller than life.
        assert_eq!(zoom_for(800.0), 1.0);
    }
}
